#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "place/anchor_frame.h"
#include "bdinterp/baselines.h"
#include "bdinterp/distortion.h"
#include "bdinterp/interpolator.h"
#include "blend/metric_blend.h"
#include "parallel/parallel.h"
#include "test_meshes.h"

namespace bdinterp {
namespace {

double max_abs(const Positions& A) { return A.cwiseAbs().maxCoeff(); }

struct Bar : ::testing::Test {
  testing::TestMesh m = testing::jittered_grid(24, 6, 1.0, 0.25, 11);
  Positions bent = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 2.5, 0.125); });
};

TEST_F(Bar, ReproducesSourceAndTarget) {
  Interpolator I({m.V, bent}, m.F);
  EXPECT_LT(max_abs(I.at(0.0) - m.V), 1e-9 * max_abs(m.V));
  EXPECT_LT(max_abs(I.at(1.0) - bent), 1e-9 * max_abs(bent));
  I.at(0.5);
  EXPECT_LE(I.last_stats().residual, 1e-10);
  EXPECT_LT(I.last_stats().flatness, 1e-10);
}

TEST_F(Bar, SymmetricUnderSwap) {
  Interpolator forward({m.V, bent}, m.F), backward({bent, m.V}, m.F);
  const Mesh mesh(m.F, static_cast<int>(m.V.rows()));
  for (double t : {0.2, 0.5, 0.7}) {
    const Eigen::VectorXd a = squared_edge_lengths(mesh, forward.at(t));
    const Eigen::VectorXd b = squared_edge_lengths(mesh, backward.at(1 - t));
    EXPECT_LT(((a - b).array() / a.array()).abs().maxCoeff(), 1e-9) << t;
  }
}

TEST_F(Bar, AffineTargetGivesAffineFrames) {
  Eigen::Matrix2d A;
  A << 1.7, 0.4, -0.3, 0.6;
  const Positions target = (m.V * A.transpose()).rowwise() + Eigen::RowVector2d(0.3, -2.0);
  Interpolator I({m.V, target}, m.F);
  for (double t : {0.25, 0.5, 0.9}) {
    const Positions X = I.at(t);
    // Least-squares affine fit X ~ [V 1] M; the residual must vanish.
    Eigen::MatrixXd V1(m.V.rows(), 3);
    V1 << m.V, Eigen::VectorXd::Ones(m.V.rows());
    const Eigen::MatrixXd M = V1.colPivHouseholderQr().solve(Eigen::MatrixXd(X));
    EXPECT_LT((V1 * M - X).cwiseAbs().maxCoeff(), 1e-9) << t;
    EXPECT_EQ(I.last_stats().iterations, 0);  // the blended metric is already flat
  }
}

TEST_F(Bar, ClockwiseInputGivesTheSameGeometry) {
  Faces cw = m.F;
  cw.col(1).swap(cw.col(2));
  Interpolator ccw_I({m.V, bent}, m.F), cw_I({m.V, bent}, cw);
  EXPECT_LT(max_abs(ccw_I.at(0.4) - cw_I.at(0.4)), 1e-9);
}

TEST_F(Bar, VertexAnchorFollowsTheLinearPath) {
  const int v = 5;
  Interpolator I({m.V, bent}, m.F, Anchor::at_vertex(v));
  for (double t : {0.0, 0.3, 1.0}) {
    const Positions X = I.at(t);
    EXPECT_LT((X.row(v) - ((1 - t) * m.V.row(v) + t * bent.row(v))).norm(), 1e-12) << t;
  }
  EXPECT_LT(max_abs(I.at(1.0) - bent), 1e-9);
}

