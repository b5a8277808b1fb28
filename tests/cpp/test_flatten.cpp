#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "flatten/flatten.h"
#include "blend/metric_blend.h"
#include "flatten/flatten_energy.h"
#include "test_meshes.h"

namespace bdinterp {
namespace {

// A curved metric: half way between a jittered grid and its bend by 120 degrees.
struct CurvedMetric : ::testing::Test {
  testing::TestMesh m = testing::jittered_grid(12, 6, 1.0, 0.3);
  Mesh mesh{m.F, static_cast<int>(m.V.rows())};
  Positions bent = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 2.1, 0.15); });
  Eigen::VectorXd l2 = blend_squared_lengths(
      mesh, {squared_edge_lengths(mesh, m.V), squared_edge_lengths(mesh, bent)},
      Eigen::Vector2d(0.5, 0.5));

  Eigen::VectorXd random_u(double scale, unsigned seed) const {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> d(-scale, scale);
    Eigen::VectorXd u(mesh.num_vertices());
    for (int v = 0; v < u.size(); ++v) u[v] = mesh.is_boundary_vertex(v) ? 0.0 : d(rng);
    return u;
  }
};

// 2 pi - angle sum at every interior vertex, straight from the law of cosines in long double (atan2
// of 4 area and twice the adjacent sides' dot product: 64-bit mantissas keep even 1e-8 needles to
// ~1e-12), (pi, 0, 0) for broken faces: an independent reference for the solver's angle sums.
Eigen::VectorXd reference_gradient(const Mesh& mesh, const Eigen::VectorXd& l2, const Eigen::VectorXd& u) {
  const long double kPi = 3.14159265358979323846264338L;
  std::vector<long double> sum(mesh.num_vertices(), 0.0L);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    long double a2[3], a[3];
    for (int c = 0; c < 3; ++c) {
      const int e = mesh.face_edges()(f, c);
      a2[c] = static_cast<long double>(l2[e]) *
              expl(static_cast<long double>(u[mesh.edges()(e, 0)]) + u[mesh.edges()(e, 1)]);
      a[c] = sqrtl(a2[c]);
    }
    const int longest = a[0] >= a[1] && a[0] >= a[2] ? 0 : (a[1] >= a[2] ? 1 : 2);
    const long double rest = a[(longest + 1) % 3] + a[(longest + 2) % 3];
    for (int c = 0; c < 3; ++c) {
      long double angle = c == longest ? kPi : 0.0L;
      if (a[longest] < rest) {
        const long double d = a2[(c + 1) % 3] + a2[(c + 2) % 3] - a2[c];
        const long double q2 = 4 * a2[(c + 1) % 3] * a2[(c + 2) % 3] - d * d;
        angle = atan2l(sqrtl(std::max(q2, 0.0L)), d);
      }
      sum[mesh.faces()(f, c)] += angle;
    }
  }
  Eigen::VectorXd g = Eigen::VectorXd::Zero(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (!mesh.is_boundary_vertex(v)) g[v] = static_cast<double>(2 * kPi - sum[v]);
  return g;
}

TEST_F(CurvedMetric, AngleSumsMatchTheLawOfCosinesFarFromFlat) {
  // Far from flat: sums well away from 2 pi (whole extra turns included) and broken faces.
  Flattener fl(mesh);
  for (const double scale : {0.0, 0.3, 3.0}) {
    const Eigen::VectorXd u = random_u(scale, 11);
    const Eigen::VectorXd g = fl.gradient(l2, u), ref = reference_gradient(mesh, l2, u);
    EXPECT_LT((g - ref).cwiseAbs().maxCoeff(), 1e-9) << "scale " << scale;
    if (scale == 3.0) EXPECT_GT(ref.cwiseAbs().maxCoeff(), 3.2);  // more than half a turn off
  }
}

TEST_F(CurvedMetric, BothAngleSumPathsMatchTheLawOfCosines) {
  // The energy path (line search) and the gradient-only path (every other step) share one
  // accumulator: both must match the long-double reference, far from flat too.
  const FlattenPlan plan(mesh);
  detail::EnergyEvaluator evaluator(plan);
  detail::Evaluation with_energy, without;
  for (const double scale : {0.0, 0.3, 3.0}) {
    const Eigen::VectorXd u = random_u(scale, 12), ref = reference_gradient(mesh, l2, u);
    evaluator.evaluate(l2, u, true, nullptr, with_energy);
    evaluator.evaluate(l2, u, false, nullptr, without);
    EXPECT_TRUE(with_energy.has_energy);
    EXPECT_FALSE(without.has_energy);
    double worst_with = 0, worst_without = 0;
    for (int i = 0; i < plan.num_interior(); ++i) {
      const int v = plan.pattern.vertex[i];
      worst_with = std::max(worst_with, std::abs(with_energy.defect[i] - ref[v]));
      worst_without = std::max(worst_without, std::abs(without.defect[i] - ref[v]));
    }
    EXPECT_LT(worst_with, 1e-9) << "scale " << scale;
    EXPECT_LT(worst_without, 1e-9) << "scale " << scale;
    EXPECT_EQ(with_energy.residual, without.residual);
  }
}

