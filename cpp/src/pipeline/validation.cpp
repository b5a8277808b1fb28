#include "pipeline/validation.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <sstream>

#include "mesh/geometry.h"
#include "blend/metric_blend.h"

namespace bdinterp::detail {
namespace {

// The residual max |2pi - angle sum| is a difference of doubles in [4, 8), hence 0 or at least their
// spacing 2^-50 (~8.9e-16): a smaller tolerance asks for an exact zero at every interior vertex,
// which Newton steps on rounded angles cannot aim for. Scale-free: the inputs are normalised.
constexpr double kToleranceFloor = 0x1p-50;

void validate_path(const AnchorPath& p, int num_shapes) {
  if (num_shapes != 2) throw InvalidInput("an anchor path needs exactly two shapes");
  if (p.t.empty() || p.angle.size() != p.t.size() || p.position.rows() != static_cast<int>(p.t.size()))
    throw InvalidInput("anchor path: t, positions and angles must have the same non-zero length");
  for (size_t k = 0; k < p.t.size(); ++k) {
    const std::string at = " (entry " + std::to_string(k) + ")";
    if (!std::isfinite(p.t[k])) throw InvalidInput("anchor path: t must be finite" + at);
    if (k > 0 && !(p.t[k] > p.t[k - 1])) throw InvalidInput("anchor path: t must be strictly increasing" + at);
    if (!std::isfinite(p.angle[k])) throw InvalidInput("anchor path: angles must be finite" + at);
    if (!p.position.row(k).allFinite()) throw InvalidInput("anchor path: positions must be finite" + at);
  }
}

}  // namespace

std::string weights_text(const Eigen::VectorXd& w) {
  std::ostringstream s;
  s.precision(17);
  s << "(";
  for (Eigen::Index i = 0; i < w.size(); ++i) s << (i ? ", " : "") << w[i];
  s << ")";
  return s.str();
}

void validate_options(const InterpolatorOptions& o, int num_shapes) {
  validate(o.flatten);
  if (o.flatten.tolerance < kToleranceFloor) {
    std::ostringstream s;
    s.precision(3);
    s << "tolerance " << o.flatten.tolerance << " is below " << kToleranceFloor
      << ", the smallest angle-sum residual a double can reach (the spacing of doubles at 2 pi)";
    throw InvalidInput(s.str());
  }
  if (o.base < 0 || o.base >= num_shapes) {
    std::ostringstream s;
    s << "base shape index " << o.base << " out of range [0, " << num_shapes << ")";
    throw InvalidInput(s.str());
  }
  if (o.threads < 0 || o.threads > InterpolatorOptions::kMaxThreads) {
    std::ostringstream s;
    s << "threads must be in [0, " << InterpolatorOptions::kMaxThreads << "] (got " << o.threads << ")";
    throw InvalidInput(s.str());
  }
  if (!(o.max_flatness >= 0)) throw InvalidInput("max_flatness must be >= 0");
}

void validate_anchor(const Anchor& anchor, const Mesh& mesh, int num_shapes) {
  const int v = anchor.vertex, nv = mesh.num_vertices();
  if (anchor.mode == Anchor::Mode::Vertex && v < 0) throw InvalidInput("vertex anchor needs a vertex index");
  if (v < -1 || v >= nv) {
    std::ostringstream s;
    // Where carries an index >= 0; a negative one stays in the text.
    s << "the anchor vertex " << (v < 0 ? std::to_string(v) + " " : "") << "is out of range [0, " << nv
      << ") (-1: the centroid)";
    throw InvalidInput(Where::of_vertex(v), s.str());
  }
  if (v >= 0 && anchor.mode != Anchor::Mode::Centroid && mesh.is_isolated_vertex(v))
    throw InvalidInput(Where::of_vertex(v), "the anchor vertex is in no face");
  if (anchor.mode == Anchor::Mode::Path) validate_path(anchor.path, num_shapes);
}

void check_orientation(const Positions& X, const Piece& p, int shape, int piece) {
  const Faces& F = p.mesh.faces();
  double total = 0, absolute = 0;
  for (int f = 0; f < F.rows(); ++f) {
    const double a = doubled_area(X, F, f);
    total += a;
    absolute += std::abs(a);
  }
  if (std::abs(total) > 1e-3 * absolute) return;
  std::ostringstream s;
  const auto [first, last] = std::minmax_element(p.faces.begin(), p.faces.end());  // split() sorts them
  s << "the signed areas of piece " << piece << " (the piece of this face: faces " << *first << ".." << *last
    << ") cancel (sum " << 0.5 * total << " of total " << 0.5 * absolute
    << "): its faces are folded over each other and its centroid is undefined";
  throw InvalidInput(Where::of_face(*first, shape), s.str());
}

}  // namespace bdinterp::detail

namespace bdinterp {
using detail::weights_text;

// The Interpolator's own checks of its shapes, weights and frames (members: they set or read its
// scale and options).
std::vector<Positions> Interpolator::normalise(const std::vector<Positions>& shapes, const Mesh& mesh) {
  // The bounding box of every finite coordinate; the scale a power of two, so that scaling is exact
  // and a shape scaled by 2^k gives exactly the scaled frames.
  Eigen::RowVector2d lo = Eigen::RowVector2d::Constant(HUGE_VAL), hi = -lo, base_lo = lo, base_hi = hi;
  for (size_t i = 0; i < shapes.size(); ++i)
    for (Eigen::Index v = 0; v < shapes[i].rows(); ++v) {
      const auto x = shapes[i].row(v);
      if (!x.allFinite()) continue;
      lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
      if (i == static_cast<size_t>(options_.base)) base_lo = base_lo.cwiseMin(x), base_hi = base_hi.cwiseMax(x);
    }
  const bool any = (lo.array() <= hi.array()).all();
  offset_ = any ? Eigen::RowVector2d(0.5 * lo + 0.5 * hi) : Eigen::RowVector2d::Zero();
  const double extent = any ? (0.5 * hi - 0.5 * lo).maxCoeff() : 0.0;
  scale_ = extent > 0 ? std::ldexp(1.0, std::ilogb(extent)) : 1.0;
  // Rounding is monotone: the normalised base's box is its box moved and scaled.
  const auto normalised = [&](const Eigen::RowVector2d& x) { return Eigen::RowVector2d((x - offset_) / scale_); };
  base_size_ = any ? (normalised(base_hi) - normalised(base_lo)).norm() : 0.0;
  std::vector<Positions> unit;
  for (size_t i = 0; i < shapes.size(); ++i) {
    unit.push_back((shapes[i].rowwise() - offset_) / scale_);
    check_shape(mesh, unit.back(), static_cast<int>(i));
  }
  return unit;
}

void Interpolator::check_weights(const Eigen::VectorXd& w) const {
  if (w.size() != num_shapes()) {
    std::ostringstream s;
    s << "got " << w.size() << " weights for " << num_shapes() << " shapes";
    throw InvalidInput(s.str());
  }
  if (!w.allFinite()) throw InvalidInput("weights must be finite, got " + weights_text(w));
  if (std::abs(w.sum() - 1.0) > 1e-9) {
    std::ostringstream s;
    s.precision(17);
    s << "weights must sum to 1 (they sum to " << w.sum() << ")";
    throw InvalidInput(s.str());
  }
}

}  // namespace bdinterp
