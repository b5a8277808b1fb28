// The helpers that several units share (one helper per idiom): the symmetric pattern and
// factorise() over SparseCholesky, the edge matrix, and the rotation branch.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <vector>

#include "mesh/turns.h"
#include "mesh/geometry.h"
#include "linalg/sparse_cholesky.h"
#include "test_checks.h"

namespace bdinterp {
namespace {

using testing::expect_invalid;

TEST(SymmetricPattern, LowerTriangleByColumnsDiagonalFirstRepeatsOnce) {
  // 4 x 4 with the pairs (0, 1) (twice, both orders), (3, 1), (0, 3) and a diagonal pair (2, 2).
  const SymmetricPattern p(4, {{1, 0}, {0, 1}, {3, 1}, {2, 2}, {0, 3}});
  EXPECT_EQ(p.size(), 4);
  EXPECT_EQ(p.col_ptr, (std::vector<int>{0, 3, 5, 6, 7}));
  EXPECT_EQ(p.rows, (std::vector<int>{0, 1, 3, 1, 3, 2, 3}));
  EXPECT_EQ(p.position(0, 0), 0);
  EXPECT_EQ(p.position(1, 0), 1);
  EXPECT_EQ(p.position(0, 1), 1);
  EXPECT_EQ(p.position(1, 3), 4);
  EXPECT_EQ(p.position(3, 3), 6);
  EXPECT_EQ(p.position(2, 0), -1);  // not in the pattern
  expect_invalid([] { SymmetricPattern(3, {{0, 3}}); }, "entry (0, 3) outside a 3-by-3 matrix");
}

TEST(Factorise, SumsRepeatsSkipsTheUpperTriangleAndSolves) {
  // A = [[4, 1, 0], [1, 3, -1], [0, -1, 2]] given by both triangles, A(1, 1) = 3 as 1 + 2.
  const std::vector<SymmetricEntry> entries = {{0, 0, 4}, {0, 1, 1}, {1, 0, 1}, {1, 1, 1}, {1, 2, -1},
                                               {2, 1, -1}, {2, 2, 2}, {1, 1, 2}};
  const auto chol = factorise(3, entries);
  ASSERT_EQ(chol->size(), 3);
  // x = (1, -2, 3): b = A x = (4 - 2, 1 - 6 - 3, 2 + 6) = (2, -8, 8).
  const double b[3] = {2, -8, 8};
  double x[3];
  chol->solve(b, x);
  EXPECT_NEAR(x[0], 1, 1e-14);
  EXPECT_NEAR(x[1], -2, 1e-14);
  EXPECT_NEAR(x[2], 3, 1e-14);
  expect_invalid([] { factorise(2, {{0, 2, 1.0}}); }, "entry (0, 2) outside a 2-by-2 matrix");
  EXPECT_THROW(factorise(2, {{0, 0, 1.0}, {1, 0, 2.0}, {1, 1, 1.0}}), SolverError);  // indefinite
}

TEST(EdgeMatrix, ColumnsAreTheEdgesFromTheFirstCornerAndTheDeterminantTheDoubledArea) {
  Positions X(4, 2);
  X << 9, 9, 1, 2, 4, 3, 2, 7;
  Faces F(1, 3);
  F << 1, 2, 3;
  const Eigen::Matrix2d E = edge_matrix(X, F, 0);
  EXPECT_EQ(E(0, 0), 3);
  EXPECT_EQ(E(1, 0), 1);
  EXPECT_EQ(E(0, 1), 1);
  EXPECT_EQ(E(1, 1), 5);
  EXPECT_EQ(E.determinant(), doubled_area(X, F, 0));
  EXPECT_EQ(edge_matrix(X, 1, 2, 3), E);
}

TEST(RotationBranch, WrapTakesTheNearestBranchAndTheMedianItsWholeTurns) {
  EXPECT_NEAR(detail::wrap_angle(1.5 * kPi), -0.5 * kPi, 1e-15);
  EXPECT_NEAR(detail::wrap_angle(-7.0), -7.0 + kTwoPi, 1e-15);
  EXPECT_EQ(detail::wrap_angle(0.25), 0.25);
  // Weighted median 7.0 (the weights up to it, 0.5 + 1.5, reach half of 3): one whole turn.
  EXPECT_EQ(detail::median_turns({{7.1, 1.0}, {0.0, 0.5}, {7.0, 1.5}}), kTwoPi);
  // The body at ~0 outweighs a limb turned by 200 degrees: no turn.
  EXPECT_EQ(detail::median_turns({{3.49, 1.0}, {0.02, 2.0}, {-0.01, 0.5}}), 0.0);
  EXPECT_EQ(detail::median_turns({{-13.0, 1.0}}), -2 * kTwoPi);
}

}  // namespace
}  // namespace bdinterp
