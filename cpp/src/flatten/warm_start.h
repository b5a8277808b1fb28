// Internal: the warm start of a frame from the frames solved before it on the same workspace.
#pragma once

#include <Eigen/Core>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <deque>
#include <utility>
#include <vector>

namespace bdinterp::detail {

// Solved frames of one piece, for warm starts: the last few (weights, u) pairs, newest first.
struct History {
  static constexpr size_t kSize = 6;
  std::deque<std::pair<Eigen::VectorXd, Eigen::VectorXd>> solved;

  void add(const Eigen::VectorXd& w, const Eigen::VectorXd& u) {
    if (solved.size() == kSize) {
      solved.back().first = w;  // reuse the oldest entry's storage
      solved.back().second = u;
      solved.push_front(std::move(solved.back()));
      solved.pop_back();
    } else {
      solved.emplace_front(w, u);
    }
  }

  // Initial guess for weights w: polynomial extrapolation (degree <= 5) along the line through the
  // nearest solved frame and w, over the solved frames that lie on that line, as long as the
  // extrapolation is well conditioned (sum of |Lagrange weights| <= kMaxLebesgue, which admits degree
  // 5 on equally spaced frames: 63); else along the path of the frames before it (see along_path); else
  // the nearest solution; zero (exact at the inputs) without history. On a slider the guess is then
  // limited by the earlier solutions' own tolerance rather than by the truncation error (at 5k
  // vertices: geometric-mean residual of the guess 2.4e-9 at degree 3, 6.8e-10 at degree 5; a
  // quarter of the frames need no CG iteration instead of 7 %).
  void predict(const Eigen::VectorXd& w, Eigen::VectorXd& u) const {
    // An input shape's own metric is flat: u = 0 reproduces it exactly, in no step.
    const bool input_shape = (w.array() == 0.0).count() == w.size() - 1;
    if (solved.empty() || input_shape) {
      u.setZero();
      return;
    }
    size_t nearest = 0;
    for (size_t k = 1; k < solved.size(); ++k)
      if ((solved[k].first - w).squaredNorm() < (solved[nearest].first - w).squaredNorm()) nearest = k;
    const Eigen::VectorXd& w0 = solved[nearest].first;
    const Eigen::VectorXd d = w - w0;
    const double dd = d.squaredNorm();
    u = solved[nearest].second;
    if (dd == 0) return;
    // Parameter s along w0 + s d (w at s = 1) of every solved frame on that line.
    std::vector<std::pair<double, size_t>> nodes{{0.0, nearest}};
    for (size_t k = 0; k < solved.size(); ++k) {
      if (k == nearest) continue;
      const Eigen::VectorXd q = solved[k].first - w0;
      const double sk = q.dot(d) / dd;
      if ((q - sk * d).norm() <= 1e-12 * (1.0 + w0.norm()) && std::abs(sk) > 1e-12) nodes.push_back({sk, k});
    }
    std::sort(nodes.begin(), nodes.end(), [](const auto& a, const auto& b) {
      return std::abs(1.0 - a.first) < std::abs(1.0 - b.first);
    });
    if (extrapolate(nodes, 1.0, u)) return;
    along_path(w, u);
  }

 private:
  static constexpr double kMaxLebesgue = 80.0;

  // u = the Lagrange extrapolation to s of the solutions at nodes (s_i, entry), over the first m
  // nodes for the largest m >= 2 that is well conditioned; false (u untouched) if none is.
  bool extrapolate(const std::vector<std::pair<double, size_t>>& nodes, double s, Eigen::VectorXd& u) const {
    double L[kSize];
    for (size_t m = std::min(nodes.size(), kSize); m >= 2; --m) {
      if (!lagrange(nodes, m, s, L)) continue;
      u = L[0] * solved[nodes[0].second].second;
      for (size_t i = 1; i < m; ++i) u += L[i] * solved[nodes[i].second].second;
      return true;
    }
    return false;
  }

