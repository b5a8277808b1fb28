// Tracing the sprite's outline: marching squares on alpha - threshold at the pixel centres.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "sprite/outline.h"

namespace bdinterp::sprite {
namespace {

// Crossing ids: the horizontal edge from sample (i, j) to (i+1, j) is j*width + i, the vertical one
// from (i, j) to (i, j+1) is width*height + j*width + i.
struct Edges {
  int64_t width, count;
  int64_t h(int i, int j) const { return int64_t(j) * width + i; }
  int64_t v(int i, int j) const { return count + int64_t(j) * width + i; }
};

Point crossing(const Field& f, const Edges& e, int64_t id) {
  const bool vertical = id >= e.count;
  const int64_t k = vertical ? id - e.count : id;
  const int i = int(k % e.width), j = int(k / e.width);
  const double a = f.at(i, j), b = vertical ? f.at(i, j + 1) : f.at(i + 1, j);
  const double t = a / (a - b);
  return vertical ? f.position(i, j + t) : f.position(i + t, j);
}

// The segments of one cell, from -> to with the inside on the left; bit 0: (i, j), bit 1: (i+1, j),
// bit 2: (i+1, j+1), bit 3: (i, j+1). Returns the number of segments (0, 1 or 2).
int cell_segments(const Field& f, const Edges& e, int i, int j, int64_t seg[4]) {
  const float c[4] = {f.at(i, j), f.at(i + 1, j), f.at(i + 1, j + 1), f.at(i, j + 1)};
  const int code = (c[0] >= 0) | (c[1] >= 0) << 1 | (c[2] >= 0) << 2 | (c[3] >= 0) << 3;
  if (code == 0 || code == 15) return 0;
  const int64_t B = e.h(i, j), R = e.v(i + 1, j), T = e.h(i, j + 1), L = e.v(i, j);
  auto one = [&](int64_t a, int64_t b) { seg[0] = a, seg[1] = b; return 1; };
  auto two = [&](int64_t a, int64_t b, int64_t p, int64_t q) {
    seg[0] = a, seg[1] = b, seg[2] = p, seg[3] = q;
    return 2;
  };
  const bool centre_in = c[0] + c[1] + c[2] + c[3] >= 0;
  switch (code) {
    case 1: return one(B, L);
    case 2: return one(R, B);
    case 3: return one(R, L);
    case 4: return one(T, R);
    case 5: return centre_in ? two(B, R, T, L) : two(B, L, T, R);
    case 6: return one(T, B);
    case 7: return one(T, L);
    case 8: return one(L, T);
    case 9: return one(B, T);
    case 10: return centre_in ? two(L, B, R, T) : two(R, B, L, T);
    case 11: return one(R, T);
    case 12: return one(L, R);
    case 13: return one(B, R);
    default: return one(L, B);  // 14
  }
}

bool inside_loop(const Loop& loop, const Point& p) {
  bool in = false;
  for (size_t a = 0, b = loop.size() - 1; a < loop.size(); b = a++) {
    const Point &u = loop[a], &w = loop[b];
    if ((u.y() > p.y()) != (w.y() > p.y()) &&
        p.x() < (w.x() - u.x()) * (p.y() - u.y()) / (w.y() - u.y()) + u.x())
      in = !in;
  }
  return in;
}

double segment_distance(const Point& p, const Point& a, const Point& b) {
  const Point ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

}  // namespace

Field alpha_field(const Eigen::Ref<const AlphaImage>& alpha, double threshold, int margin) {
  Field f;
  const int h = int(alpha.rows()), w = int(alpha.cols());
  f.margin = margin, f.width = w + 2 * margin, f.height = h + 2 * margin;
  f.value.assign(size_t(f.width) * f.height, float(-threshold));
  const float th = float(threshold);
  f.lo_i = f.width, f.lo_j = f.height, f.hi_i = f.hi_j = -1;
  for (int r = 0; r < h; ++r) {
    const int j = h - 1 - r + margin;
    float* row = &f.at(margin, j);
    for (int c = 0; c < w; ++c) {
      const float v = alpha(r, c) - th;
      row[c] = v == 0.0f ? 1e-6f : v;
      if (v >= 0) {
        f.lo_i = std::min(f.lo_i, c + margin), f.hi_i = std::max(f.hi_i, c + margin);
        f.lo_j = std::min(f.lo_j, j), f.hi_j = std::max(f.hi_j, j);
      }
    }
  }
  return f;
}

std::vector<Loop> trace(const Field& f) {
  const Edges e{f.width, int64_t(f.width) * f.height};
  std::unordered_map<int64_t, int64_t> next;  // from -> to, per crossing (few: the outline's)
  std::vector<int64_t> starts;
  int64_t seg[4];
  // Only the cells that touch a sample that may be inside.
  for (int j = std::max(0, f.lo_j - 1); j + 1 < f.height && j <= f.hi_j; ++j)
    for (int i = std::max(0, f.lo_i - 1); i + 1 < f.width && i <= f.hi_i; ++i) {
      const int n = cell_segments(f, e, i, j, seg);
      for (int s = 0; s < n; ++s) {
        next[seg[2 * s]] = seg[2 * s + 1];
        starts.push_back(seg[2 * s]);
      }
    }
  std::vector<Loop> loops;
  for (int64_t start : starts) {
    auto at = next.find(start);
    if (at == next.end()) continue;  // already on a loop
    Loop loop;
    while (at != next.end()) {
      loop.push_back(crossing(f, e, at->first));
      const int64_t to = at->second;
      next.erase(at);
      at = next.find(to);
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

double signed_area(const Loop& loop) {
  double a = 0;
  for (size_t k = 0, l = loop.size() - 1; k < loop.size(); l = k++)
    a += loop[l].x() * loop[k].y() - loop[k].x() * loop[l].y();
  return 0.5 * a;
}

Dropped drop_small(Field& f, std::vector<Loop>& loops, double min_area) {
  Dropped dropped;
  std::vector<Loop> kept, small;
  for (Loop& loop : loops)
    (std::abs(signed_area(loop)) >= min_area ? kept : small).push_back(std::move(loop));
  // Smallest first: an island inside a small hole is flipped out, then the hole (and it) filled.
  std::sort(small.begin(), small.end(), [](const Loop& a, const Loop& b) {
    return std::abs(signed_area(a)) < std::abs(signed_area(b));
  });
  for (const Loop& loop : small) {
    const double area = signed_area(loop);
    (area > 0 ? dropped.islands : dropped.holes) += 1;
    // An island's samples become outside, a hole's inside (they lie in the loop's bounding box).
    Eigen::AlignedBox2d box;
    for (const Point& p : loop) box.extend(p);
    const float flipped = area > 0 ? -1.0f : 1.0f;
    for (int j = std::max(0, int(box.min().y() + f.margin - 1)); j < f.height; ++j) {
      if (f.position(0, j).y() > box.max().y()) break;
      for (int i = std::max(0, int(box.min().x() + f.margin - 1)); i < f.width; ++i) {
        const Point p = f.position(i, j);
        if (p.x() > box.max().x()) break;
        if ((f.at(i, j) >= 0) == (area > 0) && inside_loop(loop, p)) f.at(i, j) = flipped;
      }
    }
  }
  loops.swap(kept);
  return dropped;
}

Field grown(const Field& f, const std::vector<Loop>& loops, double padding) {
  // Outside samples: padding - (distance to the outline, capped at `reach`), so the zero level is
  // exact where it matters (neighbours of a crossing lie within padding + 1 of the outline).
  const double reach = padding + 1.5;
  Field g = f;
  std::vector<float> distance(g.value.size(), float(reach));
  for (const Loop& loop : loops)
    for (size_t k = 0, l = loop.size() - 1; k < loop.size(); l = k++) {
      const Point &a = loop[l], &b = loop[k];
      const int i0 = std::max(0, int(std::floor(std::min(a.x(), b.x()) - reach + f.margin - 0.5)));
      const int i1 = std::min(f.width - 1, int(std::ceil(std::max(a.x(), b.x()) + reach + f.margin - 0.5)));
      const int j0 = std::max(0, int(std::floor(std::min(a.y(), b.y()) - reach + f.margin - 0.5)));
      const int j1 = std::min(f.height - 1, int(std::ceil(std::max(a.y(), b.y()) + reach + f.margin - 0.5)));
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
          float& d = distance[size_t(j) * f.width + i];
          d = std::min(d, float(segment_distance(f.position(i, j), a, b)));
        }
    }
  const int grow = int(std::ceil(reach));
  g.lo_i = std::max(0, f.lo_i - grow), g.hi_i = std::min(f.width - 1, f.hi_i + grow);
  g.lo_j = std::max(0, f.lo_j - grow), g.hi_j = std::min(f.height - 1, f.hi_j + grow);
  for (int j = g.lo_j; j <= g.hi_j; ++j)
    for (int i = g.lo_i; i <= g.hi_i; ++i) {
      const size_t s = size_t(j) * f.width + i;
      const float v = g.value[s] >= 0 ? float(padding + 1.0) : float(padding) - distance[s];
      g.value[s] = v == 0.0f ? 1e-6f : v;
    }
  return g;
}

}  // namespace bdinterp::sprite
