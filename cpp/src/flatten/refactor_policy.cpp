#include "flatten/refactor_policy.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bdinterp::detail {

double chord_cost(double r, double tol, double rate, double step_cost) {
  if (rate >= 0.5) return std::numeric_limits<double>::infinity();
  return std::ceil(std::log(tol / r) / std::log(rate)) * step_cost;
}

double newton_cost(double r, double tol, double c, double newton_step_cost, double step_cost) {
  double cost = 0;
  for (int k = 0; k < 8 && r > tol; ++k) {
    const double next = std::min(c * r * r, 0.5 * r);
    cost += newton_step_cost;
    if (next <= tol) return cost;
    const double rate = std::min(c * r, 0.5);
    const double chord = chord_cost(next, tol, rate, step_cost);
    if (chord < newton_step_cost) return cost + chord;
    r = next;
  }
  return cost;
}

void RefactorPolicy::full_newton_step(double r_old, double r_new) {
  if (r_old > 0) newton_c_ = r_new / (r_old * r_old);
}

void RefactorPolicy::chord_attempt(int cg_iterations) {
  chord_cost_ = (cg_iterations + 1) * (solve_ + multiply_) + evaluation_;
}

bool RefactorPolicy::chord_accepted(int cg_iterations) {
  stale_ += std::max(0, cg_iterations - kFreshIterations) * (solve_ + multiply_);
  return stale_ >= factor_;
}

bool RefactorPolicy::prefer_chord(double r, double tol, double rate) const {
  const double step = step_cost();
  return chord_cost(r, tol, rate, step) <= newton_cost(r, tol, newton_c_, factor_ + step, step);
}

}  // namespace bdinterp::detail
