#include "bdinterp/holes.h"

#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include "bdinterp/geometry.h"
#include "bdinterp/lobachevsky.h"
#include "bdinterp/triangle.h"

namespace bdinterp {
namespace {
// Closing the holes' periods: at most this many Newton steps on the dipoles, until every period
// (relative to the loop's length) is below tolerance * refinement or stops halving (the angle
// residual limits the periods' accuracy to about that); the finite-difference step of the Jacobian.
constexpr int kClosureIterations = 12;
constexpr double kDipoleStep = 1e-6;

// Lower-triangle compressed-column pattern of a symmetric matrix over n unknowns with the given
// off-diagonal pairs; position(i, j) finds an entry.
struct LowerPattern {
  std::vector<int> col_ptr, rows;
  LowerPattern(int n, std::vector<std::pair<int, int>> pairs) {
    for (auto& p : pairs)
      if (p.first < p.second) std::swap(p.first, p.second);  // (row, col), row > col
    std::sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) {
      return a.second != b.second ? a.second < b.second : a.first < b.first;
    });
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    col_ptr.assign(n + 1, 0);
    size_t k = 0;
    for (int j = 0; j < n; ++j) {
      rows.push_back(j);
      for (; k < pairs.size() && pairs[k].second == j; ++k) rows.push_back(pairs[k].first);
      col_ptr[j + 1] = static_cast<int>(rows.size());
    }
  }
  int position(int i, int j) const {
    if (i < j) std::swap(i, j);
    const auto b = rows.begin() + col_ptr[j], e = rows.begin() + col_ptr[j + 1];
    return static_cast<int>(std::lower_bound(b, e, i) - rows.begin());
  }
};

}  // namespace

HoleSolver::HoleSolver(const Mesh& piece, const Positions& base) : mesh_(&piece), walk_(piece.dual_walk({0})) {
  const int nv = piece.num_vertices();
  std::vector<std::vector<int>> all = piece.boundary_loops();
  if (all.empty()) throw InvalidInput("a piece without boundary cannot be flattened");
  size_t outer = 0;
  for (size_t k = 1; k < all.size(); ++k)
    if (std::abs(loop_area(base, all[k])) > std::abs(loop_area(base, all[outer]))) outer = k;
  unknown_.assign(nv, -1);
  std::vector<double> target;
  for (int v = 0; v < nv; ++v) {
    if (piece.is_boundary_vertex(v) || piece.is_isolated_vertex(v)) continue;
    unknown_[v] = n_++;
    vertex_of_.push_back(v);
    target.push_back(2 * kPi);
  }
  for (size_t k = 0; k < all.size(); ++k) {
    if (k == outer) continue;
    for (int v : all[k]) unknown_[v] = n_;
    vertex_of_.push_back(all[k][0]);
    target.push_back((static_cast<double>(all[k].size()) + 2) * kPi);
    ++n_;
    loops_.push_back(all[k]);
  }
  // Each inner loop's edges in loop order, with +1 where the edge runs E(e,0) -> E(e,1) along it.
  const Edges& E0 = piece.edges();
  std::vector<std::vector<int>> boundary_edges(nv);
  for (int e = 0; e < E0.rows(); ++e)
    if (piece.edge_faces()(e, 1) < 0) boundary_edges[E0(e, 0)].push_back(e), boundary_edges[E0(e, 1)].push_back(e);
  for (const auto& loop : loops_) {
    loop_edges_.emplace_back();
    for (size_t k = 0; k < loop.size(); ++k) {
      const int a = loop[k], b = loop[(k + 1) % loop.size()];
      for (int e : boundary_edges[a])
        if (E0(e, 0) == b || E0(e, 1) == b) loop_edges_.back().push_back({e, E0(e, 0) == a ? 1.0 : -1.0});
    }
  }
  target_ = Eigen::Map<Eigen::VectorXd>(target.data(), n_);
  loop_xy_.resize(loops_.size());
  dipole_.setZero(2 * num_holes());
  build_hessian_slots();
  build_layout_system();
}

