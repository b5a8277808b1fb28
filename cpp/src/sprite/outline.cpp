// Tracing the sprite's outline: marching squares on alpha - threshold at the pixel centres.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "sprite/outline.h"

namespace bdinterp::sprite {
namespace {

// The sides of a cell (i, j): bottom (i, j)-(i+1, j), right (i+1, j)-(i+1, j+1), top
// (i, j+1)-(i+1, j+1), left (i, j)-(i, j+1). A side's opposite is (side + 2) & 3, in the
// neighbour that shares it, which lies one step in kStep[side].
enum Side { kBottom, kRight, kTop, kLeft };
constexpr int kStep[4][2] = {{0, -1}, {1, 0}, {0, 1}, {-1, 0}};

// The zero of the field on a side of cell (i, j), linear between the side's two samples.
Point crossing(const Field& f, int i, int j, int side) {
  const int i0 = i + (side == kRight), j0 = j + (side == kTop);  // the side's first sample
  const bool vertical = side == kRight || side == kLeft;
  const double a = f.at(i0, j0), b = vertical ? f.at(i0, j0 + 1) : f.at(i0 + 1, j0);
  const double t = a / (a - b);
  return vertical ? f.position(i0, j0 + t) : f.position(i0 + t, j0);
}

// The cells that may hold a crossing (those touching a sample that may be inside), inclusive.
struct Cells {
  int i0, i1, j0, j1;
  bool empty() const { return i1 < i0 || j1 < j0; }
  size_t index(int i, int j) const { return size_t(j - j0) * size_t(i1 - i0 + 1) + size_t(i - i0); }
  size_t count() const { return empty() ? 0 : index(i1, j1) + 1; }
  bool has(int i, int j) const { return i0 <= i && i <= i1 && j0 <= j && j <= j1; }
};

Cells cells_of(const Field& f) {
  return {std::max(0, f.lo_i - 1), std::min(f.width - 2, f.hi_i), std::max(0, f.lo_j - 1),
          std::min(f.height - 2, f.hi_j)};
}

// Corner bits of cell (i, j): bit 0: (i, j), bit 1: (i+1, j), bit 2: (i+1, j+1), bit 3: (i, j+1).
int code_of(const Field& f, int i, int j) {
  return (f.at(i, j) >= 0) | (f.at(i + 1, j) >= 0) << 1 | (f.at(i + 1, j + 1) >= 0) << 2 | (f.at(i, j + 1) >= 0) << 3;
}

// visit(i, j, code) for every cell of c that the zero level crosses, row by row (j, then i); each
// row reads its two sample rows once, the right column's bits becoming the next cell's left ones.
template <class Visit>
void for_each_crossed_cell(const Field& f, const Cells& c, Visit visit) {
  for (int j = c.j0; j <= c.j1; ++j) {
    const float* lo = &f.value[size_t(j) * f.width];
    const float* hi = lo + f.width;
    int left = (lo[c.i0] >= 0) | (hi[c.i0] >= 0) << 3;
    for (int i = c.i0; i <= c.i1; ++i) {
      const int right = (lo[i + 1] >= 0) << 1 | (hi[i + 1] >= 0) << 2;
      const int code = left | right;
      left = (right >> 1 & 1) | (right << 1 & 8);
      if (code != 0 && code != 15) visit(i, j, code);
    }
  }
}

// The segments of one cell (its corner code) as sides, from -> to with the inside on the left.
// Returns the number of segments (0, 1 or 2).
int cell_segments(const Field& f, int i, int j, int code, int seg[4]) {
  constexpr int B = kBottom, R = kRight, T = kTop, L = kLeft;
  auto one = [&](int a, int b) { seg[0] = a, seg[1] = b; return 1; };
  auto two = [&](int a, int b, int p, int q) {
    seg[0] = a, seg[1] = b, seg[2] = p, seg[3] = q;
    return 2;
  };
  auto centre_in = [&] { return f.at(i, j) + f.at(i + 1, j) + f.at(i + 1, j + 1) + f.at(i, j + 1) >= 0; };
  switch (code) {
    case 0: case 15: return 0;
    case 1: return one(B, L);
    case 2: return one(R, B);
    case 3: return one(R, L);
    case 4: return one(T, R);
    case 5: return centre_in() ? two(B, R, T, L) : two(B, L, T, R);
    case 6: return one(T, B);
    case 7: return one(T, L);
    case 8: return one(L, T);
    case 9: return one(B, T);
    case 10: return centre_in() ? two(L, B, R, T) : two(R, B, L, T);
    case 11: return one(R, T);
    case 12: return one(L, R);
    case 13: return one(B, R);
    default: return one(L, B);  // 14
  }
}

// The loop through segment s of cell (i, j): from cell to cell across each segment's `to` side
// (the neighbour's segment that starts there comes next), marking each segment used, until it
// closes.
Loop follow(const Field& f, const Cells& c, std::vector<uint8_t>& used, int i, int j, int s) {
  Loop loop;
  int seg[4];
  cell_segments(f, i, j, code_of(f, i, j), seg);
  for (;;) {
    used[c.index(i, j)] |= uint8_t(1 << s);
    loop.push_back(crossing(f, i, j, seg[2 * s]));
    const int out = seg[2 * s + 1], in = (out + 2) & 3;
    i += kStep[out][0], j += kStep[out][1];
    if (!c.has(i, j)) return loop;  // (never: a crossing's cells both touch an inside sample)
    const int n = cell_segments(f, i, j, code_of(f, i, j), seg);
    s = n > 0 && seg[0] == in ? 0 : n > 1 && seg[2] == in ? 1 : -1;
    if (s < 0 || (used[c.index(i, j)] >> s & 1)) return loop;
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

double squared_distance(const Point& p, const Point& a, const Point& b) {
  const Point ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).squaredNorm();
}

// The outline's segments (from, to), cell by cell.
std::vector<std::pair<Point, Point>> segments_of(const Field& f) {
  const Cells c = cells_of(f);
  std::vector<std::pair<Point, Point>> out;
  if (!c.empty())
    for_each_crossed_cell(f, c, [&](int i, int j, int code) {
      int seg[4];
      for (int s = 0, n = cell_segments(f, i, j, code, seg); s < n; ++s)
        out.emplace_back(crossing(f, i, j, seg[2 * s]), crossing(f, i, j, seg[2 * s + 1]));
    });
  return out;
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
  const Cells c = cells_of(f);
  std::vector<uint8_t> used(c.count(), 0);  // per cell: bit s set once its segment s is on a loop
  std::vector<Loop> loops;
  if (c.empty()) return loops;
  for_each_crossed_cell(f, c, [&](int i, int j, int code) {
    int seg[4];
    const int n = cell_segments(f, i, j, code, seg);
    for (int s = 0; s < n; ++s)
      if (!(used[c.index(i, j)] >> s & 1)) loops.push_back(follow(f, c, used, i, j, s));
  });
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
  std::vector<Loop> kept;
  std::vector<std::pair<double, Loop>> small;  // (signed area, loop)
  for (Loop& loop : loops) {
    const double area = signed_area(loop);
    if (std::abs(area) >= min_area) kept.push_back(std::move(loop));
    else small.emplace_back(area, std::move(loop));
  }
  // Smallest first: an island inside a small hole is flipped out, then the hole (and it) filled.
  std::stable_sort(small.begin(), small.end(),
                   [](const auto& a, const auto& b) { return std::abs(a.first) < std::abs(b.first); });
  for (const auto& [area, loop] : small) {
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

Field grown(Field f, double padding) {
  const std::vector<std::pair<Point, Point>> segments = segments_of(f);  // before the field changes
  // Outside samples: padding - (distance to the outline, capped at `reach`), so the zero level is
  // exact where it matters (neighbours of a crossing lie within padding + 1 of the outline). While
  // the segments are visited an outside sample holds minus its distance so far; a segment's square
  // root is taken only where its squared distance is smaller.
  const double reach = padding + 1.5;
  const int grow = int(std::ceil(reach));
  f.lo_i = std::max(0, f.lo_i - grow), f.hi_i = std::min(f.width - 1, f.hi_i + grow);
  f.lo_j = std::max(0, f.lo_j - grow), f.hi_j = std::min(f.height - 1, f.hi_j + grow);
  const float inside = float(padding + 1.0);
  for (int j = f.lo_j; j <= f.hi_j; ++j)
    for (int i = f.lo_i; i <= f.hi_i; ++i) f.at(i, j) = f.at(i, j) >= 0 ? inside : -float(reach);
  for (const auto& [a, b] : segments) {
    const int i0 = std::max(f.lo_i, int(std::floor(std::min(a.x(), b.x()) - reach + f.margin - 0.5)));
    const int i1 = std::min(f.hi_i, int(std::ceil(std::max(a.x(), b.x()) + reach + f.margin - 0.5)));
    const int j0 = std::max(f.lo_j, int(std::floor(std::min(a.y(), b.y()) - reach + f.margin - 0.5)));
    const int j1 = std::min(f.hi_j, int(std::ceil(std::max(a.y(), b.y()) + reach + f.margin - 0.5)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        float& v = f.at(i, j);
        if (v > 0) continue;  // inside
        const double d2 = squared_distance(f.position(i, j), a, b);
        if (d2 < double(v) * double(v)) v = std::max(v, -float(std::sqrt(d2)));
      }
  }
  for (int j = f.lo_j; j <= f.hi_j; ++j)
    for (int i = f.lo_i; i <= f.hi_i; ++i) {
      float& v = f.at(i, j);
      if (v > 0) continue;
      v = float(padding) + v;  // padding - distance
      if (v == 0.0f) v = 1e-6f;  // no crossing on a sample
    }
  return f;
}

}  // namespace bdinterp::sprite
