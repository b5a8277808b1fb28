// The convex solve of a piece with holes at fixed dipoles (holes.h): Newton with chord steps on the
// last factorisation, an Armijo line search, and the refinement below the tolerance that makes
// frames independent of the previous frame's start (issue #11; as flatten_newton.cpp for disks).
#include <algorithm>
#include <cmath>
#include <limits>

#include "bdinterp/holes.h"
#include "bdinterp/sparse_cholesky.h"
#include "detail/refining.h"

namespace bdinterp {
namespace {
// Chord steps (the last factorisation) are tried below this residual: at 14.7k vertices they cut
// the factorisations of an 11-frame sweep through a Moebius pair from 88 to 8.
constexpr double kChordResidual = 1e-2;
// The energy (Lobachevsky's function per corner: most of an evaluation's cost) is computed only
// when a line search needs it; NaN marks it unknown.
constexpr double kUnknownEnergy = std::numeric_limits<double>::quiet_NaN();
}  // namespace

// Armijo on the convex energy from u along step (residual r0 at u); a step that halves the residual
// is taken without the energy test. Below the tolerance (refining) only the full step is tried:
// false when it does not halve the residual, with grad_ and broken restored to u's.
bool HoleSolver::line_search(const Eigen::VectorXd& l2, const Eigen::VectorXd& u, const Eigen::VectorXd& step,
                             double r0, bool refining, double& energy, Eigen::VectorXd& trial, int& broken,
                             FlattenReport& fr) const {
  const int nv = mesh_->num_vertices();
  auto residual = [&] { return grad_.cwiseAbs().maxCoeff(); };
  const double slope = grad_.dot(step);
  const Eigen::VectorXd g0 = grad_;
  for (double s = 1.0;; s *= 0.5) {
    if (s < 1e-12) throw SolverError("flattening (piece with holes): line search failed");
    for (int v = 0; v < nv; ++v) trial[v] = unknown_[v] < 0 ? 0.0 : u[v] + s * step[unknown_[v]];
    evaluate(l2, trial, false, true, &broken);
    if (residual() <= 0.5 * r0) {
      energy = kUnknownEnergy;
      return true;
    }
    if (refining) {
      evaluate(l2, u, false, false, &broken);
      return false;
    }
    if (std::isnan(energy)) {
      const Eigen::VectorXd g = grad_;
      energy = evaluate(l2, u, true, false, &broken);
      grad_ = g;
    }
    const double e = evaluate(l2, trial, true, true, &broken);
    if (std::isfinite(e) && (e <= energy + 1e-4 * s * slope ||
                             (std::abs(s * slope) < 1e-13 * (std::abs(energy) + 1) && residual() < r0))) {
      energy = e;
      return true;
    }
    ++fr.line_search_steps;
    grad_ = g0;
  }
}

void HoleSolver::newton(const Eigen::VectorXd& l2, Eigen::VectorXd& u, const FlattenOptions& options,
                        FlattenReport& fr) const {
  const int nv = mesh_->num_vertices();
  int broken = 0;
  auto residual = [&] { return n_ ? grad_.cwiseAbs().maxCoeff() : 0.0; };
  double energy = kUnknownEnergy;
  evaluate(l2, u, false, n_ > 0, &broken);
  fr.max_broken_triangles = std::max(fr.max_broken_triangles, broken);
  Eigen::VectorXd step(n_), trial(nv);
  // The stopping rule of the disk flattening (detail/refining.h); the roundoff floor is the first
  // full step that does not halve the residual (line_search returns false).
  const detail::RefiningStop stop(options, "flattening (piece with holes)");
  for (int steps = 0; stop.another(residual(), steps); ++steps) {
    const bool refining = stop.refining(residual());
    ++fr.iterations;
    const double r0 = residual();
    if (factored_ && r0 < kChordResidual) {
      // A chord step with the last factorisation (the dipoles' finite differences and the next
      // frame start next to it); kept only if it contracts the residual 4x (slower chords cost more
      // steps than a factorisation saves).
      step = -grad_;
      chol_->solve(step.data(), step.data());
      for (int v = 0; v < nv; ++v) trial[v] = unknown_[v] < 0 ? 0.0 : u[v] + step[unknown_[v]];
      const Eigen::VectorXd g0 = grad_;
      evaluate(l2, trial, false, true, &broken);
      if (residual() <= 0.25 * r0) {  // NaN fails
        energy = kUnknownEnergy;
        u.swap(trial);
        ++fr.chord_steps;
        fr.max_broken_triangles = std::max(fr.max_broken_triangles, broken);
        continue;
      }
      grad_ = g0;
      evaluate(l2, u, false, true, &broken);  // the Hessian at u again
    }
    std::copy(hvals_.begin(), hvals_.end(), chol_->values());
    chol_->factorize();
    factored_ = true;
    ++fr.factorizations;
    step = -grad_;
    chol_->solve(step.data(), step.data());
    detail::cap_newton_step(step);
    if (!line_search(l2, u, step, r0, refining, energy, trial, broken, fr)) break;  // roundoff floor
    u.swap(trial);
    fr.max_broken_triangles = std::max(fr.max_broken_triangles, broken);
  }
  fr.residual = residual();
  fr.broken_triangles = broken;
}

}  // namespace bdinterp
