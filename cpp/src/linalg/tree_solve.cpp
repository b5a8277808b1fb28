#include "linalg/tree_solve.h"

#include <algorithm>
#include <numeric>

#include "parallel/parallel.h"

namespace bdinterp::detail {
namespace {
// Split only when the work on the critical path (the top plus the heaviest bin) is at most this
// share of nnz(L): below, the buffers and fork/joins would eat the gain.
constexpr double kWorthSplitting = 0.8;
constexpr size_t kMaxRootsPerBin = 64;

struct Tree {
  std::vector<int> parent, first, head, next;  // first: the subtree's smallest column
  std::vector<double> work;                    // nnz(L) of the subtree
};

// The elimination tree from the factor's pattern (parent = the smallest row below the diagonal),
// or an empty tree when the pattern is not as CHOLMOD documents it (diagonal first, rows sorted)
// or not postordered (every subtree a contiguous range of columns ending at its root).
Tree elimination_tree(const FactorView& L) {
  const int n = L.n;
  Tree t{std::vector<int>(n, -1), std::vector<int>(n), std::vector<int>(n, -1), std::vector<int>(n, -1),
         std::vector<double>(n)};
  std::vector<int> count(n, 1);
  std::iota(t.first.begin(), t.first.end(), 0);
  for (int j = 0; j < n; ++j) {  // children come before their parents
    const int p0 = L.p[j], p1 = p0 + L.nz[j];
    if (L.nz[j] < 1 || L.i[p0] != j) return {};
    for (int q = p0 + 1; q < p1; ++q) {  // rows sorted, below the diagonal
      if (L.i[q] <= L.i[q - 1] || L.i[q] >= n) return {};
    }
    t.work[j] += L.nz[j];
    if (L.nz[j] == 1) continue;  // a root
    const int parent = L.i[p0 + 1];
    t.parent[j] = parent;
    t.work[parent] += t.work[j];
    count[parent] += count[j];
    t.first[parent] = std::min(t.first[parent], t.first[j]);
    t.next[j] = t.head[parent];
    t.head[parent] = j;
  }
  for (int j = 0; j < n; ++j) {
    if (t.first[j] != j - count[j] + 1) return {};
  }
  return t;
}

// Greedy longest-first assignment of `roots` (by subtree work) to `bins` bins, into `out`;
// returns the heaviest bin's work.
double assign(const Tree& t, std::vector<int> roots, int bins, std::vector<std::vector<int>>& out) {
  std::sort(roots.begin(), roots.end(), [&](int a, int b) { return t.work[a] > t.work[b] || (t.work[a] == t.work[b] && a < b); });
  std::vector<double> load(bins, 0.0);
  out.assign(bins, {});
  for (int r : roots) {
    const int b = static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin());
    load[b] += t.work[r];
    out[b].push_back(r);
  }
  return *std::max_element(load.begin(), load.end());
}

struct Split {
  std::vector<std::vector<int>> bins;  // subtree roots per bin
  std::vector<int> top;                // the columns above them
  double top_work = 0, critical = 0;   // nnz(L) of the top, and of the top plus the heaviest bin
};

// Geist and Ng's split: replace the heaviest subtree by its children (its root joins the top),
// again and again; keep the split with the least work on the critical path.
Split best_split(const Tree& t, const FactorView& L, int bins) {
  std::vector<int> roots;
  for (int j = 0; j < L.n; ++j) {
    if (t.parent[j] < 0) roots.push_back(j);
  }
  Split serial, now;
  serial.critical = assign(t, roots, 1, serial.bins);  // every tree whole
  const double total = serial.critical;
  Split best = serial;
  // Until even perfectly balanced bins could not beat the best split (or be worth splitting), or
  // the subtrees are so many that longest-first balances them anyway (this bounds the work).
  while (bins > 1 && !roots.empty() && roots.size() <= kMaxRootsPerBin * static_cast<size_t>(bins) &&
         now.top_work + (total - now.top_work) / bins < std::min(best.critical, kWorthSplitting * total)) {
    now.critical = now.top_work + assign(t, roots, bins, now.bins);
    if (now.critical < best.critical) best = now;
    const auto heaviest = std::max_element(roots.begin(), roots.end(), [&](int a, int b) { return t.work[a] < t.work[b]; });
    const int r = *heaviest;
    roots.erase(heaviest);
    now.top.push_back(r);
    now.top_work += L.nz[r];
    for (int c = t.head[r]; c >= 0; c = t.next[c]) roots.push_back(c);
  }
  return best.critical <= kWorthSplitting * total ? best : serial;
}

}  // namespace

