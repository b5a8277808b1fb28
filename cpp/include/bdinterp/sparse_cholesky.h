// CHOLMOD behind a small class: the symbolic analysis is done once per sparsity pattern, the numeric
// factorisation and the solves are repeated without allocating.
#pragma once

#include <memory>
#include <vector>

#include "bdinterp/types.h"

namespace bdinterp {

class SparseCholesky {
 public:
  // n: matrix size. col_ptr (n+1) and row_idx: the LOWER triangle of a symmetric matrix in compressed
  // column form, rows sorted within each column, diagonal included. Runs the symbolic analysis.
  SparseCholesky(int n, const std::vector<int>& col_ptr, const std::vector<int>& row_idx);
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  // An independent solver sharing nothing with this one (for use on another thread); copies the
  // symbolic analysis and, if present, the numeric factor.
  SparseCholesky clone() const;

  int size() const;
  // Operation counts from the symbolic analysis: a numeric factorisation, and one solve (4 nnz(L)).
  // Deterministic cost estimates for choosing between refactorising and reusing a factor.
  double factor_flops() const;
  double solve_flops() const;
  // The numeric values, in the order of row_idx; write them, then call factorize().
  double* values();
  const double* values() const;
  // The pattern given to the constructor (n + 1 column pointers, row indices).
  const int* column_pointers() const;
  const int* row_indices() const;
  // Numeric factorisation of the current values. Throws SolverError if the matrix is not positive
  // definite (naming the failing column) or CHOLMOD reports an error.
  void factorize();
  // y = A x for the symmetric matrix whose lower triangle, in the order of the pattern, is
  // `values` (not necessarily the factorised one). Loops over both cores for large patterns.
  void multiply(const double* values, const double* x, double* y) const;
  // Solves A X = B for ncols right-hand sides stored column after column (n*ncols doubles). x may alias b.
  void solve(const double* b, double* x, int ncols = 1);

 private:
  struct Impl;
  explicit SparseCholesky(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace bdinterp