TEST_F(Bar, PathAnchorKeepsEndsExactAndFollowsThePath) {
  AnchorPath path;
  path.t = {0.0, 0.5, 1.0};
  path.position.resize(3, 2);
  path.position << 0, 0, 0, 3, 0, 0;  // a detour: up by 3 at t = 0.5
  path.angle = {0.0, 0.0, 0.0};
  Interpolator with({m.V, bent}, m.F, Anchor::along(path)), without({m.V, bent}, m.F);
  EXPECT_LT(max_abs(with.at(0.0) - m.V), 1e-9);
  EXPECT_LT(max_abs(with.at(1.0) - bent), 1e-9);
  const Positions d = with.at(0.5) - without.at(0.5);
  EXPECT_LT((d.rowwise() - Eigen::RowVector2d(0, 3)).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Interpolator, LargeRotationTurnsHalfWayAtHalfTime) {
  // Bend a thin bar by 1.6 pi (288 degrees): the tip turns past 180 degrees; at t = 0.5 it must
  // have turned by about half (not the short way round).
  const auto m = testing::jittered_grid(60, 4, 1.0, 0.08, 9);
  const Positions curled =
      testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 1.6 * bdinterp::kPi, 0.04); });
  Interpolator I({m.V, curled}, m.F);
  const Mesh mesh(m.F, static_cast<int>(m.V.rows()));
  const AnchorFrame frame(mesh, m.V, -1);
  const Eigen::VectorXd rot1 = frame.bulk_rotations(curled);
  const Eigen::VectorXd rot_half = frame.bulk_rotations(I.at(0.5));
  const Eigen::VectorXd rot_next = frame.bulk_rotations(I.at(0.52));
  // Turn of the far (right) end relative to the near (left) end.
  int left = 0, right = 0;
  for (int f = 0; f < m.F.rows(); ++f) {
    const double x = m.V(m.F(f, 0), 0);
    if (x < m.V(m.F(left, 0), 0)) left = f;
    if (x > m.V(m.F(right, 0), 0)) right = f;
  }
  const double full = rot1[right] - rot1[left], half = rot_half[right] - rot_half[left];
  EXPECT_GT(full, 1.5 * bdinterp::kPi);
  EXPECT_NEAR(half / full, 0.5, 0.05);
  // Continuity in t: a small step moves every face's rotation a little.
  EXPECT_LT((rot_next - rot_half).cwiseAbs().maxCoeff(), 0.1);
}

TEST(Interpolator, PiecesAndIsolatedVerticesAreHandledSeparately) {
  const auto a = testing::jittered_grid(6, 6, 1.0, 1.0, 2);
  const int n = static_cast<int>(a.V.rows());
  Positions V(2 * n + 1, 2), T(2 * n + 1, 2);
  Eigen::Matrix2d R;
  R << 0, -1, 1, 0;
  const Positions bent = testing::apply(a.V, [](Eigen::Vector2d p) { return testing::bend(p, 1.5, 0.5); });
  V << a.V, (a.V.rowwise() + Eigen::RowVector2d(5, 0)), Eigen::RowVector2d(9, 9);
  T << bent, (a.V * R.transpose()).rowwise() + Eigen::RowVector2d(5, 0), Eigen::RowVector2d(7, 7);
  Faces F(2 * a.F.rows(), 3);
  F << a.F, (a.F.array() + n).matrix();
  Interpolator I({V, T}, F);
  const Positions X = I.at(0.5);
  EXPECT_EQ(I.last_stats().pieces, 2);
  // Second piece: rigidly rotated by 90 degrees, so at t = 0.5 it is rotated by 45 degrees.
  const Positions second = X.middleRows(n, n);
  const Eigen::RowVector2d c = second.colwise().mean();
  const Eigen::Matrix2d R45 = Eigen::Rotation2Dd(bdinterp::kPi / 4).toRotationMatrix();
  const Eigen::RowVector2d c0 = a.V.colwise().mean();
  const Positions expected = ((a.V.rowwise() - c0) * R45.transpose()).rowwise() + c;
  EXPECT_LT(max_abs(second - expected), 1e-9);
  // The isolated vertex moves linearly.
  EXPECT_LT((X.row(2 * n) - Eigen::RowVector2d(8, 8)).norm(), 1e-12);
}

TEST(Interpolator, ThreadCountDoesNotChangeTheFrames) {
  // Big enough for the face loops of one frame to be split over the cores.
  const auto m = testing::jittered_grid(80, 20, 1.0, 0.25, 5);
  const Positions bent = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 3.0, 0.125); });
  Interpolator all({m.V, bent}, m.F), one({m.V, bent}, m.F);
  one.set_threads(1);
  const std::vector<double> ts{0.2, 0.21, 0.22, 0.3, 0.5, 0.7, 0.9, 0.95};  // a worker per core in frames()
  for (double t : ts) {
    const Positions a = all.at(t), b = one.at(t);
    EXPECT_LT(max_abs(a - b), 1e-10 * max_abs(bent)) << "t = " << t;
    EXPECT_LE(all.last_stats().residual, 1e-10);
  }
  // A baked sequence (one frame per worker) agrees with single frames too, up to the solver's
  // tolerance (other warm starts converge to other points within it).
  Positions seq(ts.size() * m.V.rows(), 2);
  all.forget();
  all.frames(ts, seq);
  for (size_t k = 0; k < ts.size(); ++k)
    EXPECT_LT(max_abs(seq.middleRows(k * m.V.rows(), m.V.rows()) - one.at(ts[k])), 1e-8 * max_abs(bent));
}

