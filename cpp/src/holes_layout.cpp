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

Eigen::VectorXd HoleSolver::solved_periods() {
  develop(flattener_.flat_squared_lengths(), developed_);
  return periods_of(developed_);
}

double HoleSolver::layout(const Eigen::VectorXd& l2, Positions& X, std::vector<double>& closure) {
  develop(l2, developed_);
  return lay_out(l2, developed_, X, closure);
}

double HoleSolver::lay_out(const Eigen::VectorXd& l2, const std::vector<std::complex<double>>& d, Positions& X,
                           std::vector<double>& closure) {
  const Mesh& m = *mesh_;
  const Edges& E = m.edges();
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
