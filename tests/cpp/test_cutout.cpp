// The anchor moves on the geodesic of the rigid motions between the keys. The
// expectations are analytic: a turn by t theta about the motion's fixed point.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <utility>

#include "place/anchor_frame.h"
#include "bdinterp/interpolator.h"
#include "place/rigid_motion.h"
#include "test_meshes.h"

namespace bdinterp {
namespace {

constexpr double kDeg = bdinterp::kPi / 180;

Eigen::Vector2d turned(const Eigen::Vector2d& p, double angle, const Eigen::Vector2d& pivot) {
  return Eigen::Rotation2Dd(angle) * (p - pivot) + pivot;
}

Positions turned(const Positions& V, double angle, const Eigen::Vector2d& pivot) {
  return testing::apply(V, [&](Eigen::Vector2d p) { return turned(p, angle, pivot); });
}

TEST(RigidMotion, LogThenExpIsTheMotion) {
  for (double a : {0.0, 1e-9, 0.3, -2.0, 3.0, 4.5, -5.5, 9.0}) {
    const RigidMotion m{a, Eigen::Vector2d(0.7, -1.3)};
    const RigidMotion back = exp_twist(log_motion(m));
    EXPECT_DOUBLE_EQ(back.angle, a);
    EXPECT_LT((back.shift - m.shift).norm(), 1e-14) << a;
  }
  // A whole turn that moves has no logarithm; one that does not move has (0 shift).
  EXPECT_THROW(log_motion(RigidMotion{2 * bdinterp::kPi, Eigen::Vector2d(1, 0)}), InvalidInput);
  EXPECT_EQ(log_motion(RigidMotion{4 * bdinterp::kPi, Eigen::Vector2d::Zero()}).v.norm(), 0.0);
}

TEST(RigidMotion, TwoKeysTurnAboutTheFixedPoint) {
  const Eigen::Vector2d pivot(0.4, -1.1), p0(2.0, 0.5);
  for (double theta : {0.0, 40 * kDeg, 150 * kDeg, 250 * kDeg, -300 * kDeg}) {
    const std::vector<Frame2> keys{{p0, 0.2}, {turned(p0, theta, pivot), 0.2 + theta}};
    for (double t : {0.0, 0.25, 0.5, 1.0, 1.3}) {
      const Frame2 f = geodesic_blend(keys, Eigen::Vector2d(1 - t, t), 0);
      const Frame2 g = geodesic_blend({keys[1], keys[0]}, Eigen::Vector2d(t, 1 - t), 0);  // swapped
      const Eigen::Vector2d expect = theta == 0 ? p0 : turned(p0, t * theta, pivot);
      EXPECT_LT((f.point - expect).norm(), 1e-14) << theta << " " << t;
      EXPECT_NEAR(f.angle, 0.2 + t * theta, 1e-15);
      EXPECT_LT((g.point - f.point).norm(), 1e-14);
      EXPECT_NEAR(g.angle, f.angle, 1e-15);
    }
  }
  // No turn: a translation along the chord.
  const std::vector<Frame2> slide{{p0, 0.0}, {p0 + Eigen::Vector2d(3, 1), 0.0}};
  EXPECT_LT((geodesic_blend(slide, Eigen::Vector2d(0.5, 0.5), 0).point - p0 - Eigen::Vector2d(1.5, 0.5)).norm(),
            1e-15);
}

// A 0.5 x 4 bar hanging from the middle of its top end (the origin), swung about it.
struct Pendulum : ::testing::Test {
  testing::TestMesh m = testing::jittered_grid(4, 32, 0.5, 4.0, 7);
  Pendulum() { m.V.rowwise() -= Eigen::RowVector2d(0.25, 4.0); }
  double size() const { return (m.V.colwise().maxCoeff() - m.V.colwise().minCoeff()).norm(); }
};

TEST_F(Pendulum, TurnsAboutItsPivot) {
  // Before: the pivot left the pivot by 37 % of the bar's length half way (the chord).
  // A rigid turn by 250 degrees is the same target as one by -110 (nothing in the keys tells them
  // apart): the in-betweens take the short way round, about the same pivot.
  for (const auto& [angle, path] : {std::pair{150.0, 150.0}, {250.0, -110.0}, {-200.0, 160.0}}) {
    const Positions target = turned(m.V, angle * kDeg, Eigen::Vector2d::Zero());
    Interpolator I({m.V, target}, m.F);
    for (double t : {0.0, 0.25, 0.5, 0.75, 1.0})
      EXPECT_LT((I.at(t) - turned(m.V, t * path * kDeg, Eigen::Vector2d::Zero())).cwiseAbs().maxCoeff(),
                1e-9 * size())
          << angle << " " << t;
  }
}

TEST_F(Pendulum, ShoulderPinStaysPinned) {
  // The bar as an arm over a still torso (two loose parts), swung 150 degrees about a pin inside
  // the overlap: the torso stays, the pin stays joined.
  const testing::TestMesh torso = testing::jittered_grid(8, 8, 2.0, 2.0, 3);
  const Eigen::Index n = torso.V.rows();
  Positions V(n + m.V.rows(), 2);
  V << torso.V.rowwise() + Eigen::RowVector2d(-2.0, -1.0), m.V;  // overlap x in [-0.25, 0], y in [-1, 0]
  Faces F(torso.F.rows() + m.F.rows(), 3);
  F << torso.F, m.F.array() + static_cast<int>(n);
  const Eigen::Vector2d pin(-0.1, -0.3);
  Positions T = V;
  T.bottomRows(m.V.rows()) = turned(m.V, 150 * kDeg, pin);
  Interpolator I({V, T}, F);
  for (double t = 0; t <= 1.0; t += 0.125) {
    const Positions X = I.at(t);
    EXPECT_LT((X.topRows(n) - V.topRows(n)).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LT((X.bottomRows(m.V.rows()) - turned(m.V, 150 * t * kDeg, pin)).cwiseAbs().maxCoeff(), 1e-9) << t;
  }
}

TEST_F(Pendulum, VertexAnchorKeepsThePapersLinearBlend) {
  // The paper's mode: the anchor vertex moves on the chord between its positions in the keys.
  const Positions target = turned(m.V, 150 * kDeg, Eigen::Vector2d::Zero());
  Interpolator I({m.V, target}, m.F, Anchor::at_vertex(0));
  const Positions X = I.at(0.5);
  EXPECT_LT((X.row(0) - 0.5 * (m.V.row(0) + target.row(0))).norm(), 1e-9);
}

// Torso, upper arm and forearm as loose parts: the arm is the pendulum's bar pinned to the torso at
// the shoulder, the forearm another bar pinned to the arm's lower end at the elbow.
struct Chain : Pendulum {
  Eigen::Vector2d shoulder{-0.1, -0.3}, elbow{0.0, -3.75};
  Positions V, T;
  Faces F;
  Eigen::Index torso = 0, arm = 0;  // the rows of the torso and of the arm; the forearm's follow

  Chain() {
    const testing::TestMesh body = testing::jittered_grid(8, 8, 2.0, 2.0, 3);
    torso = body.V.rows(), arm = m.V.rows();
    V.resize(torso + 2 * arm, 2);
    V << body.V.rowwise() + Eigen::RowVector2d(-2.0, -1.0), m.V, m.V.rowwise() + Eigen::RowVector2d(0.0, -3.5);
    F.resize(body.F.rows() + 2 * m.F.rows(), 3);
    F << body.F, m.F.array() + static_cast<int>(torso), m.F.array() + static_cast<int>(torso + arm);
    T = posed(1.0);
  }
  // The pose at t: the arm turned by 60 t about the shoulder, the forearm by 90 t more at the elbow.
  Positions posed(double t) const {
    Positions X = V;
    X.middleRows(torso, arm) = turned(Positions(V.middleRows(torso, arm)), 60 * t * kDeg, shoulder);
    X.bottomRows(arm) = turned(turned(Positions(V.bottomRows(arm)), 90 * t * kDeg, elbow), 60 * t * kDeg, shoulder);
    return X;
  }
};

TEST_F(Chain, JointsKeepThePinsOfEveryKey) {
  Interpolator I({V, T}, F);
  for (double t : {0.0, 0.2, 0.5, 0.8, 1.0}) EXPECT_LT((I.at(t) - posed(t)).cwiseAbs().maxCoeff(), 1e-9) << t;
  EXPECT_EQ(I.last_stats().joints, 2);
  const std::vector<Interpolator::JointInfo> found = I.joints();
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(found[0].parent_vertex, 0);
  EXPECT_EQ(found[0].child_vertex, torso);
  EXPECT_EQ(found[1].child_vertex, torso + arm);
  EXPECT_TRUE(found[0].pin && found[1].pin);
  EXPECT_LT((found[0].point - shoulder).norm(), 1e-9);
  EXPECT_LT((found[1].point - elbow).norm(), 1e-9);
  // Off: each piece turns about its own fixed point; the forearm's is not the elbow, which opens.
  InterpolatorOptions o;
  o.joints = false;
  Interpolator off({V, T}, F, {}, o);
  const Positions X = off.at(0.5);
  EXPECT_EQ(off.last_stats().joints, 0);
  EXPECT_LT((X.topRows(torso + arm) - posed(0.5).topRows(torso + arm)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_GT((X.bottomRows(arm) - posed(0.5).bottomRows(arm)).cwiseAbs().maxCoeff(), 0.1);
}

TEST_F(Chain, ThreePosesStayJoined) {
  // Pose blends: the pins hold for any weights (each piece's angle is blended relative to its parent).
  Interpolator I({V, T, posed(-0.5)}, F);
  const Eigen::Vector3d w(0.3, 0.5, 0.2);
  EXPECT_LT((I.blend(w) - posed(0.5 * 1.0 - 0.2 * 0.5)).cwiseAbs().maxCoeff(), 1e-9);
}

TEST_F(Chain, AVertexAnchorRootsItsGroup) {
  // The anchor vertex is on the forearm: the forearm keeps the paper's linear path of that vertex
  // and the arm and torso are placed from it.
  const int v = static_cast<int>(torso + arm);
  Interpolator I({V, T}, F, Anchor::at_vertex(v));
  const Positions X = I.at(0.5);
  EXPECT_LT((X.row(v) - 0.5 * (V.row(v) + T.row(v))).norm(), 1e-9);
  EXPECT_EQ(I.last_stats().joints, 2);
}

TEST_F(Chain, WithoutTheTorsoTheArmRootsTheChain) {
  // Joined to nothing still, the chain is rooted at the piece whose own motion is a turn about a
  // point inside it (the arm, about the shoulder), not at the forearm, which turns more.
  const Eigen::Index n = 2 * arm;
  Faces G = F.bottomRows(2 * m.F.rows()).array() - static_cast<int>(torso);
  const Positions X0 = V.bottomRows(n), X1 = T.bottomRows(n);
  Interpolator I({X0, X1}, G);
  for (double t : {0.25, 0.5, 0.75}) EXPECT_LT((I.at(t) - posed(t).bottomRows(n)).cwiseAbs().maxCoeff(), 1e-9) << t;
  const std::vector<Interpolator::RootInfo> roots = I.joint_roots();
  ASSERT_EQ(roots.size(), 1u);
  EXPECT_EQ(roots[0].vertex, 0);
  EXPECT_EQ(roots[0].reason, RootReason::Turns);
  EXPECT_LT((roots[0].point - shoulder).norm(), 1e-9);
}

TEST(Cutout, EyesStayOnATiltedHead) {
  // A 4 x 5 head and two eyes laid over it, all tilted by 40 degrees about the neck (the middle of
  // the head's lower edge): every in-between is the drawing tilted by 40 t (before: the eyes slid
  // by 1.2 % of the size half way).
  const testing::TestMesh head = testing::jittered_grid(8, 10, 4.0, 5.0, 4);
  const testing::TestMesh eye = testing::jittered_grid(3, 3, 0.6, 0.6, 5);
  const Eigen::Index h = head.V.rows(), e = eye.V.rows();
  Positions V(h + 2 * e, 2);
  V << head.V.rowwise() + Eigen::RowVector2d(-2.0, 0.0), eye.V.rowwise() + Eigen::RowVector2d(-1.3, 3.0),
      eye.V.rowwise() + Eigen::RowVector2d(0.7, 3.0);
  Faces F(head.F.rows() + 2 * eye.F.rows(), 3);
  F << head.F, eye.F.array() + static_cast<int>(h), eye.F.array() + static_cast<int>(h + e);
  Interpolator I({V, turned(V, 40 * kDeg, Eigen::Vector2d::Zero())}, F);
  for (double t = 0; t <= 1.0; t += 0.125)
    EXPECT_LT((I.at(t) - turned(V, 40 * t * kDeg, Eigen::Vector2d::Zero())).cwiseAbs().maxCoeff(), 1e-9) << t;
  EXPECT_EQ(I.last_stats().joints, 2);
}

}  // namespace
}  // namespace bdinterp
