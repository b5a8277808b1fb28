#include "blend/metric_blend.h"

#include <cmath>
#include <sstream>

#include "mesh/geometry.h"

namespace bdinterp {

Eigen::VectorXd squared_edge_lengths(const Mesh& mesh, const Positions& X) {
  const Edges& E = mesh.edges();
  Eigen::VectorXd l2(E.rows());
  for (int e = 0; e < E.rows(); ++e) l2[e] = (X.row(E(e, 1)) - X.row(E(e, 0))).squaredNorm();
  return l2;
}

void check_shape(const Mesh& mesh, const Positions& X, int shape) {
  if (X.rows() != mesh.num_vertices()) {
    std::ostringstream s;
    s << "has " << X.rows() << " vertices, the faces need " << mesh.num_vertices();
    throw InvalidInput(Where::of_shape(shape), s.str());
  }
  for (int v = 0; v < X.rows(); ++v) {
    if (!std::isfinite(X(v, 0)) || !std::isfinite(X(v, 1)))
      throw InvalidInput(Where::of_vertex(v, shape), "a non-finite coordinate");
  }
  const Faces& F = mesh.faces();
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::RowVector2d a = X.row(F(f, 1)) - X.row(F(f, 0)), b = X.row(F(f, 2)) - X.row(F(f, 0));
    const Eigen::RowVector2d c = b - a;
    const double area2 = std::abs(doubled_area(X, F, f));
    const double longest = std::max({a.squaredNorm(), b.squaredNorm(), c.squaredNorm()});
    if (!(area2 > 2e-12 * longest)) throw InvalidInput(Where::of_face(f, shape), "zero area");
  }
}

Eigen::VectorXd blend_squared_lengths(const Mesh& mesh, const std::vector<Eigen::VectorXd>& l2,
                                      const Eigen::VectorXd& w) {
  Eigen::VectorXd out;
  blend_squared_lengths(mesh, l2, w, out);
  return out;
}

void blend_squared_lengths(const Mesh& mesh, const std::vector<Eigen::VectorXd>& l2, const Eigen::VectorXd& w,
                           Eigen::VectorXd& out) {
  if (l2.empty() || static_cast<Eigen::Index>(l2.size()) != w.size()) {
    std::ostringstream s;
    s << "got " << w.size() << " weights for " << l2.size() << " shapes";
    throw InvalidInput(s.str());
  }
  for (Eigen::Index i = 0; i < w.size(); ++i) {
    if (!std::isfinite(w[i])) throw InvalidInput(Where::of_shape(static_cast<int>(i)), "its weight is not finite");
  }
  // In place when sized: no large allocation a frame. A zero weight adds +0 to every (positive)
  // sum, so it is skipped: a pose grid's cell has a few nonzero weights out of all its poses.
  size_t first = 0;
  while (first + 1 < l2.size() && w[static_cast<Eigen::Index>(first)] == 0) ++first;
  out = w[static_cast<Eigen::Index>(first)] * l2[first];
  for (size_t i = first + 1; i < l2.size(); ++i)
    if (w[static_cast<Eigen::Index>(i)] != 0) out += w[static_cast<Eigen::Index>(i)] * l2[i];
  // With weights >= 0 the blend is valid by construction (paper, Sec. 4): Euclidean squared-length
  // triples form a convex cone, and 4 area = sqrt(Heron's quadratic form) is concave on it (a
  // reverse triangle inequality), so a blended face's area is at least the weighted mean of the
  // inputs' areas. Only extrapolation needs the check.
  if ((w.array() >= 0).all()) return;
  const Faces& FE = mesh.face_edges();
  for (int f = 0; f < FE.rows(); ++f) {
    const double a = out[FE(f, 0)], b = out[FE(f, 1)], c = out[FE(f, 2)];
    // Relative threshold: a blend that leaves a face with aspect ratio beyond ~1e6 is unusable.
    if (!(a > 0 && b > 0 && c > 0) || !(heron16(a, b, c) > 1e-12 * std::max({a, b, c}) * std::max({a, b, c}))) {
      std::ostringstream s;
      s << "the weights (";
      for (Eigen::Index i = 0; i < w.size(); ++i) s << (i ? ", " : "") << w[i];
      s << ") give an invalid metric: the blended edge lengths violate the triangle inequality "
        << "(extrapolating too far)";
      throw InvalidInput(Where::of_face(f), s.str());
    }
  }
}

}  // namespace bdinterp
