// Small pieces shared by folds.cpp (the region) and folds_fill.cpp (the fill).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "bdinterp/mesh.h"

namespace bdinterp::detail {

// a - 2 pi k in (-pi, pi].
inline double wrap_angle(double a) { return a - 2 * kPi * std::round(a / (2 * kPi)); }

// The faces of each vertex.
inline std::vector<std::vector<int>> vertex_faces(const Faces& F, int num_vertices) {
  std::vector<std::vector<int>> out(num_vertices);
  for (int f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) out[F(f, c)].push_back(f);
  return out;
}

// The unsigned angle of face f at its corner c in X.
inline double corner_angle(const Positions& X, const Faces& F, int f, int c) {
  const Eigen::RowVector2d u = X.row(F(f, (c + 1) % 3)) - X.row(F(f, c));
  const Eigen::RowVector2d v = X.row(F(f, (c + 2) % 3)) - X.row(F(f, c));
  return std::atan2(std::abs(u.x() * v.y() - u.y() * v.x()), u.dot(v));
}

// The Jacobian of the affine map of face f from `base` to X, given the inverse of base's edge
// matrix [x1 - x0, x2 - x0] of that face.
inline Eigen::Matrix2d face_jacobian(const Positions& X, const Faces& F, int f, const Eigen::Matrix2d& base_inverse) {
  Eigen::Matrix2d G;
  G.col(0) = (X.row(F(f, 1)) - X.row(F(f, 0))).transpose();
  G.col(1) = (X.row(F(f, 2)) - X.row(F(f, 0))).transpose();
  return G * base_inverse;
}

// The angle of the rotation nearest to J (in (-pi, pi]; for a reflection, of its rotation part).
inline double polar_angle(const Eigen::Matrix2d& J) { return std::atan2(J(1, 0) - J(0, 1), J(0, 0) + J(1, 1)); }

}  // namespace bdinterp::detail
