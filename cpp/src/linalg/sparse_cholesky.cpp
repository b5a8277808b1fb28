#include "linalg/sparse_cholesky.h"

#include <cholmod.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <string>

#include "parallel/parallel.h"
#include "linalg/tree_solve.h"

namespace bdinterp {
namespace {
constexpr int kNestedDissectionRows = 20000;

// Every CHOLMOD setting of the library, for the analysis and for every numeric factorisation alike
// (a copy that lost final_ll used to refactorise as LDL').
void configure(cholmod_common& common, int n) {
  common.print = 0;  // failures are reported through exceptions, not printed
  // Supernodal (BLAS) only when the factor is dense enough to profit (flops / nnz(L) on planar
  // meshes: ~50 at 10k rows, ~130 at 50k, ~146 at 100k, ~190 at 200k, ~280 at 500k). A supernodal
  // factorisation is faster from ~10k rows, but its solves are not: CHOLMOD's supernodal solves make
  // a BLAS call per supernode, and a warm frame does several solves per factorisation (chord steps,
  // their CG, the layout). Measured on 2 cores, one thread, 7-point grids, supernodal / simplicial:
  // 48k rows factor 65 / 75 ms, 2-column solve 9.7-12.2 / 6.1-7.0 ms (warm bar frames at 50k: 43 ->
  // 31 ms simplicial, interleaved); 100k factor 151 / 248 ms, solve 15.8 / 10.5 ms; 200k 305 / 630,
  // 36 / 24 ms. So simplicial up to ~100k rows (cold frames about even there), supernodal beyond.
  // Simplicial solves also split over the cores (tree_solve.h: 48k rows, 2 cores, 1 column 1.4-2.3
  // ms against CHOLMOD's 2.8-3.8 ms), so factorize() makes a supernodal factor simplicial for its
  // solves (it keeps the supernodes' explicit zeros: +21 % entries at 100k rows; warm blends of a
  // 100k-vertex pose grid take 0.64 of the time of CHOLMOD's supernodal solves).
  common.supernodal_switch = 140;
  // Simplicial factors are kept as LL' rather than LDL': the same factorisation cost, solves ~20 %
  // faster (no diagonal pass), and the solves are what repeated frames spend their time in.
  common.final_ll = 1;
  // Fill-reducing ordering: from ~20k rows nested dissection (METIS) gives markedly sparser factors
  // on planar meshes (measured on a 1M-vertex grid: nnz(L) -22 %, factorisation flops -37 %),
  // worth its slower, once-per-mesh analysis. Below, CHOLMOD keeps the better of AMD and its own
  // nested dissection: AMD on grid-like meshes, NESDIS on Delaunay ones (5k-vertex disk: nnz(L)
  // -12 %, factorisation -25 %).
  if (n >= kNestedDissectionRows) {
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_METIS;
  } else {
    common.nmethods = 2;
    common.method[0].ordering = CHOLMOD_AMD;
    common.method[1].ordering = CHOLMOD_NESDIS;
  }
}

void check(const cholmod_common& common, const char* what) {
  if (common.status < CHOLMOD_OK) {
    throw SolverError(std::string("CHOLMOD ") + what + " failed (status " + std::to_string(common.status) +
                      ")");
  }
}

// Throws SolverError unless CHOLMOD's calls reach the CHOLMOD this code was compiled for. Another
// one in the process (Debian's Blender 5.2 loads SuiteSparse 7's through Ceres) can take the calls
// of a CHOLMOD linked shared, and its structs differ: the shipped modules link theirs hidden.
void check_runtime_version() {
  static const std::array<int, 3> runtime = [] {
    std::array<int, 3> v{};
    cholmod_version(v.data());
    return v;
  }();
  if (runtime[0] != CHOLMOD_MAIN_VERSION || runtime[1] != CHOLMOD_SUB_VERSION) {
    throw SolverError("bdinterp was built for CHOLMOD " + std::to_string(CHOLMOD_MAIN_VERSION) + "." +
                      std::to_string(CHOLMOD_SUB_VERSION) + ", but its calls reach CHOLMOD " +
                      std::to_string(runtime[0]) + "." + std::to_string(runtime[1]) +
                      " (another library in this process); use a build that links CHOLMOD statically");
  }
}

// A CHOLMOD handle configured by configure(); finished on destruction.
struct Common {
  cholmod_common c{};
  explicit Common(int n) {
    check_runtime_version();
    cholmod_start(&c);
    configure(c, n);
  }
  ~Common() { cholmod_finish(&c); }
  Common(const Common&) = delete;
  Common& operator=(const Common&) = delete;
};

// A packed lower-triangular CHOLMOD view of the analysis' pattern (no copy) with the values x
// (null: the pattern alone).
cholmod_sparse view(const CholeskyAnalysis& a, double* x) {
  cholmod_sparse A{};
  A.nrow = A.ncol = static_cast<size_t>(a.size());
  A.nzmax = a.row_indices().size();
  A.p = const_cast<int*>(a.column_pointers().data());  // CHOLMOD reads the pattern, never writes it
  A.i = const_cast<int*>(a.row_indices().data());
  A.x = x;
  A.stype = -1;
  A.itype = CHOLMOD_INT;
  A.xtype = x ? CHOLMOD_REAL : CHOLMOD_PATTERN;
  A.dtype = CHOLMOD_DOUBLE;
  A.sorted = 1;
  A.packed = 1;
  return A;
}

}  // namespace

struct CholeskyAnalysis::Impl {
  Common common;
  cholmod_factor* L = nullptr;  // symbolic only; copied by every SparseCholesky
  explicit Impl(int n) : common(n) {}
  ~Impl() { cholmod_free_factor(&L, &common.c); }
};

CholeskyAnalysis::CholeskyAnalysis(int n, std::vector<int> col_ptr, std::vector<int> row_idx)
    : col_ptr_(std::move(col_ptr)), rows_(std::move(row_idx)) {
  if (n <= 0 || static_cast<int>(col_ptr_.size()) != n + 1 || col_ptr_.front() != 0 ||
      col_ptr_.back() != static_cast<int>(rows_.size())) {
    throw InvalidInput("SparseCholesky: inconsistent compressed-column pattern");
  }
  impl_ = std::make_unique<Impl>(n);
  cholmod_common& c = impl_->common.c;
  cholmod_sparse A = view(*this, nullptr);
  impl_->L = cholmod_analyze(&A, &c);
  if (!impl_->L) {  // a CHOLMOD built without METIS: default orderings
    c.nmethods = 0;
    c.status = CHOLMOD_OK;
    impl_->L = cholmod_analyze(&A, &c);
  }
  check(c, "analyze");
  factor_flops_ = c.fl;
  solve_flops_ = 4.0 * c.lnz;
}

CholeskyAnalysis::~CholeskyAnalysis() = default;

struct SparseCholesky::Impl {
  Common common;
  std::vector<double> values;  // in the order of the pattern
  cholmod_sparse A;            // the analysis' pattern with `values`
  cholmod_factor* L = nullptr;
  cholmod_dense* B = nullptr;
  cholmod_dense* X = nullptr;
  cholmod_dense* Y = nullptr;  // workspaces of cholmod_solve2, kept so solves do not allocate
  cholmod_dense* E = nullptr;
  int ncols = 0;
  bool factored = false;
  mutable parallel::Partials product_parts;  // other threads' shares of multiply()
  // The elimination-tree split of the solves per number of chunks (index), built on first use.
  std::vector<std::unique_ptr<detail::TreeSolve>> tree_solves;
  std::vector<float> single;  // L's values in single precision (solve_single)
  bool single_current = false;  // `single` holds this factorisation's values