  // L = the Lagrange weights at s of the first m nodes; false if their sum of |L| exceeds kMaxLebesgue.
  static bool lagrange(const std::vector<std::pair<double, size_t>>& nodes, size_t m, double s, double* L) {
    double total = 0;
    for (size_t i = 0; i < m; ++i) {
      L[i] = 1.0;
      for (size_t j = 0; j < m; ++j)
        if (j != i) L[i] *= (s - nodes[j].first) / (nodes[i].first - nodes[j].first);
      total += std::abs(L[i]);
    }
    return total <= kMaxLebesgue;
  }

  // Weights off any line through earlier frames (a blend whose point moves over a 2D grid, or across
  // cells): the combination sum c_i u_i of the solved frames with c = L + e, where L extrapolates
  // along the path of the frames (newest first; the distance travelled is the parameter, w at 0;
  // the highest well-conditioned degree, as on a line) and e is the correction with sum e_i = 0
  // that makes the weights exact, sum c_i w_i = w, with the least sum (e_i |w_i - w|^2)^2 (the
  // smallest second-order error term: near frames correct most). So the guess is exact where u
  // is affine in the weights and follows the path's curvature. Kept if well conditioned
  // (sum |c_i| <= kMaxLebesgue) and the weights it leaves unmatched are under 1e-3 of the
  // nearest frame's distance, else u stays the nearest solution.
  void along_path(const Eigen::VectorXd& w, Eigen::VectorXd& u) const {
    const Eigen::Index k = w.size(), m = static_cast<Eigen::Index>(solved.size());
    if (m < 2) return;
    Eigen::VectorXd c = path_weights(w), scale(m), b(k + 1);
    Eigen::MatrixXd M(k + 1, m);
    b << 1.0 - c.sum(), w;
    for (Eigen::Index i = 0; i < m; ++i) {
      const Eigen::VectorXd& wi = solved[static_cast<size_t>(i)].first;
      b.tail(k) -= c[i] * wi;
      scale[i] = (wi - w).squaredNorm();
      if (scale[i] == 0) return;  // w itself was solved: the nearest solution is exact
      M(0, i) = 1.0 / scale[i];
      M.col(i).tail(k) = wi / scale[i];
    }
    // Directions in which the frames barely spread (below 1e-5 of the most: the weights of a
    // path in a plane, off it only by the roundoff of float parameters) are not corrected: that
    // would take huge weights for a mismatch of roundoff size, which is left instead.
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(M.rows(), M.cols());
    cod.setThreshold(1e-5);
    const Eigen::VectorXd e = cod.compute(M).solve(b);
    if (!((M * e - b).norm() <= 1e-3 * std::sqrt(scale.minCoeff()))) return;
    c += e.cwiseQuotient(scale);
    if (!(c.cwiseAbs().sum() <= kMaxLebesgue)) return;
    u = c[0] * solved[0].second;
    for (Eigen::Index i = 1; i < m; ++i) u += c[i] * solved[static_cast<size_t>(i)].second;
  }

  // (#solved) the Lagrange weights at w of the extrapolation along the path of the solved frames
  // (zero beyond the degree used; all zero if no degree is well conditioned).
  Eigen::VectorXd path_weights(const Eigen::VectorXd& w) const {
    std::vector<std::pair<double, size_t>> nodes;
    double s = 0;
    for (size_t k = 0; k < solved.size(); ++k) {
      s -= (solved[k].first - (k == 0 ? w : solved[k - 1].first)).norm();
      if (!nodes.empty() && s == nodes.back().first) break;  // a repeated frame ends the path
      nodes.push_back({s, k});
    }
    Eigen::VectorXd c = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(solved.size()));
    double L[kSize];
    for (size_t m = nodes.size(); m >= 2; --m) {
      if (!lagrange(nodes, m, 0.0, L)) continue;
      for (size_t i = 0; i < m; ++i) c[static_cast<Eigen::Index>(nodes[i].second)] = L[i];
      break;
    }
    return c;
  }
};

}  // namespace bdinterp::detail