TEST(Interpolator, FramesRunTheWorkersAskedForEachOnAThread) {
  // threads = 8 on a machine of fewer cores: a sequence of 8 frames runs on 8 threads, one worker
  // each; never more workers than frames; a single frame's loops run on at most the usable cores.
  const auto m = testing::jittered_grid(40, 10, 1.0, 0.25, 5);
  const Positions bent = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 2.0, 0.125); });
  InterpolatorOptions options;
  options.threads = 8;
  Interpolator I({m.V, bent}, m.F, {}, options);
  const std::vector<double> eight{0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8}, five{0.1, 0.3, 0.5, 0.7, 0.9};
  Positions out(eight.size() * m.V.rows(), 2);
  I.frames(eight, out);
  EXPECT_EQ(I.last_stats().threads, 8);
  EXPECT_TRUE(I.last_stats().converged);
  I.frames(five, out.topRows(five.size() * m.V.rows()));
  EXPECT_EQ(I.last_stats().threads, 5);
  I.set_threads(3);
  I.frames(eight, out);
  EXPECT_EQ(I.last_stats().threads, 3);
  I.set_threads(1);
  I.frames(eight, out);
  EXPECT_EQ(I.last_stats().threads, 1);
  I.set_threads(0);
  I.at(0.5);
  EXPECT_GE(I.last_stats().threads, 1);
  EXPECT_LE(I.last_stats().threads, parallel::usable_cores());
}

TEST(Interpolator, MultiTargetReproducesEveryInput) {
  const auto m = testing::jittered_grid(10, 5, 1.0, 0.4, 3);
  const Positions b1 = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 1.0, 0.2); });
  const Positions b2 = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, -2.0, 0.2); });
  for (int base : {0, 1, 2}) {
    InterpolatorOptions opt;
    opt.base = base;
    Interpolator I({m.V, b1, b2}, m.F, {}, opt);
    EXPECT_LT(max_abs(I.blend(Eigen::Vector3d(0, 1, 0)) - b1), 1e-9);
    EXPECT_LT(max_abs(I.blend(Eigen::Vector3d(0, 0, 1)) - b2), 1e-9);
    EXPECT_LT(max_abs(I.blend(Eigen::Vector3d(1, 0, 0)) - m.V), 1e-9);
  }
}

TEST(Interpolator, InvalidInputIsRejectedWithNames) {
  const auto m = testing::jittered_grid(4, 4);
  Positions bad = m.V;
  bad(7, 1) = std::nan("");
  EXPECT_THROW(Interpolator({m.V, bad}, m.F), InvalidInput);
  Positions collapsed = m.V;
  collapsed.row(m.F(3, 1)) = collapsed.row(m.F(3, 0));
  try {
    Interpolator({m.V, collapsed}, m.F);
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "shape 1, face 3: zero area");
  }
  Interpolator I({m.V, (m.V * 3.0).eval()}, m.F);
  EXPECT_THROW(I.blend(Eigen::Vector2d(0.5, 0.6)), InvalidInput);  // weights do not sum to 1
  Eigen::Matrix2d S;
  S << 3, 0, 0, 0.3;
  Interpolator stretch({m.V, (m.V * S).eval()}, m.F);
  EXPECT_NO_THROW(stretch.at(1.05));  // mild extrapolation is fine
  try {
    stretch.at(-2.0);  // (3 - 9t... ) the blended y-lengths become negative
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("invalid metric"), std::string::npos) << e.what();
    EXPECT_GE(e.where().face, 0);
  }
}

TEST(Baselines, ArapAndLinearReproduceTheInputs) {
  const auto m = testing::jittered_grid(12, 4, 1.0, 0.3, 5);
  const Positions bent = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 2.0, 0.15); });
  ArapInterpolator arap(m.V, bent, m.F);
  EXPECT_LT(max_abs(arap.at(0.0) - m.V), 1e-9);
  EXPECT_LT(max_abs(arap.at(1.0) - bent), 1e-9);
  EXPECT_LT(max_abs(linear_interpolate(m.V, bent, 0.25) - (0.75 * m.V + 0.25 * bent)), 1e-15);
}

TEST(Distortion, AnalyticValues) {
  const auto m = testing::jittered_grid(5, 5);
  Eigen::Matrix2d A;
  A << 2, 0, 0, 0.5;  // K = 4 everywhere, area ratio 1
  const Positions X = m.V * A.transpose();
  const Eigen::VectorXd K = conformal_distortion(m.V, X, m.F);
  EXPECT_LT((K.array() - 4.0).abs().maxCoeff(), 1e-12);
  EXPECT_LT((area_ratio(m.V, X, m.F).array() - 1.0).abs().maxCoeff(), 1e-12);
  Positions mirrored = m.V;
  mirrored.col(0) *= -1;
  EXPECT_LT(area_ratio(m.V, mirrored, m.F).maxCoeff(), 0.0);
  EXPECT_EQ(flipped_faces(m.V, mirrored, m.F), m.F.rows());
  EXPECT_EQ(flipped_faces(m.V, X, m.F), 0);
}

}  // namespace
}  // namespace bdinterp