  explicit Impl(const CholeskyAnalysis& a, const cholmod_factor* symbolic)
      : common(a.size()), values(a.row_indices().size(), 0.0), A(view(a, values.data())) {
    L = cholmod_copy_factor(const_cast<cholmod_factor*>(symbolic), &common.c);
    check(common.c, "copy");
  }
  ~Impl() {
    cholmod_free_dense(&B, &common.c);
    cholmod_free_dense(&X, &common.c);
    cholmod_free_dense(&Y, &common.c);
    cholmod_free_dense(&E, &common.c);
    cholmod_free_factor(&L, &common.c);
  }
  void ensure_rhs(int n, int k) {
    if (B && ncols == k) return;
    cholmod_free_dense(&B, &common.c);
    B = cholmod_allocate_dense(n, k, n, CHOLMOD_REAL, &common.c);
    check(common.c, "allocate");
    ncols = k;
  }
};

SparseCholesky::SparseCholesky(std::shared_ptr<const CholeskyAnalysis> analysis)
    : analysis_(std::move(analysis)),
      impl_(std::make_unique<Impl>(*analysis_, analysis_->impl_->L)) {}

SparseCholesky::SparseCholesky(int n, const std::vector<int>& col_ptr, const std::vector<int>& row_idx)
    : SparseCholesky(std::make_shared<const CholeskyAnalysis>(n, col_ptr, row_idx)) {}

SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

double* SparseCholesky::values() { return impl_->values.data(); }
const double* SparseCholesky::values() const { return impl_->values.data(); }
bool SparseCholesky::factored() const { return impl_->factored; }
bool SparseCholesky::factor_is_ll() const { return impl_->factored && impl_->L->is_ll; }

void SparseCholesky::factorize() {
  Impl& m = *impl_;
  m.factored = m.single_current = false;
  const cholmod_factor* symbolic = analysis_->impl_->L;
  if (symbolic->is_super && !m.L->is_super) {  // the last factor was made simplicial: supernodal again
    cholmod_free_factor(&m.L, &m.common.c);
    m.L = cholmod_copy_factor(const_cast<cholmod_factor*>(symbolic), &m.common.c);
    check(m.common.c, "copy");
  }
  cholmod_factorize(&m.A, m.L, &m.common.c);
  if (m.common.c.status == CHOLMOD_NOT_POSDEF) {
    throw SolverError("matrix is not positive definite (CHOLMOD stopped at column " +
                      std::to_string(m.L->minor) + ")");
  }
  check(m.common.c, "factorize");
  if (m.L->is_super) {  // solved as a simplicial L L' (configure(): the solves split over the cores)
    cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, m.L, &m.common.c);
    check(m.common.c, "change_factor");
  }
  m.factored = true;
}

