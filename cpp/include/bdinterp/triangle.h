// Angles and cotangents of one triangle given by its squared edge lengths, with the CETM convention
// for triples that violate the triangle inequality: angle pi opposite the too-long edge, 0 elsewhere,
// zero cotangents (Springborn et al. 2008, Sec. 4.2), so callers never see NaN.
#pragma once

#include <algorithm>
#include <cmath>

namespace bdinterp {

// atan(y / x) for y, x > 0, within ~2 ulps: Cephes' atan (range reduction to |z| <= 0.66, then a
// rational approximation). Several times faster than std::atan2, which rounds correctly and is the
// hot spot of every Newton step otherwise.
inline double atan_positive(double y, double x) {
  constexpr double kPio2 = 1.57079632679489661923, kPio4 = 0.78539816339744830962;
  constexpr double kMoreBits = 6.123233995736765886130e-17, kT3p8 = 2.41421356237309504880;
  double base, z, extra;
  if (y > kT3p8 * x) {
    base = kPio2;
    z = -x / y;
    extra = kMoreBits;
  } else {
    const bool mid = y > 0.66 * x;
    base = mid ? kPio4 : 0.0;
    extra = mid ? 0.5 * kMoreBits : 0.0;
    z = mid ? (y - x) / (y + x) : y / x;
  }
  const double zz = z * z;
  const double p = (((-8.750608600031904122785e-1 * zz - 1.615753718733365076637e1) * zz -
                     7.500855792314704667340e1) * zz - 1.228866684490136173410e2) * zz -
                   6.485021904942025371773e1;
  const double q = ((((zz + 2.485846490142306297962e1) * zz + 1.650270098316988542046e2) * zz +
                     4.328810604912902668951e2) * zz + 4.853903996359136964868e2) * zz +
                   1.945506571482613964425e2;
  return base + (z + z * (zz * p / q) + extra);
}

// x[k] = l[i] + l[j] - l[k] for the lengths l of a triangle, grouped as in Kahan's area formula so
// that the differences of nearly equal lengths are exact (needles keep their accuracy). Returns the
// index of the longest edge.
inline int excesses(const double l[3], double x[3]) {
  const int a = (l[0] >= l[1] && l[0] >= l[2]) ? 0 : (l[1] >= l[2] ? 1 : 2);
  const int b = l[(a + 1) % 3] >= l[(a + 2) % 3] ? (a + 1) % 3 : (a + 2) % 3;
  const int c = 3 - a - b;  // l[a] >= l[b] >= l[c]
  x[a] = l[c] - (l[a] - l[b]);
  x[b] = l[c] + (l[a] - l[b]);
  x[c] = l[a] + (l[b] - l[c]);
  return a;
}

// 4 * area of a triangle with side lengths l: Heron's formula in Kahan's grouping, accurate for
// needles too; 0 for lengths that violate the triangle inequality (a broken triple). Branch-free
// sorting by min/max.
inline double four_area(const double l[3]) {
  const double hi = std::max(std::max(l[0], l[1]), l[2]);
  const double lo = std::min(std::min(l[0], l[1]), l[2]);
  const double mid = std::max(std::min(l[0], l[1]), std::min(std::max(l[0], l[1]), l[2]));
  const double shortfall = lo - (hi - mid);  // > 0 iff the triangle inequality holds strictly
  if (!(shortfall > 0)) return 0.0;
  return std::sqrt((hi + (mid + lo)) * shortfall * (lo + (hi - mid)) * (hi + (mid - lo)));
}

// atan2(y, x) for any signs, from atan_positive (same accuracy, same speed).
inline double fast_atan2(double y, double x) {
  constexpr double kPi = 3.14159265358979323846, kPio2 = 1.57079632679489661923;
  const double ay = std::abs(y);
  double a;
  if (x > 0) {
    a = atan_positive(ay, x);
  } else if (x < 0) {
    a = kPi - atan_positive(ay, -x);
  } else {
    a = ay > 0 ? kPio2 : 0.0;
  }
  return std::signbit(y) ? -a : a;
}

// l[c]: length of the edge opposite corner c (> 0), l2[c] = l[c]^2. Writes angle[c] (at corner c)
// and, if `cot` is given, the cotangents. Returns true for a broken triple.
inline bool triangle_angles_from_lengths(const double l[3], const double l2[3], double angle[3],
                                         double* cot = nullptr) {
  constexpr double kPi = 3.14159265358979323846;
  double x[3];
  const int longest = excesses(l, x);
  if (!(x[0] > 0 && x[1] > 0 && x[2] > 0)) {
    for (int k = 0; k < 3; ++k) angle[k] = k == longest ? kPi : 0.0;
    if (cot) cot[0] = cot[1] = cot[2] = 0.0;
    return true;
  }
  const int i = (longest + 1) % 3, j = (longest + 2) % 3;
  const double p = l[longest] + (l[i] + l[j]);
  const double q = std::sqrt(p * x[0] * x[1] * x[2]);  // 4 area (Heron, Kahan's grouping)
  // Half-angle formula, tan(a_i / 2) = sqrt(x_j x_k / (p x_i)) = q / (p x_i): accurate for needles
  // and caps alike, for the two smaller angles; the largest is pi minus them, off by a few ulps of pi.
  angle[i] = 2 * atan_positive(q, p * x[i]);
  angle[j] = 2 * atan_positive(q, p * x[j]);
  angle[longest] = kPi - angle[i] - angle[j];
  if (cot) {
    const double inv = 1.0 / q;
    cot[0] = (l2[1] + l2[2] - l2[0]) * inv;
    cot[1] = (l2[0] + l2[2] - l2[1]) * inv;
    cot[2] = (l2[0] + l2[1] - l2[2]) * inv;
  }
  return false;
}

// The same from the squared lengths alone.
inline bool triangle_angles(const double l2[3], double angle[3], double* cot = nullptr) {
  const double l[3] = {std::sqrt(l2[0]), std::sqrt(l2[1]), std::sqrt(l2[2])};
  return triangle_angles_from_lengths(l, l2, angle, cot);
}

// Cotangents only (the Hessian needs no angles); zeros and true for a broken triple.
inline bool triangle_cotangents_from_lengths(const double l[3], const double l2[3], double cot[3]) {
  double x[3];
  excesses(l, x);
  if (!(x[0] > 0 && x[1] > 0 && x[2] > 0)) {
    cot[0] = cot[1] = cot[2] = 0.0;
    return true;
  }
  const double inv = 1.0 / std::sqrt((l[0] + l[1] + l[2]) * x[0] * x[1] * x[2]);
  cot[0] = (l2[1] + l2[2] - l2[0]) * inv;
  cot[1] = (l2[0] + l2[2] - l2[1]) * inv;
  cot[2] = (l2[0] + l2[1] - l2[2]) * inv;
  return false;
}

inline bool triangle_cotangents(const double l2[3], double cot[3]) {
  const double l[3] = {std::sqrt(l2[0]), std::sqrt(l2[1]), std::sqrt(l2[2])};
  return triangle_cotangents_from_lengths(l, l2, cot);
}

}  // namespace bdinterp