TreeSolve::TreeSolve(const FactorView& L, int bins) : n_(L.n), top_index_(L.n, -1) {
  const Tree t = elimination_tree(L);
  if (t.parent.empty()) return;
  usable_ = true;
  Split split = best_split(t, L, bins);
  inside_.assign(n_, 0);
  for (std::vector<int>& bin : split.bins) {
    if (bin.empty()) continue;  // fewer subtrees than bins
    std::sort(bin.begin(), bin.end());
    bins_.emplace_back();
    for (int r : bin) {
      bins_.back().push_back({t.first[r], r});
      for (int j = t.first[r]; j <= r; ++j) {
        const int* rows = L.i + L.p[j];
        inside_[j] = static_cast<int>(std::upper_bound(rows + 1, rows + L.nz[j], r) - rows - 1);
      }
    }
  }
  std::sort(split.top.begin(), split.top.end());
  for (size_t k = 0; k < split.top.size(); ++k) {
    const int j = split.top[k];
    top_index_[j] = static_cast<int>(k);
    inside_[j] = L.nz[j] - 1;  // a top column's rows are all in the top
    if (k == 0 || split.top[k - 1] != j - 1) top_runs_.push_back({j, j});
    top_runs_.back().last = j;
  }
  top_ = split.top;
  ntop_ = static_cast<int>(top_.size());
  chain_.assign(n_, 0);
  for (int j = 0; j + 1 < n_; ++j) {  // column j+1's rows are column j's after its first two
    const int* rows = L.i + L.p[j];
    chain_[j] = L.nz[j] >= 2 && rows[1] == j + 1 && L.nz[j + 1] == L.nz[j] - 1 &&
                std::equal(rows + 2, rows + L.nz[j], L.i + L.p[j + 1] + 1);
  }
  double total = 0;
  for (int j = 0; j < n_; ++j) total += L.nz[j];
  top_share_ = split.top_work / total;
  critical_share_ = split.critical / total;
  buf_.resize(bins_.size());
}

namespace {
constexpr int kMax = TreeSolve::kMaxColumns;

// y (K right-hand sides interleaved: y[j * K + c]) on columns r of P A P' from b (column after
// column: b[c * n + i]), and back.
void gather(const FactorView& L, const double* b, TreeSolve::Range r, int k, double* y) {
  for (int j = r.first; j <= r.last; ++j) {
    const int i = L.perm ? L.perm[j] : j;
    for (int c = 0; c < k; ++c) y[j * k + c] = b[static_cast<long>(c) * L.n + i];
  }
}

// The factor's values of type T.
template <class T>
const T* values(const FactorView& L);
template <>
const double* values<double>(const FactorView& L) { return L.x; }
template <>
const float* values<float>(const FactorView& L) { return L.x_single; }

void scatter(const FactorView& L, const double* y, TreeSolve::Range r, int k, double* x) {
  for (int j = r.first; j <= r.last; ++j) {
    const int i = L.perm ? L.perm[j] : j;
    for (int c = 0; c < k; ++c) x[static_cast<long>(c) * L.n + i] = y[j * k + c];
  }
}
}  // namespace

// Forward substitution over the columns of r: each divides by its diagonal and updates the rows
// below it, the first inside_[j] directly, the rest (the top's rows) in `buf`. Two columns with one
// pattern (chain_, as in the separators' dense blocks) go together, so each row they update is
// read and written once for both, as in CHOLMOD's own simplicial solves (docs/BENCHMARKS.md).
template <int K, class T>
void TreeSolve::forward(const FactorView& L, Range r, int nc, double* y, double* buf) const {
  const int k = K > 0 ? K : nc;
  const T* x = values<T>(L);
  double u[kMax], v[kMax];
  for (int j = r.first; j <= r.last;) {
    const int* rows = L.i + L.p[j];
    const T* x0 = x + L.p[j];
    const int in = inside_[j], nz = L.nz[j];
    if (j < r.last && chain_[j]) {  // columns j and j+1; column j+1's q-1 is column j's q
      const T* x1 = x + L.p[j + 1];
      for (int c = 0; c < k; ++c) {
        u[c] = y[j * k + c] /= x0[0];
        v[c] = y[(j + 1) * k + c] = (y[(j + 1) * k + c] - x0[1] * u[c]) / x1[0];
      }
      for (int q = 2; q <= in; ++q) {
        for (int c = 0; c < k; ++c) y[rows[q] * k + c] -= x0[q] * u[c] + x1[q - 1] * v[c];
      }
      for (int q = in + 1; q < nz; ++q) {
        for (int c = 0; c < k; ++c) buf[c * ntop_ + top_index_[rows[q]]] -= x0[q] * u[c] + x1[q - 1] * v[c];
      }
      j += 2;
      continue;
    }
    for (int c = 0; c < k; ++c) u[c] = y[j * k + c] /= x0[0];
    for (int q = 1; q <= in; ++q) {
      for (int c = 0; c < k; ++c) y[rows[q] * k + c] -= x0[q] * u[c];
    }
    for (int q = in + 1; q < nz; ++q) {
      for (int c = 0; c < k; ++c) buf[c * ntop_ + top_index_[rows[q]]] -= x0[q] * u[c];
    }
    ++j;
  }
}