void HoleSolver::build_hessian_slots() {
  // The reduced Hessian: an entry for every edge between different unknowns.
  const Mesh& piece = *mesh_;
  const Edges& E = piece.edges();
  std::vector<std::pair<int, int>> pairs;
  for (int e = 0; e < E.rows(); ++e) {
    const int a = unknown_[E(e, 0)], b = unknown_[E(e, 1)];
    if (a >= 0 && b >= 0 && a != b) pairs.push_back({a, b});
  }
  const LowerPattern h(n_, pairs);
  const Faces& F = piece.faces();
  slot_a_.assign(3 * F.rows(), -1);
  slot_b_.assign(3 * F.rows(), -1);
  slot_off_.assign(3 * F.rows(), -1);
  for (int f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int a = unknown_[F(f, (c + 1) % 3)], b = unknown_[F(f, (c + 2) % 3)];
      if (a >= 0) slot_a_[3 * f + c] = h.position(a, a);
      if (b >= 0) slot_b_[3 * f + c] = h.position(b, b);
      // An edge inside one loop adds w + w - 2 w = 0 to that loop's diagonal: no entry at all.
      if (a >= 0 && b >= 0 && a == b) slot_a_[3 * f + c] = slot_b_[3 * f + c] = -1;
      if (a >= 0 && b >= 0 && a != b) slot_off_[3 * f + c] = h.position(a, b);
    }
  }
  if (n_ > 0) {
    hessian_analysis_ = std::make_shared<const CholeskyAnalysis>(n_, h.col_ptr, h.rows);
    chol_ = std::make_unique<SparseCholesky>(hessian_analysis_);
  }
  hvals_.assign(h.rows.size(), 0.0);
  grad_.resize(n_);
}

void HoleSolver::build_layout_system() {
  // The layout's uniform Laplacian over every vertex but one (the least-squares fit of edge vectors).
  const Mesh& piece = *mesh_;
  const Edges& E = piece.edges();
  const int nv = piece.num_vertices();
  layout_index_.assign(nv, -1);
  std::vector<std::pair<int, int>> pairs;
  pinned_ = piece.faces()(0, 0);
  int m = 0;
  for (int v = 0; v < nv; ++v)
    if (v != pinned_ && !piece.is_isolated_vertex(v)) layout_index_[v] = m++;
  pairs.clear();
  for (int e = 0; e < E.rows(); ++e) {
    const int a = layout_index_[E(e, 0)], b = layout_index_[E(e, 1)];
    if (a >= 0 && b >= 0) pairs.push_back({a, b});
  }
  const LowerPattern g(m, pairs);
  layout_analysis_ = std::make_shared<const CholeskyAnalysis>(m, g.col_ptr, g.rows);
  layout_values_.assign(g.rows.size(), 0.0);
  double* L = layout_values_.data();
  for (int e = 0; e < E.rows(); ++e) {
    const int a = layout_index_[E(e, 0)], b = layout_index_[E(e, 1)];
    if (a >= 0) L[g.position(a, a)] += 1;
    if (b >= 0) L[g.position(b, b)] += 1;
    if (a >= 0 && b >= 0) L[g.position(a, b)] -= 1;
  }
  factorize_layout();
}

void HoleSolver::factorize_layout() {
  layout_ = std::make_unique<SparseCholesky>(layout_analysis_);
  std::copy(layout_values_.begin(), layout_values_.end(), layout_->values());
  layout_->factorize();
}

HoleSolver::HoleSolver(const HoleSolver& o)
    : mesh_(o.mesh_), walk_(o.walk_), loops_(o.loops_), unknown_(o.unknown_), vertex_of_(o.vertex_of_),
      loop_edges_(o.loop_edges_), loop_xy_(o.loop_xy_), dipole_(o.dipole_), target_(o.target_), n_(o.n_),
      slot_a_(o.slot_a_), slot_b_(o.slot_b_), slot_off_(o.slot_off_),
      hessian_analysis_(o.hessian_analysis_), layout_analysis_(o.layout_analysis_),
      layout_values_(o.layout_values_), layout_index_(o.layout_index_), pinned_(o.pinned_),
      grad_(o.grad_), hvals_(o.hvals_) {
  if (hessian_analysis_) chol_ = std::make_unique<SparseCholesky>(hessian_analysis_);
  factorize_layout();
}

