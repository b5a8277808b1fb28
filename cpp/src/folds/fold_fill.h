// Small pieces shared by folds.cpp (the region) and folds_fill.cpp (the fill).
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <vector>

#include "folds/folds.h"
#include "mesh/geometry.h"
#include "mesh/mesh.h"

namespace bdinterp::detail {

// The unsigned angle of face f at its corner c in X.
inline double corner_angle(const Positions& X, const Faces& F, int f, int c) {
  const Eigen::RowVector2d u = X.row(F(f, (c + 1) % 3)) - X.row(F(f, c));
  const Eigen::RowVector2d v = X.row(F(f, (c + 2) % 3)) - X.row(F(f, c));
  return std::atan2(std::abs(u.x() * v.y() - u.y() * v.x()), u.dot(v));
}

// The Jacobian of the affine map of face f from `base` to X, given the inverse of base's edge
// matrix [x1 - x0, x2 - x0] of that face. A template (as doubled_area): X may be a Positions or an
// Eigen::Ref to one without a copy (fill()'s frame is a Ref: a `const Positions&` copied all #V rows
// on every call).
template <typename P>
inline Eigen::Matrix2d face_jacobian(const P& X, const Faces& F, int f, const Eigen::Matrix2d& base_inverse) {
  return edge_matrix(X, F, f) * base_inverse;
}

// The area factor the squared-length blend at t = 1/2 of two inputs gives face f, relative to the
// larger of their areas: sqrt(det((G_a + G_b) / 2)) / max |det E| for the edge matrices E and Gram
// matrices G = E^T E of the face (independent of the base). The largest over all pairs of shapes;
// infinite for a face collapsed in both of a pair.
inline double blend_inflation(const std::vector<Positions>& shapes, const Faces& F, int f) {
  std::vector<Eigen::Matrix2d> E;
  for (const Positions& X : shapes) E.push_back(edge_matrix(X, F, f));
  double worst = 0;
  for (size_t a = 0; a < E.size(); ++a)
    for (size_t b = a + 1; b < E.size(); ++b) {
      const double area = std::max(std::abs(E[a].determinant()), std::abs(E[b].determinant()));
      const Eigen::Matrix2d G = 0.5 * (E[a].transpose() * E[a] + E[b].transpose() * E[b]);
      worst = std::max(worst, std::sqrt(std::max(0.0, G.determinant())) / area);
    }
  return worst;
}

// The angle of the rotation nearest to J (in (-pi, pi]; for a reflection, of its rotation part).
inline double polar_angle(const Eigen::Matrix2d& J) { return std::atan2(J(1, 0) - J(0, 1), J(0, 0) + J(1, 1)); }

// The rotation by a (radians, counter-clockwise).
inline Eigen::Matrix2d rotation(double a) {
  Eigen::Matrix2d R;
  R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  return R;
}

// The conformal distortion sigma_1 / sigma_2 of J (infinite when J is singular).
inline double distortion(const Eigen::Matrix2d& J) {
  const double f2 = J.squaredNorm(), d = std::abs(J.determinant());
  return (f2 + std::sqrt(std::max(0.0, f2 * f2 - 4 * d * d))) / (2 * d);
}

// The change that clamps the singular values' ratio of J (det > 0) to `bound`, keeping their product
// and the singular vectors (so J's rotation and area); 0 when J is within the bound. In the split
// J = conformal + anticonformal (complex z1, z2), K = (|z1| + |z2|) / (|z1| - |z2|): both are scaled.
inline Eigen::Matrix2d clamp_change(const Eigen::Matrix2d& J, double bound) {
  const double a1 = 0.5 * (J(0, 0) + J(1, 1)), b1 = 0.5 * (J(1, 0) - J(0, 1));  // z1 = a1 + i b1
  const double a2 = 0.5 * (J(0, 0) - J(1, 1)), b2 = 0.5 * (J(1, 0) + J(0, 1));  // z2 = a2 + i b2
  const double r1 = std::hypot(a1, b1), r2 = std::hypot(a2, b2), k = (bound - 1) / (bound + 1);
  if (r2 <= k * r1) return Eigen::Matrix2d::Zero();
  const double s1 = std::sqrt((r1 * r1 - r2 * r2) / (1 - k * k)) / r1 - 1, s2 = k * (s1 + 1) * r1 / r2 - 1;
  Eigen::Matrix2d D;
  D << s1 * a1 + s2 * a2, -s1 * b1 + s2 * b2, s1 * b1 + s2 * b2, s1 * a1 - s2 * a2;
  return D;
}

// Per face (unfolded: #F, 1 for the faces no input folds relative to the base): 1 for the faces of
// R that no input folds, in a connected component of R (across edges) holding a face whose length
// blend inflates beyond options.inflation (a sheared, unfolded face). Those keep the harmonic
// extension of the rotations instead of their own polar angle (folds_fill.cpp). With its
// own, a sheared face's target (1 - t) I + t P (P its stretch: the symmetric polar factor) grows
// by 0.5 + sqrt(s^2 + 4) / 4 at t = 1/2 (2.5 x at K = 60; measured 3.3 x); with the smooth
// rotation, about 0, it is near the vertex blend (1 - t) I + t J, whose area is linear in t.
// Per component: smooth rotations on the sheared faces only gave K 3.2 x the key's next to them.
std::vector<char> smooth_faces(const Mesh& mesh, const std::vector<Positions>& shapes, const FoldRegion& region,
                               const std::vector<char>& unfolded, const FoldOptions& options);

}  // namespace bdinterp::detail
