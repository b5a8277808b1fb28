// The options and the report of step 2 (flatten.h, private): what Interpolator users set and read.
#pragma once

#include "bdinterp/types.h"

namespace bdinterp {

struct FlattenOptions {
  double tolerance = 1e-10;  // must reach max |2pi - angle sum| over interior vertices <= tolerance
  // Then refine towards tolerance * refinement, as far as steps halve the residual (no error if
  // they stop doing so first: roundoff). Why: positions move by up to ~2e-10 of the size per 1e-10
  // of residual (5k vertices), so solves that stop anywhere below 1e-10 differ by that much
  // depending on where they started (the previous frame); refined, frames after any history agree
  // to ~1e-13 of the size. Costs 9-13 % more instructions per frame (docs/robustness.md). 1: stop at
  // the tolerance.
  double refinement = 1e-3;
  int max_iterations = 50;   // Newton steps before giving up with SolverError
  // Allow chord steps: Newton steps with the factorisation of an earlier iterate (of this solve or of
  // the previous solve on this Flattener) instead of a new one, while they contract fast enough.
  // Every step, chord or not, is accepted only if it reduces the residual; the tolerance is the same.
  bool reuse_factorization = true;
};

// Throws InvalidInput naming the field unless tolerance >= 0 (finite), refinement is in [0, 1] and
// max_iterations >= 0.
void validate(const FlattenOptions& options);

struct FlattenReport {
  // Newton steps of one convex solve; a piece with holes solves several (convex_solves), and
  // reports the most any one took, as merge() does over pieces and frames.
  int iterations = 0;
  double residual = 0;           // final max |2pi - angle sum| (radians)
  int broken_triangles = 0;      // faces violating the triangle inequality in the final metric
  int max_broken_triangles = 0;  // the most seen at any Newton iterate
  int line_search_steps = 0;     // step halvings over all iterations
  int factorizations = 0;        // numeric factorisations (Newton steps with a fresh Hessian)
  int chord_steps = 0;           // steps that reused an earlier factorisation (also in iterations)
  int convex_solves = 0;         // convex solves (Newton runs): 1 a disk, more to close holes' periods
};

// Reports of several solves (pieces of a frame, frames of a sequence) combined by one rule: the
// worst of each state measure (iterations, residual, broken_triangles, max_broken_triangles: the
// most in any one solve), the sum of the work (line_search_steps, factorizations, chord_steps,
// convex_solves).
void merge(FlattenReport& into, const FlattenReport& other);

}  // namespace bdinterp
