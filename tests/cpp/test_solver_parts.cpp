// The flattening's internal parts on their own: the refactorisation policy, the warm-start
// predictor, and the Cholesky factors that every thread's workspace computes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <thread>

#include "flatten/refactor_policy.h"
#include "mesh/turns.h"
#include "flatten/warm_start.h"
#include "flatten/flatten.h"
#include "blend/metric_blend.h"
#include "test_meshes.h"

namespace bdinterp {
namespace {

TEST(RefactorPolicy, CostModelsCountSteps) {
  // Contraction 0.09 per chord step from 1e-2 to 1e-10: 8 steps (0.09^8 = 4.3e-9).
  EXPECT_DOUBLE_EQ(detail::chord_cost(1e-2, 1e-10, 0.09, 5.0), 40.0);
  EXPECT_TRUE(std::isinf(detail::chord_cost(1e-2, 1e-10, 0.5, 5.0)));
  // Newton r -> r^2: 1e-2 -> 1e-4 (one step, 100), then chords contracting by 1e-2: 1e-4 -> 1e-10
  // in 3 steps (3 < 100).
  EXPECT_DOUBLE_EQ(detail::newton_cost(1e-2, 1e-10, 1.0, 100.0, 1.0), 103.0);
  // Chords costing as much as Newton steps: Newton all the way, 1e-2 -> 1e-4 -> 1e-8 -> 1e-16.
  EXPECT_DOUBLE_EQ(detail::newton_cost(1e-2, 1e-10, 1.0, 100.0, 100.0), 300.0);
}

TEST(RefactorPolicy, ChordsWhileTheyAreCheaperThanAFactorisation) {
  // factor 1000, solve 10, product 2, evaluation 20 flops: a chord step costs 30 before any is seen.
  detail::RefactorPolicy p(1000, 10, 2, 20);
  EXPECT_TRUE(p.prefer_chord(1e-6, 1e-10, 0.01));   // 2 chords (60) < a Newton step (1030)
  EXPECT_FALSE(p.prefer_chord(1e-6, 1e-10, 0.6));   // too slow a contraction
  detail::RefactorPolicy cheap_factor(0, 10, 2, 20);
  EXPECT_FALSE(cheap_factor.prefer_chord(1e-6, 1e-10, 0.01));  // a Newton step (30) beats 2 chords
  // Chord steps that need 100 CG iterations (101 * 12 + 20 = 1232 flops): 2 of them cost more than
  // the Newton step that finishes at once (1000 + 1232): Newton preferred.
  p.chord_attempt(100);
  EXPECT_FALSE(p.prefer_chord(1e-6, 1e-10, 0.01));
  // The quadratic model: a full Newton step 1e-3 -> 1e-5 gives c = 10.
  p.full_newton_step(1e-3, 1e-5);
  EXPECT_DOUBLE_EQ(p.newton_constant(), 10.0);
}

TEST(RefactorPolicy, SkiRentalRefactorisesOnceStaleIterationsCostAFactorisation) {
  detail::RefactorPolicy p(1000, 10, 2, 20);
  // Each chord step with 5 CG iterations wastes 4 over a fresh factor: 4 * 12 = 48 flops.
  int steps = 0;
  while (!p.chord_accepted(5)) ++steps;
  EXPECT_EQ(steps, 20);  // 21 * 48 = 1008 >= 1000 > 20 * 48
  p.refactorised();
  EXPECT_FALSE(p.chord_accepted(5));
  // Iterations a fresh factor needs as well cost nothing.
  detail::RefactorPolicy q(1000, 10, 2, 20);
  for (int k = 0; k < 1000; ++k) EXPECT_FALSE(q.chord_accepted(detail::RefactorPolicy::kFreshIterations));
}

// u(t) with polynomial coordinates of the given degree, at weights (1 - t, t).
Eigen::VectorXd polynomial_u(const Eigen::MatrixXd& coefficients, double t) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(coefficients.rows());
  for (Eigen::Index k = coefficients.cols() - 1; k >= 0; --k) u = u * t + coefficients.col(k);
  return u;
}

TEST(WarmStart, PredictorIsExactOnPolynomialsUpToDegreeFive) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> d(-1, 1);
  for (int degree = 0; degree <= 6; ++degree) {
    Eigen::MatrixXd c(30, degree + 1);
    for (Eigen::Index i = 0; i < c.size(); ++i) c.data()[i] = d(rng);
    detail::History h;
    for (int j = 0; j < 6; ++j) {  // a slider: t = 0.10, 0.15, ..., 0.35, then predict 0.40
      const double t = 0.1 + 0.05 * j;
      h.add(Eigen::Vector2d(1 - t, t), polynomial_u(c, t));
    }
    Eigen::VectorXd u;
    h.predict(Eigen::Vector2d(0.6, 0.4), u);
    const double err = (u - polynomial_u(c, 0.4)).cwiseAbs().maxCoeff();
    if (degree <= 5) {
      EXPECT_LT(err, 1e-12) << "degree " << degree;
    } else {
      EXPECT_GT(err, 1e-6) << "degree 6 cannot be exact from 6 frames";
    }
  }
}

