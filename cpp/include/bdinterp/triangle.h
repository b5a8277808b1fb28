// Angles and cotangents of one triangle given by its squared edge lengths, with the CETM convention
// for triples that violate the triangle inequality: angle pi opposite the too-long edge, 0 elsewhere,
// zero cotangents (Springborn et al. 2008, Sec. 4.2), so callers never see NaN.
#pragma once

#include <algorithm>
#include <cmath>

namespace bdinterp {

struct TriangleAngles {
  double angle[3];  // angle[c] at corner c, opposite edge c
  double cot[3];
  bool broken;  // the triangle inequality fails (or holds with equality)
};

// l2[c]: squared length of the edge opposite corner c (> 0).
inline TriangleAngles triangle_angles(const double l2[3]) {
  constexpr double kPi = 3.14159265358979323846;
  TriangleAngles t{};
  const double a = std::sqrt(l2[0]), b = std::sqrt(l2[1]), c = std::sqrt(l2[2]);
  const double xa = b + c - a, xb = a + c - b, xc = a + b - c;
  if (!(xa > 0 && xb > 0 && xc > 0)) {
    const int longest = (a >= b && a >= c) ? 0 : (b >= c ? 1 : 2);
    for (int k = 0; k < 3; ++k) t.angle[k] = k == longest ? kPi : 0.0;
    t.broken = true;
    return t;
  }
  const double s = a + b + c;
  // Half-angle formula: accurate for needle and cap triangles alike.
  t.angle[0] = 2 * std::atan2(std::sqrt(xb * xc), std::sqrt(s * xa));
  t.angle[1] = 2 * std::atan2(std::sqrt(xa * xc), std::sqrt(s * xb));
  t.angle[2] = 2 * std::atan2(std::sqrt(xa * xb), std::sqrt(s * xc));
  const double four_area = std::sqrt(s * xa * xb * xc);  // 4 * area
  t.cot[0] = (l2[1] + l2[2] - l2[0]) / four_area;
  t.cot[1] = (l2[0] + l2[2] - l2[1]) / four_area;
  t.cot[2] = (l2[0] + l2[1] - l2[2]) / four_area;
  t.broken = false;
  return t;
}

}  // namespace bdinterp
