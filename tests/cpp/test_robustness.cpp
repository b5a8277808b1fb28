// On the C++ side: no hidden state, self-checks, scale invariance, parameter validation,
// concurrent use.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <thread>

#include "bdinterp/baselines.h"
#include "bdinterp/distortion.h"
#include "bdinterp/interpolator.h"
#include "test_checks.h"
#include "test_meshes.h"

namespace bdinterp {
namespace {

double max_abs(const Positions& A) { return A.cwiseAbs().maxCoeff(); }
using testing::expect_invalid;

// A disk whose middle is twisted by up to `turns` radians: blends towards it end with triangles
// that violate the triangle inequality in the flattened metric (from t ~ 0.75 on). The twisted
// shape folds 30 of its 200 faces; the tests solve it without the fold path (options.folds =
// false), which cuts out and fills that region and then meets no broken triangle.
struct Twist : ::testing::Test {
  testing::TestMesh m = testing::jittered_grid(10, 10, 1.0, 1.0, 3);
  Positions twisted = twist(8.0);
  Positions twist(double turns) const {
    return testing::apply(m.V, [turns](Eigen::Vector2d p) {
      const Eigen::Vector2d c = p - Eigen::Vector2d(0.5, 0.5);
      const double a = turns * std::max(0.0, 0.5 - c.norm());
      return Eigen::Vector2d(std::cos(a) * c.x() - std::sin(a) * c.y(), std::sin(a) * c.x() + std::cos(a) * c.y());
    });
  }
};

struct BentBar : ::testing::Test {
  testing::TestMesh m = testing::jittered_grid(24, 6, 1.0, 0.25, 11);
  Positions bent = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 2.5, 0.125); });
};

// Largest extent of a shape: the history tests' 2e-12 is relative to it.
double extent(const Positions& V) { return (V.colwise().maxCoeff() - V.colwise().minCoeff()).maxCoeff(); }

// The options of the tests that need the Twist's broken triangles: the defaults without the fold
// path (which cuts the Twist's folded faces out and then meets no broken triangle).
InterpolatorOptions without_folds() {
  InterpolatorOptions o;
  o.folds = false;
  return o;
}

// What a replayed history measured: the worst deviation from fresh frames (relative to the size),
// how many frames were compared, and how many of them are ill-conditioned (see below).
struct History {
  double worst = 0;
  int frames = 0, ill_conditioned = 0;
};

// Replays a random history of `calls` calls of at, blend and frames on one Interpolator with the
// DEFAULT options and compares every frame with a fresh Interpolator's frame for the same weights:
// equal to 2e-12 of the size, or to twice the frame's own conditioning if that is worse (how far
// a fresh frame moves when a weight moves by 4 ulps: a frame on the verge of broken triangles has
// a roundoff floor in the residual ~5e-13 that the layout amplifies to ~2e-12 of the size; no
// start can do better there; the probe can miss it: 1.3e-12 where it measured 3.6e-13, with
// SuiteSparse 7.14's orderings, on both sides). Weights are (1 - t, t) for two shapes, points of the simplex for
// more; each call either jumps (to one of `ts` for two shapes) or moves a slider by 0.01 from the
// last weights, where warm starts and reused factorisations matter most.
// The weights of a random history: each call either jumps (to one of `ts` for two shapes, to a uniform
// point of the simplex for more) or moves a slider by 0.01 from the last weights.
class RandomWeights {
 public:
  RandomWeights(int k, const std::vector<double>& ts, unsigned seed)
      : k_(k), ts_(ts), rng_(seed), w_(Eigen::VectorXd::Unit(k, 0)), dir_(Eigen::VectorXd::Zero(k)) {}
  int pick(int n) { return static_cast<int>(rng_() % static_cast<unsigned>(n)); }
  const Eigen::VectorXd& next() {
    if (pick(2) == 0) {
      jump();
    } else {
      if ((w_ + dir_).minCoeff() < 0) dir_ = -dir_;
      w_ += dir_;
    }
    if (k_ == 2) w_[0] = 1.0 - w_[1];
    return w_;
  }

 private:
  void jump() {
    if (k_ == 2) {
      w_[1] = ts_[pick(static_cast<int>(ts_.size()))];
    } else {
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      for (int i = 0; i < k_; ++i) w_[i] = -std::log(1.0 - unit(rng_));
      w_ /= w_.sum();
    }
    const int a = pick(k_), b = (a + 1 + pick(k_ - 1)) % k_;
    dir_ = Eigen::VectorXd::Zero(k_);
    dir_[a] = -0.01;
    dir_[b] = 0.01;
  }

