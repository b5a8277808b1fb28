#include "flatten/lobachevsky.h"

#include "bdinterp/types.h"

#include <array>
#include <cmath>

namespace bdinterp {
namespace {

constexpr int kTerms = 28;  // (x/2pi)^(2k) <= 4^-k on [0, pi]: 28 terms reach 1e-17

// c_k = zeta(2k) / (k (2k+1)), from Cl2(x) = x - x log x + x sum_k c_k (x / 2pi)^(2k), |x| < 2pi,
// i.e. the Bernoulli series |B_2k| x^(2k+1) / (2k (2k+1)!) rewritten with |B_2k| = 2 (2k)! zeta(2k) / (2pi)^(2k).
std::array<double, kTerms + 1> series_coefficients() {
  std::array<double, kTerms + 1> c{};
  const double pi2 = kPi * kPi;
  const std::array<double, 5> exact = {pi2 / 6, pi2 * pi2 / 90, pi2 * pi2 * pi2 / 945,
                                       pi2 * pi2 * pi2 * pi2 / 9450,
                                       pi2 * pi2 * pi2 * pi2 * pi2 / 93555};
  for (int k = 1; k <= kTerms; ++k) {
    double zeta = 0;
    if (k <= 5) {
      zeta = exact[k - 1];
    } else {
      for (int n = 60; n >= 1; --n) zeta += std::pow(static_cast<double>(n), -2.0 * k);  // tail < 1e-20
    }
    c[k] = zeta / (k * (2.0 * k + 1));
  }
  return c;
}

}  // namespace

double clausen2(double x) {
  static const std::array<double, kTerms + 1> c = series_coefficients();
  // Reduce to (-pi, pi], then use oddness.
  double r = std::remainder(x, kTwoPi);
  const double sign = r < 0 ? -1.0 : 1.0;
  r = std::abs(r);
  if (r == 0) return 0.0;
  const double q = (r / kTwoPi) * (r / kTwoPi);
  double sum = 0, p = 1;
  for (int k = 1; k <= kTerms; ++k) {
    p *= q;
    sum += c[k] * p;
  }
  return sign * (r - r * std::log(r) + r * sum);
}

}  // namespace bdinterp
