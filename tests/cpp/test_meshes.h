// Test meshes for the C++ suite: jittered, randomly triangulated grids (never grid-aligned results).
#pragma once

#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "bdinterp/types.h"

namespace bdinterp::testing {

struct TestMesh {
  Positions V;
  Faces F;
};

// A (nx+1) x (ny+1) grid over [0, w] x [0, h], interior vertices jittered by up to 0.25 of a cell,
// each quad split along a random diagonal; counter-clockwise faces.
// Two triangles of the quad with corners a, b, c, d in order into rows f, f + 1 of F (f advances by
// 2), split along a-c or, with `other_diagonal`, along b-d.
inline void split_quad(Faces& F, int& f, int a, int b, int c, int d, bool other_diagonal) {
  if (other_diagonal) {
    F.row(f++) << a, b, d;
    F.row(f++) << b, c, d;
  } else {
    F.row(f++) << a, b, c;
    F.row(f++) << a, c, d;
  }
}

inline TestMesh jittered_grid(int nx, int ny, double w = 1.0, double h = 1.0, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.25, 0.25);
  std::bernoulli_distribution coin(0.5);
  TestMesh m;
  m.V.resize((nx + 1) * (ny + 1), 2);
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const bool interior = i > 0 && i < nx && j > 0 && j < ny;
      m.V.row(j * (nx + 1) + i) << w * (i + (interior ? jitter(rng) : 0.0)) / nx,
          h * (j + (interior ? jitter(rng) : 0.0)) / ny;
    }
  }
  m.F.resize(2 * nx * ny, 3);
  int f = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 2, d = a + nx + 1;
      split_quad(m.F, f, a, b, c, d, !coin(rng));
    }
  }
  return m;
}

// An annulus: nr rings of nt cells between radii 0.4 and 1, interior vertices jittered, random
// diagonals; counter-clockwise faces.
inline TestMesh annulus(int nr, int nt, unsigned seed = 3) {
  const double pi = bdinterp::kPi;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  TestMesh a;
  a.V.resize((nr + 1) * nt, 2);
  for (int i = 0; i <= nr; ++i) {
    for (int j = 0; j < nt; ++j) {
      const bool inner = i > 0 && i < nr;
      const double r = 0.4 + 0.6 * (i + (inner ? jitter(rng) : 0.0)) / nr;
      const double t = 2 * pi * (j + (inner ? jitter(rng) : 0.0)) / nt;
      a.V.row(i * nt + j) << r * std::cos(t), r * std::sin(t);
    }
  }
  a.F.resize(2 * nr * nt, 3);
  int f = 0;
  for (int i = 0; i < nr; ++i) {
    for (int j = 0; j < nt; ++j) {
      const int p = i * nt + j, q = i * nt + (j + 1) % nt, r = q + nt, s = p + nt;
      split_quad(a.F, f, p, q, r, s, rng() % 2 == 0);
    }
  }
  return a;
}

// The rows `pick` of M, in that order (Eigen 5 has no Eigen::all to index with).
template <class Matrix>
Matrix rows_of(const Matrix& M, const std::vector<int>& pick) {
  Matrix out(static_cast<Eigen::Index>(pick.size()), M.cols());
  for (size_t r = 0; r < pick.size(); ++r) out.row(static_cast<Eigen::Index>(r)) = M.row(pick[r]);
  return out;
}

// Applies a map R^2 -> R^2 to every vertex.
inline Positions apply(const Positions& V, const std::function<Eigen::Vector2d(Eigen::Vector2d)>& map) {
  Positions out(V.rows(), 2);
  for (int v = 0; v < V.rows(); ++v) out.row(v) = map(V.row(v).transpose()).transpose();
  return out;
}

// A bend: the bar [0, 1] x [0, 2 mid] wrapped around a circle, turning by `angle` radians in total;
// the centre line y = mid keeps its length 1. Needs mid < 1 / |angle| (no fold).
inline Eigen::Vector2d bend(const Eigen::Vector2d& p, double angle, double mid = 0.05) {
  const double radius = 1.0 / angle;
  const double a = p.x() * angle, r = radius - (p.y() - mid);
  return {r * std::sin(a), radius - r * std::cos(a)};
}

}  // namespace bdinterp::testing
