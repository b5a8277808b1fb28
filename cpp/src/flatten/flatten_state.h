// Internal: a Flattener's workspace, shared by the public methods (flatten.cpp) and the Newton
// driver (flatten_newton.cpp).
#pragma once

#include <cmath>
#include <optional>
#include <vector>

#include "flatten/flatten.h"
#include "flatten_energy.h"
#include "pcg.h"
#include "refactor_policy.h"

namespace bdinterp {
namespace detail {
// Operation-count estimate of one evaluation of the angle sums per face (sqrt, exp, products).
constexpr double kFlopsPerFace = 150;
// CG iterations a chord step may take before a fresh factorisation is the better deal (also the
// bound of the holes' linear solves, holes_response.cpp).
constexpr int kMaxCgIterations = 12;
}  // namespace detail

// One thread's workspace: evaluations, the Hessian values, the numeric factor and the cost model.
struct Flattener::State {
  explicit State(const FlattenPlan& p)
      : plan(p),
        evaluator(p),
        hessian(p.nnz() + 1, 0.0),
        policy(fresh_policy(p)) {
    if (p.analysis) factor.emplace(p.analysis);
  }
  static detail::RefactorPolicy fresh_policy(const FlattenPlan& p) {
    const double eval = detail::kFlopsPerFace * p.mesh.num_faces();
    if (!p.analysis) return {0, 0, 0, eval};
    return {p.analysis->factor_flops(), p.analysis->solve_flops(), 4.0 * p.nnz(), eval};
  }
  // Factorises `hessian`; while that fails (faces degenerate to (pi, 0, 0) around a vertex make it
  // singular), adds a growing diagonal shift so the step stays a descent direction.
  void factorize_with_shift();
  void evaluate(const Eigen::VectorXd& l2, const Eigen::VectorXd& u, bool want_energy, bool want_hessian,
                detail::Evaluation& out) {
    evaluator.evaluate(l2, u, want_energy, want_hessian ? hessian.data() : nullptr, out);
  }

  const FlattenPlan& plan;
  detail::EnergyEvaluator evaluator;
  detail::Evaluation cur, trial;  // cur: at the iterate u of solve(); trial: a candidate
  std::vector<double> hessian;    // nnz + 1: the Hessian values PCG and the factorisation use
  bool hessian_at_cur = false;    // `hessian` is the Hessian at cur
  double hessian_drift = HUGE_VAL;  // max |u - u where `hessian` was assembled|, summed over cur's moves
  std::optional<SparseCholesky> factor;
  double shift = 0;               // diagonal shift of the factorisation in `factor`
  bool factor_reusable = false;   // `factor` holds a factorisation usable for chord steps
  detail::RefactorPolicy policy;
  detail::PcgScratch pcg;
  Eigen::VectorXd step, rhs, trial_u;
  // The holes' linear steps (holes_response.cpp): the defects after the offsets (#unknowns + 1), the move (#V).
  Eigen::VectorXd shifted, move;
};

}  // namespace bdinterp