  int k_;
  std::vector<double> ts_;
  std::mt19937 rng_;
  Eigen::VectorXd w_, dir_;
};

History expect_history_free(const std::vector<Positions>& shapes, const Faces& F, const std::vector<double>& ts,
                            unsigned seed, int calls, const InterpolatorOptions& options = {}) {
  const double size = extent(shapes[0]);
  const int k = static_cast<int>(shapes.size());
  RandomWeights weights(k, ts, seed);
  auto pick = [&](int n) { return weights.pick(n); };
  auto next = [&] { return weights.next(); };
  Interpolator I(shapes, F, {}, options);
  History h;
  auto check = [&](const Positions& X, const Eigen::VectorXd& weights, const char* how, int call) {
    const Positions expected = Interpolator(shapes, F, {}, options).blend(weights);
    Eigen::VectorXd nudged = weights;
    for (int ulp = 0; ulp < 4; ++ulp) nudged[1] = std::nextafter(nudged[1], 2.0);
    nudged[0] -= nudged[1] - weights[1];
    const double own = max_abs(Interpolator(shapes, F, {}, options).blend(nudged) - expected) / size;
    const double dev = max_abs(X - expected) / size;
    h.worst = std::max(h.worst, dev);
    ++h.frames;
    h.ill_conditioned += own > 0.5e-12;
    EXPECT_LT(dev, std::max(2e-12, 2 * own))
        << how << " at weights " << weights.transpose() << " (own conditioning " << own << "), call " << call
        << ", seed " << seed;
  };
  for (int call = 0; call < calls; ++call) {
    const int method = k == 2 ? pick(3) : 1;
    if (method == 0) {
      const Eigen::VectorXd v = next();
      check(I.at(v[1]), v, "at", call);
    } else if (method == 1) {
      const Eigen::VectorXd v = next();
      check(I.blend(v), v, "blend", call);
    } else {
      std::vector<double> seq;
      for (int j = 0, n = 1 + pick(6); j < n; ++j) seq.push_back(next()[1]);
      Positions out(seq.size() * I.num_vertices(), 2);
      I.frames(seq, out);
      for (size_t j = 0; j < seq.size(); ++j)
        check(out.middleRows(j * I.num_vertices(), I.num_vertices()), Eigen::Vector2d(1 - seq[j], seq[j]), "frames",
              call);
    }
  }
  return h;
}

TEST_F(Twist, FramesDoNotDependOnTheCallsBefore) {
  // at(1) here ends with broken triangles; at(0) after it used to reuse a singular factorisation.
  Interpolator I({m.V, twisted}, m.F, {}, without_folds());
  I.at(1.0);
  EXPECT_GT(I.last_stats().broken_triangles, 0);
  EXPECT_LT(max_abs(I.at(0.0) - m.V), 1e-12);
  // Frames from t ~ 0.52 on end with broken triangles.
  const std::vector<double> ts{0.0, 0.2, 0.5, 0.75, 0.8, 0.9, 1.0};
  int broken = 0;
  for (double t : ts) broken += (I.at(t), I.last_stats().broken_triangles > 0);
  EXPECT_EQ(broken, 4);
  History all;
  for (unsigned seed : {1u, 2u, 3u}) {
    const History h = expect_history_free({m.V, twisted}, m.F, ts, seed, 40, without_folds());
    all.worst = std::max(all.worst, h.worst);
    all.frames += h.frames;
    all.ill_conditioned += h.ill_conditioned;
  }
  // Only frames near the onset of broken triangles (t ~ 0.51) or near degenerate broken ones are
  // that ill-conditioned; the rest meet 2e-12.
  EXPECT_LE(all.ill_conditioned, all.frames / 5) << all.ill_conditioned << " of " << all.frames;
  std::printf("twist: %d frames, %d ill-conditioned, worst deviation %.3g of the size\n", all.frames,
              all.ill_conditioned, all.worst);
}

