// Angles and cotangents of one triangle given by its squared edge lengths, with the CETM convention
// for triples that violate the triangle inequality: angle pi opposite the too-long edge, 0 elsewhere,
// zero cotangents (Springborn et al. 2008, Sec. 4.2), so callers never see NaN.
#pragma once

#include <algorithm>
#include <cmath>

#include "bdinterp/types.h"

namespace bdinterp {

// atan(y / x) for y, x > 0, within ~2 ulps: Cephes' atan (range reduction to |z| <= 0.66, then a
// rational approximation). Several times faster than std::atan2, which rounds correctly and is the
// hot spot of every Newton step otherwise.
inline double atan_positive(double y, double x) {
  constexpr double kMoreBits = 6.123233995736765886130e-17, kT3p8 = 2.41421356237309504880;
  double base, z, extra;
  if (y > kT3p8 * x) {
    base = kHalfPi;
    z = -x / y;
    extra = kMoreBits;
  } else {
    const bool mid = y > 0.66 * x;
    base = mid ? 0.5 * kHalfPi : 0.0;  // pi / 4, exact
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

// For side lengths l (l[c] opposite corner c): the excesses x[c] = l[c+1] + l[c+2] - l[c], grouped as
// in Kahan's area formula so that differences of nearly equal lengths are exact (needles keep their
// accuracy; the sides are sorted by min/max, without branches), and *perimeter. Returns 4 * area by
// Heron's formula, or 0 for lengths that violate the triangle inequality (a broken triple).
// The half-angle formula tan(a_c / 2) = 4 area / (perimeter x[c]) then gives every angle accurately.
inline double excesses(const double l[3], double x[3], double* perimeter) {
  const double hi = std::max(std::max(l[0], l[1]), l[2]);
  const double lo = std::min(std::min(l[0], l[1]), l[2]);
  const double mid = std::max(std::min(l[0], l[1]), std::min(std::max(l[0], l[1]), l[2]));
  const double x_hi = lo - (hi - mid), x_mid = lo + (hi - mid), x_lo = hi + (mid - lo);
  for (int c = 0; c < 3; ++c) x[c] = l[c] == hi ? x_hi : (l[c] == lo ? x_lo : x_mid);  // ties agree
  *perimeter = hi + (mid + lo);
  if (!(x_hi > 0)) return 0.0;  // x_hi > 0 iff the triangle inequality holds strictly
  return std::sqrt(*perimeter * x_hi * x_mid * x_lo);
}

// atan2(y, x) for any signs, from atan_positive (same accuracy, same speed).
inline double fast_atan2(double y, double x) {
  const double ay = std::abs(y);
  double a;
  if (x > 0) {
    a = atan_positive(ay, x);
  } else if (x < 0) {
    a = kPi - atan_positive(ay, -x);
  } else {
    a = ay > 0 ? kHalfPi : 0.0;
  }
  return std::signbit(y) ? -a : a;
}

// Index of the longest of the lengths l: the corner that gets the angle pi in a broken triple.
inline int longest_side(const double l[3]) {
  return (l[0] >= l[1] && l[0] >= l[2]) ? 0 : (l[1] >= l[2] ? 1 : 2);
}

// cot[c] = (l2[c+1] + l2[c+2] - l2[c]) / q for the squared lengths l2 and q = 4 area > 0.
inline void cotangents(const double l2[3], double q, double cot[3]) {
  const double inv = 1.0 / q;
  cot[0] = (l2[1] + l2[2] - l2[0]) * inv;
  cot[1] = (l2[0] + l2[2] - l2[1]) * inv;
  cot[2] = (l2[0] + l2[1] - l2[2]) * inv;
}

// l[c]: length of the edge opposite corner c (> 0), l2[c] = l[c]^2. Writes the cotangents
// (l2[c+1] + l2[c+2] - l2[c]) / (4 area); zeros and true for a broken triple.
inline bool triangle_cotangents_from_lengths(const double l[3], const double l2[3], double cot[3]) {
  double x[3], perimeter;
  const double q = excesses(l, x, &perimeter);
  if (!(q > 0)) {
    cot[0] = cot[1] = cot[2] = 0.0;
    return true;
  }
  cotangents(l2, q, cot);
  return false;
}

inline bool triangle_cotangents(const double l2[3], double cot[3]) {
  const double l[3] = {std::sqrt(l2[0]), std::sqrt(l2[1]), std::sqrt(l2[2])};
  return triangle_cotangents_from_lengths(l, l2, cot);
}

// Angles by the half-angle formula (accurate for needles and caps alike) and, if `cot` is given,
// the cotangents, from the squared lengths l2; (pi, 0, 0) and true for a broken triple.
inline bool triangle_angles(const double l2[3], double angle[3], double* cot = nullptr) {
  const double l[3] = {std::sqrt(l2[0]), std::sqrt(l2[1]), std::sqrt(l2[2])};
  double x[3], perimeter;
  const double q = excesses(l, x, &perimeter);
  const bool broken = !(q > 0);
  for (int k = 0; k < 3; ++k)
    angle[k] = broken ? (k == longest_side(l) ? kPi : 0.0) : 2 * atan_positive(q, perimeter * x[k]);
  if (cot) triangle_cotangents_from_lengths(l, l2, cot);
  return broken;
}

}  // namespace bdinterp
