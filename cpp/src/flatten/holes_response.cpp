// The holes' first-order steps (holes.h): a solved Flattener moved along a change of its fixed
// offsets by one linear solve (follow_offsets), its response to them (offset_response), and the
// HoleSolver's steps built on them: the dipoles' Jacobian from the response and the free step by
// the sensitivity S (docs/HOLES.md).
#include <cmath>

#include "flatten/holes.h"
#include "mesh/triangle.h"
#include "flatten/flatten_state.h"

namespace bdinterp {
namespace {
// follow_offsets linearises with a Hessian assembled up to this far from u (max norm): its error,
// about this times the move (<= 1e-9), stays far below the aim.
constexpr double kHessianDrift = 1e-6;
// Free first-order steps on one sensitivity S before a solve refreshes it (S drifts; docs/HOLES.md).
constexpr int kLinearSteps = 8;
// The largest move |S delta|_inf of a first-order step: the angle residual it leaves is up to ~10 %
// of the move (S's accuracy, docs/HOLES.md), and exp(move) = 1 + move in doubles.
constexpr double kLinearMove = 1e-10;
// The largest move of a step by follow_offsets (error second order in it, ~1e-18); the relative
// accuracy of the response's solves and the central differences' step for the Jacobian.
constexpr double kFollowMove = 1e-9;
constexpr double kResponseAccuracy = 1e-5;
constexpr double kProbe = 1e-7;

// Adds to `defect` (#unknowns + 1, the last a spare row) the change of the defects when u moves by
// `offset` (#V) to first order: the cotan Laplacian of the offsets at the scaled lengths of `at`,
// each vertex's row added to its unknown's. Broken faces have zero cotangents, as in the Hessian.
void add_laplacian(const FlattenPlan& plan, const detail::Evaluation& at, const Eigen::VectorXd& offset,
                   Eigen::VectorXd& defect) {
  const Faces& F = plan.mesh.faces();
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const double o[3] = {offset[F(f, 0)], offset[F(f, 1)], offset[F(f, 2)]};
    if (o[0] == 0 && o[1] == 0 && o[2] == 0) continue;
    const FlattenPlan::FaceSlots& s = plan.slots[f];
    const double l[3] = {at.scaled_len[s.edge[0]], at.scaled_len[s.edge[1]], at.scaled_len[s.edge[2]]};
    const double l2[3] = {at.scaled_l2[s.edge[0]], at.scaled_l2[s.edge[1]], at.scaled_l2[s.edge[2]]};
    double cot[3];
    if (triangle_cotangents_from_lengths(l, l2, cot)) continue;
    for (int c = 0; c < 3; ++c) {  // the edge opposite corner c, weight cot / 2
      const int i = (c + 1) % 3, j = (c + 2) % 3;
      const double d = 0.5 * cot[c] * (o[i] - o[j]);
      defect[s.row[i]] += d;
      defect[s.row[j]] -= d;
    }
  }
}

// Into s.move (#V, 0 where u is fixed): offset + x, where CG solves H x = -(defects at cur, if
// with_defects, + the cotan Laplacian of the offsets) to max |residual| <= eta + relative * max
// |right-hand side| (in s.pcg.r), with a Hessian assembled at most kHessianDrift from cur. False if
// CG does not get there.
bool solve_response(Flattener::State& s, const Eigen::VectorXd& offset, bool with_defects, double eta,
                    double relative) {
  const FlattenPlan& p = s.plan;
  const int n = p.num_interior();
  if (offset.size() != p.mesh.num_vertices()) throw InvalidInput("follow: offset must have one entry per vertex");
  if (with_defects) s.shifted = s.cur.defect;
  else s.shifted.setZero(n + 1);
  add_laplacian(p, s.cur, offset, s.shifted);
  s.rhs = -s.shifted.head(n);
  if (s.hessian_drift > kHessianDrift) {
    s.evaluator.assemble_hessian(s.cur, s.hessian.data());
    s.hessian_drift = 0;
  }
  eta += relative * s.rhs.cwiseAbs().maxCoeff();
  detail::preconditioned_cg(*s.factor, s.hessian.data(), s.rhs, eta, detail::kMaxCgIterations, s.step, s.pcg);
  if (!(s.pcg.r.cwiseAbs().maxCoeff() <= eta)) return false;
  if (s.move.size() != offset.size()) s.move.setZero(offset.size());
  for (int v : p.moved) s.move[v] = offset[v] + s.step[p.pattern.index[v]];
  return true;
}
}  // namespace