TEST_F(Twist, FoldPathFramesDoNotDependOnTheCallsBefore) {
  // With the defaults the Twist's 30 folded faces take the fold path (cut, interpolate the rest with
  // its holes, fill): its frames must not depend on the calls before either.
  const std::vector<double> ts{0.0, 0.2, 0.5, 0.75, 0.8, 0.9, 1.0};
  Interpolator I({m.V, twisted}, m.F);
  I.at(0.5);
  ASSERT_GT(I.last_stats().fold_faces, 0);
  for (unsigned seed : {1u, 2u}) EXPECT_EQ(expect_history_free({m.V, twisted}, m.F, ts, seed, 30).ill_conditioned, 0);
}

TEST_F(BentBar, FramesDoNotDependOnTheCallsBefore) {
  const std::vector<double> ts{0.0, 0.1, 0.11, 0.12, 0.3, 0.5, 0.52, 0.9, 1.0};
  // Three shapes (the bar, bent up, bent down and stretched): blends at points of the simplex.
  const Positions down =
      testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend({1.3 * p.x(), p.y()}, -1.5, 0.125); });
  double worst = 0;
  for (unsigned seed : {1u, 2u, 3u, 4u, 5u}) {
    const History h = seed <= 3 ? expect_history_free({m.V, bent}, m.F, ts, seed, 40)
                                : expect_history_free({m.V, bent, down}, m.F, ts, seed, 40);
    EXPECT_EQ(h.ill_conditioned, 0);  // so every frame was held to 2e-12
    worst = std::max(worst, h.worst);
  }
  std::printf("bent bar: worst deviation %.3g of the size\n", worst);
  // A baked sequence equals fresh single frames too.
  const std::vector<double> seq_ts{0.9, 0.1, 0.2, 0.3, 0.31, 0.32, 0.33, 0.34, 0.6, 0.0};
  Interpolator I({m.V, bent}, m.F);
  I.at(0.45);
  Positions seq(seq_ts.size() * m.V.rows(), 2);
  I.frames(seq_ts, seq);
  for (size_t k = 0; k < seq_ts.size(); ++k) {
    Interpolator fresh({m.V, bent}, m.F);
    EXPECT_LT(max_abs(seq.middleRows(k * m.V.rows(), m.V.rows()) - fresh.at(seq_ts[k])), 1e-12) << seq_ts[k];
  }
}

TEST_F(BentBar, WithoutRefinementFramesDependOnTheCallsBefore) {
  // The control for the tests above: stopping at the tolerance leaves ~1e-11 of history.
  InterpolatorOptions stop;
  stop.flatten.refinement = 1.0;
  Interpolator I({m.V, bent}, m.F, {}, stop);
  double worst = 0;
  for (double t : {0.5, 0.51, 0.52, 0.53, 0.3, 0.31, 0.32}) {
    Interpolator fresh({m.V, bent}, m.F, {}, stop);
    worst = std::max(worst, max_abs(I.at(t) - fresh.at(t)));
  }
  EXPECT_GT(worst, 1e-12);
}

TEST_F(BentBar, ReusingFactorisationsGivesTheSameFrames) {
  InterpolatorOptions off;
  off.flatten.reuse_factorization = false;
  Interpolator with({m.V, bent}, m.F), without({m.V, bent}, m.F, {}, off);
  int chords = 0;
  for (double t : {0.2, 0.21, 0.22, 0.23, 0.24, 0.5, 0.51, 0.8}) {
    const Positions a = with.at(t), b = without.at(t);
    chords += with.last_stats().chord_steps;
    EXPECT_EQ(without.last_stats().chord_steps, 0);
    EXPECT_LT(max_abs(a - b), 1e-12) << "t = " << t;
  }
  EXPECT_GT(chords, 0);  // the option made a difference to the work done
}

