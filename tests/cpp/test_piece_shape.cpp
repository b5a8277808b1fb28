// Point location in one piece of a cut-out character (place/piece_shape.h) against brute force over
// every face and every outline edge, on pieces whose walks the outline stops: an L (a concave
// outline), a strip wound twice, an annulus (a hole) and a U whose walks end in the search.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "mesh/mesh.h"
#include "place/anchor_frame.h"
#include "place/piece_shape.h"
#include "test_meshes.h"

namespace bdinterp {
namespace {

using detail::PieceShape;

// A piece and what PieceShape reads of it.
struct TestPiece {
  TestPiece(const Positions& V, const Faces& F)
      : base(V), mesh(F, static_cast<int>(V.rows())), vertices(static_cast<size_t>(V.rows())) {
    std::iota(vertices.begin(), vertices.end(), 0);
  }
  JointPiece joint() const { return {&vertices, &mesh, &base, &frames}; }
  Positions base;
  Mesh mesh;
  std::vector<int> vertices;
  std::vector<Frame2> frames;
};

// [0, 1]^2 without the quads of [0.5, 1] x [0.5, 1]: an L whose notch stops straight walks.
TestPiece l_shape() {
  const testing::TestMesh grid = testing::jittered_grid(10, 10, 1.0, 1.0, 5);
  std::vector<int> keep;
  for (int f = 0; f < grid.F.rows(); ++f) {
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (int k = 0; k < 3; ++k) c += grid.V.row(grid.F(f, k)).transpose() / 3.0;
    if (c.x() < 0.5 || c.y() < 0.5) keep.push_back(f);
  }
  return TestPiece(grid.V, testing::rows_of(grid.F, keep));
}

// The weights of q in face f, as PieceShape computes them.
Eigen::Vector3d weights(const TestPiece& p, const Eigen::Vector2d& q, int f) {
  const Eigen::Vector2d a = p.base.row(p.mesh.faces()(f, 0)).transpose();
  Eigen::Matrix2d E;
  E << p.base.row(p.mesh.faces()(f, 1)).transpose() - a, p.base.row(p.mesh.faces()(f, 2)).transpose() - a;
  const Eigen::Vector2d st = E.inverse() * (q - a);
  return {1 - st.sum(), st.x(), st.y()};
}

// Brute force: the largest least weight of q over every face.
double best_weight(const TestPiece& p, const Eigen::Vector2d& q) {
  double best = -HUGE_VAL;
  for (int f = 0; f < p.mesh.num_faces(); ++f) best = std::max(best, weights(p, q, f).minCoeff());
  return best;
}

// Brute force: the distance from q to the outline.
double outline_distance(const TestPiece& p, const Eigen::Vector2d& q) {
  double best = HUGE_VAL;
  for (const std::vector<int>& loop : p.mesh.boundary_loops())
    for (size_t k = 0; k < loop.size(); ++k) {
      const Eigen::Vector2d a = p.base.row(loop[k]).transpose(), e = p.base.row(loop[(k + 1) % loop.size()]).transpose() - a;
      const double t = std::clamp((q - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
      best = std::min(best, (a + t * e - q).norm());
    }
  return best;
}

// Every query on random points (and points from one arm to the other, so that the walk from the
// last face must cross the outline) agrees with brute force.
void check_against_brute_force(const TestPiece& p, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                               int samples = 400) {
  const PieceShape shape(p.joint());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> x(lo.x(), hi.x()), y(lo.y(), hi.y());
  int inside = 0, outside = 0;
  for (int k = 0; k < samples; ++k) {
    const Eigen::Vector2d q(x(rng), y(rng));
    const double best = best_weight(p, q), distance = outline_distance(p, q);
    int face;
    Eigen::Vector3d bary;
    const double found = shape.locate(q, face, bary);
    if (best >= detail::kInside) {  // clearly inside: a face holding q is found
      ++inside;
      ASSERT_GE(face, 0) << q.transpose();
      EXPECT_GE(found, -detail::kInside);
      EXPECT_NEAR((bary - weights(p, q, face)).norm(), 0, 1e-12);
      EXPECT_TRUE(shape.contains(q)) << q.transpose();
      EXPECT_EQ(shape.outside(q, 1.0), 0.0);
    } else if (best < -1e-6) {  // clearly outside
      ++outside;
      EXPECT_EQ(face, -1) << q.transpose();
      EXPECT_FALSE(shape.contains(q));
      EXPECT_NEAR(shape.outside(q, 10.0), distance, 1e-12);
      EXPECT_EQ(shape.outside(q, 0.5 * distance), 0.5 * distance);
      shape.locate_nearest(q, face, bary);  // the face on the nearest outline edge
      ASSERT_GE(face, 0);
      double on_edge = HUGE_VAL;
      for (int c = 0; c < 3; ++c) {
        const Eigen::Vector2d a = p.base.row(p.mesh.faces()(face, c)).transpose();
        const Eigen::Vector2d e = p.base.row(p.mesh.faces()(face, (c + 1) % 3)).transpose() - a;
        on_edge = std::min(on_edge, (a + std::clamp((q - a).dot(e) / e.squaredNorm(), 0.0, 1.0) * e - q).norm());
      }
      EXPECT_NEAR(on_edge, distance, 1e-12);
    }
  }
  EXPECT_GT(inside, 100);
  EXPECT_GT(outside, 50);
}

TEST(PieceShape, LocatesInAConcavePieceAsBruteForce) {
  const TestPiece p = l_shape();
  check_against_brute_force(p, {-0.2, -0.2}, {1.2, 1.2});
  EXPECT_NEAR(PieceShape(p.joint()).diagonal(), std::sqrt(2.0), 1e-12);
}

TEST(PieceShape, WalksRoundTheNotchFromOneArmToTheOther) {
  const TestPiece p = l_shape();
  const PieceShape shape(p.joint());
  int face;
  Eigen::Vector3d bary;
  for (int k = 0; k < 20; ++k) {  // alternate between the arms' ends: each walk from the last face hits the notch
    const Eigen::Vector2d q = k % 2 ? Eigen::Vector2d(0.93, 0.21 + 0.01 * k) : Eigen::Vector2d(0.21 + 0.01 * k, 0.93);
    ASSERT_GE(shape.locate(q, face, bary), -detail::kInside);
    EXPECT_NEAR((bary - weights(p, q, face)).norm(), 0, 1e-12);
  }
}

// A strip wound twice round the origin (radius 0.3 + 0.045 theta, 0.03 wide, 4 x 160 cells):
// straight walks from the last face found meet its outline at almost every turn.
TestPiece spiral() {
  const testing::TestMesh strip = testing::jittered_grid(160, 4, 1.0, 1.0, 9);
  Positions V(strip.V.rows(), 2);
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    const double theta = 4 * kPi * strip.V(v, 0), r = 0.3 + 0.045 * theta + 0.03 * strip.V(v, 1);
    V.row(v) << r * std::cos(theta), r * std::sin(theta);
  }
  return TestPiece(V, strip.F);
}

TEST(PieceShape, LocatesInAWoundStripAsBruteForce) {
  const TestPiece p = spiral();
  check_against_brute_force(p, {-0.9, -0.9}, {0.9, 0.9}, 4000);
}

TEST(PieceShape, TheHoleIsOutside) {
  const testing::TestMesh a = testing::annulus(6, 48);
  const TestPiece p(a.V, a.F);
  check_against_brute_force(p, {-1.1, -1.1}, {1.1, 1.1});
  const PieceShape shape(p.joint());
  int face;
  Eigen::Vector3d bary;
  EXPECT_EQ(shape.locate(Eigen::Vector2d(0.05, -0.1), face, bary), -HUGE_VAL);
  EXPECT_FALSE(shape.contains(Eigen::Vector2d(0.05, -0.1)));
}

TEST(PieceShape, AVertexOnTheOutlineIsNotInside) {
  const TestPiece p = l_shape();
  const PieceShape shape(p.joint());
  for (const std::vector<int>& loop : p.mesh.boundary_loops())
    for (int v : loop) EXPECT_FALSE(shape.contains(p.base.row(v).transpose())) << "vertex " << v;
  EXPECT_TRUE(shape.contains(Eigen::Vector2d(0.25, 0.25)));
}

// A U of five triangles whose notch is a V with one vertex at its foot: that vertex's fan reaches
// from one arm round the foot to the other, so a walk from it may start in the wrong arm, meet the
// notch and end in the search of every face. Both mirror images, every point of both arms.
TEST(PieceShape, AWalkTheNotchStopsEndsInTheSearch) {
  for (const double mirror : {1.0, -1.0}) {
    Positions V(7, 2);
    V << 0, 0, 2, 0, 2, 2, 1.1, 2, 1, 0.2, 0.9, 2, 0, 2;
    Faces F(5, 3);
    F << 0, 4, 5, 0, 5, 6, 0, 1, 4, 1, 3, 4, 1, 2, 3;
    V.col(0) = (mirror * (V.col(0).array() - 1) + 1).matrix();
    if (mirror < 0) F.col(1).swap(F.col(2));  // counter-clockwise again
    const TestPiece p(V, F);
    for (double y = 0.3; y < 1.95; y += 0.05)
      for (const double x : {0.15, 0.6, 0.85, 1.15, 1.4, 1.85}) {
        const Eigen::Vector2d q(x, y);
        if (best_weight(p, q) < detail::kInside) continue;
        const PieceShape shape(p.joint());  // a fresh one each time, as the joints first meet a piece
        int face;
        Eigen::Vector3d bary;
        ASSERT_GE(shape.locate(q, face, bary), -detail::kInside) << q.transpose();
        EXPECT_NEAR((bary - weights(p, q, face)).norm(), 0, 1e-12);
      }
  }
}

// A square piece of 3 x 3 cells, side `side`, its lower left corner at `at`.
TestPiece square(const Eigen::Vector2d& at, double side) {
  const testing::TestMesh g = testing::jittered_grid(3, 3, side, side, 4);
  return TestPiece(g.V.rowwise() + at.transpose(), g.F);
}

// holds() against contains() at the square's vertices and its faces' centroids, squares of four
// sizes at random places round an L and an annulus: where it holds, every one of them is contained;
// it holds wherever the square lies farther than its own side from the holder's outline; and not
// where the holder's outline enters the square though every vertex of the square is contained
// (the notch's corner, the hole).
TEST(PieceShape, HoldsOnlyWhatItContainsEverywhere) {
  const testing::TestMesh a = testing::annulus(6, 48);
  const std::vector<TestPiece> holders{l_shape(), TestPiece(a.V, a.F)};
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> at(-1.2, 1.2);
  int held = 0, far = 0;
  for (const TestPiece& h : holders) {
    const PieceShape holder(h.joint());
    for (int k = 0; k < 1500; ++k) {
      const double side = std::vector<double>{0.02, 0.05, 0.1, 0.3}[static_cast<size_t>(k % 4)];
      const TestPiece sq = square({at(rng), at(rng)}, side);
      const PieceShape other(sq.joint());
      bool all = true;
      for (Eigen::Index v = 0; v < sq.base.rows(); ++v) all = all && holder.contains(sq.base.row(v).transpose());
      for (int f = 0; f < sq.mesh.num_faces(); ++f) {
        Eigen::Vector2d c = Eigen::Vector2d::Zero();
        for (int j = 0; j < 3; ++j) c += sq.base.row(sq.mesh.faces()(f, j)).transpose() / 3.0;
        all = all && holder.contains(c);
      }
      const bool holds = holder.holds(other);
      if (holds) ++held;
      EXPECT_TRUE(!holds || all) << "a square of side " << side << " at " << sq.base.row(0);
      const Eigen::Vector2d centre = sq.base.colwise().mean().transpose();
      if (holder.contains(centre) && outline_distance(h, centre) > 1.5 * side) {
        ++far;
        EXPECT_TRUE(holds) << "a square of side " << side << " at " << sq.base.row(0);
      }
    }
  }
  EXPECT_GT(held, 400);
  EXPECT_GT(far, 300);
  // The L's notch corner (0.5, 0.5) inside a square whose four corners lie in the L, and the
  // annulus's hole inside a square whose corners lie in its ring: every vertex is contained.
  const Faces two = (Faces(2, 3) << 0, 1, 2, 0, 2, 3).finished();
  const std::vector<std::pair<TestPiece, TestPiece>> entered{
      {l_shape(), TestPiece((Positions(4, 2) << 0.42, 0.3, 0.7, 0.42, 0.42, 0.7, 0.3, 0.42).finished(), two)},
      {TestPiece(a.V, a.F), TestPiece((Positions(4, 2) << -0.45, -0.45, 0.45, -0.45, 0.45, 0.45, -0.45, 0.45).finished(), two)}};
  for (const auto& [h, sq] : entered) {
    const PieceShape holder(h.joint()), other(sq.joint());
    for (Eigen::Index v = 0; v < sq.base.rows(); ++v) EXPECT_TRUE(holder.contains(sq.base.row(v).transpose()));
    EXPECT_FALSE(holder.holds(other));
  }
}

}  // namespace
}  // namespace bdinterp
