// Internal: the triangular solves of a simplicial L L' factor split over the cores along its
// elimination tree. CHOLMOD's own solves are serial, and at 50k vertices they were about 40 % of a
// warm frame (three to four columns: the chord steps and the layout), the part the pool could not
// split. Columns in disjoint subtrees of the elimination tree do not touch each other in either
// pass: forward (L y = b), a column updates only its ancestors; backward (L' x = y), it reads only
// its ancestors. So each chunk ("bin") takes a few whole subtrees, and the few columns above them
// (the top separators of the nested dissection) are done on the calling thread: after the bins in
// the forward pass, before them in the backward one. The bins' updates of top rows go to buffers of
// their own, added in bin order: results depend on the number of bins, never on timing.
#pragma once

#include <vector>

namespace bdinterp::detail {

// A simplicial factor of P A P' = L L' as CHOLMOD stores it: column j's entries are
// i[p[j] .. p[j] + nz[j]), diagonal first; perm[k] = the row of A that is row k of P A P'.
struct FactorView {
  int n = 0;
  const int* p = nullptr;
  const int* i = nullptr;
  const int* nz = nullptr;
  const double* x = nullptr;
  const int* perm = nullptr;  // null: the identity
  const float* x_single = nullptr;  // x rounded to single precision (optional: solve's `single`)
};

class TreeSolve {
 public:
  static constexpr int kMaxColumns = 8;  // right-hand sides per solve

  // The split of `L`'s columns into up to `bins` chunks (from the pattern only; valid for every
  // numeric factorisation of the same analysis). bins() is 1 when the tree does not split well (a
  // chain: the critical path would keep more than 80 % of the work). usable() is false when the
  // factor is not postordered with diagonals first and rows sorted (callers then use CHOLMOD's solve).
  TreeSolve(const FactorView& L, int bins);

  bool usable() const { return usable_; }
  int bins() const { return static_cast<int>(bins_.size()); }
  // The share of nnz(L) done on the calling thread, and on the critical path (the top and the
  // heaviest bin; 1 / bins at best). Diagnostics, tests.
  double top_share() const { return top_share_; }
  double critical_share() const { return critical_share_; }

  // Solves A X = B for ncols right-hand sides stored column after column (n * ncols doubles) with
  // the numeric values of `L` (same pattern as at construction), ncols <= kMaxColumns. x may alias b.
  // single: with L.x_single instead of L.x (sums still in double): half the values' memory traffic,
  // for a preconditioner.
  void solve(const FactorView& L, const double* b, double* x, int ncols, bool single = false);

  struct Range {
    int first, last;  // columns first..last (a whole subtree: last is its root)
  };

 private:
  // One bin's or the top's share of each pass (solve_k's parts); K: ncols fixed at compile time
  // (0: ncols at run time). y: the permuted solution in progress, K columns interleaved.
  // T: the values' type (double: L.x, float: L.x_single).
  template <int K, class T>
  void forward(const FactorView& L, Range r, int ncols, double* y, double* buf) const;
  template <int K, class T>
  void backward(const FactorView& L, Range r, int ncols, double* y) const;
  template <int K, class T>
  void solve_k(const FactorView& L, const double* b, double* x, int ncols);

  bool usable_ = false;
  int n_ = 0, ntop_ = 0;
  std::vector<std::vector<Range>> bins_;  // each bin's subtrees
  std::vector<int> top_;                  // the other columns, ascending
  std::vector<Range> top_runs_;           // ... as runs of consecutive columns
  std::vector<int> top_index_;            // n: position in top_, or -1
  std::vector<int> inside_;    // n: rows below the diagonal updated directly (not via buf_)
  std::vector<char> chain_;    // n: column j+1's rows are column j's without its first two
  double top_share_ = 0, critical_share_ = 1;
  std::vector<double> y_;                 // n * ncols
  std::vector<std::vector<double>> buf_;  // per bin: its updates of the top rows (ntop * ncols)
};

}  // namespace bdinterp::detail
