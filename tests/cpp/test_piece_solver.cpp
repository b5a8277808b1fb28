// The Interpolator's stages: a piece solved by its kind (disk or holed; cpp/src/pipeline/piece_solver.h) and
// frames() on the pool (contiguous chunks, errors of any chunk raised on the caller).
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "pipeline/piece_solver.h"
#include "bdinterp/interpolator.h"
#include "blend/metric_blend.h"
#include "test_meshes.h"

namespace bdinterp {
namespace {

double max_abs(const Positions& A) { return A.cwiseAbs().maxCoeff(); }

// The rows of X of the piece's vertices, in its local order.
Positions rows_of(const Positions& X, const Piece& p) {
  Positions out(p.vertices.size(), 2);
  for (size_t i = 0; i < p.vertices.size(); ++i) out.row(i) = X.row(p.vertices[i]);
  return out;
}

// A jittered 8 x 8 grid without the faces around its middle vertex: one piece with one hole.
testing::TestMesh holed_square() {
  testing::TestMesh m = testing::jittered_grid(8, 8, 1.0, 1.0, 7);
  const int middle = 4 * 9 + 4;
  Faces kept(m.F.rows(), 3);
  int n = 0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    if ((m.F.row(f).array() != middle).all()) kept.row(n++) = m.F.row(f);
  m.F = kept.topRows(n);
  return m;
}

// The plan of the mesh's one piece for inputs {V, T}, base 0, centroid anchor.
std::unique_ptr<detail::PiecePlan> plan_of(const testing::TestMesh& m, const Positions& T) {
  std::vector<Piece> pieces = split_into_pieces(Mesh(m.F, static_cast<int>(m.V.rows())));
  EXPECT_EQ(pieces.size(), 1u);
  const std::vector<Positions> local{rows_of(m.V, pieces[0]), rows_of(T, pieces[0])};
  auto plan = std::make_unique<detail::PiecePlan>(std::move(pieces[0]), local, 0, -1, false, false);
  plan->plan_solve(local, 0);
  return plan;
}

// Largest | |x_i - x_j|^2 / l2_ij - 1 | over the piece's edges.
double metric_error(const detail::PiecePlan& plan, const Positions& out, const Eigen::VectorXd& l2) {
  const Mesh& mesh = plan.piece.mesh;
  double worst = 0;
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const int i = plan.piece.vertices[mesh.edges()(e, 0)], j = plan.piece.vertices[mesh.edges()(e, 1)];
    worst = std::max(worst, std::abs((out.row(i) - out.row(j)).squaredNorm() / l2[e] - 1.0));
  }
  return worst;
}

TEST(PieceSolver, ADiskReachesItsTargetAndFlattensABlend) {
  const testing::TestMesh m = testing::jittered_grid(24, 6, 1.0, 0.25, 11);
  const Positions bent = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 2.5, 0.125); });
  const auto plan = plan_of(m, bent);
  ASSERT_FALSE(plan->holes);
  const auto solver = detail::PieceSolver::make(*plan);
  Positions out = Positions::Zero(m.V.rows(), 2);
  const detail::PieceOutcome at_target = solver->solve(Eigen::Vector2d(0, 1), {}, Anchor(), out);
  EXPECT_LT(max_abs(out - bent), 1e-9);  // the input's own metric, placed at the input's anchor
  EXPECT_LT(at_target.flatness, 1e-12);
  EXPECT_TRUE(at_target.closure.empty());
  const detail::PieceOutcome half = solver->solve(Eigen::Vector2d(0.5, 0.5), {}, Anchor(), out);
  EXPECT_LE(half.report.residual, 1e-10);
  // A bend's blend is not flat: the flattening changes lengths, by at most a few percent here.
  const Eigen::VectorXd l2 = blend_squared_lengths(plan->piece.mesh, plan->l2, Eigen::Vector2d(0.5, 0.5));
  EXPECT_GT(metric_error(*plan, out, l2), 1e-6);
  EXPECT_LT(metric_error(*plan, out, l2), 0.1);
}

