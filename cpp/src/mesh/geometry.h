// Edge matrices and signed areas of faces, signed areas of boundary loops and area-weighted centroids
// of faces, the one place the library computes them.
#pragma once

#include <Eigen/Core>

#include "bdinterp/types.h"

namespace bdinterp {

// Twice the signed area of face f of X: cross(X[b] - X[a], X[c] - X[a]) for F.row(f) = (a, b, c);
// positive when the face is counter-clockwise.
template <typename P, typename Fc>
inline double doubled_area(const P& X, const Fc& F, int f) {
  const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
  return (X(b, 0) - X(a, 0)) * (X(c, 1) - X(a, 1)) - (X(b, 1) - X(a, 1)) * (X(c, 0) - X(a, 0));
}

// The edge matrix [X[b] - X[a], X[c] - X[a]] (columns) of the triangle (a, b, c) of X (a Positions
// or an Eigen::Ref to one); its determinant is the doubled signed area.
template <typename P>
inline Eigen::Matrix2d edge_matrix(const P& X, int a, int b, int c) {
  Eigen::Matrix2d E;
  E.col(0) = (X.row(b) - X.row(a)).transpose();
  E.col(1) = (X.row(c) - X.row(a)).transpose();
  return E;
}

// The edge matrix of face f of X (F.row(f) = (a, b, c)).
template <typename P, typename Fc>
inline Eigen::Matrix2d edge_matrix(const P& X, const Fc& F, int f) {
  return edge_matrix(X, F(f, 0), F(f, 1), F(f, 2));
}

// Twice the total signed area of the faces F of X (positive when they are counter-clockwise).
template <typename P, typename Fc>
inline double doubled_total_area(const P& X, const Fc& F) {
  double sum = 0;
  for (int f = 0; f < F.rows(); ++f) sum += doubled_area(X, F, f);
  return sum;
}

// The area-weighted centroid of the faces F of X (signed areas: either consistent orientation).
// Requires a non-zero total area (callers check it: see Interpolator's validation).
template <typename P, typename Fc>
inline Eigen::Vector2d area_centroid(const P& X, const Fc& F) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double area = 0;
  for (int f = 0; f < F.rows(); ++f) {
    const double a = doubled_area(X, F, f);
    for (int c = 0; c < 3; ++c) sum += a * Eigen::Vector2d(X(F(f, c), 0), X(F(f, c), 1));
    area += a;
  }
  return sum / (3 * area);
}

// The signed area of the closed polygon X[loop[0]], X[loop[1]], ... (shoelace; positive when it runs
// counter-clockwise), e.g. a boundary loop of a Mesh.
template <typename P, typename Loop>
inline double loop_area(const P& X, const Loop& loop) {
  double a = 0;
  for (size_t k = 0; k < loop.size(); ++k) {
    const int p = loop[k], q = loop[(k + 1) % loop.size()];
    a += X(p, 0) * X(q, 1) - X(p, 1) * X(q, 0);
  }
  return 0.5 * a;
}

}  // namespace bdinterp
