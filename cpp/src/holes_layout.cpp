// The layout of a piece with holes (holes.h): the holes' translation periods, faces developed
// across a dual spanning tree, and the least-squares fit of all edge vectors.
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>

#include "holes.h"
#include "triangle.h"

namespace bdinterp {
namespace {

// Corner positions of a face from its three squared lengths (l2[c] opposite corner c): corner 0 at
// the origin, corner 1 on the positive x axis, corner 2 above it (counter-clockwise).
void local_triangle(const double l2[3], std::complex<double> p[3]) {
  const double l01 = std::sqrt(l2[2]);
  const double cx = (l2[2] + l2[1] - l2[0]) / (2 * l01);
  p[0] = 0;
  p[1] = l01;
  p[2] = {cx, std::sqrt(std::max(l2[1] - cx * cx, 0.0))};
}

}  // namespace

void HoleSolver::develop(const Eigen::VectorXd& l2, std::vector<std::complex<double>>& d) const {
  const Mesh& m = *mesh_;
  const Faces& F = m.faces();
  const Faces& FE = m.face_edges();
  const Edges& E = m.edges();
  const Edges& EF = m.edge_faces();
  const int nf = static_cast<int>(F.rows());
  // Each face in its own frame, then rotations across a dual spanning tree (walk_, breadth first
  // from face 0): a child turns by its parent's rotation times the unit turn taking the shared edge
  // as the child sees it (run the other way) to the edge as the parent sees it. Only that product
  // is serial; the turns' square roots are not on its chain (they were most of a warm frame).
  std::vector<std::array<std::complex<double>, 3>>& q = local_;
  std::vector<std::complex<double>>& R = rotation_;
  q.resize(nf);
  R.resize(nf);
  for (int f = 0; f < nf; ++f) {
    const double fl2[3] = {l2[FE(f, 0)], l2[FE(f, 1)], l2[FE(f, 2)]};
    local_triangle(fl2, q[f].data());
  }
  R[0] = 1.0;
  for (const Mesh::DualStep& st : walk_) {
    const int c = st.parent_corner, k = st.face_corner;
    const std::complex<double> hf = q[st.parent][(c + 2) % 3] - q[st.parent][(c + 1) % 3];
    const std::complex<double> hg = q[st.face][(k + 1) % 3] - q[st.face][(k + 2) % 3];
    const std::complex<double> z = hf * std::conj(hg);
    R[st.face] = R[st.parent] * (z / std::sqrt(std::norm(z)));
  }
  // Every edge's vector E(e,0) -> E(e,1), averaged over its faces.
  d.assign(E.rows(), 0.0);
  for (int f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      const int e = FE(f, c), a = F(f, (c + 1) % 3);
      const std::complex<double> h = R[f] * (q[f][(c + 2) % 3] - q[f][(c + 1) % 3]);
      d[e] += (a == E(e, 0) ? h : -h) * (EF(e, 1) >= 0 ? 0.5 : 1.0);
    }
  }
}

Eigen::VectorXd HoleSolver::periods(const Eigen::VectorXd& l2) const {
  const Faces& FE = mesh_->face_edges();
  Eigen::VectorXd out(2 * num_holes());
  std::vector<double> angle;
  for (int k = 0; k < num_holes(); ++k) {
    const size_t n = loops_[k].size();
    angle.assign(n, 0.0);
    for (const auto& [i, f, c] : loop_corners_[k]) {
      const double fl2[3] = {l2[FE(f, 0)], l2[FE(f, 1)], l2[FE(f, 2)]};
      double a[3];
      triangle_angles(fl2, a);
      angle[i] += a[c];
    }
    // Edge i runs from loop[i] to loop[i + 1]; the direction turns at loop[i + 1]. (Walking the
    // other way conjugates every period: the closure and the Newton on it do not see the difference.)
    std::complex<double> gap = 0;
    double length = 0, direction = 0;
    for (size_t i = 0; i < n; ++i) {
      const double l = std::sqrt(l2[loop_edges_[k][i].first]);
      gap += std::polar(l, direction);
      length += l;
      direction += kPi - angle[(i + 1) % n];
    }
    out[2 * k] = gap.real() / length;
    out[2 * k + 1] = gap.imag() / length;
  }
  return out;
}

double HoleSolver::layout(const Eigen::VectorXd& l2, Positions& X, std::vector<double>& closure) {
  const Mesh& m = *mesh_;
  const Edges& E = m.edges();
  std::vector<std::complex<double>>& d = developed_;
  develop(l2, d);
  // The gap of the developed loop (the same period as periods() up to the flattening's residual).
  closure.resize(num_holes());
  for (int k = 0; k < num_holes(); ++k) {
    std::complex<double> gap = 0;
    double length = 0;
    for (const auto& [e, sign] : loop_edges_[k]) {
      gap += sign * d[e];
      length += std::abs(d[e]);
    }
    closure[k] = std::abs(gap) / length;
  }
  // Least-squares fit of all edge vectors, the pinned vertex at the origin.
  const int rows = layout_->size();
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * rows);
  for (int e = 0; e < E.rows(); ++e) {
    const int a = layout_index_[E(e, 0)], b = layout_index_[E(e, 1)];
    if (a >= 0) rhs[a] -= d[e].real(), rhs[rows + a] -= d[e].imag();
    if (b >= 0) rhs[b] += d[e].real(), rhs[rows + b] += d[e].imag();
  }
  layout_->solve(rhs.data(), rhs.data(), 2);
  X.setZero(m.num_vertices(), 2);
  for (int v = 0; v < m.num_vertices(); ++v) {
    const int r = layout_index_[v];
    if (r >= 0) X(v, 0) = rhs[r], X(v, 1) = rhs[rows + r];
  }
  double flatness = 0;
  for (int e = 0; e < E.rows(); ++e)
    flatness = std::max(flatness, std::abs((X.row(E(e, 0)) - X.row(E(e, 1))).squaredNorm() / l2[e] - 1));
  return flatness;
}

}  // namespace bdinterp