TEST_F(Twist, BrokenTrianglesAreFlaggedAndStrictModeRaises) {
  InterpolatorOptions whole;
  whole.folds = false;
  Interpolator I({m.V, twisted}, m.F, {}, whole);
  I.at(0.5);
  EXPECT_TRUE(I.last_stats().converged) << I.last_stats().warnings;
  EXPECT_TRUE(I.last_stats().warnings.empty());
  I.at(0.8);
  const FrameStats st = I.last_stats();
  EXPECT_FALSE(st.converged);
  EXPECT_GT(st.broken_triangles, 0);
  EXPECT_NE(st.warnings.find("triangle inequality"), std::string::npos) << st.warnings;
  EXPECT_NE(st.warnings.find("0.8"), std::string::npos) << st.warnings;  // names the frame
  InterpolatorOptions strict = whole;
  strict.strict = true;
  Interpolator S({m.V, twisted}, m.F, {}, strict);
  EXPECT_NO_THROW(S.at(0.5));
  EXPECT_THROW(S.at(0.8), SolverError);
  Positions seq(3 * m.V.rows(), 2);
  EXPECT_THROW(S.frames({0.2, 0.5, 0.8}, seq), SolverError);
  // A large flatness residual alone is flagged too.
  InterpolatorOptions picky = whole;
  picky.max_flatness = 0.0;
  Interpolator P({m.V, twisted}, m.F, {}, picky);
  P.at(0.3);
  EXPECT_FALSE(P.last_stats().converged);
  EXPECT_NE(P.last_stats().warnings.find("flatness"), std::string::npos) << P.last_stats().warnings;
}

TEST_F(BentBar, CoordinatesOfAnyMagnitudeGiveTheScaledFrames) {
  AnchorPath path;
  path.t = {0.0, 0.5, 1.0};
  path.position.resize(3, 2);
  path.position << 0, 0, 0.3, 0.2, 0, 0;
  path.angle = {0.0, 0.4, 0.0};
  for (const Anchor& anchor : {Anchor::centroid(), Anchor::at_vertex(9), Anchor::along(path)}) {
    Interpolator unit({m.V, bent}, m.F, anchor);
    for (const double scale : {1e150, 1e-150, 3e77, 1e-77}) {
      Anchor scaled_anchor = anchor;
      scaled_anchor.path.position *= scale;
      Interpolator big({(scale * m.V).eval(), (scale * bent).eval()}, m.F, scaled_anchor);
      for (double t : {0.0, 0.3, 0.7}) {
        const Positions X = big.at(t) / scale;
        EXPECT_TRUE(X.allFinite());
        EXPECT_LT(max_abs(X - unit.at(t)), 1e-9) << "scale " << scale << ", t = " << t;
      }
    }
  }
  // Far from the origin as well.
  const Eigen::RowVector2d far(1e12, -3e12);
  Interpolator moved({(m.V.rowwise() + far).eval(), (bent.rowwise() + far).eval()}, m.F), unit({m.V, bent}, m.F);
  EXPECT_LT(max_abs((moved.at(0.4).rowwise() - far) - unit.at(0.4)), 1e-3);  // 1e12 * 1e-15
}

TEST_F(BentBar, DistortionOfAnyMagnitude) {
  Interpolator I({m.V, bent}, m.F);
  const Positions X = I.at(0.5);
  const Eigen::VectorXd K = conformal_distortion(m.V, X, m.F), A = area_ratio(m.V, X, m.F);
  EXPECT_GT(K.maxCoeff(), 1.01);
  for (const double scale : {1e150, 1e-150}) {
    const Positions V = scale * m.V, Y = scale * X;
    EXPECT_LT((conformal_distortion(V, Y, m.F) - K).cwiseAbs().maxCoeff(), 1e-12 * K.maxCoeff()) << scale;
    EXPECT_LT((area_ratio(V, Y, m.F) - A).cwiseAbs().maxCoeff(), 1e-12 * A.cwiseAbs().maxCoeff()) << scale;
  }
}

