// Internal: angle sums as running products of unit-free complex numbers (one arctangent per vertex
// and pass instead of one per corner), with whole turns counted exactly.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "mesh/triangle.h"
#include "bdinterp/types.h"

namespace bdinterp::detail {

// Rescales (re, im) by a power of two (exactly) before it could overflow or underflow.
inline void keep_in_range(double& re, double& im) {
  const double size = std::abs(re) + std::abs(im);
  if (size > 0x1p500 || size < 0x1p-500) {
    const double scale = size > 1 ? 0x1p-500 : 0x1p500;
    re *= scale;
    im *= scale;
  }
}

// Multiplies the running product (re, im) of a vertex's corner factors by the factor (a, b) of one
// more corner, a, b > 0: its argument, half the corner's angle, is in (0, pi / 2), so the product's
// argument passed a multiple of 2 pi exactly when it moved from the lower half-plane to the upper
// one; whole turns are added to `sum`. The product is rescaled (by a power of two, exactly) before
// it could overflow or underflow.
inline void turn(double& re, double& im, double& sum, double a, double b) {
  double nr = re * a - im * b, ni = re * b + im * a;
  sum += (im < 0 && !(ni < 0)) ? kTwoPi : 0.0;
  keep_in_range(nr, ni);
  re = nr;
  im = ni;
}

// The argument of (re, im) in [0, 2 pi), classified by the sign of im as turn() does.
inline double argument(double re, double im) { return fast_atan2(im, re) + (im < 0 ? kTwoPi : 0.0); }

// Multiplies the running product (re, im), argument in [0, 2 pi) classified as argument() does,
// by another such product (re2, im2), adding 2 pi to `sum` when the arguments' sum reaches 2 pi:
// always when both lie in the lower half-plane (pi, 2 pi); when exactly one does, iff the product is
// not in it (the arguments' sum is in (pi, 3 pi), and near pi the product's sign is exact: no
// cancellation there); when neither does, only if both are exactly pi (the negative real axis,
// e.g. four right angles: the sum is 2 pi, the product positive real). Zeros are signed +0, so a
// product on the negative real axis has the argument pi.
inline void combine_turns(double& re, double& im, double& sum, double re2, double im2) {
  const bool lower = im < 0, lower2 = im2 < 0;
  double nr = re * re2 - im * im2, ni = re * im2 + im * re2 + 0.0;
  const bool wraps = lower && lower2 ? true
                     : lower != lower2 ? !(ni < 0)
                                       : im == 0 && re < 0 && im2 == 0 && re2 < 0;
  sum += wraps ? kTwoPi : 0.0;
  keep_in_range(nr, ni);
  re = nr;
  im = ni;
}

// a - 2 pi k in [-pi, pi] for the nearest whole k; wrap_angle(a - ref) is a's step from ref to the
// branch nearest ref.
inline double wrap_angle(double a) { return a - kTwoPi * std::round(a / kTwoPi); }

// The whole turns 2 pi k nearest the weighted median of a rotation field, given as (angle, weight)
// pairs (weights >= 0, not all zero; not empty). Subtracting it puts the field's bulk on the
// principal branch: a limb turned past 180 degrees keeps its large rotation, the body ~0.
inline double median_turns(std::vector<std::pair<double, double>> angle_weight) {
  std::sort(angle_weight.begin(), angle_weight.end());
  double total = 0, acc = 0, median = angle_weight.back().first;
  for (const auto& aw : angle_weight) total += aw.second;
  for (const auto& [angle, weight] : angle_weight)
    if ((acc += weight) >= 0.5 * total) {
      median = angle;
      break;
    }
  return kTwoPi * std::round(median / kTwoPi);
}

}  // namespace bdinterp::detail
