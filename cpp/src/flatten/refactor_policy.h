// Internal: when the flattening refactorises the Hessian and when it reuses an earlier factor
// (chord steps: Newton steps solved by conjugate gradients preconditioned with the old factor).
// Decisions use operation counts, not timings, so a solve takes the same path on every machine and
// every run.
#pragma once

namespace bdinterp::detail {

// Expected cost of reaching `tol` from residual r with steps contracting by `rate` each, costing
// `step_cost` each; infinite for rate >= 0.5 (not worth chording).
double chord_cost(double r, double tol, double rate, double step_cost);

// Expected cost with Newton steps r <- min(c r^2, r / 2) (each `newton_step_cost`), where the steps
// after one may instead be chord steps with the factor it leaves (contracting by about c r) when
// that is cheaper.
double newton_cost(double r, double tol, double c, double newton_step_cost, double step_cost);

class RefactorPolicy {
 public:
  // CG iterations after the chord step that a factor of a neighbouring frame typically needs.
  static constexpr int kFreshIterations = 1;

  // Costs in flops: a numeric factorisation, one solve with the factor, one product with the
  // Hessian, one evaluation of the angle sums.
  RefactorPolicy(double factor, double solve, double multiply, double evaluation)
      : factor_(factor), solve_(solve), multiply_(multiply), evaluation_(evaluation) {}

  // A full Newton step (fresh factor, no halving) took the residual from r_old to r_new: it
  // calibrates the quadratic model r_new = c r_old^2.
  void full_newton_step(double r_old, double r_new);
  // A chord step solved with `cg_iterations` CG iterations (accepted or not): its cost is the
  // estimate for the next ones.
  void chord_attempt(int cg_iterations);
  // An accepted chord step. Ski rental across solves: an aging factor needs more CG iterations
  // than a fresh one would; returns true once those extra iterations have cost as much as a
  // factorisation (then refactorise: never worse than twice the better of always and never
  // refactorising).
  bool chord_accepted(int cg_iterations);
  // A fresh factorisation was made: the ski rental starts again.
  void refactorised() { stale_ = 0; }
  // At residual r after a step that contracted by `rate`: is chording on expected to reach `tol`
  // more cheaply than a fresh Newton step?
  bool prefer_chord(double r, double tol, double rate) const;
  double newton_constant() const { return newton_c_; }

 private:
  double step_cost() const { return chord_cost_ > 0 ? chord_cost_ : solve_ + evaluation_; }

  double factor_, solve_, multiply_, evaluation_;
  double newton_c_ = 1.0;  // last observed r_new / r_old^2 of a full Newton step
  double chord_cost_ = 0;  // cost of the last chord step (0: none yet)
  double stale_ = 0;       // flops spent on CG iterations a fresh factor would not need
};

}  // namespace bdinterp::detail
