// Internal: the loop control of the flattening's Newton solve (flatten_newton.cpp): the step cap,
// and the refinement below the tolerance that makes frames independent of the previous frame's
// start.
#pragma once

#include <Eigen/Core>
#include <sstream>
#include <string>
#include <utility>

#include "flatten/flatten.h"
#include "bdinterp/types.h"

namespace bdinterp::detail {

constexpr double kMaxNewtonStep = 4.0;  // largest change of any u_i in one Newton step (e^4 ~ 55x a length)

// Scales d down so that no entry exceeds kMaxNewtonStep in magnitude (d non-empty).
inline void cap_newton_step(Eigen::VectorXd& d) {
  const double longest = d.cwiseAbs().maxCoeff();
  if (longest > kMaxNewtonStep) d *= kMaxNewtonStep / longest;
}

// The stopping rule: steps go on while the residual is above the aim, tolerance * refinement.
// Below the tolerance the solve only refines: it ends without error at the step limit (and, the
// caller's part, at the first step that does not halve the residual: roundoff). At the step limit
// above the tolerance it throws SolverError.
class RefiningStop {
 public:
  // `what` names the solve in the error ("flattening ...").
  RefiningStop(const FlattenOptions& options, std::string what) : opt_(options), what_(std::move(what)) {}

  double aim() const { return aim_; }
  bool refining(double residual) const { return residual <= opt_.tolerance; }

  // Whether to take another step at `residual` after `steps` steps; throws SolverError when the
  // step limit is reached above the tolerance.
  bool another(double residual, int steps) const {
    if (!(residual > aim_)) return false;
    if (steps < opt_.max_iterations) return true;
    if (refining(residual)) return false;
    fail(" did not converge in " + std::to_string(opt_.max_iterations) + " Newton steps", residual);
  }

  // Throws SolverError(what + detail + " (residual r > tolerance t)").
  [[noreturn]] void fail(const std::string& detail, double residual) const {
    std::ostringstream s;
    s << what_ << detail << " (residual " << residual << " > tolerance " << opt_.tolerance << ")";
    throw SolverError(s.str());
  }

 private:
  const FlattenOptions& opt_;
  const std::string what_;
  const double aim_ = opt_.tolerance * opt_.refinement;
};

}  // namespace bdinterp::detail
