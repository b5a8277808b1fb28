#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "mesh/triangle.h"

namespace bdinterp {
namespace {

TEST(Triangle, FastArctangentMatchesTheLibraryToTwoUlps) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> exponent(-8, 8);
  double worst = 0;
  for (int k = 0; k < 200000; ++k) {
    const double y = std::pow(10.0, exponent(rng)), x = std::pow(10.0, exponent(rng));
    const double exact = std::atan2(y, x);
    worst = std::max(worst, std::abs(atan_positive(y, x) - exact) / exact);
  }
  EXPECT_LT(worst, 4.5e-16);
  // All four quadrants and the axes.
  for (int k = 0; k < 100000; ++k) {
    const double y = std::sin(0.001 * k) * std::pow(10.0, exponent(rng));
    const double x = std::cos(0.001 * k) * std::pow(10.0, exponent(rng));
    EXPECT_NEAR(fast_atan2(y, x), std::atan2(y, x), 1e-15) << y << " " << x;
  }
  for (double y : {-1.0, 0.0, 1.0})
    for (double x : {-1.0, 0.0, 1.0}) EXPECT_NEAR(fast_atan2(y, x), std::atan2(y, x), 1e-15);
}

TEST(Triangle, AnglesAndCotangentsOfKnownTriangles) {
  double angle[3], cot[3];
  const double right[3] = {2.0, 1.0, 1.0};  // legs 1, 1, hypotenuse sqrt 2 opposite corner 0
  EXPECT_FALSE(triangle_angles(right, angle, cot));
  EXPECT_NEAR(angle[0], bdinterp::kPi / 2, 1e-15);
  EXPECT_NEAR(angle[1], bdinterp::kPi / 4, 1e-15);
  EXPECT_NEAR(cot[0], 0.0, 1e-15);
  EXPECT_NEAR(cot[1], 1.0, 1e-15);
  // A needle: angles from the law of cosines lose accuracy here; the half-angle formula does not.
  const double a = 1e-7, b = 1.0;
  const double needle[3] = {a * a, b * b, b * b};
  EXPECT_FALSE(triangle_angles(needle, angle));
  EXPECT_NEAR(angle[0], 2 * std::asin(a / (2 * b)), 1e-22);
  EXPECT_NEAR(angle[0] + angle[1] + angle[2], bdinterp::kPi, 1e-15);
}

TEST(Triangle, BrokenTriplesGetPiZeroZero) {
  double angle[3], cot[3];
  const double broken[3] = {1.0, 9.0, 1.0};  // 3 > 1 + 1
  EXPECT_TRUE(triangle_angles(broken, angle, cot));
  EXPECT_EQ(angle[1], bdinterp::kPi);
  EXPECT_EQ(angle[0], 0.0);
  EXPECT_EQ(cot[0] + cot[1] + cot[2], 0.0);
  EXPECT_TRUE(triangle_cotangents(broken, cot));
}

}  // namespace
}  // namespace bdinterp