TEST(PieceSolver, AHoledPieceClosesItsHoleOnAnAffineBlend) {
  const testing::TestMesh m = holed_square();
  Eigen::Matrix2d A;
  A << 1.3, 0.4, -0.2, 0.8;  // the blend of two affine metrics is an affine (flat) metric
  const Positions T = m.V * A.transpose();
  const auto plan = plan_of(m, T);
  ASSERT_TRUE(plan->holes);
  const auto solver = detail::PieceSolver::make(*plan);
  Positions out = Positions::Zero(m.V.rows(), 2);
  const Eigen::Vector2d w(0.4, 0.6);
  const detail::PieceOutcome r = solver->solve(w, {}, Anchor(), out);
  ASSERT_EQ(r.closure.size(), 1u);
  EXPECT_LT(r.closure[0], 1e-9);
  EXPECT_LT(r.flatness, 1e-9);
  const Eigen::VectorXd l2 = blend_squared_lengths(plan->piece.mesh, plan->l2, w);
  EXPECT_LT(metric_error(*plan, out, l2), 1e-9);  // the flat metric kept: an affine frame
  solver->solve(Eigen::Vector2d(0, 1), {}, Anchor(), out);
  EXPECT_LT(max_abs(rows_of(out, plan->piece) - rows_of(T, plan->piece)), 1e-9);  // not the middle vertex
}

TEST(PieceSolver, ContinuingFromAnotherSolverWarmStartsFromItsFrames) {
  const testing::TestMesh m = testing::jittered_grid(24, 6, 1.0, 0.25, 11);
  const Positions bent = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 2.5, 0.125); });
  const auto plan = plan_of(m, bent);
  const auto warm = detail::PieceSolver::make(*plan), next = detail::PieceSolver::make(*plan),
             cold = detail::PieceSolver::make(*plan);
  Positions a = Positions::Zero(m.V.rows(), 2), b = a;
  for (double t : {0.1, 0.2, 0.3, 0.4}) warm->solve(Eigen::Vector2d(1 - t, t), {}, Anchor(), a);
  next->continue_from(*warm);
  const detail::PieceOutcome continued = next->solve(Eigen::Vector2d(0.5, 0.5), {}, Anchor(), a);
  const detail::PieceOutcome fresh = cold->solve(Eigen::Vector2d(0.5, 0.5), {}, Anchor(), b);
  EXPECT_LT(continued.report.iterations, fresh.report.iterations);
  EXPECT_LT(max_abs(a - b), 1e-9 * max_abs(bent));
}

TEST(InterpolatorFrames, MoreChunksThanCoresMatchSingleFrames) {
  const testing::TestMesh m = testing::jittered_grid(24, 6, 1.0, 0.25, 11);
  const Positions bent = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 2.5, 0.125); });
  InterpolatorOptions five;
  five.threads = 5;
  Interpolator chunks({m.V, bent}, m.F, {}, five), single({m.V, bent}, m.F);
  std::vector<double> ts;
  for (int k = 0; k < 21; ++k) ts.push_back(k / 20.0);  // 5 chunks of 4 or 5 frames
  Positions seq(ts.size() * m.V.rows(), 2);
  chunks.frames(ts, seq);
  for (size_t k = 0; k < ts.size(); ++k)
    EXPECT_LT(max_abs(seq.middleRows(k * m.V.rows(), m.V.rows()) - single.at(ts[k])), 1e-8 * max_abs(bent));
  EXPECT_LT(max_abs(seq.bottomRows(m.V.rows()) - bent), 1e-9);
}

TEST(InterpolatorFrames, AChunksErrorIsRaisedOnTheCaller) {
  const testing::TestMesh m = testing::jittered_grid(24, 6, 1.0, 0.25, 11);
  const Positions bent = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 2.5, 0.125); });
  InterpolatorOptions strict;
  strict.threads = 2;
  strict.strict = true;
  strict.max_flatness = 0;  // a blend's layout is never exact: every in-between fails the check
  Interpolator I({m.V, bent}, m.F, {}, strict);
  Positions seq(8 * m.V.rows(), 2);
  try {
    I.frames({0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8}, seq);
    FAIL() << "no SolverError";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("exceeds max_flatness 0 (strict)"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace bdinterp
