#include "bdinterp/interpolator.h"

#include <cmath>
#include <sstream>

#include "bdinterp/layout.h"
#include "bdinterp/metric_blend.h"

namespace bdinterp {

// Everything about one disk-shaped piece of the mesh.
struct Interpolator::PieceSolver {
  Piece piece;
  std::vector<Eigen::VectorXd> l2;  // per input shape: squared edge lengths
  Flattener flattener;
  Layout layout;
  AnchorFrame anchor;
  std::vector<Frame2> frames;  // per input shape: its anchor
  bool mirrored;               // the base shape is clockwise: lay out counter-clockwise, then reflect
  // Warm start: the last two solutions and their weights.
  Eigen::VectorXd u, u_last, u_prev, w_last, w_prev;

  PieceSolver(Piece p, const std::vector<Positions>& local_shapes, int base, int anchor_vertex)
      : piece(std::move(p)),
        flattener(piece.mesh),
        layout(piece.mesh),
        anchor(piece.mesh, local_shapes[base], anchor_vertex) {
    for (const Positions& X : local_shapes) {
      l2.push_back(squared_edge_lengths(piece.mesh, X));
      frames.push_back(anchor.measure_input(X));
    }
    const Positions& B = local_shapes[base];
    double area = 0;
    const Faces& F = piece.mesh.faces();
    for (int f = 0; f < F.rows(); ++f) {
      const Eigen::RowVector2d a = B.row(F(f, 1)) - B.row(F(f, 0)), b = B.row(F(f, 2)) - B.row(F(f, 0));
      area += a.x() * b.y() - a.y() * b.x();
    }
    mirrored = area < 0;
  }

  // Picks the initial guess with the smallest residual among: zero (exact at the inputs), the last
  // solution, and its linear extrapolation along the last two solves.
  void warm_start(const Eigen::VectorXd& l2w, const Eigen::VectorXd& w) {
    u = Eigen::VectorXd::Zero(piece.mesh.num_vertices());
    if (u_last.size() == 0) return;
    double best = flattener.residual(l2w, u);
    auto consider = [&](const Eigen::VectorXd& cand) {
      const double r = flattener.residual(l2w, cand);
      if (r < best) {
        best = r;
        u = cand;
      }
    };
    consider(u_last);
    if (u_prev.size() && (w_last - w_prev).squaredNorm() > 0) {
      const double a = (w - w_last).dot(w_last - w_prev) / (w_last - w_prev).squaredNorm();
      consider(u_last + a * (u_last - u_prev));
    }
  }