TEST_F(CurvedMetric, LazyHessianEqualsTheOneAssembledWithTheAngles) {
  // Newton assembles the Hessian with the angle sums, or later from the scaled lengths alone.
  const FlattenPlan plan(mesh);
  detail::EnergyEvaluator evaluator(plan);
  detail::Evaluation at;
  const Eigen::VectorXd u = random_u(0.05, 6);
  std::vector<double> fused(plan.nnz() + 1), lazy(plan.nnz() + 1);
  evaluator.evaluate(l2, u, false, fused.data(), at);
  evaluator.assemble_hessian(at, lazy.data());
  double worst = 0, largest = 0;
  for (int p = 0; p < plan.nnz(); ++p) {
    worst = std::max(worst, std::abs(fused[p] - lazy[p]));
    largest = std::max(largest, std::abs(fused[p]));
  }
  EXPECT_GT(largest, 0.1);
  EXPECT_LT(worst, 1e-14 * largest);
}

TEST(Flatten, AngleSumsAtAVertexOfValence400) {
  // A fan of 400 thin faces: the product of the corners' factors (1 / sin 0.9 degree each) would
  // overflow without rescaling. A non-uniform ring radius makes the sum differ from 2 pi.
  constexpr int kRing = 400;
  Positions V(kRing + 1, 2);
  Faces F(kRing, 3);
  V.row(0) << 0, 0;
  for (int k = 0; k < kRing; ++k) {
    const double a = 2 * bdinterp::kPi * k / kRing, r = 1 + 0.3 * std::sin(3 * a);
    V.row(k + 1) << r * std::cos(a), r * std::sin(a);
    F.row(k) << 0, k + 1, (k + 1) % kRing + 1;
  }
  const Mesh mesh(F, kRing + 1);
  Flattener fl(mesh);
  const Eigen::VectorXd l2 = squared_edge_lengths(mesh, V);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(kRing + 1);
  EXPECT_NEAR(fl.gradient(l2, u)[0], 0.0, 1e-12);  // a flat fan
  u[0] = 0.7;                                     // a cone
  const double g = fl.gradient(l2, u)[0];
  EXPECT_NEAR(g, reference_gradient(mesh, l2, u)[0], 1e-10);
  EXPECT_GT(std::abs(g), 0.1);
}

TEST(Flatten, AngleSumsAtRightAnglesOfNeedles) {
  // Four needles (legs 1 and 1e-8) meet at their right angles: the law of cosines in doubles loses
  // ~1e-8 there (l_a^2 + l_b^2 - l_c^2 cancels), the half-angle formula does not.
  Positions V(5, 2);
  V << 0, 0, 1, 0, 0, 1e-8, -1, 0, 0, -1e-8;
  Faces F(4, 3);
  F << 0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1;
  const Mesh mesh(F, 5);
  Flattener fl(mesh);
  const Eigen::VectorXd l2 = squared_edge_lengths(mesh, V);
  // The rounded squared lengths are themselves 2e-8 away from flat at vertex 0; the sum must be
  // right to well within the solver's tolerance (the law of cosines in doubles says 0 here).
  for (const double u0 : {0.0, 0.3}) {
    Eigen::VectorXd u = Eigen::VectorXd::Zero(5);
    u[0] = u0;
    const double expected = reference_gradient(mesh, l2, u)[0];
    EXPECT_NEAR(fl.gradient(l2, u)[0], expected, 1e-11) << "u0 = " << u0;
    EXPECT_NEAR(fl.residual(l2, u), std::abs(expected), 1e-11);
  }
}

TEST_F(CurvedMetric, GradientMatchesFiniteDifferencesOfEnergy) {
  Flattener fl(mesh);
  const Eigen::VectorXd u = random_u(0.05, 3);
  const Eigen::VectorXd g = fl.gradient(l2, u);
  // E is a sum of O(1) terms over all faces: a larger step keeps roundoff (eps |E| / h) small.
  const double h = 1e-4;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (!fl.is_interior(v)) continue;
    Eigen::VectorXd up = u, um = u;
    up[v] += h;
    um[v] -= h;
    const double fd = (fl.energy(l2, up) - fl.energy(l2, um)) / (2 * h);
    EXPECT_NEAR(fd, g[v], 1e-7) << "vertex " << v;
  }
}

