// CHOLMOD behind two small classes: the symbolic analysis of a sparsity pattern, done once and then
// read-only (shared by every thread), and a numeric factorisation with its solve workspaces (one per
// thread), repeated without allocating. Every CHOLMOD setting is made in one function
// (sparse_cholesky.cpp), so every factorisation of a pattern is computed the same way.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "bdinterp/types.h"

namespace bdinterp {
namespace detail {
class TreeSolve;
}

// The fill-reducing ordering and symbolic factor of one symmetric pattern. Immutable after
// construction; any number of SparseCholesky objects on any threads may share it.
class CholeskyAnalysis {
 public:
  // n: matrix size. col_ptr (n+1) and row_idx: the LOWER triangle of a symmetric matrix in compressed
  // column form, rows sorted within each column, diagonal included. Throws InvalidInput for an
  // inconsistent pattern, SolverError if CHOLMOD fails.
  CholeskyAnalysis(int n, std::vector<int> col_ptr, std::vector<int> row_idx);
  ~CholeskyAnalysis();
  CholeskyAnalysis(const CholeskyAnalysis&) = delete;
  CholeskyAnalysis& operator=(const CholeskyAnalysis&) = delete;

  int size() const { return static_cast<int>(col_ptr_.size()) - 1; }
  const std::vector<int>& column_pointers() const { return col_ptr_; }
  const std::vector<int>& row_indices() const { return rows_; }
  // Operation counts: a numeric factorisation, and one solve (4 nnz(L)). Deterministic cost
  // estimates for choosing between refactorising and reusing a factor.
  double factor_flops() const { return factor_flops_; }
  double solve_flops() const { return solve_flops_; }

 private:
  friend class SparseCholesky;
  struct Impl;
  std::vector<int> col_ptr_, rows_;
  double factor_flops_ = 0, solve_flops_ = 0;
  std::unique_ptr<Impl> impl_;
};

class SparseCholesky {
 public:
  // A numeric factorisation over `analysis`'s pattern (values zero until written).
  explicit SparseCholesky(std::shared_ptr<const CholeskyAnalysis> analysis);
  // The same with an analysis of its own (see CholeskyAnalysis for the arguments).
  SparseCholesky(int n, const std::vector<int>& col_ptr, const std::vector<int>& row_idx);
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  const CholeskyAnalysis& analysis() const { return *analysis_; }
  int size() const { return analysis_->size(); }
  double factor_flops() const { return analysis_->factor_flops(); }
  double solve_flops() const { return analysis_->solve_flops(); }
  // The numeric values, in the order of row_idx; write them, then call factorize().
  double* values();
  const double* values() const;
  // The pattern (n + 1 column pointers, row indices).
  const int* column_pointers() const { return analysis_->column_pointers().data(); }
  const int* row_indices() const { return analysis_->row_indices().data(); }
  // Numeric factorisation of the current values (supernodal on dense enough factors, then kept as
  // a simplicial L L' for the solves). Throws SolverError if the matrix is not positive definite
  // (naming the failing column) or CHOLMOD reports an error; the factor is then invalid.
  void factorize();
  // A valid factorisation is at hand (factorize() succeeded since the last failure).
  bool factored() const;
  // The factor is stored as L L' (not L D L'), as configured for speed (for tests).
  bool factor_is_ll() const;
  // y = A x for the symmetric matrix whose lower triangle, in the order of the pattern, is
  // `values` (not necessarily the factorised one). Loops over both cores for large patterns.
  void multiply(const double* values, const double* x, double* y) const;
  // Solves A X = B for ncols right-hand sides stored column after column (n*ncols doubles). x may
  // alias b. Throws SolverError without a valid factorisation. Split over the cores for simplicial
  // factors from ~1k rows (the elimination tree's subtrees in parallel, see
  // src/detail/tree_solve.h); serial solves are CHOLMOD's (1.0-1.1x faster than the split code
  // run on one thread, 48k rows).
  void solve(const double* b, double* x, int ncols = 1);
  // solve() with the factor's values rounded to single precision (the sums in double): a
  // preconditioner's solve, reading half the bytes of values where the solve splits over the cores
  // (their copy made on the first such call after each factorisation); elsewhere solve() itself.
  void solve_single(const double* b, double* x);
  // Whether solve_single() is worth it for a preconditioner: nnz(L) of 3M or more (24 MB of
  // values), where the solves wait on memory. Measured: a 100k-vertex pose grid (nnz(L) 4.0M)
  // 8 % faster a warm update; 50k-vertex warm frames (1.9M) 5 % slower, their values read from
  // the caches.
  bool single_pays() const { return solve_flops() >= 4.0 * 3e6; }
  // A preconditioner's solve: solve_single() where it pays, else solve().
  void precondition(const double* b, double* x) {
    if (single_pays()) solve_single(b, x);
    else solve(b, x);
  }
  // How solve() splits when `chunks` are allowed: the chunks used (1: serial), the share of nnz(L)
  // left to the calling thread (the separators above the subtrees), and the share on the critical
  // path (those plus the heaviest chunk; 1 / chunks at best). Diagnostics and tests.
  struct SolveSplit {
    int chunks = 1;
    double serial_share = 1.0, critical_share = 1.0;
  };
  SolveSplit solve_split(int chunks);

 private:
  detail::TreeSolve* tree_solve(int chunks);  // the split for `chunks`, or null: serial
  detail::TreeSolve* solve_plan();            // tree_solve() for the chunks a solve may use now
  struct Impl;
  std::shared_ptr<const CholeskyAnalysis> analysis_;
  std::unique_ptr<Impl> impl_;
};

// The lower triangle of the sparsity pattern of a symmetric n-by-n matrix in compressed columns, as
// CholeskyAnalysis takes it: every diagonal entry and the given off-diagonal pairs, rows sorted
// within each column, diagonal first.
struct SymmetricPattern {
  std::vector<int> col_ptr;  // n + 1
  std::vector<int> rows;     // one per entry
  // pairs: (i, j) in [0, n) in either order; repeats and pairs on the diagonal add nothing. Throws
  // InvalidInput for n < 0 or an index outside [0, n).
  SymmetricPattern(int n, std::vector<std::pair<int, int>> pairs);
  int size() const { return static_cast<int>(col_ptr.size()) - 1; }
  // The position in `rows` of entry (i, j), either order; -1 if the pattern lacks it.
  int position(int i, int j) const;
};

// One entry (row, col, value) of a symmetric matrix given by both triangles.
struct SymmetricEntry {
  int row, col;
  double value;
};

// The symmetric positive definite n-by-n matrix of `entries`, factorised over an analysis of its
// own: the entries on and below the diagonal (row >= col) are summed in their order, those above are
// skipped (their mirror images carry them). Throws InvalidInput for n < 1 or an index outside
// [0, n), SolverError if the matrix is not positive definite.
std::unique_ptr<SparseCholesky> factorise(int n, const std::vector<SymmetricEntry>& entries);

}  // namespace bdinterp
