// The outer step of a piece with holes (holes.h): the holes' unknowns for the Flattener and the
// closure of their translation periods by Newton on the dipoles around the convex solves (the
// periods themselves and the layout: holes_periods.cpp).
#include "flatten/holes.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>

#include "mesh/geometry.h"

namespace bdinterp {
namespace {
// Closing the holes' periods: at most this many Newton steps on the dipoles, until every period
// (relative to the loop's length) is below tolerance * refinement or stops halving (the angle
// residual limits the periods' accuracy to about that); the finite-difference step of the Jacobian.
constexpr int kClosureIterations = 12;
constexpr double kDipoleStep = 1e-6;

// The outer loop of `piece`: the index of the boundary loop enclosing the largest area in `base`.
int outer_loop(const Mesh& piece, const Positions& base) {
  const std::vector<std::vector<int>>& all = piece.boundary_loops();
  if (all.empty()) throw InvalidInput("a piece without boundary cannot be flattened");
  size_t outer = 0;
  for (size_t k = 1; k < all.size(); ++k)
    if (std::abs(loop_area(base, all[k])) > std::abs(loop_area(base, all[outer]))) outer = k;
  return static_cast<int>(outer);
}

// The inner loops of `piece`: every boundary loop but the one `layout` walks (the outer one).
std::vector<std::vector<int>> inner_loops(const Mesh& piece, const LayoutPlan& layout) {
  std::vector<std::vector<int>> inner = piece.boundary_loops();
  inner.erase(inner.begin() + layout.outer);
  return inner;
}

// One unknown per interior vertex (2 pi) and one per inner loop of n vertices ((n + 2) pi: the
// hole's boundary turns once); u = 0 on the outer loop.
FlattenUnknowns hole_unknowns(const Mesh& piece, const std::vector<std::vector<int>>& loops) {
  FlattenUnknowns u = interior_unknowns(piece);
  for (const std::vector<int>& loop : loops) {
    for (int v : loop) u.of_vertex[v] = static_cast<int>(u.target.size());
    u.target.push_back((static_cast<double>(loop.size()) + 2) * kPi);
  }
  return u;
}

// One more convex solve added to `into` as merge() adds a piece's, but for the state of the final
// u: its residual and broken faces are the last solve's.
void add_solve(FlattenReport& into, const FlattenReport& r) {
  merge(into, r);
  into.residual = r.residual;
  into.broken_triangles = r.broken_triangles;
}

}  // namespace

HoleSolver::HoleSolver(const Mesh& piece, const Positions& base)
    : mesh_(&piece),
      layout_plan_(std::make_shared<const LayoutPlan>(piece, outer_loop(piece, base), /*share_analysis=*/true)),
      loops_(inner_loops(piece, *layout_plan_)),
      plan_(std::make_shared<const FlattenPlan>(piece, hole_unknowns(piece, loops_))),
      flattener_(plan_),
      layout_(layout_plan_) {
  // Each inner loop's edges in loop order, with +1 where the edge runs E(e,0) -> E(e,1) along it.
  const Edges& E0 = piece.edges();
  std::vector<std::vector<int>> boundary_edges(piece.num_vertices());
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
  // Each inner loop's face corners, for its vertices' angles (periods()).
  std::vector<int> owner(piece.num_vertices(), -1), position(piece.num_vertices(), -1);
  for (int k = 0; k < num_holes(); ++k)
    for (size_t i = 0; i < loops_[k].size(); ++i) owner[loops_[k][i]] = k, position[loops_[k][i]] = static_cast<int>(i);
  loop_corners_.resize(loops_.size());
  const Faces& F = piece.faces();
  for (int f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      if (owner[F(f, c)] >= 0) loop_corners_[owner[F(f, c)]].push_back({position[F(f, c)], f, c});
  for (const std::vector<int>& loop : loops_) half_turns_.emplace_back(2 * loop.size());
  loop_xy_.resize(loops_.size());
  dipole_.setZero(2 * num_holes());
}

HoleSolver::HoleSolver(const HoleSolver& o)
    : mesh_(o.mesh_), layout_plan_(o.layout_plan_), loops_(o.loops_), loop_edges_(o.loop_edges_),
      loop_corners_(o.loop_corners_), half_turns_(o.half_turns_),
      loop_xy_(o.loop_xy_), dipole_(o.dipole_), plan_(o.plan_), flattener_(o.plan_), layout_(o.layout_plan_) {}

HoleSolver::~HoleSolver() = default;

std::unique_ptr<HoleSolver> HoleSolver::clone() const {
  return std::unique_ptr<HoleSolver>(new HoleSolver(*this));
}

void HoleSolver::forget() {
  dipole_.resize(0);
  jacobian_.resize(0, 0);
  sensitivity_.resize(0, 0);
  flattener_.forget();
}

double HoleSolver::energy(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) { return flattener_.energy(l2, u); }

Eigen::VectorXd HoleSolver::gradient(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) {
  const Eigen::VectorXd g = flattener_.gradient(l2, u);
  return g(plan_->pattern.vertex);  // unknown k's entry sits at its vertex
}

void HoleSolver::convex_solve(const Eigen::VectorXd& l2, Eigen::VectorXd& u, const FlattenOptions& options,
                              FlattenReport& report) {
  add_solve(report, flattener_.solve(l2, u, options));
}

void HoleSolver::set_dipole_shapes(const Eigen::VectorXd& l2) {
  // cos and sin of the arc-length angle in the blended metric: intrinsic, so that the pair reversed
  // gives the same frames (base coordinates would not).
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
}

Eigen::VectorXd HoleSolver::fit_dipoles(Eigen::VectorXd& u) const {
  Eigen::VectorXd ab = Eigen::VectorXd::Zero(2 * num_holes());
  for (int k = 0; k < num_holes(); ++k) {
    const std::vector<int>& loop = loops_[k];
    Eigen::MatrixX3d basis(loop.size(), 3);
    Eigen::VectorXd along(loop.size());
    for (size_t i = 0; i < loop.size(); ++i) {
      basis.row(i) << 1.0, loop_xy_[k](i, 0), loop_xy_[k](i, 1);
      along[i] = u[loop[i]];
    }
    const Eigen::Vector3d c = (basis.transpose() * basis).ldlt().solve(basis.transpose() * along);
    ab.segment<2>(2 * k) = c.tail<2>();
    for (int v : loop) u[v] = c[0];  // with dipole_ = 0, set_dipoles adds the profile to c
  }
  return ab;
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

Eigen::MatrixXd HoleSolver::dipole_jacobian(const Eigen::VectorXd& l2, Eigen::VectorXd& u,
                                            const Eigen::VectorXd& period, const FlattenOptions& options,
                                            FlattenReport& report) {
  const int m = 2 * num_holes();
  const Eigen::VectorXd ab = dipole_;
  Eigen::MatrixXd J(m, m);
  sensitivity_.resize(u.size(), m);
  sensitivity_age_ = 0;
  Eigen::VectorXd trial;
  for (int j = 0; j < m; ++j) {
    Eigen::VectorXd abj = ab;
    abj[j] += kDipoleStep;
    trial = u;
    set_dipoles(abj, trial);
    convex_solve(l2, trial, options, report);
    J.col(j) = (solved_periods() - period) / kDipoleStep;
    sensitivity_.col(j) = (trial - u) / kDipoleStep;
    set_dipoles(ab, trial);  // dipole_ back to ab
  }
  convex_solve(l2, u, options, report);  // the Flattener back at u (solved: one evaluation)
  return J;
}

void HoleSolver::refresh_jacobian(const Eigen::VectorXd& l2, Eigen::VectorXd& u, const Eigen::VectorXd& period,
                                  const FlattenOptions& options, FlattenReport& report) {
  if (!options.reuse_factorization || !linear_jacobian()) jacobian_ = dipole_jacobian(l2, u, period, options, report);
}

bool HoleSolver::try_step(PeriodStep step, const Eigen::VectorXd& l2, const Eigen::VectorXd& delta, double aim,
                          Eigen::VectorXd& u, Eigen::VectorXd& next, const FlattenOptions& options,
                          FlattenReport& report) {
  switch (step) {
    case PeriodStep::Linear:
      return linear_step(delta, aim, u, next);
    case PeriodStep::Follow:
      if (!follow(delta, u, options)) return false;
      break;
    case PeriodStep::Convex:
      set_dipoles(dipole_ + delta, u);
      convex_solve(l2, u, options, report);
      break;
  }
  next = solved_periods();
  return true;
}

const Eigen::VectorXd& HoleSolver::close_periods(const Eigen::VectorXd& l2, Eigen::VectorXd& u,
                                                 const FlattenOptions& options, FlattenReport& report) {
  const int m = 2 * num_holes();
  Eigen::VectorXd period = solved_periods(), next;
  // Newton on the dipoles, the Jacobian and the sensitivity du/d dipoles kept across frames (they
  // change slowly along a slider). Each Newton step is taken by the first of kPeriodSteps that
  // applies, and judged by one rule: accepted if it halves the largest period or closes them all
  // (below tolerance * refinement, like the flattening). An accepted step updates the Jacobian and
  // the sensitivity by Broyden's rule; a rejected one is kept and refreshes them, or ends the loop
  // if they were fresh (the periods' accuracy, about the flattening's tolerance, is reached).
  bool fresh = false;
  const double aim = options.tolerance * options.refinement;
  for (int it = 0; it < kClosureIterations && period.cwiseAbs().maxCoeff() > aim; ++it) {
    if (jacobian_.rows() != m) refresh_jacobian(l2, u, period, options, report), fresh = true;
    const Eigen::VectorXd delta = -jacobian_.fullPivLu().solve(period);
    before_ = u;
    PeriodStep step = PeriodStep::Convex;
    for (PeriodStep s : kPeriodSteps)
      if (try_step(s, l2, delta, aim, u, next, options, report)) {
        step = s;
        break;
      }
    if (next.cwiseAbs().maxCoeff() <= std::max(aim, 0.5 * period.cwiseAbs().maxCoeff())) {
      jacobian_ += (next - period - jacobian_ * delta) * delta.transpose() / delta.squaredNorm();
      if (step == PeriodStep::Linear) return flat_;  // u is S's step, not the Flattener's solution
      move_.noalias() = sensitivity_ * delta;
      move_ = u - before_ - move_;
      sensitivity_.noalias() += move_ * (delta.transpose() / delta.squaredNorm());
      sensitivity_age_ = 0;
      fresh = false;
    } else if (fresh) {
      break;
    } else {
      refresh_jacobian(l2, u, next, options, report);
      fresh = true;
    }
    period = next;
  }
  return flattener_.flat_squared_lengths();
}

FlattenReport HoleSolver::flatten(const Eigen::VectorXd& l2, Eigen::VectorXd& u, const FlattenOptions& options) {
  const int nv = mesh_->num_vertices(), m = 2 * num_holes();
  if (l2.size() != mesh_->num_edges()) throw InvalidInput("flatten: l2 must have one entry per edge");
  if (u.size() != nv || !u.allFinite()) u = Eigen::VectorXd::Zero(nv);
  for (int v = 0; v < nv; ++v)
    if (unknown(v) < 0) u[v] = 0.0;
  set_dipole_shapes(l2);
  // The dipoles start from the guess's profile along each hole (the interpolator extrapolates
  // solved frames, dipoles included), or from 0 with a cold start u = 0 (the guess at an input,
  // whose own metric closes with zero dipoles: exact in zero steps).
  dipole_.setZero(m);
  set_dipoles(fit_dipoles(u), u);
  FlattenReport rep;
  convex_solve(l2, u, options, rep);
  flat_result_ = &close_periods(l2, u, options, rep);
  return rep;
}

HolesReport HoleSolver::solve(const Eigen::VectorXd& l2, Eigen::VectorXd& u, Positions& X,
                              const FlattenOptions& options) {
  HolesReport rep;
  rep.flatten = flatten(l2, u, options);
  rep.flatness = layout(flat_squared_lengths(), X, rep.closure);
  return rep;
}

}  // namespace bdinterp
