#include <gtest/gtest.h>

#include <cmath>

#include "bdinterp/types.h"
#include "flatten/lobachevsky.h"

namespace bdinterp {
namespace {

// -integral_0^x log|2 sin(t/2)| dt, independent of the library's series: the singular part log t is
// integrated exactly, the smooth rest log(2 sin(t/2) / t) by composite Gauss-Legendre.
double clausen_by_quadrature(double x) {
  double sum = -(x * std::log(x) - x);
  const int n = 2000;
  const double h = x / n;
  const double g[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, w[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
  for (int k = 0; k < n; ++k) {
    const double mid = (k + 0.5) * h;
    for (int q = 0; q < 3; ++q) {
      const double t = mid + 0.5 * h * g[q];
      sum -= 0.5 * h * w[q] * std::log(2 * std::sin(0.5 * t) / t);
    }
  }
  return sum;
}

TEST(Lobachevsky, KnownValues) {
  const double pi = bdinterp::kPi;
  EXPECT_NEAR(clausen2(pi / 2), 0.915965594177219015054603514932, 1e-15);  // Catalan's constant
  EXPECT_NEAR(clausen2(pi / 3), 1.014941606409653625021202554275, 1e-15);  // Gieseking-related max
  EXPECT_NEAR(clausen2(pi), 0.0, 1e-15);
  EXPECT_NEAR(lobachevsky(0.0), 0.0, 1e-16);
  EXPECT_NEAR(lobachevsky(pi / 2), 0.0, 1e-15);
  EXPECT_NEAR(lobachevsky(pi), 0.0, 1e-15);
}

TEST(Lobachevsky, SymmetriesAndQuadrature) {
  for (double x : {0.01, 0.3, 1.0, 2.0, 3.0}) {
    EXPECT_NEAR(clausen2(x), clausen_by_quadrature(x), 1e-13) << x;
    EXPECT_NEAR(clausen2(-x), -clausen2(x), 1e-15);
    EXPECT_NEAR(clausen2(x + 2 * bdinterp::kPi), clausen2(x), 1e-14);
    // L is pi-periodic and odd.
    EXPECT_NEAR(lobachevsky(x + bdinterp::kPi), lobachevsky(x), 1e-14);
  }
}

TEST(Lobachevsky, DerivativeIsMinusLog2Sin) {
  for (double x : {0.2, 0.7, 1.3, 2.5}) {
    const double h = 1e-5;
    const double fd = (lobachevsky(x + h) - lobachevsky(x - h)) / (2 * h);
    EXPECT_NEAR(fd, -std::log(2 * std::sin(x)), 1e-9) << x;
  }
}

}  // namespace
}  // namespace bdinterp
