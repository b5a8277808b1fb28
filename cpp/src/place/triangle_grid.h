// Internal: point location in the triangles of one piece of a cut-out character (joints.h).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
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
  // Faces per cell, as if each face lay in one: a face of a regular mesh spans several cells of
  // a finer grid, each of which then lists it.
  static constexpr double kFacesPerCell = 4;
  TriangleGrid(const Positions& X, const JointPiece& piece) : X_(X), piece_(piece) {
    const Faces& F = *piece.faces;
    lo_ = hi_ = X.row((*piece.vertices)[0]).transpose();
    for (int v : *piece.vertices) lo_ = lo_.cwiseMin(X.row(v).transpose()), hi_ = hi_.cwiseMax(X.row(v).transpose());
    n_ = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(F.rows()) / kFacesPerCell)));
    // Each vertex's cell, once: cell() is monotone in each coordinate, so the cells of a face's
    // bounding box are the least and the largest of its corners' cells.
    const std::vector<int>& vs = *piece.vertices;
    std::vector<std::pair<int, int>> at_vertex(vs.size());
    for (size_t v = 0; v < vs.size(); ++v) at_vertex[v] = cell(X.row(vs[v]).transpose());
    // The faces of each cell in one array (counted, then filled): one allocation per piece.
    std::vector<std::array<int, 4>> span(static_cast<size_t>(F.rows()));  // each face's cells
    start_.assign(static_cast<size_t>(n_) * n_ + 1, 0);
    for (int f = 0; f < F.rows(); ++f) {
      const auto& p = at_vertex[static_cast<size_t>(F(f, 0))];
      const auto& q = at_vertex[static_cast<size_t>(F(f, 1))];
      const auto& r = at_vertex[static_cast<size_t>(F(f, 2))];
      const int i0 = std::min({p.first, q.first, r.first}), i1 = std::max({p.first, q.first, r.first});
      const int j0 = std::min({p.second, q.second, r.second}), j1 = std::max({p.second, q.second, r.second});
      span[static_cast<size_t>(f)] = {i0, j0, i1, j1};
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) ++start_[static_cast<size_t>(j) * n_ + i + 1];
    }
    std::partial_sum(start_.begin(), start_.end(), start_.begin());
    faces_.resize(static_cast<size_t>(start_.back()));
    std::vector<int> at(start_.begin(), start_.end() - 1);
    for (int f = 0; f < F.rows(); ++f) {
      const auto [i0, j0, i1, j1] = span[static_cast<size_t>(f)];
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) faces_[static_cast<size_t>(at[static_cast<size_t>(j) * n_ + i]++)] = f;
    }
  }

  // Whether the two pieces' bounding boxes meet once each is grown by `margin`.
  bool boxes_meet(const TriangleGrid& o, double margin = 0) const {
    return (lo_.array() <= o.hi_.array() + 2 * margin).all() && (o.lo_.array() <= hi_.array() + 2 * margin).all();
  }
  // The piece's size: its bounding box's diagonal in the base shape.
  double diagonal() const { return (hi_ - lo_).norm(); }
  // How far q lies outside the piece (0 inside or on its outline), exact below `within`; `within`
  // when it lies that far or farther (only the faces of the grid cells within reach are read).
  double outside(const Eigen::Vector2d& q, double within) const {
    int f;
    Eigen::Vector3d bary;
    if (locate(q, f, bary) >= -kInside) return 0;
    const Eigen::Vector2d reach = Eigen::Vector2d::Constant(within);
    if (((q - reach).array() > hi_.array()).any() || ((q + reach).array() < lo_.array()).any()) return within;
    const auto [i0, j0] = cell(q - reach);
    const auto [i1, j1] = cell(q + reach);
    double best = within;
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        for (int g : faces_of(i, j))
          for (int c = 0; c < 3; ++c) {  // outside every face: the nearest point lies on an edge
            const Eigen::Vector2d a = corner(g, c), e = corner(g, (c + 1) % 3) - a;
            const double s = std::clamp((q - a).dot(e) / std::max(e.squaredNorm(), 1e-300), 0.0, 1.0);
            best = std::min(best, (a + s * e - q).norm());
          }
    return best;
  }
  // The face holding q with the largest least barycentric weight (-inf and face -1 if q is outside
  // the box); bary gets its weights.
  double locate(const Eigen::Vector2d& q, int& face, Eigen::Vector3d& bary) const {
    face = -1;
    double best = -HUGE_VAL;
    if (!((q.array() >= lo_.array()).all() && (q.array() <= hi_.array()).all())) return best;
    const auto [i, j] = cell(q);
    for (int f : faces_of(i, j)) consider(q, f, best, face, bary);
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
  // The faces of cell (i, j), as a range.
  struct Range {
    const int *b, *e;
    const int* begin() const { return b; }
    const int* end() const { return e; }
  };
  Range faces_of(int i, int j) const {
    const size_t k = static_cast<size_t>(j) * n_ + i;
    return {faces_.data() + start_[k], faces_.data() + start_[k + 1]};
  }
  std::pair<int, int> cell(const Eigen::Vector2d& q) const {
    const Eigen::Vector2d r = ((q - lo_).array() / (hi_ - lo_).cwiseMax(1e-300).array() * n_).matrix();
    return {std::clamp(static_cast<int>(r.x()), 0, n_ - 1), std::clamp(static_cast<int>(r.y()), 0, n_ - 1)};
  }
  const Positions& X_;
  const JointPiece& piece_;
  Eigen::Vector2d lo_, hi_;
  int n_;
  std::vector<int> start_, faces_;  // cell k's faces: faces_[start_[k], start_[k + 1])
};

}  // namespace detail
}  // namespace bdinterp