void SparseCholesky::multiply(const double* values, const double* x, double* y) const {
  // Lower triangle by columns: column j gives y_j its dot product and scatters x_j into the rows
  // below it (per-thread arrays for the scatter, summed after).
  const int* col_ptr = column_pointers();
  const int* rows = row_indices();
  const int n = size();
  // A column an iteration, costing a quarter of its entries (a multiply-add each).
  const parallel::Loop columns(n, col_ptr[n] / (4.0 * std::max(n, 1)));
  parallel::Partials& parts = impl_->product_parts;
  parts.prepare(columns.chunks(), n);
  for (int k = 0; k < columns.chunks(); ++k) std::fill_n(parts.buffer(k, y), n, 0.0);
  columns.run([&](int k, long j) {
    double* out = parts.buffer(k, y);
    const int p0 = col_ptr[j], p1 = col_ptr[j + 1];
    double acc = values[p0] * x[j];  // diagonal first in every column
    const double xj = x[j];
    for (int p = p0 + 1; p < p1; ++p) {
      const int i = rows[p];
      acc += values[p] * x[i];
      out[i] += values[p] * xj;
    }
    out[j] += acc;
  });
  parts.add_into(y);
}

namespace {
// The factor as TreeSolve reads it; n = 0 unless simplicial L L' (a factor that stays supernodal
// keeps CHOLMOD's solve).
detail::FactorView factor_view(const cholmod_factor& L) {
  if (L.is_super || !L.is_ll || L.xtype != CHOLMOD_REAL || L.itype != CHOLMOD_INT) return {};
  return {static_cast<int>(L.n), static_cast<const int*>(L.p), static_cast<const int*>(L.i),
          static_cast<const int*>(L.nz), static_cast<const double*>(L.x), static_cast<const int*>(L.Perm)};
}
}  // namespace

detail::TreeSolve* SparseCholesky::tree_solve(int chunks) {
  Impl& m = *impl_;
  const detail::FactorView view = factor_view(*m.L);
  if (chunks <= 1 || view.n != size()) return nullptr;
  if (static_cast<int>(m.tree_solves.size()) <= chunks) m.tree_solves.resize(chunks + 1);
  std::unique_ptr<detail::TreeSolve>& plan = m.tree_solves[chunks];
  if (!plan) plan = std::make_unique<detail::TreeSolve>(view, chunks);
  return plan->usable() && plan->bins() > 1 ? plan.get() : nullptr;
}

SparseCholesky::SolveSplit SparseCholesky::solve_split(int chunks) {
  if (!factored()) throw SolverError("SparseCholesky::solve_split called without a valid factorisation");
  const detail::TreeSolve* plan = tree_solve(chunks);
  if (!plan) return {};
  return {plan->bins(), plan->top_share(), plan->critical_share()};
}

