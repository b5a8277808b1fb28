// The triangular solves split along the elimination tree (src/detail/tree_solve.h): against dense
// and Eigen solves, on hand-built factors of every shape and on CHOLMOD's factors of mesh systems
// (a supernodal one made simplicial too).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <functional>
#include <memory>
#include <random>

#include "flatten/pcg.h"
#include "linalg/tree_solve.h"
#include "parallel/parallel.h"
#include "linalg/sparse_cholesky.h"
#include "test_meshes.h"

namespace bdinterp {
namespace {

// A factor in CHOLMOD's simplicial layout with a random postordered elimination forest: each
// column's rows are its parent and a random subset of its further ancestors, sorted, or (for half
// of the columns whose parent is the next column) that column's rows.
struct HandFactor {
  int n = 0;
  std::vector<int> p, i, nz, perm;
  std::vector<double> x;
  detail::FactorView view() const { return {n, p.data(), i.data(), nz.data(), x.data(), perm.data()}; }
  Eigen::MatrixXd A() const {  // P' L L' P
    Eigen::MatrixXd L = Eigen::MatrixXd::Zero(n, n), P = Eigen::MatrixXd::Zero(n, n);
    for (int j = 0; j < n; ++j) {
      for (int q = p[j]; q < p[j] + nz[j]; ++q) L(i[q], j) = x[q];
      P(j, perm[j]) = 1.0;
    }
    return P.transpose() * L * L.transpose() * P;
  }
};

HandFactor hand_factor(int n, unsigned seed, int max_children, int trees = 3) {
  std::mt19937 rng(seed);
  std::vector<int> parent(n, -1);
  // Subtree of `size` columns ending at `last` (postorder): children cover the columns before it.
  std::function<void(int, int)> grow = [&](int last, int size) {
    int first = last - size + 1, left = size - 1;
    while (left > 0) {
      const int take = left == 1 || max_children == 1 ? left : 1 + static_cast<int>(rng() % left);
      const int child = first + take - 1;
      parent[child] = last;
      grow(child, take);
      first += take;
      left -= take;
    }
  };
  for (int first = 0; first < n;) {  // a forest of a few trees
    const int size = std::min(n - first, n / trees + 1);
    grow(first + size - 1, size);
    first += size;
  }
  // Columns last first, so that half of the columns whose parent is the next one can take its
  // pattern (a chain of two, which the solves treat together).
  std::vector<std::vector<int>> rows(n);
  for (int j = n - 1; j >= 0; --j) {
    rows[j] = {j};
    if (parent[j] == j + 1 && rng() % 2 == 0) {
      rows[j].insert(rows[j].end(), rows[j + 1].begin(), rows[j + 1].end());
      continue;
    }
    for (int a = parent[j]; a >= 0; a = parent[a]) {
      if (a == parent[j] || rng() % 3 == 0) rows[j].push_back(a);
    }
  }
  HandFactor f;
  f.n = n;
  std::uniform_real_distribution<double> value(-0.5, 0.5);
  for (int j = 0; j < n; ++j) {
    f.p.push_back(static_cast<int>(f.i.size()));
    for (int r : rows[j]) {
      f.i.push_back(r);
      f.x.push_back(r == j ? 1.0 + std::abs(value(rng)) : value(rng));
    }
    f.nz.push_back(static_cast<int>(rows[j].size()));
  }
  f.perm.resize(n);
  std::iota(f.perm.begin(), f.perm.end(), 0);
  std::shuffle(f.perm.begin(), f.perm.end(), rng);
  return f;
}

TEST(TreeSolve, HandBuiltFactorsSolveLikeADenseSolve) {
  for (unsigned seed = 1; seed <= 6; ++seed) {
    const HandFactor f = hand_factor(240, seed, seed % 3 == 0 ? 2 : 6);
    const Eigen::MatrixXd A = f.A();
    for (int bins : {1, 2, 3, 4}) {
      detail::TreeSolve plan(f.view(), bins);
      ASSERT_TRUE(plan.usable());
      EXPECT_LE(plan.bins(), bins);
      for (int ncols : {1, 2, 3}) {
        const Eigen::MatrixXd B = Eigen::MatrixXd::Random(f.n, ncols);
        Eigen::MatrixXd X(f.n, ncols), Y = B;
        plan.solve(f.view(), B.data(), X.data(), ncols);
        const Eigen::MatrixXd expected = A.llt().solve(B);
        EXPECT_LT((X - expected).cwiseAbs().maxCoeff(), 1e-10 * (1 + expected.cwiseAbs().maxCoeff()))
            << "seed " << seed << " bins " << bins << " ncols " << ncols;
        plan.solve(f.view(), Y.data(), Y.data(), ncols);  // in place
        EXPECT_EQ((Y - X).cwiseAbs().maxCoeff(), 0.0);
      }
    }
  }
}

TEST(TreeSolve, ChainsStaySerialAndOtherLayoutsAreRefused) {
  // A chain (each column's parent the next): no two subtrees to split.
  HandFactor chain = hand_factor(100, 3, 1, 1);
  detail::TreeSolve serial(chain.view(), 2);
  EXPECT_TRUE(serial.usable());
  EXPECT_EQ(serial.bins(), 1);
  HandFactor f = hand_factor(100, 4, 4);
  EXPECT_EQ(detail::TreeSolve(f.view(), 2).bins(), 2);
  HandFactor unsorted = f, diagonal_last = f;
  for (int j = 0; j < f.n; ++j) {
    if (f.nz[j] < 3) continue;
    std::swap(unsorted.i[f.p[j] + 1], unsorted.i[f.p[j] + 2]);
    std::swap(diagonal_last.i[f.p[j]], diagonal_last.i[f.p[j] + f.nz[j] - 1]);
    break;
  }
  EXPECT_FALSE(detail::TreeSolve(unsorted.view(), 2).usable());
  EXPECT_FALSE(detail::TreeSolve(diagonal_last.view(), 2).usable());
  // Two trees whose columns interleave (0, 2 -> 4 and 1, 3 -> 5): not contiguous subtrees.
  HandFactor inter;
  inter.n = 6;
  const int parents[6] = {2, 3, 4, 5, -1, -1};
  for (int j = 0; j < 6; ++j) {
    inter.p.push_back(static_cast<int>(inter.i.size()));
    inter.i.push_back(j);
    inter.x.push_back(2.0);
    if (parents[j] >= 0) {
      inter.i.push_back(parents[j]);
      inter.x.push_back(0.5);
    }
    inter.nz.push_back(static_cast<int>(inter.i.size()) - inter.p.back());
    inter.perm.push_back(j);
  }
  EXPECT_FALSE(detail::TreeSolve(inter.view(), 2).usable());
}

// The graph Laplacian of a mesh plus the identity, lower triangle by columns (rows sorted).
Eigen::SparseMatrix<double> shifted_laplacian(const testing::TestMesh& m) {
  std::vector<Eigen::Triplet<double>> t;
  const int n = static_cast<int>(m.V.rows());
  std::vector<double> degree(n, 1.0);
  for (int f = 0; f < m.F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int a = m.F(f, c), b = m.F(f, (c + 1) % 3);
      t.emplace_back(std::max(a, b), std::min(a, b), -0.5);  // each edge is seen from two faces
      degree[a] += 0.5;
      degree[b] += 0.5;
    }
  }
  for (int v = 0; v < n; ++v) t.emplace_back(v, v, degree[v]);
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(t.begin(), t.end());
  L.makeCompressed();
  return L;
}

// CHOLMOD's factorisation of the matrix whose lower triangle by columns is `lower`.
std::unique_ptr<SparseCholesky> factorised(const Eigen::SparseMatrix<double>& lower) {
  const int n = static_cast<int>(lower.rows());
  const std::vector<int> col_ptr(lower.outerIndexPtr(), lower.outerIndexPtr() + n + 1);
  const std::vector<int> rows(lower.innerIndexPtr(), lower.innerIndexPtr() + lower.nonZeros());
  auto chol = std::make_unique<SparseCholesky>(n, col_ptr, rows);
  std::copy(lower.valuePtr(), lower.valuePtr() + lower.nonZeros(), chol->values());
  chol->factorize();
  return chol;
}

TEST(TreeSolve, MeshSystemsSplitOverTheCoresAndMatchEigen) {
  // ~5k rows (AMD or CHOLMOD's nested dissection) and ~25k (METIS): the split leaves a few
  // separators to the calling thread and shares the rest evenly enough, and every way of running
  // gives Eigen's solution.
  for (const int nx : {100, 220}) {
    const testing::TestMesh m = testing::jittered_grid(nx, nx / 2, 2.0, 1.0, 5);
    const Eigen::SparseMatrix<double> lower = shifted_laplacian(m);
    const int n = static_cast<int>(lower.rows());
    const std::unique_ptr<SparseCholesky> factor = factorised(lower);
    SparseCholesky& chol = *factor;
    for (int chunks : {2, 3, 4}) {
      const SparseCholesky::SolveSplit split = chol.solve_split(chunks);
      EXPECT_EQ(split.chunks, chunks) << n << " rows";
      // Measured: serial 0.09 / 0.01 (5k / 25k rows, 2 chunks), critical 0.56 / 0.51 at 2 chunks,
      // 0.43 / 0.31 at 4 (a nested dissection's subtrees come in halves, so 3 chunks balance worse).
      EXPECT_LT(split.serial_share, 0.25) << n << " rows, " << chunks << " chunks";
      EXPECT_LT(split.critical_share, chunks == 2 ? 0.6 : 0.5) << n << " rows, " << chunks << " chunks";
    }
    EXPECT_EQ(chol.solve_split(1).chunks, 1);
    const Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower> reference(lower);
    const Eigen::MatrixXd B = Eigen::MatrixXd::Random(n, 2);
    const Eigen::MatrixXd expected = reference.solve(B);
    Eigen::MatrixXd first;
    for (int threads : {1, 0, 0, 0}) {
      const parallel::ThreadLimit limit(threads);
      Eigen::MatrixXd X(n, 2), x1(n, 1);
      chol.solve(B.data(), X.data(), 2);
      chol.solve(B.data(), x1.data(), 1);
      EXPECT_LT((X - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff());
      EXPECT_LT((X.col(0) - x1).cwiseAbs().maxCoeff(), 1e-14 * expected.cwiseAbs().maxCoeff());
      if (threads == 0 && first.size() == 0) first = X;
      if (threads == 0) EXPECT_EQ((X - first).cwiseAbs().maxCoeff(), 0.0);  // whoever runs the chunks
    }
  }
}

// The 7-point Laplacian of a k x k x k grid plus the identity, lower triangle by columns: a factor
// dense enough (flops / nnz(L) far above CHOLMOD's supernodal switch) to be made supernodally.
Eigen::SparseMatrix<double> cube_laplacian(int k) {
  std::vector<Eigen::Triplet<double>> t;
  const auto at = [k](int x, int y, int z) { return (z * k + y) * k + x; };
  for (int z = 0; z < k; ++z)
    for (int y = 0; y < k; ++y)
      for (int x = 0; x < k; ++x) {
        t.emplace_back(at(x, y, z), at(x, y, z), 7.0);
        if (x > 0) t.emplace_back(at(x, y, z), at(x - 1, y, z), -1.0);
        if (y > 0) t.emplace_back(at(x, y, z), at(x, y - 1, z), -1.0);
        if (z > 0) t.emplace_back(at(x, y, z), at(x, y, z - 1), -1.0);
      }
  Eigen::SparseMatrix<double> L(k * k * k, k * k * k);
  L.setFromTriplets(t.begin(), t.end());
  L.makeCompressed();
  return L;
}

TEST(TreeSolve, ASupernodalFactorIsSolvedAsASimplicialOneOverTheCores) {
  const Eigen::SparseMatrix<double> lower = cube_laplacian(24);
  const int n = static_cast<int>(lower.rows());
  std::vector<int> col_ptr(lower.outerIndexPtr(), lower.outerIndexPtr() + n + 1);
  std::vector<int> rows(lower.innerIndexPtr(), lower.innerIndexPtr() + lower.nonZeros());
  SparseCholesky chol(n, col_ptr, rows);
  ASSERT_GT(chol.factor_flops() / (chol.solve_flops() / 4), 2 * 140.0);  // CHOLMOD goes supernodal
  const Eigen::VectorXd b = Eigen::VectorXd::Random(n);
  for (const double shift : {0.0, 5.0}) {  // the second factorisation starts from the analysis again
    std::copy(lower.valuePtr(), lower.valuePtr() + lower.nonZeros(), chol.values());
    for (int j = 0; j < n; ++j) chol.values()[col_ptr[j]] += shift;  // diagonal first in each column
    chol.factorize();
    EXPECT_TRUE(chol.factor_is_ll());
    EXPECT_EQ(chol.solve_split(2).chunks, 2);  // the elimination-tree split: a simplicial factor
    Eigen::VectorXd x(n), Ax(n);
    chol.solve(b.data(), x.data(), 1);
    chol.multiply(chol.values(), x.data(), Ax.data());
    EXPECT_LT((Ax - b).norm(), 1e-12 * b.norm()) << "shift " << shift;
    EXPECT_GT(x.norm(), 0.1 * b.norm() / (7.0 + shift + 6.0));
  }
}

TEST(TreeSolve, TheSinglePrecisionSolveIsAFloatAccuratePreconditioner) {
  // A 100k-row mesh Laplacian, a factor large enough for the chord steps' CG to precondition in
  // single precision: solve_single() differs from solve() by about float's rounding times the
  // condition (not by double's: the single values are read), is the same on every run, and
  // preconditions CG as well as the exact factor (the residual falls by 1e-12 in a few steps).
  const testing::TestMesh m = testing::jittered_grid(450, 225, 2.0, 1.0, 5);
  const Eigen::SparseMatrix<double> lower = shifted_laplacian(m);
  const int n = static_cast<int>(lower.rows());
  const std::unique_ptr<SparseCholesky> factor = factorised(lower);
  SparseCholesky& chol = *factor;
  ASSERT_TRUE(chol.single_pays());
  const parallel::ThreadLimit limit(0);
  ASSERT_EQ(chol.solve_split(parallel::usable_cores()).chunks > 1, parallel::usable_cores() > 1);
  const Eigen::VectorXd b = Eigen::VectorXd::Random(n);
  Eigen::VectorXd exact(n), single(n), again(n);
  chol.solve(b.data(), exact.data());
  chol.solve_single(b.data(), single.data());
  chol.solve_single(b.data(), again.data());
  const double error = (single - exact).cwiseAbs().maxCoeff() / exact.cwiseAbs().maxCoeff();
  EXPECT_LT(error, 1e-3);
  if (parallel::usable_cores() > 1) EXPECT_GT(error, 1e-10);
  EXPECT_EQ((single - again).cwiseAbs().maxCoeff(), 0.0);
  // The flattening's CG on A x = b, preconditioned with the same factor.
  Eigen::VectorXd x(n);
  detail::PcgScratch scratch;
  const int steps = detail::preconditioned_cg(chol, chol.values(), b, 1e-12 * b.cwiseAbs().maxCoeff(), 20, x, scratch);
  EXPECT_LE(steps, 5);
  EXPECT_LT((x - exact).cwiseAbs().maxCoeff(), 1e-10 * exact.cwiseAbs().maxCoeff());
}

}  // namespace
}  // namespace bdinterp