// Backward substitution over the columns of r, last first (rows above r are solved already).
template <int K, class T>
void TreeSolve::backward(const FactorView& L, Range r, int nc, double* y) const {
  const int k = K > 0 ? K : nc;
  const T* x = values<T>(L);
  double s[kMax], t[kMax];
  for (int j = r.last; j >= r.first;) {
    if (j > r.first && chain_[j - 1]) {  // columns j-1 and j together
      const int* rows = L.i + L.p[j - 1];
      const T *x0 = x + L.p[j - 1], *x1 = x + L.p[j];
      for (int c = 0; c < k; ++c) {
        s[c] = y[(j - 1) * k + c];
        t[c] = y[j * k + c];
      }
      for (int q = 2; q < L.nz[j - 1]; ++q) {
        for (int c = 0; c < k; ++c) {
          const double yr = y[rows[q] * k + c];
          s[c] -= x0[q] * yr;
          t[c] -= x1[q - 1] * yr;
        }
      }
      for (int c = 0; c < k; ++c) {
        const double yj = y[j * k + c] = t[c] / x1[0];
        y[(j - 1) * k + c] = (s[c] - x0[1] * yj) / x0[0];
      }
      j -= 2;
      continue;
    }
    const int* rows = L.i + L.p[j];
    const T* x0 = x + L.p[j];
    for (int c = 0; c < k; ++c) s[c] = y[j * k + c];
    for (int q = 1; q < L.nz[j]; ++q) {
      for (int c = 0; c < k; ++c) s[c] -= x0[q] * y[rows[q] * k + c];
    }
    for (int c = 0; c < k; ++c) y[j * k + c] = s[c] / x0[0];
    --j;
  }
}

template <int K, class T>
void TreeSolve::solve_k(const FactorView& L, const double* b, double* x, int nc) {
  const int k = K > 0 ? K : nc, nb = bins();
  y_.resize(static_cast<size_t>(n_) * k);
  double* y = y_.data();
  for (std::vector<double>& buf : buf_) buf.assign(static_cast<size_t>(ntop_) * k, 0.0);
  for (const Range& r : top_runs_) gather(L, b, r, k, y);
  // A bin an iteration, costing its share of the rows.
  const parallel::Loop bins(nb, static_cast<double>(n_) / nb);
  bins.run([&](int, long bin) {
    for (const Range& r : bins_[bin]) {
      gather(L, b, r, k, y);
      forward<K, T>(L, r, k, y, buf_[bin].data());
    }
  });
  for (int bin = 0; bin < nb; ++bin) {  // the bins' updates of the top, in bin order
    for (int t = 0; t < ntop_; ++t) {
      for (int c = 0; c < k; ++c) y[top_[t] * k + c] += buf_[bin][c * ntop_ + t];
    }
  }
  for (const Range& r : top_runs_) forward<K, T>(L, r, k, y, nullptr);
  for (auto r = top_runs_.rbegin(); r != top_runs_.rend(); ++r) backward<K, T>(L, *r, k, y);
  for (const Range& r : top_runs_) scatter(L, y, r, k, x);  // b is read in full: x may alias it
  bins.run([&](int, long bin) {
    for (auto r = bins_[bin].rbegin(); r != bins_[bin].rend(); ++r) {
      backward<K, T>(L, *r, k, y);
      scatter(L, y, *r, k, x);
    }
  });
}

void TreeSolve::solve(const FactorView& L, const double* b, double* x, int ncols, bool single) {
  if (single && ncols == 1) solve_k<1, float>(L, b, x, 1);
  else if (single) solve_k<0, float>(L, b, x, ncols);
  else if (ncols == 1) solve_k<1, double>(L, b, x, 1);
  else if (ncols == 2) solve_k<2, double>(L, b, x, 2);
  else solve_k<0, double>(L, b, x, ncols);
}

}  // namespace bdinterp::detail
