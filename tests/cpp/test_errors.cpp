// InvalidInput says where (shape, face, vertex) apart from what, and a tolerance
// no double can reach is refused before any Newton step.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>

#include "bdinterp/interpolator.h"
#include "mesh/mesh.h"
#include "test_checks.h"
#include "test_meshes.h"

namespace bdinterp {
namespace {

// The InvalidInput that fn throws (fails the test, and returns an empty one, if none).
template <typename Fn>
InvalidInput invalid_of(Fn fn) {
  try {
    fn();
  } catch (const InvalidInput& e) {
    return e;
  }
  ADD_FAILURE() << "no InvalidInput";
  return InvalidInput("none");
}

void expect_at(const InvalidInput& e, int shape, int face, int vertex) {
  EXPECT_EQ(e.where().shape, shape) << e.what();
  EXPECT_EQ(e.where().face, face) << e.what();
  EXPECT_EQ(e.where().vertex, vertex) << e.what();
}

TEST(Errors, TheMessageIsTheLocationThenTheDetail) {
  const InvalidInput at(Where{1, 12, 7}, "broken");
  EXPECT_EQ(std::string(at.what()), "shape 1, face 12, vertex 7: broken");
  EXPECT_EQ(at.detail(), "broken");
  EXPECT_EQ(std::string(InvalidInput(Where::of_vertex(3), "x").what()), "vertex 3: x");
  const InvalidInput nowhere("no shapes");
  EXPECT_EQ(std::string(nowhere.what()), "no shapes");
  EXPECT_TRUE(nowhere.where().empty());
  EXPECT_THROW(throw at, std::invalid_argument);  // what callers caught before
}

TEST(Errors, MeshErrorsNameTheFaceOrVertex) {
  Faces out(1, 3), bowtie(2, 3);
  out << 0, 1, 5;
  bowtie << 0, 1, 2, 0, 3, 4;  // two triangles sharing only vertex 0
  const InvalidInput e = invalid_of([&] { Mesh(out, 3); });
  expect_at(e, -1, 0, -1);
  EXPECT_EQ(e.detail(), "vertex index 5 out of range [0, 3)");
  expect_at(invalid_of([&] { Mesh(bowtie, 5); }), -1, -1, 0);
}

TEST(Errors, ShapeErrorsNameTheShapeAndTheFaceOrVertex) {
  const auto m = testing::jittered_grid(4, 3);  // 20 vertices
  Positions nan = m.V, collapsed = m.V;
  nan(9, 0) = std::nan("");
  collapsed.row(m.F(5, 2)) = collapsed.row(m.F(5, 0));
  expect_at(invalid_of([&] { Interpolator({m.V, nan}, m.F); }), 1, -1, 9);
  const InvalidInput e = invalid_of([&] { Interpolator({m.V, m.V, collapsed}, m.F); });
  EXPECT_EQ(e.where().shape, 2);
  // Only a face of the moved vertex can have lost its area.
  EXPECT_TRUE(m.F.row(e.where().face).cwiseEqual(m.F(5, 2)).any()) << e.what();
  EXPECT_EQ(e.detail(), "zero area");
  const Positions mirrored = m.V * Eigen::Vector2d(-1, 1).asDiagonal();
  expect_at(invalid_of([&] { Interpolator({m.V, mirrored}, m.F); }), 1, -1, -1);
}

TEST(Errors, AnAnchorVertexOutOfRangeIsNamedOnce) {
  const auto m = testing::jittered_grid(4, 3);
  const InvalidInput e = invalid_of([&] { Interpolator({m.V, m.V}, m.F, Anchor::at_vertex(20)); });
  expect_at(e, -1, -1, 20);
  EXPECT_EQ(std::string(e.what()), "vertex 20: the anchor vertex is out of range [0, 20) (-1: the centroid)");
}

TEST(Errors, AToleranceBelowTheSpacingOfDoublesAt2PiIsRefusedAtOnce) {
  // The fuzzer's finding: 20 vertices, tol = 1.9e-304, 24,739 iterations ran a second of futile
  // Newton steps before the SolverError.
  const auto m = testing::jittered_grid(4, 3);
  const Positions target = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 1.0); });
  InterpolatorOptions o;
  o.flatten.tolerance = 1.9e-304;
  o.flatten.max_iterations = 24739;
  const auto start = std::chrono::steady_clock::now();
  const InvalidInput e = invalid_of([&] { Interpolator({m.V, target}, m.F, Anchor(), o).at(0.5); });
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(ms, 10.0);
  EXPECT_NE(std::string(e.what()).find("tolerance 1.9e-304 is below 8.88e-16"), std::string::npos) << e.what();
  o.flatten.tolerance = std::ldexp(1.0, -50) * 0.99;
  EXPECT_THROW(Interpolator({m.V, target}, m.F, Anchor(), o), InvalidInput);
  o.flatten.tolerance = 1e-14;  // reachable: solves
  Interpolator I({m.V, target}, m.F, Anchor(), o);
  I.at(0.5);
  EXPECT_TRUE(I.last_stats().converged);
  EXPECT_LE(I.last_stats().residual, 1e-14);
}

}  // namespace
}  // namespace bdinterp
