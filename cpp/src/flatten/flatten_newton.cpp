// The Newton driver of the flattening: from the iterate u, repeat until the residual (max |2 pi -
// angle sum|) is below the aim, tolerance * refinement:
//   - a chord step when the cost model prefers it: the Newton step at u solved by CG preconditioned
//     with an earlier factorisation, accepted if it halves the residual;
//   - otherwise a Newton step with a fresh factorisation and a line search on the energy.
// Missing the tolerance is an error; between tolerance and aim the solve only refines, and ends at
// the first step that does not halve the residual (roundoff) instead of failing.
// `cur` always describes u; candidates are evaluated into `trial` and swapped in when accepted.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <sstream>

#include "flatten/flatten.h"
#include "mesh/triangle.h"
#include "flatten/flatten_state.h"
#include "flatten/refining.h"

namespace bdinterp {
namespace {

class NewtonDriver {
 public:
  NewtonDriver(Flattener::State& s, const Eigen::VectorXd& l2, Eigen::VectorXd& u, const FlattenOptions& o)
      : s_(s), l2_(l2), u_(u), opt_(o), n_(s.plan.num_interior()) {}

  FlattenReport run() {
    s_.evaluate(l2_, u_, false, n_ > 0, s_.cur);  // the Hessian too: a step is likely to follow
    s_.hessian_at_cur = n_ > 0;
    s_.hessian_drift = n_ > 0 ? 0.0 : HUGE_VAL;
    rep_.max_broken_triangles = s_.cur.broken;
    s_.step.resize(n_);
    s_.trial_u = u_;
    // Chord steps first when an earlier factorisation is at hand (the previous frame's).
    bool chord = opt_.reuse_factorization && s_.factor_reusable;
    while (n_ > 0 && stop_.another(s_.cur.residual, rep_.iterations)) {
      const bool refining = stop_.refining(s_.cur.residual);
      ++rep_.iterations;
      const bool try_chord = chord || (refining && opt_.reuse_factorization && s_.factor_reusable);
      if (try_chord && chord_step(chord)) continue;
      if (refining) {
        // A chord step whose linear solve converged failed on roundoff: a new factor cannot help.
        if ((try_chord && last_cg_ < detail::kMaxCgIterations) || !refining_newton_step()) break;
        continue;
      }
      chord = newton_step();
    }
    rep_.residual = s_.cur.residual;
    rep_.broken_triangles = s_.cur.broken;
    return rep_;
  }

 private:
  // Tries a chord step; on success sets `keep` to whether the next step should be one too.
  bool chord_step(bool& keep) {
    ensure_hessian();
    const double r = s_.cur.residual;
    // Inexact Newton: the linear residual need only be small next to the aim and to the
    // quadratic error term; solving further costs solves without improving the accepted step.
    const double eta = std::max(0.5 * aim_, std::min(1e-3 * r, 0.1 * r * r));
    s_.rhs = -s_.cur.defect.head(n_);
    const int cg = detail::preconditioned_cg(*s_.factor, s_.hessian.data(), s_.rhs, eta, detail::kMaxCgIterations,
                                             s_.step, s_.pcg);
    s_.policy.chord_attempt(cg);
    last_cg_ = cg;
    evaluate_trial(1.0, false);
    if (!trial_halves_residual()) return false;
    accept_trial();
    ++rep_.chord_steps;
    if (s_.policy.chord_accepted(cg)) {  // refresh the aging factor for the solves to come
      s_.factorize_with_shift();
      s_.policy.refactorised();
      ++rep_.factorizations;
    }
    keep = s_.policy.prefer_chord(s_.cur.residual, aim_, s_.cur.residual / r);
    return true;
  }

  // Below the tolerance: a full Newton step with a fresh factorisation, kept only if it halves the
  // residual (no line search: the iterate is already acceptable). Returns whether it was kept.
  bool refining_newton_step() {
    fresh_factorization();
    descent_direction();
    evaluate_trial(1.0, false);
    if (!trial_halves_residual()) return false;
    accept_trial();
    return true;
  }

  // Factorises the Hessian at u (for this step and chord steps after it).
  void fresh_factorization() {
    ensure_hessian();
    s_.factorize_with_shift();
    s_.policy.refactorised();
    s_.factor_reusable = true;
    ++rep_.factorizations;
  }

  bool trial_halves_residual() const {
    return std::isfinite(s_.trial.residual) && s_.trial.residual <= 0.5 * s_.cur.residual;
  }

  // A Newton step with a fresh factorisation at u and a line search; returns whether chord steps
  // with the new factor should follow.
  bool newton_step() {
    fresh_factorization();
    const double r = s_.cur.residual, slope = descent_direction();
    const double step = line_search(slope);
    if (step == 1.0) s_.policy.full_newton_step(r, s_.trial.residual);
    accept_trial();
    // Chord steps with this factor contract about as much as this Newton step did.
    return opt_.reuse_factorization && step == 1.0 && s_.cur.residual > aim_ &&
           s_.policy.prefer_chord(s_.cur.residual, aim_, s_.cur.residual / r);
  }