HoleSolver::~HoleSolver() = default;

std::unique_ptr<HoleSolver> HoleSolver::clone() const {
  return std::unique_ptr<HoleSolver>(new HoleSolver(*this));
}

double HoleSolver::evaluate(const Eigen::VectorXd& l2, const Eigen::VectorXd& u, bool want_energy,
                            bool want_hessian, int* broken) const {
  const Faces& F = mesh_->faces();
  const Faces& FE = mesh_->face_edges();
  grad_ = target_;
  if (want_hessian) std::fill(hvals_.begin(), hvals_.end(), 0.0);
  double energy = 0;
  *broken = 0;
  for (int f = 0; f < F.rows(); ++f) {
    double fl2[3], angle[3], cot[3];
    for (int c = 0; c < 3; ++c) {
      const int e = FE(f, c);
      fl2[c] = l2[e] * std::exp(u[F(f, (c + 1) % 3)] + u[F(f, (c + 2) % 3)]);
    }
    *broken += triangle_angles(fl2, angle, cot) ? 1 : 0;
    for (int c = 0; c < 3; ++c) {
      const int k = unknown_[F(f, c)];
      if (k >= 0) grad_[k] -= angle[c];
      if (want_energy) {
        const double lambda = std::log(fl2[c]);
        energy += angle[c] * lambda + 2 * lobachevsky(angle[c]) - 0.5 * kPi * lambda;
      }
      if (!want_hessian) continue;
      const double w = 0.5 * cot[c];
      const int s = 3 * f + c;
      if (slot_a_[s] >= 0) hvals_[slot_a_[s]] += w;
      if (slot_b_[s] >= 0) hvals_[slot_b_[s]] += w;
      if (slot_off_[s] >= 0) hvals_[slot_off_[s]] -= w;
    }
  }
  if (want_energy)
    for (int k = 0; k < n_; ++k) energy += target_[k] * u[vertex_of_[k]];
  return energy;
}

double HoleSolver::energy(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) const {
  int broken = 0;
  return evaluate(l2, u, true, false, &broken);
}

Eigen::VectorXd HoleSolver::gradient(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) const {
  int broken = 0;
  evaluate(l2, u, false, false, &broken);
  return grad_;
}

void HoleSolver::set_dipoles(const Eigen::VectorXd& ab, Eigen::VectorXd& u) {
  for (int k = 0; k < num_holes(); ++k) {
    const std::vector<int>& loop = loops_[k];
    const double base = u[loop[0]] - loop_xy_[k](0, 0) * dipole_[2 * k] - loop_xy_[k](0, 1) * dipole_[2 * k + 1];
    for (size_t i = 0; i < loop.size(); ++i)
      u[loop[i]] = base + loop_xy_[k](i, 0) * ab[2 * k] + loop_xy_[k](i, 1) * ab[2 * k + 1];
  }
  dipole_ = ab;
}

Eigen::MatrixXd HoleSolver::dipole_jacobian(const Eigen::VectorXd& l2, const Eigen::VectorXd& u,
                                            const Eigen::VectorXd& period, const FlattenOptions& options,
                                            FlattenReport& report) {
  const int m = 2 * num_holes();
  const Eigen::VectorXd ab = dipole_;
  Eigen::MatrixXd J(m, m);
  Eigen::VectorXd trial;
  for (int j = 0; j < m; ++j) {
    Eigen::VectorXd abj = ab;
    abj[j] += kDipoleStep;
    trial = u;
    set_dipoles(abj, trial);
    newton(l2, trial, options, report);
    J.col(j) = (periods(scale_lengths(*mesh_, l2, trial)) - period) / kDipoleStep;
    set_dipoles(ab, trial);  // dipole_ back to ab
  }
  return J;
}