TEST(WarmStart, InputsAndEmptyHistoryStartFromZero) {
  detail::History h;
  Eigen::VectorXd u = Eigen::VectorXd::Ones(4);
  h.predict(Eigen::Vector2d(0.5, 0.5), u);
  EXPECT_EQ(u.cwiseAbs().maxCoeff(), 0.0);
  h.add(Eigen::Vector2d(0.5, 0.5), Eigen::VectorXd::Ones(4));
  h.predict(Eigen::Vector2d(0.0, 1.0), u);  // an input shape: its own metric is flat
  EXPECT_EQ(u.cwiseAbs().maxCoeff(), 0.0);
  h.predict(Eigen::Vector2d(0.6, 0.4), u);  // one frame: the nearest solution
  EXPECT_EQ(u, Eigen::VectorXd::Ones(4));
}

TEST(SparseCholesky, EveryWorkspaceFactorisesAsLLtOnAnyThread) {
  // Workspaces share one analysis; each must factorise the way configure() sets (LL', as chosen
  // for speed), including on worker threads.
  const auto m = testing::jittered_grid(30, 30, 1.0, 1.0, 8);
  const Mesh mesh(m.F, static_cast<int>(m.V.rows()));
  const auto plan = std::make_shared<const FlattenPlan>(mesh);
  const Eigen::VectorXd l2 = squared_edge_lengths(mesh, m.V), u = Eigen::VectorXd::Zero(mesh.num_vertices());
  Flattener main(plan);
  double shift = -1;
  SparseCholesky& mine = main.factored_hessian(l2, u, &shift);
  EXPECT_TRUE(mine.factor_is_ll());
  EXPECT_EQ(shift, 0.0);
  Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(plan->num_interior(), -1, 1), x0(b.size()), x1(b.size());
  mine.solve(b.data(), x0.data());
  bool worker_ll = false;
  std::thread worker([&] {
    Flattener other(plan);
    double s = -1;
    SparseCholesky& theirs = other.factored_hessian(l2, u, &s);
    worker_ll = theirs.factor_is_ll();
    theirs.solve(b.data(), x1.data());
  });
  worker.join();
  EXPECT_TRUE(worker_ll);
  EXPECT_EQ((x0 - x1).cwiseAbs().maxCoeff(), 0.0);  // the same factorisation, bit for bit
}

TEST(Turns, ChunksCombineToTheSameAngleSum) {
  // A vertex's corners split over chunks: each chunk's running product, multiplied together with
  // combine_turns, must give the angle sum of one running product over all corners (and of the
  // half-angles summed directly), including products exactly on the axes (right angles: factor
  // (1, 1)) and sums of several turns.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> half_angle(1e-9, 1.5707963);
  for (int trial = 0; trial < 4000; ++trial) {
    const int corners = 1 + static_cast<int>(rng() % 24), chunks = 1 + static_cast<int>(rng() % 5);
    const bool right = trial % 3 == 0;
    double exact = 0, one_re = 1, one_im = 0, one_sum = 0;
    std::vector<double> re(chunks, 1.0), im(chunks, 0.0), sum(chunks, 0.0);
    for (int c = 0; c < corners; ++c) {
      const double h = right ? 0.78539816339744830962 : half_angle(rng);
      const double a = right ? 1.0 : std::cos(h), b = right ? 1.0 : std::sin(h);
      exact += h;
      detail::turn(one_re, one_im, one_sum, a, b);
      const int k = static_cast<int>(rng() % chunks);
      detail::turn(re[k], im[k], sum[k], a, b);
    }
    double r = re[0], i = im[0], total = sum[0];
    for (int k = 1; k < chunks; ++k) {
      total += sum[k];
      detail::combine_turns(r, i, total, re[k], im[k]);
    }
    const double combined = total + detail::argument(r, i), single = one_sum + detail::argument(one_re, one_im);
    ASSERT_NEAR(single, exact, 1e-9) << "trial " << trial;
    ASSERT_NEAR(combined, exact, 1e-9) << "trial " << trial << ", " << corners << " corners in " << chunks << " chunks";
  }
}

}  // namespace
}  // namespace bdinterp
