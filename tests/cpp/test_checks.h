// Checks shared by the C++ tests.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <string>

#include "bdinterp/types.h"

namespace bdinterp::testing {

// Expects InvalidInput whose message contains `needle`.
template <typename Fn>
void expect_invalid(Fn fn, const std::string& needle) {
  try {
    fn();
    FAIL() << "no exception, expected one mentioning '" << needle << "'";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

// Max distance after the best rigid alignment of X onto Y (Kabsch); expects a rotation, not a
// reflection (the layouts keep the faces' orientation).
inline double rigid_error(const Positions& X, const Positions& Y) {
  const Eigen::RowVector2d cx = X.colwise().mean(), cy = Y.colwise().mean();
  const Eigen::MatrixX2d A = X.rowwise() - cx, B = Y.rowwise() - cy;
  Eigen::JacobiSVD<Eigen::Matrix2d> svd(A.transpose() * B, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix2d R = svd.matrixV() * svd.matrixU().transpose();
  EXPECT_GT(R.determinant(), 0);
  return ((A * R.transpose()) - B).rowwise().norm().maxCoeff();
}

}  // namespace bdinterp::testing