bool offset_response(Flattener& f, const Eigen::VectorXd& offset, double relative, Eigen::VectorXd& move) {
  Flattener::State& s = *f.state_;
  if (f.num_interior() == 0 || !s.factor_reusable || s.cur.broken > 0) return false;
  if (!solve_response(s, offset, false, 0.0, relative)) return false;
  move = s.move;
  return true;
}

bool follow_offsets(Flattener& f, const Eigen::VectorXd& offset, Eigen::VectorXd& u, double max_move,
                    const FlattenOptions& options) {
  Flattener::State& s = *f.state_;
  const int n = f.num_interior();
  if (n == 0 || !options.reuse_factorization || !s.factor_reusable || s.cur.broken > 0) return false;
  if (u.size() != offset.size()) throw InvalidInput("follow: u must have one entry per vertex");
  if (!solve_response(s, offset, true, 0.5 * options.tolerance * options.refinement, 0.0)) return false;
  const double largest = s.move.cwiseAbs().maxCoeff();
  if (!(largest <= max_move)) return false;
  u += s.move;
  // exp(m_i + m_j) = 1 + m_i + m_j to double precision for moves this small.
  const Edges& E = f.plan().mesh.edges();
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const double m = s.move[E(e, 0)] + s.move[E(e, 1)];
    s.cur.scaled_l2[e] *= 1.0 + m;
    s.cur.scaled_len[e] *= 1.0 + 0.5 * m;
  }
  s.cur.defect.head(n) = -s.pcg.r;  // the linear model's defects: g + L offset + H x
  s.cur.residual = s.pcg.r.cwiseAbs().maxCoeff();
  s.cur.has_energy = false;
  s.hessian_at_cur = false;
  s.hessian_drift += largest;
  return true;
}

void HoleSolver::dipole_offsets(const Eigen::VectorXd& delta, Eigen::VectorXd& offset) const {
  if (offset.size() != mesh_->num_vertices()) offset.setZero(mesh_->num_vertices());
  for (int k = 0; k < num_holes(); ++k)
    for (size_t i = 0; i < loops_[k].size(); ++i)
      offset[loops_[k][i]] = loop_xy_[k](i, 0) * delta[2 * k] + loop_xy_[k](i, 1) * delta[2 * k + 1];
}

void HoleSolver::move_lengths(const Eigen::VectorXd& flat, double h) {
  // exp(h move_i) exp(h move_j) = 1 + h (move_i + move_j) to double precision for moves this small.
  const Edges& E = mesh_->edges();
  trial_flat_.resize(E.rows());
  for (Eigen::Index e = 0; e < E.rows(); ++e) trial_flat_[e] = flat[e] * (1.0 + h * (move_[E(e, 0)] + move_[E(e, 1)]));
}

bool HoleSolver::linear_jacobian() {
  const int m = 2 * num_holes();
  sensitivity_.resize(mesh_->num_vertices(), m);
  sensitivity_age_ = 0;
  Eigen::MatrixXd J(m, m);
  for (int j = 0; j < m; ++j) {  // central differences of the periods along the response
    dipole_offsets(Eigen::VectorXd::Unit(m, j), offset_);
    if (!offset_response(flattener_, offset_, kResponseAccuracy, move_)) return false;
    sensitivity_.col(j) = move_;
    move_lengths(flattener_.flat_squared_lengths(), kProbe);
    J.col(j) = periods(trial_flat_);
    move_lengths(flattener_.flat_squared_lengths(), -kProbe);
    J.col(j) = (J.col(j) - periods(trial_flat_)) / (2 * kProbe);
  }
  jacobian_ = J;
  return true;
}

bool HoleSolver::follow(const Eigen::VectorXd& delta, Eigen::VectorXd& u, const FlattenOptions& options) {
  dipole_offsets(delta, offset_);
  if (!follow_offsets(flattener_, offset_, u, kFollowMove, options)) return false;
  dipole_ += delta;
  return true;
}

bool HoleSolver::linear_step(const Eigen::VectorXd& delta, double aim, Eigen::VectorXd& u, Eigen::VectorXd& next) {
  // u moves by S delta, free: right up to the step squared and S's error (a few %) times the move,
  // so only for small moves, and kept only if it closes the periods.
  if (sensitivity_age_ >= kLinearSteps) return false;
  move_.noalias() = sensitivity_ * delta;
  if (!(move_.cwiseAbs().maxCoeff() <= kLinearMove)) return false;
  move_lengths(flattener_.flat_squared_lengths(), 1.0);
  next = periods(trial_flat_);
  if (!next.allFinite() || next.cwiseAbs().maxCoeff() > aim) return false;
  ++sensitivity_age_;
  u += move_;
  dipole_ += delta;
  flat_.swap(trial_flat_);
  return true;
}

}  // namespace bdinterp