TEST_F(BentBar, BadParametersAreRejectedByName) {
  for (const double tol : {-1e-10, std::nan("")}) {
    InterpolatorOptions o;
    o.flatten.tolerance = tol;
    expect_invalid([&] { Interpolator({m.V, bent}, m.F, {}, o); }, "tolerance");
    // A piece without interior vertices (a strip one face wide) used to crash on a negative tol.
    const auto strip = testing::jittered_grid(5, 1);
    expect_invalid([&] { Interpolator({strip.V, (strip.V * 2.0).eval()}, strip.F, {}, o); }, "tolerance");
  }
  for (const double refinement : {-0.5, 2.0, std::nan("")}) {
    InterpolatorOptions o;
    o.flatten.refinement = refinement;
    expect_invalid([&] { Interpolator({m.V, bent}, m.F, {}, o); }, "refinement");
  }
  InterpolatorOptions o;
  o.flatten.max_iterations = -3;
  expect_invalid([&] { Interpolator({m.V, bent}, m.F, {}, o); }, "max_iterations");
  for (const int threads : {-1, 1 << 30}) {
    InterpolatorOptions ot;
    ot.threads = threads;
    expect_invalid([&] { Interpolator({m.V, bent}, m.F, {}, ot); }, "threads");
  }
  Interpolator I({m.V, bent}, m.F);
  expect_invalid([&] { I.set_threads(-2); }, "threads");
  AnchorPath path;
  path.t = {0.0, std::nan(""), 1.0};
  path.position = Positions::Zero(3, 2);
  path.angle = {0.0, 0.0, 0.0};
  expect_invalid([&] { Interpolator({m.V, bent}, m.F, Anchor::along(path)); }, "t must be finite (entry 1)");
  path.t = {0.0, 0.5, 1.0};
  path.angle = {0.0, std::nan(""), 0.0};
  expect_invalid([&] { Interpolator({m.V, bent}, m.F, Anchor::along(path)); }, "angles must be finite");
  path.angle = {0.0, 0.0, 0.0};
  expect_invalid([&] { Interpolator({m.V, bent}, m.F, Anchor::along(path, -5)); }, "anchor vertex -5");
  expect_invalid([&] { Interpolator({m.V, bent}, m.F, Anchor::at_vertex(-5)); }, "vertex");
  expect_invalid([&] { Interpolator({m.V, bent}, m.F, Anchor::at_vertex(static_cast<int>(m.V.rows()))); },
                 "out of range");
}

TEST(Robustness, NonFiniteTIsRejectedByEveryMethod) {
  const auto m = testing::jittered_grid(6, 3);
  const Positions target = (m.V * 1.5).eval();
  const double nan = std::nan("");
  Interpolator I({m.V, target}, m.F);
  expect_invalid([&] { I.at(nan); }, "t must be finite");
  expect_invalid([&] { I.blend(Eigen::Vector2d(nan, 1.0)); }, "finite");
  Positions seq(2 * m.V.rows(), 2);
  expect_invalid([&] { I.frames({0.5, nan}, seq); }, "entry 1");
  expect_invalid([&] { linear_interpolate(m.V, target, nan); }, "t must be finite");
  ArapInterpolator arap(m.V, target, m.F);
  expect_invalid([&] { arap.at(HUGE_VAL); }, "t must be finite");
}

TEST(Robustness, ShapesWhoseSignedAreasCancelAreRejected) {
  // Two faces of equal area, the second folded over the first: the signed areas sum to zero and
  // the centroid (the anchor) would divide by it.
  Positions ok(4, 2), folded(4, 2);
  ok << 0, 0, 1, 0, 1, 1, 0, 1;
  folded << 0, 0, 1, 0, 1, 1, 0.9, -0.1;
  Faces F(2, 3);
  F << 0, 1, 2, 0, 2, 3;
  expect_invalid([&] { Interpolator({ok, folded}, F); }, "shape 1, face 0: the signed areas of piece 0");
  expect_invalid([&] { Interpolator({folded, ok}, F); }, "cancel");
}

TEST_F(BentBar, ConcurrentCallsAreSerialisedNotCorrupted) {
  Interpolator shared({m.V, bent}, m.F);
  std::vector<double> ts;
  for (int k = 0; k <= 20; ++k) ts.push_back(k / 20.0);
  std::vector<Positions> expected;
  for (double t : ts) expected.push_back(Interpolator({m.V, bent}, m.F).at(t));
  std::vector<double> worst(4, 0.0);
  std::vector<std::thread> threads;
  for (int k = 0; k < 4; ++k) {
    threads.emplace_back([&, k] {
      for (int rep = 0; rep < 3; ++rep) {
        for (size_t j = k; j < ts.size(); j += 2) {
          const double err = max_abs(shared.at(ts[j]) - expected[j]);
          worst[k] = std::max(worst[k], err);
        }
        Positions seq(8 * m.V.rows(), 2);
        shared.frames(std::vector<double>(ts.begin() + k, ts.begin() + k + 8), seq);
        for (size_t j = 0; j < 8; ++j)
          worst[k] = std::max(worst[k], max_abs(seq.middleRows(j * m.V.rows(), m.V.rows()) - expected[k + j]));
      }
    });
  }
  for (auto& th : threads) th.join();
  for (int k = 0; k < 4; ++k) EXPECT_LT(worst[k], 1e-12) << "thread " << k;
}

}  // namespace
}  // namespace bdinterp