TEST_F(CurvedMetric, HessianMatchesFiniteDifferencesOfGradient) {
  // hessian() is the assembly Newton factorises (evaluated with the angle sums).
  Flattener fl(mesh);
  const Eigen::VectorXd u = random_u(0.05, 4);
  const Eigen::MatrixXd H = Eigen::MatrixXd(fl.hessian(l2, u));
  const double h = 1e-6;
  double worst = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (!fl.is_interior(v)) continue;
    Eigen::VectorXd up = u, um = u;
    up[v] += h;
    um[v] -= h;
    const Eigen::VectorXd col = (fl.gradient(l2, up) - fl.gradient(l2, um)) / (2 * h);
    for (int w = 0; w < mesh.num_vertices(); ++w)
      if (fl.is_interior(w)) worst = std::max(worst, std::abs(col[w] - H(w, v)));
  }
  EXPECT_LT(worst, 1e-7);
  // The Hessian restricted to interior vertices is symmetric positive definite.
  std::vector<int> in;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (fl.is_interior(v)) in.push_back(v);
  Eigen::MatrixXd Hi(in.size(), in.size());
  for (size_t a = 0; a < in.size(); ++a)
    for (size_t b = 0; b < in.size(); ++b) Hi(a, b) = H(in[a], in[b]);
  EXPECT_LT((Hi - Hi.transpose()).norm(), 1e-12);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Hi).eigenvalues().minCoeff(), 0.0);
}

TEST_F(CurvedMetric, NewtonReachesTolInAFewSteps) {
  Flattener fl(mesh);
  Eigen::VectorXd u;
  const FlattenReport r = fl.solve(l2, u);
  EXPECT_LE(r.residual, 1e-10);
  EXPECT_LE(r.iterations, 6);
  EXPECT_GE(r.iterations, 1);  // the blended metric is curved: there was work to do
  EXPECT_EQ(r.broken_triangles, 0);
  EXPECT_LE(fl.residual(l2, u), 1e-10);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (mesh.is_boundary_vertex(v)) EXPECT_EQ(u[v], 0.0);
}

TEST_F(CurvedMetric, ScaleInvariant) {
  Flattener fl(mesh);
  Eigen::VectorXd u1, u2;
  fl.solve(l2, u1);
  fl.solve(1e6 * l2, u2);
  EXPECT_LT((u1 - u2).cwiseAbs().maxCoeff(), 1e-9);
}

TEST_F(CurvedMetric, FlatMetricNeedsNoStep) {
  Flattener fl(mesh);
  Eigen::VectorXd u;
  const FlattenReport r = fl.solve(squared_edge_lengths(mesh, m.V), u);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(u.cwiseAbs().maxCoeff(), 0.0);
}

TEST_F(CurvedMetric, BrokenTrianglesDuringNewtonStayFiniteAndConverge) {
  Flattener fl(mesh);
  Eigen::VectorXd reference;
  fl.solve(l2, reference);
  // A wild start: many triangles violate the triangle inequality at first.
  Eigen::VectorXd u = random_u(3.0, 5);
  EXPECT_TRUE(std::isfinite(fl.energy(l2, u)));
  EXPECT_TRUE(fl.gradient(l2, u).allFinite());
  FlattenOptions opt;
  opt.max_iterations = 200;
  const FlattenReport r = fl.solve(l2, u, opt);
  EXPECT_GT(r.max_broken_triangles, 0);
  EXPECT_EQ(r.broken_triangles, 0);
  EXPECT_LE(r.residual, 1e-10);
  // Strict convexity where no triangle is broken: the same solution.
  EXPECT_LT((u - reference).cwiseAbs().maxCoeff(), 1e-8);
}

TEST_F(CurvedMetric, BadOptionsAndLengthsAreRejected) {
  Flattener fl(mesh);
  Eigen::VectorXd u;
  for (const double tol : {-1.0, std::nan(""), HUGE_VAL}) {
    FlattenOptions opt;
    opt.tolerance = tol;
    try {
      fl.solve(l2, u, opt);
      ADD_FAILURE() << "tolerance " << tol << " accepted";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("tolerance"), std::string::npos) << e.what();
    }
  }
  FlattenOptions opt;
  opt.max_iterations = -1;
  EXPECT_THROW(fl.solve(l2, u, opt), InvalidInput);
  Eigen::VectorXd bad = l2;
  bad[3] = std::nan("");
  try {
    fl.solve(bad, u);
    ADD_FAILURE();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("edge 3"), std::string::npos) << e.what();
  }
}

TEST(Flatten, APieceWithoutInteriorVerticesNeedsNoStep) {
  // A strip one face wide: every vertex on the boundary (used to dereference a null factor).
  const auto m = testing::jittered_grid(6, 1);
  const Mesh mesh(m.F, static_cast<int>(m.V.rows()));
  Flattener fl(mesh);
  EXPECT_EQ(fl.num_interior(), 0);
  Eigen::VectorXd u;
  FlattenOptions opt;
  opt.tolerance = 0.0;
  const FlattenReport r = fl.solve(squared_edge_lengths(mesh, m.V), u, opt);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(r.residual, 0.0);
}

TEST_F(CurvedMetric, NonConvergenceIsASolverError) {
  Flattener fl(mesh);
  Eigen::VectorXd u;
  FlattenOptions opt;
  opt.max_iterations = 1;
  opt.tolerance = 1e-15;
  EXPECT_THROW(fl.solve(l2, u, opt), SolverError);
}

}  // namespace
}  // namespace bdinterp
