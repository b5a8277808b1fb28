#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "bdinterp/layout.h"
#include "bdinterp/metric_blend.h"
#include "test_meshes.h"

namespace bdinterp {
namespace {

// Max distance after the best rigid alignment of X onto Y (Kabsch).
double rigid_error(const Positions& X, const Positions& Y) {
  const Eigen::RowVector2d cx = X.colwise().mean(), cy = Y.colwise().mean();
  const Eigen::MatrixX2d A = X.rowwise() - cx, B = Y.rowwise() - cy;
  Eigen::JacobiSVD<Eigen::Matrix2d> svd(A.transpose() * B, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix2d R = svd.matrixV() * svd.matrixU().transpose();
  EXPECT_GT(R.determinant(), 0);  // a rotation, not a reflection
  return ((A * R.transpose()) - B).rowwise().norm().maxCoeff();
}

TEST(Layout, ReproducesAShapeFromItsEdgeLengthsWithoutDrift) {
  // A long, thin, curved strip: propagation errors would accumulate along it.
  const auto m = testing::jittered_grid(400, 8, 1.0, 0.02, 7);
  const Positions bent = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 5.0, 0.01); });
  const Mesh mesh(m.F, static_cast<int>(m.V.rows()));
  Layout layout(mesh);
  double flatness = 1;
  const Positions X = layout.embed(squared_edge_lengths(mesh, bent), &flatness);
  // Roundoff only: the strip's Laplacian has condition ~1e5, so relative edge errors of ~1e-11.
  EXPECT_LT(flatness, 1e-9);
  EXPECT_LT(rigid_error(X, bent), 1e-11);
}

TEST(Layout, FacesComeOutCounterClockwise) {
  const auto m = testing::jittered_grid(10, 10);
  const Mesh mesh(m.F, static_cast<int>(m.V.rows()));
  Layout layout(mesh);
  const Positions X = layout.embed(squared_edge_lengths(mesh, m.V));
  for (int f = 0; f < m.F.rows(); ++f) {
    const Eigen::RowVector2d a = X.row(m.F(f, 1)) - X.row(m.F(f, 0)), b = X.row(m.F(f, 2)) - X.row(m.F(f, 0));
    EXPECT_GT(a.x() * b.y() - a.y() * b.x(), 0) << f;
  }
}

}  // namespace
}  // namespace bdinterp