detail::TreeSolve* SparseCholesky::solve_plan() {
  // Split over the cores when a solve is worth two fork/joins (nnz(L) >= 8000: from ~1k rows).
  const int n = size();
  return tree_solve(parallel::Loop(n, solve_flops() / (64.0 * std::max(n, 1))).chunks());
}

void SparseCholesky::solve(const double* b, double* x, int ncols) {
  Impl& m = *impl_;
  if (!m.factored) throw SolverError("SparseCholesky::solve called without a valid factorisation");
  const int n = size();
  if (detail::TreeSolve* plan = ncols <= detail::TreeSolve::kMaxColumns ? solve_plan() : nullptr) {
    plan->solve(factor_view(*m.L), b, x, ncols);
    return;
  }
  m.ensure_rhs(n, ncols);
  std::memcpy(m.B->x, b, sizeof(double) * n * ncols);
  cholmod_solve2(CHOLMOD_A, m.L, m.B, nullptr, &m.X, nullptr, &m.Y, &m.E, &m.common.c);
  check(m.common.c, "solve");
  std::memcpy(x, m.X->x, sizeof(double) * n * ncols);
}

void SparseCholesky::solve_single(const double* b, double* x) {
  Impl& m = *impl_;
  if (!m.factored) throw SolverError("SparseCholesky::solve_single called without a valid factorisation");
  detail::TreeSolve* plan = solve_plan();
  if (!plan) return solve(b, x, 1);
  detail::FactorView view = factor_view(*m.L);
  if (!m.single_current) {
    const double* values = view.x;
    m.single.resize(m.L->nzmax);
    parallel::Loop(static_cast<long>(m.L->nzmax)).run([&](int, long k) { m.single[k] = static_cast<float>(values[k]); });
    m.single_current = true;
  }
  view.x_single = m.single.data();
  plan->solve(view, b, x, 1, /*single=*/true);
}

namespace {
void check_entry(const char* who, int n, int i, int j) {
  if (i < 0 || j < 0 || i >= n || j >= n) {
    throw InvalidInput(std::string(who) + ": entry (" + std::to_string(i) + ", " + std::to_string(j) +
                       ") outside a " + std::to_string(n) + "-by-" + std::to_string(n) + " matrix");
  }
}
}  // namespace

SymmetricPattern::SymmetricPattern(int n, std::vector<std::pair<int, int>> pairs) {
  if (n < 0) throw InvalidInput("SymmetricPattern: negative size " + std::to_string(n));
  for (auto& [i, j] : pairs) {
    check_entry("SymmetricPattern", n, i, j);
    if (i < j) std::swap(i, j);  // (row, col) below the diagonal
  }
  // By column, then row; pairs on the diagonal are skipped below (each column has its diagonal).
  std::sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) {
    return a.second != b.second ? a.second < b.second : a.first < b.first;
  });
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  col_ptr.assign(n + 1, 0);
  rows.reserve(static_cast<size_t>(n) + pairs.size());
  size_t k = 0;
  for (int j = 0; j < n; ++j) {
    rows.push_back(j);
    for (; k < pairs.size() && pairs[k].second == j; ++k)
      if (pairs[k].first != j) rows.push_back(pairs[k].first);
    col_ptr[j + 1] = static_cast<int>(rows.size());
  }
}

int SymmetricPattern::position(int i, int j) const {
  if (i < j) std::swap(i, j);
  const auto first = rows.begin() + col_ptr[j], last = rows.begin() + col_ptr[j + 1];
  const auto it = std::lower_bound(first, last, i);
  return it != last && *it == i ? static_cast<int>(it - rows.begin()) : -1;
}

std::unique_ptr<SparseCholesky> factorise(int n, const std::vector<SymmetricEntry>& entries) {
  if (n < 1) throw InvalidInput("factorise: matrix size " + std::to_string(n) + " (need at least 1)");
  std::vector<std::pair<int, int>> lower;
  for (const SymmetricEntry& t : entries) {
    check_entry("factorise", n, t.row, t.col);
    if (t.row > t.col) lower.emplace_back(t.row, t.col);
  }
  const SymmetricPattern pattern(n, std::move(lower));
  auto chol = std::make_unique<SparseCholesky>(n, pattern.col_ptr, pattern.rows);
  double* values = chol->values();
  for (const SymmetricEntry& t : entries)
    if (t.row >= t.col) values[pattern.position(t.row, t.col)] += t.value;
  chol->factorize();
  return chol;
}

}  // namespace bdinterp
