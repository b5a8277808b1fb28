// Internal: conjugate gradients preconditioned with a Cholesky factorisation of a nearby matrix.
#pragma once

#include <Eigen/Core>

#include "linalg/sparse_cholesky.h"

namespace bdinterp::detail {

struct PcgScratch {
  Eigen::VectorXd r, z, p;  // H p shares z's storage (never both alive)
};

// Solves A x = b (n = M.size()) for the SPD matrix A whose lower triangle, in M's pattern order, is
// `A_values`, preconditioned with M's factorisation (SparseCholesky::precondition: its values in
// single precision where that pays). Starts from the chord step x = M^-1 b and stops
// when max |b - A x| <= eta, or after max_iterations iterations, or when A stops being positive
// definite along a search direction. Returns the iterations after the chord step (max_iterations + 1
// if exhausted).
int preconditioned_cg(SparseCholesky& M, const double* A_values, const Eigen::VectorXd& b, double eta,
                      int max_iterations, Eigen::VectorXd& x, PcgScratch& scratch);

}  // namespace bdinterp::detail
