// A piece with holes (holes.h): the holes' translation periods, intrinsic (each loop walked with the
// domain's angles, no development of the faces), and the layout by the shared Layout with the gap
// each hole's loop is left with.
#include <algorithm>
#include <cmath>
#include <complex>

#include "flatten/holes.h"
#include "parallel/parallel.h"
#include "mesh/triangle.h"
#include "mesh/turns.h"

namespace bdinterp {

Eigen::VectorXd HoleSolver::periods(const Eigen::VectorXd& l2) const {
  Eigen::VectorXd out(2 * num_holes());
  // A hole an iteration (each walk is serial), costing the corners it walks.
  long corners = 0;
  for (const auto& loop : loop_corners_) corners += static_cast<long>(loop.size());
  parallel::Loop(num_holes(), static_cast<double>(corners) / std::max(num_holes(), 1)).run([&](int, long k) {
    const std::complex<double> p = hole_period(static_cast<int>(k), l2);
    out[2 * k] = p.real();
    out[2 * k + 1] = p.imag();
  });
  return out;
}

std::complex<double> HoleSolver::hole_period(int k, const Eigen::VectorXd& l2) const {
  const Faces& FE = mesh_->face_edges();
  const size_t n = loops_[k].size();
  // Per loop vertex: exp(i angle / 2) up to a positive factor, in the hole's own workspace (allocated
  // with the solver: a chunk on the pool must not throw).
  std::vector<double>& turns = half_turns_[k];
  std::fill_n(turns.begin(), n, 1.0);
  std::fill_n(turns.begin() + n, n, 0.0);
  double* re = turns.data();
  double* im = re + n;
  double l[3], x[3], perimeter = 0, q = 0;
  int face = -1;
  for (const auto& [i, f, c] : loop_corners_[k]) {
    if (f != face) {  // a face's corners at the loop are consecutive: its shape once
      face = f;
      for (int j = 0; j < 3; ++j) l[j] = std::sqrt(l2[FE(f, j)]);
      q = excesses(l, x, &perimeter);
    }
    // tan(angle / 2) = q / (perimeter x[c]); a broken face's (pi, 0, 0): pi / 2 at its longest side.
    const bool up = !(q > 0) && c == longest_side(l);
    const double a = q > 0 ? perimeter * x[c] : (up ? 0.0 : 1.0), b = q > 0 ? q : (up ? 1.0 : 0.0);
    const double r = re[i] * a - im[i] * b;
    im[i] = re[i] * b + im[i] * a;
    re[i] = r;
    detail::keep_in_range(re[i], im[i]);
  }
  // Edge i runs from loop[i] to loop[i + 1]; the direction turns by pi - angle at loop[i + 1]:
  // times -conj(exp(i angle)), the half-angle product squared and normalised (no trigonometry).
  // (Walking the other way conjugates every period: the closure does not see the difference.)
  std::complex<double> gap = 0;
  double length = 0, dx = 1, dy = 0;
  for (size_t i = 0; i < n; ++i) {
    const double li = std::sqrt(l2[loop_edges_[k][i].first]);
    gap += std::complex<double>(li * dx, li * dy);
    length += li;
    const size_t j = (i + 1) % n;
    const double norm = re[j] * re[j] + im[j] * im[j];
    const double tx = (im[j] * im[j] - re[j] * re[j]) / norm, ty = 2 * re[j] * im[j] / norm;
    const double nx = dx * tx - dy * ty;
    dy = dx * ty + dy * tx;
    dx = nx;
  }
  return gap / length;
}

double HoleSolver::layout(const Eigen::VectorXd& l2, Positions& X, std::vector<double>& closure) {
  double flatness = 0;
  layout_.embed(l2, X, &flatness);
  // The gap of each hole's loop developed by the Layout's faces (each hole edge has one face): the
  // period of periods() up to the flattening's residual.
  closure.resize(num_holes());
  for (int k = 0; k < num_holes(); ++k) {
    std::complex<double> gap = 0;
    double length = 0;
    for (size_t i = 0; i < loops_[k].size(); ++i) {
      double v[2];
      layout_.vector_of(layout_plan_->half_edge(loop_edges_[k][i].first, loops_[k][i]), v);
      gap += std::complex<double>(v[0], v[1]);
      length += std::sqrt(v[0] * v[0] + v[1] * v[1]);
    }
    closure[k] = std::abs(gap) / length;
  }
  return flatness;
}

}  // namespace bdinterp
