// The traced outline made light: Douglas-Peucker per loop, sharp convex corners blunted, and the
// loops kept simple and apart (the mesher needs non-crossing constraints).
#include <algorithm>
#include <cmath>
#include <utility>

#include "bdinterp/types.h"
#include "sprite/outline.h"

namespace bdinterp::sprite {
namespace {


double cross(const Point& a, const Point& b) { return a.x() * b.y() - a.y() * b.x(); }

double line_distance(const Point& p, const Point& a, const Point& b) {
  const Point ab = b - a;
  const double len = ab.norm();
  return len > 0 ? std::abs(cross(ab, p - a)) / len : (p - a).norm();
}

// Marks in `keep` the points of loop[s..e] (indices mod n) Douglas-Peucker keeps within `tol`;
// `force`: keep the farthest point even within tol (so a loop keeps at least four points).
void douglas_peucker(const Loop& loop, size_t s, size_t e, double tol, bool force, std::vector<char>& keep) {
  const size_t n = loop.size();
  std::vector<std::pair<size_t, size_t>> stack{{s, e}};
  while (!stack.empty()) {
    auto [a, b] = stack.back();
    stack.pop_back();
    double far = -1;
    size_t at = a;
    for (size_t k = a + 1; k < b; ++k) {
      const double d = line_distance(loop[k % n], loop[a % n], loop[b % n]);
      if (d > far) far = d, at = k;
    }
    if (at == a || (far <= tol && !force)) continue;
    force = false;
    keep[at % n] = 1;
    stack.push_back({a, at});
    stack.push_back({at, b});
  }
}

Loop simplified(const Loop& loop, double tol) {
  const size_t n = loop.size();
  if (tol <= 0 || n < 5) return loop;
  size_t far = 0;
  for (size_t k = 1; k < n; ++k)
    if ((loop[k] - loop[0]).squaredNorm() > (loop[far] - loop[0]).squaredNorm()) far = k;
  std::vector<char> keep(n, 0);
  keep[0] = keep[far] = 1;
  douglas_peucker(loop, 0, far, tol, true, keep);
  douglas_peucker(loop, far, n, tol, true, keep);
  Loop out;
  for (size_t k = 0; k < n; ++k)
    if (keep[k]) out.push_back(loop[k]);
  return out;
}

// Convex corners sharper than min_angle cut off at most `detail` deep: two corners of 90+ degrees.
Loop blunted(const Loop& loop, double detail, double min_angle) {
  const size_t n = loop.size();
  if (detail <= 0 || n < 4) return loop;
  Loop out;
  for (size_t k = 0; k < n; ++k) {
    const Point &p = loop[(k + n - 1) % n], &v = loop[k], &q = loop[(k + 1) % n];
    const Point a = p - v, b = q - v;
    const double angle = std::atan2(std::abs(cross(a, b)), a.dot(b));
    if (cross(v - p, q - v) <= 0 || angle >= min_angle * kPi / 180) {
      out.push_back(v);
      continue;
    }
    const double d = std::min({detail / std::cos(angle / 2), 0.4 * a.norm(), 0.4 * b.norm()});
    out.push_back(v + d * a.normalized());
    out.push_back(v + d * b.normalized());
  }
  return out;
}

double orient(const Point& a, const Point& b, const Point& c) { return cross(b - a, c - a); }

bool segments_meet(const Point& a, const Point& b, const Point& c, const Point& d) {
  auto side = [](double o) { return (o > 0) - (o < 0); };
  const int s1 = side(orient(a, b, c)), s2 = side(orient(a, b, d));
  const int s3 = side(orient(c, d, a)), s4 = side(orient(c, d, b));
  if (s1 == 0 && s2 == 0)  // collinear: whether their extents overlap
    return std::max(std::min(a.x(), b.x()), std::min(c.x(), d.x())) <=
               std::min(std::max(a.x(), b.x()), std::max(c.x(), d.x())) &&
           std::max(std::min(a.y(), b.y()), std::min(c.y(), d.y())) <=
               std::min(std::max(a.y(), b.y()), std::max(c.y(), d.y()));
  return s1 * s2 <= 0 && s3 * s4 <= 0;
}

struct Segment {
  double x0, x1;
  int loop;
  size_t k;
};

// The loops that cross or touch another segment (of themselves, not their neighbours, or another
// loop), by a sweep over the segments' x extents.
std::vector<char> crossing_loops(const std::vector<Loop>& loops) {
  std::vector<Segment> segs;
  for (int l = 0; l < int(loops.size()); ++l)
    for (size_t k = 0; k < loops[l].size(); ++k) {
      const Point &a = loops[l][k], &b = loops[l][(k + 1) % loops[l].size()];
      segs.push_back({std::min(a.x(), b.x()), std::max(a.x(), b.x()), l, k});
    }
  std::sort(segs.begin(), segs.end(), [](const Segment& a, const Segment& b) { return a.x0 < b.x0; });
  std::vector<char> bad(loops.size(), 0);
  for (size_t s = 0; s < segs.size(); ++s)
    for (size_t t = s + 1; t < segs.size() && segs[t].x0 <= segs[s].x1; ++t) {
      const Segment &u = segs[s], &w = segs[t];
      const Loop &lu = loops[u.loop], &lw = loops[w.loop];
      const size_t n = lu.size();
      if (u.loop == w.loop && ((u.k + 1) % n == w.k || (w.k + 1) % n == u.k)) continue;
      if (segments_meet(lu[u.k], lu[(u.k + 1) % n], lw[w.k], lw[(w.k + 1) % lw.size()]))
        bad[u.loop] = bad[w.loop] = 1;
    }
  return bad;
}

}  // namespace

std::vector<Loop> simplify(const std::vector<Loop>& loops, double detail, double min_angle) {
  std::vector<double> tol(loops.size(), detail);
  std::vector<Loop> out(loops.size());
  for (int round = 0;; ++round) {
    for (size_t l = 0; l < loops.size(); ++l)
      out[l] = blunted(simplified(loops[l], tol[l]), tol[l], min_angle);
    const std::vector<char> bad = crossing_loops(out);
    if (std::find(bad.begin(), bad.end(), 1) == bad.end()) return out;
    // Traced loops never cross: the last round keeps the crossing ones as traced.
    for (size_t l = 0; l < loops.size(); ++l)
      if (bad[l]) tol[l] = round < 6 ? tol[l] / 2 : 0.0;
    if (round > 7) return out;
  }
}

}  // namespace bdinterp::sprite
