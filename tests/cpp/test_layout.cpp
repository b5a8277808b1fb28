#include <gtest/gtest.h>

#include "flatten/flatten.h"
#include "layout/layout.h"
#include "blend/metric_blend.h"
#include "test_checks.h"
#include "test_meshes.h"

namespace bdinterp {
namespace {

using testing::rigid_error;

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

// A disk's frame is the plan's: its walked loop's first vertex at the origin, the root face's edge
// from corner 0 to corner 1 along +x. Against the input shape moved into that frame (a reference
// computed without the layout), an exactly flat metric comes out to roundoff, not just up to a
// rigid motion: the disks' path is unchanged by the free hole vertices (holes: test_holes.cpp).
TEST(Layout, ADiskComesOutInThePlansFrame) {
  const auto m = testing::jittered_grid(30, 10, 1.0, 0.3, 5);
  const Positions bent = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 3.0, 0.15); });
  const Mesh mesh(m.F, static_cast<int>(m.V.rows()));
  Layout layout(mesh);
  const Positions X = layout.embed(squared_edge_lengths(mesh, bent));
  const LayoutPlan& plan = layout.plan();
  EXPECT_EQ(plan.loop.size(), mesh.boundary_loops()[0].size());
  EXPECT_EQ(plan.pattern.size(), mesh.num_vertices() - static_cast<int>(plan.loop.size()));
  EXPECT_FALSE(plan.one_sided);  // every edge between free vertices has two faces
  const Eigen::RowVector2d axis = (bent.row(m.F(plan.root, 1)) - bent.row(m.F(plan.root, 0))).normalized();
  Positions reference(bent.rows(), 2);
  for (int v = 0; v < bent.rows(); ++v) {
    const Eigen::RowVector2d d = bent.row(v) - bent.row(plan.loop.front());
    reference.row(v) << axis.x() * d.x() + axis.y() * d.y(), axis.x() * d.y() - axis.y() * d.x();
  }
  EXPECT_LT((X - reference).cwiseAbs().maxCoeff(), 1e-12);
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

// The layout's system matrix only weighs edge vectors that agree: for an exactly flat metric every
// SPD matrix over the interior pattern gives the same positions, including a factorisation of the
// matrix plus a diagonal shift (undone by iterative refinement).
TEST(Layout, AnyInteriorSystemGivesTheSameExactLayout) {
  const auto m = testing::jittered_grid(40, 8, 1.0, 0.2, 3);
  const Positions bent = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 2.5, 0.1); });
  const Mesh mesh(m.F, static_cast<int>(m.V.rows()));
  const Eigen::VectorXd l2 = squared_edge_lengths(mesh, bent);
  Layout own(mesh);
  const Positions X0 = own.embed(l2);
  EXPECT_LT(rigid_error(X0, bent), 1e-12);

  // The flattening's cotan Laplacian (what the interpolator passes).
  Flattener flattener(mesh);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(mesh.num_vertices());
  double shift = -1;
  SparseCholesky& cotan = flattener.factored_hessian(l2, u, &shift);
  EXPECT_EQ(shift, 0.0);
  Layout shared(mesh, /*own_system=*/false);
  Positions X1;
  double flatness = 1;
  shared.embed(l2, &cotan, 0.0, X1, &flatness);
  EXPECT_LT(flatness, 1e-12);
  EXPECT_LT(rigid_error(X1, bent), 1e-12);

  // The same matrix factorised with a large diagonal shift.
  std::vector<int> col_ptr, rows;
  const InteriorPattern pattern = interior_pattern(mesh, col_ptr, rows);
  SparseCholesky shifted(pattern.size(), col_ptr, rows);
  std::copy_n(cotan.values(), rows.size(), shifted.values());
  const double s = 1e-3;
  for (int p : pattern.diag_pos) shifted.values()[p] += s;
  shifted.factorize();
  Positions X2;
  shared.embed(l2, &shifted, s, X2);
  EXPECT_LT(rigid_error(X2, bent), 1e-12);
  EXPECT_THROW(shared.embed(l2, X2), InvalidInput);  // no system of its own
}

}  // namespace
}  // namespace bdinterp