  FlattenReport solve(const Eigen::VectorXd& w, const FlattenOptions& opt, const Anchor& anchor_mode,
                      Eigen::Ref<Positions> out, double* flatness) {
    const Eigen::VectorXd l2w = blend_squared_lengths(piece.mesh, l2, w);
    warm_start(l2w, w);
    const FlattenReport rep = flattener.solve(l2w, u, opt);
    u_prev.swap(u_last);
    w_prev.swap(w_last);
    u_last = u;
    w_last = w;
    Positions X = layout.embed(scale_lengths(piece.mesh, l2w, u), flatness);
    if (mirrored) X.col(0) *= -1.0;
    anchor.place(X, blend_frames(frames, w, anchor_mode));
    for (size_t i = 0; i < piece.vertices.size(); ++i) out.row(piece.vertices[i]) = X.row(i);
    return rep;
  }
};

Interpolator::Interpolator(const std::vector<Positions>& shapes, const Faces& F, const Anchor& anchor,
                           const InterpolatorOptions& options)
    : shapes_(shapes), F_(F), anchor_(anchor), options_(options) {
  if (shapes.empty()) throw InvalidInput("need at least one shape");
  if (options.base < 0 || options.base >= num_shapes()) {
    std::ostringstream s;
    s << "base shape index " << options.base << " out of range [0, " << num_shapes() << ")";
    throw InvalidInput(s.str());
  }
  const int nv = static_cast<int>(shapes[0].rows());
  const Mesh mesh(F, nv);
  for (int i = 0; i < num_shapes(); ++i) check_shape(mesh, shapes[i], "shape " + std::to_string(i));
  if (anchor.mode != Anchor::Mode::Centroid && anchor.vertex >= 0) {
    if (anchor.vertex >= nv || mesh.is_isolated_vertex(anchor.vertex)) {
      std::ostringstream s;
      s << "anchor vertex " << anchor.vertex << " is " << (anchor.vertex >= nv ? "out of range" : "in no face");
      throw InvalidInput(s.str());
    }
  }
  if (anchor.mode == Anchor::Mode::Vertex && anchor.vertex < 0)
    throw InvalidInput("vertex anchor needs a vertex index");
  if (anchor.mode == Anchor::Mode::Path) {
    const AnchorPath& p = anchor.path;
    if (num_shapes() != 2) throw InvalidInput("an anchor path needs exactly two shapes");
    if (p.t.empty() || p.angle.size() != p.t.size() || p.position.rows() != static_cast<int>(p.t.size()))
      throw InvalidInput("anchor path: t, positions and angles must have the same non-zero length");
    for (size_t k = 1; k < p.t.size(); ++k)
      if (!(p.t[k] > p.t[k - 1])) throw InvalidInput("anchor path: t must be strictly increasing");
    if (!p.position.allFinite()) throw InvalidInput("anchor path: positions must be finite");
  }
  for (int v = 0; v < nv; ++v)
    if (mesh.is_isolated_vertex(v)) isolated_.push_back(v);
  for (Piece& p : split_into_disks(mesh)) {
    std::vector<Positions> local(shapes.size(), Positions(p.vertices.size(), 2));
    for (size_t i = 0; i < shapes.size(); ++i)
      for (size_t k = 0; k < p.vertices.size(); ++k) local[i].row(k) = shapes[i].row(p.vertices[k]);
    int av = -1;
    if (anchor.vertex >= 0) {
      const auto it = std::find(p.vertices.begin(), p.vertices.end(), anchor.vertex);
      if (it != p.vertices.end()) av = static_cast<int>(it - p.vertices.begin());
    }
    pieces_.push_back(std::make_unique<PieceSolver>(std::move(p), local, options.base, av));
  }
}

Interpolator::~Interpolator() = default;

void Interpolator::check_weights(const Eigen::VectorXd& w) const {
  if (w.size() != num_shapes()) {
    std::ostringstream s;
    s << "got " << w.size() << " weights for " << num_shapes() << " shapes";
    throw InvalidInput(s.str());
  }
  if (!w.allFinite()) throw InvalidInput("weights must be finite");
  if (std::abs(w.sum() - 1.0) > 1e-9) {
    std::ostringstream s;
    s.precision(17);
    s << "weights must sum to 1 (they sum to " << w.sum() << ")";
    throw InvalidInput(s.str());
  }
}

void Interpolator::blend_into(const Eigen::VectorXd& w, Eigen::Ref<Positions> out) {
  check_weights(w);
  if (out.rows() != num_vertices()) throw InvalidInput("output has the wrong number of rows");
  FrameStats st;
  st.pieces = static_cast<int>(pieces_.size());
  for (auto& p : pieces_) {
    double flat = 0;
    const FlattenReport r = p->solve(w, options_.flatten, anchor_, out, &flat);
    st.iterations = std::max(st.iterations, r.iterations);
    st.residual = std::max(st.residual, r.residual);
    st.broken_triangles += r.broken_triangles;
    st.max_broken_triangles += r.max_broken_triangles;
    st.flatness = std::max(st.flatness, flat);
  }
  for (int v : isolated_) {
    out.row(v).setZero();
    for (int i = 0; i < num_shapes(); ++i) out.row(v) += w[i] * shapes_[i].row(v);
  }
  stats_ = st;
}

Positions Interpolator::blend(const Eigen::VectorXd& w) {
  Positions out(num_vertices(), 2);
  blend_into(w, out);
  return out;
}

Positions Interpolator::at(double t) {
  if (num_shapes() != 2) {
    std::ostringstream s;
    s << "at(t) needs exactly two shapes (have " << num_shapes() << "); use blend(weights)";
    throw InvalidInput(s.str());
  }
  if (!std::isfinite(t)) throw InvalidInput("t must be finite");
  return blend(Eigen::Vector2d(1.0 - t, t));
}

void Interpolator::frames(const std::vector<double>& ts, Eigen::Ref<Positions> out) {
  if (num_shapes() != 2) throw InvalidInput("frames(ts) needs exactly two shapes");
  const Eigen::Index n = num_vertices();
  if (out.rows() != n * static_cast<Eigen::Index>(ts.size()))
    throw InvalidInput("frames: output must have len(ts) * num_vertices rows");
  for (size_t j = 0; j < ts.size(); ++j) {
    if (!std::isfinite(ts[j])) throw InvalidInput("t must be finite (entry " + std::to_string(j) + ")");
    blend_into(Eigen::Vector2d(1.0 - ts[j], ts[j]), out.middleRows(j * n, n));
  }
}

Positions interpolate(const Positions& source, const Positions& target, const Faces& F, double t,
                      const Anchor& anchor) {
  Interpolator I({source, target}, F, anchor);
  return I.at(t);
}

}  // namespace bdinterp
