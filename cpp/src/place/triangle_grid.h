// Internal: point location in the triangles of one piece of a cut-out character (joints.h).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "bdinterp/types.h"

namespace bdinterp {

// What the joints need of one piece: its vertices (global indices), its faces (local indices into
// `vertices`), and its anchor frame in every input (angles relative to the base, unwrapped).
struct Frame2;
struct JointPiece {
  const std::vector<int>* vertices;
  const Faces* faces;
  const std::vector<Frame2>* frames;
};

namespace detail {

// A point counts as inside a triangle when its least barycentric weight is at least this (so
// vertices on a shared outline do not make an overlap).
constexpr double kInside = 1e-9;

// Finds the triangle of one piece (in the base shape X) that contains a point: a uniform grid of
// about one face per cell over the piece's bounding box.
class TriangleGrid {
 public:
  TriangleGrid(const Positions& X, const JointPiece& piece) : X_(X), piece_(piece) {
    const Faces& F = *piece.faces;
    lo_ = hi_ = X.row((*piece.vertices)[0]).transpose();
    for (int v : *piece.vertices) lo_ = lo_.cwiseMin(X.row(v).transpose()), hi_ = hi_.cwiseMax(X.row(v).transpose());
    n_ = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(F.rows()))));
    cells_.resize(static_cast<size_t>(n_) * n_);
    for (int f = 0; f < F.rows(); ++f) {
      Eigen::Vector2d a = corner(f, 0), b = a;
      for (int c = 1; c < 3; ++c) a = a.cwiseMin(corner(f, c)), b = b.cwiseMax(corner(f, c));
      const auto [i0, j0] = cell(a);
      const auto [i1, j1] = cell(b);
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) cells_[static_cast<size_t>(j) * n_ + i].push_back(f);
    }
  }

  bool boxes_meet(const TriangleGrid& o) const {
    return (lo_.array() <= o.hi_.array()).all() && (o.lo_.array() <= hi_.array()).all();
  }
  // The face holding q with the largest least barycentric weight (-inf and face -1 if q is outside
  // the box); bary gets its weights.
  double locate(const Eigen::Vector2d& q, int& face, Eigen::Vector3d& bary) const {
    face = -1;
    double best = -HUGE_VAL;
    if (!((q.array() >= lo_.array()).all() && (q.array() <= hi_.array()).all())) return best;
    const auto [i, j] = cell(q);
    for (int f : cells_[static_cast<size_t>(j) * n_ + i]) consider(q, f, best, face, bary);
    return best;
  }
  // As locate(), but a point outside the piece gets the face whose affine extension is nearest
  // (the largest least barycentric weight over every face), so it is never -1.
  double locate_nearest(const Eigen::Vector2d& q, int& face, Eigen::Vector3d& bary) const {
    double best = locate(q, face, bary);
    if (best >= -kInside) return best;
    for (int f = 0; f < piece_.faces->rows(); ++f) consider(q, f, best, face, bary);
    return best;
  }
  int vertex(int f, int c) const { return (*piece_.vertices)[(*piece_.faces)(f, c)]; }
  const JointPiece& piece() const { return piece_; }

 private:
  void consider(const Eigen::Vector2d& q, int f, double& best, int& face, Eigen::Vector3d& bary) const {
    const Eigen::Vector2d a = corner(f, 0), e1 = corner(f, 1) - a, e2 = corner(f, 2) - a, d = q - a;
    const double det = e1.x() * e2.y() - e1.y() * e2.x();
    const double s = (d.x() * e2.y() - d.y() * e2.x()) / det, t = (e1.x() * d.y() - e1.y() * d.x()) / det;
    const Eigen::Vector3d b(1 - s - t, s, t);
    if (b.minCoeff() > best) best = b.minCoeff(), face = f, bary = b;
  }
  Eigen::Vector2d corner(int f, int c) const { return X_.row(vertex(f, c)).transpose(); }
  std::pair<int, int> cell(const Eigen::Vector2d& q) const {
    const Eigen::Vector2d r = ((q - lo_).array() / (hi_ - lo_).cwiseMax(1e-300).array() * n_).matrix();
    return {std::clamp(static_cast<int>(r.x()), 0, n_ - 1), std::clamp(static_cast<int>(r.y()), 0, n_ - 1)};
  }
  const Positions& X_;
  const JointPiece& piece_;
  Eigen::Vector2d lo_, hi_;
  int n_;
  std::vector<std::vector<int>> cells_;
};

}  // namespace detail
}  // namespace bdinterp
