// Folded inputs (folds.h): the fold region's growth at pinches, exactness at the keys, and the
// unchanged path for fold-free inputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "folds/folds.h"
#include "mesh/geometry.h"
#include "bdinterp/interpolator.h"
#include "folds/fold_fill.h"
#include "test_checks.h"
#include "test_meshes.h"

namespace bdinterp {
namespace {

// An nx x ny grid of unit cells, every quad split along its (i, j)-(i+1, j+1) diagonal.
testing::TestMesh regular_grid(int nx, int ny) {
  testing::TestMesh m;
  m.V.resize((nx + 1) * (ny + 1), 2);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.V.row(j * (nx + 1) + i) << i, j;
  m.F.resize(2 * nx * ny, 3);
  int f = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i;
      testing::split_quad(m.F, f, a, a + 1, a + nx + 2, a + nx + 1, false);
    }
  return m;
}

std::vector<int> faces_of_vertex(const Faces& F, int v) {
  std::vector<int> out;
  for (int f = 0; f < F.rows(); ++f)
    if (F(f, 0) == v || F(f, 1) == v || F(f, 2) == v) out.push_back(f);
  return out;
}

TEST(FoldRegion, GrowsAtAPinchedVertex) {
  // Cells (1, 1) and (2, 2) touch only at vertex (2, 2): the rest would pinch there (its faces at
  // (2, 2) form two fans), so the region takes every face of that vertex, and nothing else.
  const testing::TestMesh m = regular_grid(6, 6);
  const Mesh mesh(m.F, static_cast<int>(m.V.rows()));
  auto cell = [](int i, int j) { return 2 * (j * 6 + i); };
  std::vector<char> in(m.F.rows(), 0);
  for (int f : {cell(1, 1), cell(1, 1) + 1, cell(2, 2), cell(2, 2) + 1}) in[f] = 1;
  close_region(mesh, {m.V}, 0, in);
  const int pinch = 2 * 7 + 2;
  std::vector<int> got;
  for (int f = 0; f < m.F.rows(); ++f)
    if (in[f]) got.push_back(f);
  EXPECT_EQ(got, faces_of_vertex(m.F, pinch));
  Faces rest(m.F.rows() - static_cast<int>(got.size()), 3);
  for (int f = 0, r = 0; f < m.F.rows(); ++f)
    if (!in[f]) rest.row(r++) = m.F.row(f);
  EXPECT_NO_THROW(Mesh(rest, static_cast<int>(m.V.rows())));  // one fan per vertex: manifold
}

struct FoldedGrid : ::testing::Test {
  testing::TestMesh m = testing::jittered_grid(12, 12, 1.0, 1.0, 5);
  int pushed = 6 * 13 + 6;  // an interior vertex, pushed 1.6 cells across its neighbours
  Positions target = turned();
  Positions turned() const {
    Positions T = testing::apply(m.V, [](Eigen::Vector2d p) {
      return Eigen::Vector2d(std::cos(0.5) * p.x() - std::sin(0.5) * p.y(), std::sin(0.5) * p.x() + std::cos(0.5) * p.y());
    });
    T.row(pushed) += Eigen::RowVector2d(std::cos(0.5), std::sin(0.5)) * (1.6 / 12);
    return T;
  }
};

TEST_F(FoldedGrid, TheRegionHoldsTheFoldsAndItsFreeVerticesAreThoseOfOnlyRegionFaces) {
  const Mesh mesh(m.F, static_cast<int>(m.V.rows()));
  const FoldRegion r = fold_region(mesh, {m.V, target}, 0);
  int folded = 0;
  for (int f = 0; f < m.F.rows(); ++f) {
    if (doubled_area(target, m.F, f) > 0) continue;
    ++folded;
    for (int c = 0; c < 3; ++c)  // every face at a folded face's vertex is in R
      for (int g : faces_of_vertex(m.F, m.F(f, c))) EXPECT_TRUE(r.in_region[g]) << g;
  }
  EXPECT_GT(folded, 0);
  for (int v = 0; v < m.V.rows(); ++v) {
    const std::vector<int> fv = faces_of_vertex(m.F, v);
    const bool only = std::all_of(fv.begin(), fv.end(), [&](int f) { return r.in_region[f] == 1; });
    EXPECT_EQ(only, std::binary_search(r.free_vertices.begin(), r.free_vertices.end(), v)) << v;
  }
  EXPECT_TRUE(std::binary_search(r.free_vertices.begin(), r.free_vertices.end(), pushed));
  EXPECT_EQ(r.rest.rows() + static_cast<int>(r.faces.size()), m.F.rows());
}

TEST_F(FoldedGrid, FoldedKeysAreReachedExactlyAndTheFramesMoveContinuously) {
  Interpolator I({m.V, target}, m.F);
  ASSERT_FALSE(I.folded_faces(1).empty());
  EXPECT_LT((I.at(0.0) - m.V).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((I.at(1.0) - target).cwiseAbs().maxCoeff(), 1e-9);  // before: the folded metric was flattened
  EXPECT_GT(I.last_stats().fold_faces, 0);
  EXPECT_GE(I.last_stats().fold_free_vertices, 1);
  std::vector<double> ts, steps;
  for (int k = 0; k <= 20; ++k) ts.push_back(k / 20.0);
  Positions seq(ts.size() * m.V.rows(), 2);
  I.frames(ts, seq);
  EXPECT_TRUE(I.last_stats().converged) << I.last_stats().warnings;
  for (size_t k = 0; k + 1 < ts.size(); ++k)
    steps.push_back((seq.middleRows((k + 1) * m.V.rows(), m.V.rows()) - seq.middleRows(k * m.V.rows(), m.V.rows()))
                        .rowwise().norm().maxCoeff());
  std::vector<double> sorted = steps;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  EXPECT_LE(*std::max_element(steps.begin(), steps.end()), 3 * sorted[sorted.size() / 2]);
}

// A polar disk: a centre vertex, nr rings of nt vertices (radii 1/nr .. 1), a fan around the
// centre and quads split between the rings.
testing::TestMesh polar_disk(int nr, int nt) {
  testing::TestMesh m;
  m.V.resize(1 + nr * nt, 2);
  m.V.row(0) << 0, 0;
  for (int i = 0; i < nr; ++i)
    for (int j = 0; j < nt; ++j)
      m.V.row(1 + i * nt + j) << (i + 1.0) / nr * std::cos(2 * kPi * j / nt), (i + 1.0) / nr * std::sin(2 * kPi * j / nt);
  m.F.resize(nt + 2 * (nr - 1) * nt, 3);
  int f = 0;
  for (int j = 0; j < nt; ++j) m.F.row(f++) << 0, 1 + j, 1 + (j + 1) % nt;
  for (int i = 0; i + 1 < nr; ++i)
    for (int j = 0; j < nt; ++j) {
      const int a = 1 + i * nt + j, b = 1 + i * nt + (j + 1) % nt;
      testing::split_quad(m.F, f, a, a + nt, b + nt, b, false);
    }
  return m;
}

TEST(FoldRegion, ARestThatWindsTwiceGrowsUntilNothingIsLeft) {
  // z -> z^2: the centre is a branch point (angle sum 4 pi), so the fan joins R; the rest is a
  // fold-free flat annulus whose loops turn by 4 pi and -4 pi instead of 2 pi and -2 pi. Growing
  // at those loops never ends before R is the whole disk: refused, naming the piece.
  const testing::TestMesh m = polar_disk(6, 24);
  const Positions squared = testing::apply(m.V, [](Eigen::Vector2d p) {
    return Eigen::Vector2d(p.x() * p.x() - p.y() * p.y(), 2 * p.x() * p.y());
  });
  const Mesh mesh(m.F, static_cast<int>(m.V.rows()));
  for (int f = 0; f < m.F.rows(); ++f) ASSERT_GT(doubled_area(squared, m.F, f), 0) << f;  // no fold
  testing::expect_invalid([&] { fold_region(mesh, {m.V, squared}, 0); }, "vertex 0: the inputs fold or shrink");
  // A conformal map that does not wind (z -> z + 0.1 z^2, areas 0.81 .. 1.21) seeds nothing.
  const Positions mild = testing::apply(m.V, [](Eigen::Vector2d p) {
    return Eigen::Vector2d(p.x() + 0.1 * (p.x() * p.x() - p.y() * p.y()), p.y() + 0.2 * p.x() * p.y());
  });
  EXPECT_TRUE(fold_region(mesh, {m.V, mild}, 0).faces.empty());
}

TEST(FoldRegion, FacesTheLengthBlendWouldInflateSeedItToo) {
  // The grid's top rows (y >= 3) sheared by [[1, s], [0, 1]], the rest fixed: nothing folds or
  // shrinks, but the length blend at t = 1/2 gives the sheared faces sqrt(1 + s^2 / 4) of their
  // area: 1.80 for s = 3 (above FoldOptions::inflation = 1.6), 1.41 for s = 2 (below).
  const testing::TestMesh m = regular_grid(6, 6);
  const Mesh mesh(m.F, static_cast<int>(m.V.rows()));
  for (double s : {2.0, 3.0}) {
    const Positions sheared = testing::apply(m.V, [s](Eigen::Vector2d p) {
      return Eigen::Vector2d(p.x() + s * std::max(0.0, p.y() - 3), p.y());
    });
    const FoldRegion r = fold_region(mesh, {m.V, sheared}, 0);
    if (s == 2.0) {
      EXPECT_TRUE(r.faces.empty());
      continue;
    }
    for (int f = 0; f < m.F.rows(); ++f) {  // the faces at a vertex of a sheared face: rows 2 .. 5
      const double y = (m.V(m.F(f, 0), 1) + m.V(m.F(f, 1), 1) + m.V(m.F(f, 2), 1)) / 3;
      EXPECT_EQ(r.in_region[f], y > 2) << f;
    }
  }
}

TEST(FoldRegion, FoldFreeInputsTakeTheUsualPath) {
  const testing::TestMesh m = testing::jittered_grid(24, 6, 1.0, 0.25, 11);
  const Positions bent = testing::apply(m.V, [](Eigen::Vector2d p) { return testing::bend(p, 2.5, 0.125); });
  InterpolatorOptions off;
  off.folds = false;
  Interpolator with({m.V, bent}, m.F), without({m.V, bent}, m.F, {}, off);
  EXPECT_TRUE(with.folded_faces(1).empty());
  EXPECT_EQ(with.at(0.5), without.at(0.5));  // bit for bit
  EXPECT_EQ(with.last_stats().fold_faces, 0);
}

TEST(FoldFill, TheClampKeepsRotationAndAreaAndBringsKToTheBound) {
  // J = R(0.7) U diag(3, 0.5) V^T (K = 6, det 1.5) clamped to K = 2: the singular values become
  // sqrt(1.5) (sqrt 2, 1 / sqrt 2), the singular vectors (so the polar rotation) stay.
  const Eigen::Matrix2d U = detail::rotation(0.3), V = detail::rotation(-1.1);
  const Eigen::Matrix2d J = detail::rotation(0.7) * U * Eigen::Vector2d(3, 0.5).asDiagonal() * V.transpose();
  const Eigen::Matrix2d C = J + detail::clamp_change(J, 2.0);
  const Eigen::Matrix2d expected = detail::rotation(0.7) * U *
                                   Eigen::Vector2d(std::sqrt(3.0), std::sqrt(0.75)).asDiagonal() * V.transpose();
  EXPECT_LT((C - expected).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(detail::distortion(C), 2.0, 1e-12);
  EXPECT_NEAR(C.determinant(), J.determinant(), 1e-12);
  EXPECT_NEAR(detail::polar_angle(C), detail::polar_angle(J), 1e-12);
  EXPECT_NEAR(detail::distortion(J), 6.0, 1e-12);
  // Within the bound nothing changes; just above it the change is small (continuous at the bound).
  EXPECT_TRUE(detail::clamp_change(J, 6.5).isZero(0));
  EXPECT_LT(detail::clamp_change(J, 6.0 * (1 - 1e-9)).norm(), 1e-8);
}

}  // namespace
}  // namespace bdinterp