HolesReport HoleSolver::solve(const Eigen::VectorXd& l2, Eigen::VectorXd& u, Positions& X,
                              const FlattenOptions& options) {
  const int nv = mesh_->num_vertices(), m = 2 * num_holes();
  if (l2.size() != mesh_->num_edges()) throw InvalidInput("flatten: l2 must have one entry per edge");
  if (u.size() != nv || !u.allFinite()) u = Eigen::VectorXd::Zero(nv);
  for (int v = 0; v < nv; ++v) u[v] = unknown_[v] < 0 ? 0.0 : u[vertex_of_[unknown_[v]]];
  // The dipoles start from the last solve's (the previous frame on a slider), or from 0 with a cold
  // start u = 0 (the interpolator's guess at an input, whose own metric closes with zero dipoles:
  // exact in zero steps).
  const bool cold = (u.array() == 0.0).all();
  const Eigen::VectorXd start = dipole_.size() == m && !cold ? dipole_ : Eigen::VectorXd::Zero(m);
  dipole_.setZero(m);
  // The dipoles' shape on each hole: cos and sin of the arc-length angle in the blended metric.
  // Intrinsic, so that the pair reversed gives the same frames (base coordinates would not).
  for (int k = 0; k < num_holes(); ++k) {
    const auto& edges = loop_edges_[k];
    Eigen::VectorXd s(edges.size() + 1);
    s[0] = 0;
    for (size_t i = 0; i < edges.size(); ++i) s[i + 1] = s[i] + std::sqrt(l2[edges[i].first]);
    loop_xy_[k].resize(edges.size(), 2);
    for (size_t i = 0; i < edges.size(); ++i) {
      const double angle = 2 * kPi * s[i] / s[edges.size()];
      loop_xy_[k].row(i) << std::cos(angle), std::sin(angle);
    }
  }
  set_dipoles(start, u);
  HolesReport rep;
  newton(l2, u, options, rep.flatten);
  // Close the translation periods: u along hole k is c_k + a_k x + b_k y (base coordinates); Newton
  // on (a, b) with a finite-difference Jacobian, each evaluation a warm-started convex solve.
  Eigen::VectorXd period = periods(scale_lengths(*mesh_, l2, u)), ab = dipole_;
  // The Jacobian is kept across frames (it changes slowly along a slider) and updated by Broyden's
  // rule; it is recomputed by finite differences when missing or when a step fails to halve the
  // periods.
  bool fresh = false;
  // Closed to tolerance * refinement like the flattening; the loop ends at the accuracy the periods
  // allow (a fresh Jacobian's step that does not halve them).
  const double aim = options.tolerance * options.refinement;
  for (int it = 0; it < kClosureIterations && period.cwiseAbs().maxCoeff() > aim; ++it) {
    if (jacobian_.rows() != m) jacobian_ = dipole_jacobian(l2, u, period, options, rep.flatten), fresh = true;
    const Eigen::VectorXd delta = -jacobian_.fullPivLu().solve(period);
    ab += delta;
    set_dipoles(ab, u);
    newton(l2, u, options, rep.flatten);
    const Eigen::VectorXd next = periods(scale_lengths(*mesh_, l2, u));
    const bool halved = next.cwiseAbs().maxCoeff() <= 0.5 * period.cwiseAbs().maxCoeff();
    if (!halved && fresh) {  // the accuracy of the periods (~ the flattening's tolerance) is reached
      period = next;
      break;
    }
    if (halved) {
      jacobian_ += (next - period - jacobian_ * delta) * delta.transpose() / delta.squaredNorm();
      fresh = false;
    } else {
      jacobian_ = dipole_jacobian(l2, u, next, options, rep.flatten);
      fresh = true;
    }
    period = next;
  }
  rep.flatness = layout(scale_lengths(*mesh_, l2, u), X, rep.closure);
  return rep;
}

}  // namespace bdinterp