  // The Newton direction into s_.step (capped), or steepest descent where the Hessian is
  // numerically singular; returns the directional derivative (< 0).
  double descent_direction() {
    Eigen::VectorXd& d = s_.step;
    const auto g = s_.cur.defect.head(n_);
    d = -g;
    s_.factor->solve(d.data(), d.data());
    // Far from the solution, faces broken to (pi, 0, 0) make the energy piecewise linear and the
    // Hessian nearly singular: cap the change of the log-scale factors (e^4 ~ 55x a length).
    detail::cap_newton_step(d);
    const double slope = g.dot(d);
    if (slope < 0) return slope;
    d = -g * (detail::kMaxNewtonStep / std::max(g.cwiseAbs().maxCoeff(), 1e-300));
    return g.dot(d);
  }

  // Halves the step until it halves the residual (the quadratic phase, no energy needed) or
  // decreases the energy enough (Armijo); returns the accepted fraction, left evaluated in trial.
  double line_search(double slope) {
    for (double s = 1.0;; s *= 0.5) {
      evaluate_trial(s, false);
      bool accept = trial_halves_residual();
      if (!accept && std::isfinite(s_.trial.residual)) {
        if (!s_.cur.has_energy) s_.evaluate(l2_, u_, true, false, s_.cur);
        evaluate_trial(s, true);
        const double roundoff = 1e-13 * (std::abs(s_.cur.energy) + 1.0);
        accept = s_.trial.energy <= s_.cur.energy + 1e-4 * s * slope ||
                 (std::abs(slope) * s < roundoff && s_.trial.residual < s_.cur.residual);
      }
      if (accept) return s;
      ++rep_.line_search_steps;
      if (s * 0.5 < 1e-12) stop_.fail(" line search failed", s_.cur.residual);
    }
  }

  void ensure_hessian() {
    if (!s_.hessian_at_cur) s_.evaluator.assemble_hessian(s_.cur, s_.hessian.data());
    s_.hessian_at_cur = true;
    s_.hessian_drift = 0;
  }

  // trial_u = u + fraction * step at every vertex with an unknown, evaluated into trial.
  void evaluate_trial(double fraction, bool want_energy) {
    const std::vector<int>& index = s_.plan.pattern.index;
    for (int v : s_.plan.moved) s_.trial_u[v] = u_[v] + fraction * s_.step[index[v]];
    fraction_ = fraction;
    s_.evaluate(l2_, s_.trial_u, want_energy, false, s_.trial);
  }

  void accept_trial() {
    u_.swap(s_.trial_u);
    std::swap(s_.cur, s_.trial);  // trial_u keeps the old u: fixed entries alike, moved ones rewritten
    s_.hessian_at_cur = false;
    s_.hessian_drift += fraction_ * s_.step.cwiseAbs().maxCoeff();
    rep_.max_broken_triangles = std::max(rep_.max_broken_triangles, s_.cur.broken);
  }

  Flattener::State& s_;
  const Eigen::VectorXd& l2_;
  Eigen::VectorXd& u_;
  const FlattenOptions& opt_;
  const int n_;
  const detail::RefiningStop stop_{opt_, "flattening"};
  const double aim_ = stop_.aim();  // where the steps stop
  FlattenReport rep_;
  int last_cg_ = 0;  // CG iterations of the last chord step
  double fraction_ = 0;  // of the step, in trial
};

}  // namespace

FlattenReport Flattener::solve(const Eigen::VectorXd& l2, Eigen::VectorXd& u, const FlattenOptions& options) {
  validate(options);
  const Mesh& m = plan_->mesh;
  if (l2.size() != m.num_edges()) {
    std::ostringstream s;
    s << "flatten: l2 has " << l2.size() << " entries for " << m.num_edges() << " edges";
    throw InvalidInput(s.str());
  }
  bool valid = true;  // one branch-free pass; the loop below names the edge
  for (Eigen::Index e = 0; e < l2.size(); ++e) valid &= l2[e] > 0 && l2[e] <= DBL_MAX;
  for (int e = 0; !valid && e < l2.size(); ++e) {
    if (!(l2[e] > 0) || !std::isfinite(l2[e])) {
      std::ostringstream s;
      s << "flatten: squared length " << l2[e] << " of edge " << e << " (vertices " << m.edges()(e, 0) << ", "
        << m.edges()(e, 1) << ") is not positive and finite";
      throw InvalidInput(s.str());
    }
  }
  if (u.size() != m.num_vertices()) u = Eigen::VectorXd::Zero(m.num_vertices());
  for (int v = 0; v < m.num_vertices(); ++v)
    if (!is_interior(v) || !std::isfinite(u[v])) u[v] = 0.0;
  FlattenReport report = NewtonDriver(*state_, l2, u, options).run();
  report.convex_solves = 1;
  return report;
}

}  // namespace bdinterp
