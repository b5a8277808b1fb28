// Step 1 of the method (paper Sec. 4, Algorithm 2): blend the metric as per-edge squared lengths.
// Blending squared lengths equals blending the per-face pullback metrics J^T J (Lemma 4.1), which is
// what bounds the conformal distortion (Appendix A); blending plain lengths does not (Sec. 4.4).
#pragma once

#include <vector>

#include "mesh/mesh.h"

namespace bdinterp {

// #E list of squared edge lengths of `X` (#V by 2) on the edges of `mesh`.
Eigen::VectorXd squared_edge_lengths(const Mesh& mesh, const Positions& X);

// Checks that X (#V by 2) is finite and no face of `mesh` is collapsed (|area| <= 1e-12 times its
// longest edge squared). Throws InvalidInput at `shape` (the index the caller knows X by) and the
// vertex or face.
void check_shape(const Mesh& mesh, const Positions& X, int shape);

// Blended metric sum_i w_i * l2[i] (#E). Weights may extrapolate (negative entries) as long as every
// face of the result is a valid Euclidean triangle; otherwise throws InvalidInput naming the face.
// Requires l2.size() == w.size() >= 1 and every l2[i].size() == mesh.num_edges().
Eigen::VectorXd blend_squared_lengths(const Mesh& mesh, const std::vector<Eigen::VectorXd>& l2,
                                      const Eigen::VectorXd& w);
// The same into `out` (resized to #E; its storage reused when it has that size already).
void blend_squared_lengths(const Mesh& mesh, const std::vector<Eigen::VectorXd>& l2, const Eigen::VectorXd& w,
                           Eigen::VectorXd& out);

// 16 * area^2 of a triangle from its squared edge lengths (Heron); <= 0 when the triangle
// inequality fails.
inline double heron16(double a2, double b2, double c2) {
  return 2.0 * (a2 * b2 + b2 * c2 + c2 * a2) - (a2 * a2 + b2 * b2 + c2 * c2);
}

}  // namespace bdinterp
