// The layout of a piece with holes (holes.h): faces developed across a dual spanning tree, the
// holes' translation periods, and the least-squares fit of all edge vectors.
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>

#include "bdinterp/holes.h"

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
  // Faces placed one after another across a dual spanning tree (walk_, breadth first from face 0):
  // each child takes its parent's direction of the shared edge, so the rotations are consistent.
  std::vector<std::array<std::complex<double>, 3>> P(F.rows());
  auto lengths = [&](int f, double out[3]) {
    for (int c = 0; c < 3; ++c) out[c] = l2[FE(f, c)];
  };
  double fl2[3];
  lengths(0, fl2);
  local_triangle(fl2, P[0].data());
  for (const Mesh::DualStep& step : walk_) {
    const int f = step.parent, c = step.parent_corner, g = step.face;
    const int a = F(f, (c + 1) % 3), b = F(f, (c + 2) % 3);
    std::complex<double> q[3];
    lengths(g, fl2);
    local_triangle(fl2, q);
    int ca = 0, cb = 0;
    for (int k = 0; k < 3; ++k) {
      if (F(g, k) == a) ca = k;
      if (F(g, k) == b) cb = k;
    }
    const std::complex<double> pa = P[f][(c + 1) % 3], d = P[f][(c + 2) % 3] - pa, ld = q[cb] - q[ca];
    const std::complex<double> r = (d / ld) / std::abs(d / ld);
    for (int k = 0; k < 3; ++k) P[g][k] = pa + r * (q[k] - q[ca]);
  }
  // Every edge's vector E(e,0) -> E(e,1), averaged over its faces.
  d.assign(E.rows(), 0.0);
  for (int f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int e = FE(f, c), a = F(f, (c + 1) % 3);
      const std::complex<double> h = P[f][(c + 2) % 3] - P[f][(c + 1) % 3];
      d[e] += (a == E(e, 0) ? h : -h) * (EF(e, 1) >= 0 ? 0.5 : 1.0);
    }
  }
}

Eigen::VectorXd HoleSolver::periods(const Eigen::VectorXd& l2) const {
  std::vector<std::complex<double>> d;
  develop(l2, d);
  return periods_of(d);
}

Eigen::VectorXd HoleSolver::periods_of(const std::vector<std::complex<double>>& d) const {
  // Translation period of each hole: its edge vectors summed along the loop, over its length.
  Eigen::VectorXd out(2 * num_holes());
  for (int k = 0; k < num_holes(); ++k) {
    std::complex<double> gap = 0;
    double length = 0;
    for (const auto& [e, sign] : loop_edges_[k]) {
      gap += sign * d[e];
      length += std::abs(d[e]);
    }
    out[2 * k] = gap.real() / length;
    out[2 * k + 1] = gap.imag() / length;
  }
  return out;
}

double HoleSolver::layout(const Eigen::VectorXd& l2, Positions& X, std::vector<double>& closure) {
  const Mesh& m = *mesh_;
  const Edges& E = m.edges();
  std::vector<std::complex<double>> d;
  develop(l2, d);
  const Eigen::VectorXd p = periods_of(d);
  closure.resize(num_holes());
  for (int k = 0; k < num_holes(); ++k) closure[k] = std::hypot(p[2 * k], p[2 * k + 1]);
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
