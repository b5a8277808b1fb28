#include "place/piece_shape.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace bdinterp::detail {
namespace {

// The squared distance from q to the segment [a, b].
double squared_distance(const Eigen::Vector2d& q, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d e = b - a;
  const double t = std::clamp((q - a).dot(e) / std::max(e.squaredNorm(), 1e-300), 0.0, 1.0);
  return (a + t * e - q).squaredNorm();
}

// Whether the segments [a, b] and [c, d] cross or come within sqrt(margin2): true also when
// unsure (collinear, touching).
bool segments_near(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                   const Eigen::Vector2d& d, double margin2) {
  const auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); };
  if (cross(b - a, c - a) * cross(b - a, d - a) <= 0 && cross(d - c, a - c) * cross(d - c, b - c) <= 0) return true;
  return std::min({squared_distance(a, c, d), squared_distance(b, c, d), squared_distance(c, a, b),
                   squared_distance(d, a, b)}) < margin2;
}

}  // namespace

PieceShape::PieceShape(const JointPiece& piece) : piece_(piece) {
  const std::vector<std::vector<int>>& loops = piece.mesh->boundary_loops();
  size_t points = 0;
  for (const std::vector<int>& loop : loops) points += loop.size() + 1;
  outline_vertex_.reserve(points), outline_.reserve(points), runs_.reserve(points / kRunEdges + loops.size());
  for (const std::vector<int>& loop : loops) {
    const int first = static_cast<int>(outline_.size()), n = static_cast<int>(loop.size());
    outline_vertex_.insert(outline_vertex_.end(), loop.begin(), loop.end());
    outline_vertex_.push_back(loop.front());  // closed: the loop's first vertex again at its end
    for (int k = first; k <= first + n; ++k) outline_.push_back(piece.base->row(outline_vertex_[k]).transpose());
    for (int k = first; k < first + n; k += kRunEdges) {
      Run run{Eigen::AlignedBox2d(outline_[static_cast<size_t>(k)]), k, std::min(first + n, k + kRunEdges)};
      for (int i = k + 1; i <= run.end; ++i) run.box.extend(outline_[static_cast<size_t>(i)]);
      runs_.push_back(run);
    }
  }
  Eigen::AlignedBox2d box;
  for (const Run& r : runs_) box.extend(r.box);
  lo_ = box.min(), hi_ = box.max();
}

Eigen::Vector3d PieceShape::barycentric(const Eigen::Vector2d& q, int f) const {
  const Eigen::Vector2d a = corner(f, 0), e1 = corner(f, 1) - a, e2 = corner(f, 2) - a, d = q - a;
  const double det = e1.x() * e2.y() - e1.y() * e2.x();
  const double s = (d.x() * e2.y() - d.y() * e2.x()) / det, t = (e1.x() * d.y() - e1.y() * d.x()) / det;
  return {1 - s - t, s, t};
}

int PieceShape::walk(const Eigen::Vector2d& q, int f, Eigen::Vector3d& bary, int steps) const {
  const Mesh& mesh = *piece_.mesh;
  for (int step = 0; step <= steps; ++step) {
    bary = barycentric(q, f);
    if (bary.minCoeff() >= -kInside) return f;
    std::array<int, 3> order = {0, 1, 2};  // across the edge q lies farthest beyond, else the next
    std::sort(order.begin(), order.end(), [&](int i, int j) { return bary[i] < bary[j]; });
    int next = -1;
    for (int k = 0; k < 3 && next < 0 && bary[order[k]] < -kInside; ++k)
      next = mesh.opposite_face(mesh.face_edges()(f, order[k]), f);
    if (next < 0) return -1;  // the outline
    f = next;
  }
  return -1;
}

int PieceShape::scan(const Eigen::Vector2d& q, Eigen::Vector3d& bary) const {
  int face = -1;
  double best = -kInside;
  for (int f = 0; f < piece_.mesh->num_faces(); ++f) {
    const Eigen::Vector3d b = barycentric(q, f);
    if (b.minCoeff() >= best) best = b.minCoeff(), face = f, bary = b;
  }
  return face;
}

double PieceShape::locate(const Eigen::Vector2d& q, int& face, Eigen::Vector3d& bary) const {
  face = -1;
  if (!in_box(q)) return -HUGE_VAL;
  // From the last face found when q lies near it (a least weight above -kNearWalk / 2)
  int f = barycentric(q, hint_).minCoeff() > -0.5 * kNearWalk ? walk(q, hint_, bary, kNearWalk) : -1;
  if (f < 0) {  // else, or where the outline stopped that walk, from a face at the outline nearest
    double distance;  // q, whose segment to q crosses no outline
    f = walk(q, *piece_.mesh->vertex_faces(nearest_edge(q, HUGE_VAL, distance)[0]).begin(), bary,
             piece_.mesh->num_faces());
    // A face holding q strictly inside settles it (the faces cover what the outline winds round);
    // else the outline decides, and where it winds round q, the search of every face.
    if (!(f >= 0 && bary.minCoeff() > 0) && !winds(q)) return -HUGE_VAL;
    if (f < 0) f = scan(q, bary);  // a walk that turned back on itself
  }
  if (f < 0) return -HUGE_VAL;
  hint_ = face = f;
  return bary.minCoeff();
}

bool PieceShape::contains(const Eigen::Vector2d& q) const {
  const double margin = kOnOutline * diagonal();
  bool near = false;
  const int w = winding(q, margin * margin, near);
  return !near && w != 0;
}

bool PieceShape::holds(const PieceShape& other) const {
  if ((other.lo_.array() < lo_.array()).any() || (other.hi_.array() > hi_.array()).any()) return false;
  const double margin = kOnOutline * diagonal(), margin2 = margin * margin;
  const Eigen::AlignedBox2d box(other.lo_, other.hi_);
  for (const Run& r : runs_) {
    if (!(r.box.squaredExteriorDistance(box) < margin2)) continue;
    for (const Run& s : other.runs_) {
      if (!(r.box.squaredExteriorDistance(s.box) < margin2)) continue;
      for (int k = r.begin; k < r.end; ++k)
        for (int j = s.begin; j < s.end; ++j)
          if (segments_near(outline_[static_cast<size_t>(k)], outline_[static_cast<size_t>(k) + 1],
                            other.outline_[static_cast<size_t>(j)], other.outline_[static_cast<size_t>(j) + 1], margin2))
            return false;
    }
    for (int k = r.begin; k < r.end; ++k)
      if (other.in_box(outline_[static_cast<size_t>(k)]) && other.winds(outline_[static_cast<size_t>(k)])) return false;
  }
  return contains(other.outline_.front());
}

double PieceShape::locate_nearest(const Eigen::Vector2d& q, int& face, Eigen::Vector3d& bary) const {
  const double inside = locate(q, face, bary);
  if (face >= 0) return inside;
  double distance;
  face = edge_face(nearest_edge(q, HUGE_VAL, distance));
  bary = barycentric(q, face);
  return bary.minCoeff();
}

double PieceShape::outside(const Eigen::Vector2d& q, double within) const {
  const Eigen::Vector2d reach = Eigen::Vector2d::Constant(within);
  if (((q - reach).array() > hi_.array()).any() || ((q + reach).array() < lo_.array()).any()) return within;
  int face;
  Eigen::Vector3d bary;
  if (locate(q, face, bary) > -HUGE_VAL) return 0;
  double distance;
  nearest_edge(q, within, distance);
  return distance;
}

int PieceShape::winding(const Eigen::Vector2d& q, double margin2, bool& near) const {
  int winding = 0;  // signed crossings of the ray from q to +x
  const double m = std::sqrt(margin2);
  for (const Run& r : runs_) {  // a run neither near q nor crossed by the ray first, in three comparisons
    if (q.y() < r.box.min().y() - m || q.y() > r.box.max().y() + m || q.x() > r.box.max().x() + m) continue;
    near = r.box.squaredExteriorDistance(q) < margin2;
    for (int k = r.begin; k < r.end; ++k) {
      const Eigen::Vector2d &a = outline_[static_cast<size_t>(k)], &b = outline_[static_cast<size_t>(k) + 1];
      if (near && squared_distance(q, a, b) < margin2) return 0;
      if ((a.y() <= q.y()) != (b.y() <= q.y()) && a.x() + (q.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()) > q.x())
        winding += b.y() > a.y() ? 1 : -1;
    }
  }
  near = false;
  return winding;
}

std::array<int, 2> PieceShape::nearest_edge(const Eigen::Vector2d& q, double within, double& distance) const {
  double least = within * within;  // squared distances, one root at the end
  int best = -1;
  const auto edges = [&](const Run& r) {
    for (int k = r.begin; k < r.end; ++k) {
      const double d = squared_distance(q, outline_[static_cast<size_t>(k)], outline_[static_cast<size_t>(k) + 1]);
      if (d < least || (d == least && k < best)) least = d, best = k;  // ties: the first edge
    }
  };
  // The run whose box is nearest first: its edges bound the distance the other runs must beat.
  const auto first = std::min_element(runs_.begin(), runs_.end(), [&](const Run& a, const Run& b) {
    return a.box.squaredExteriorDistance(q) < b.box.squaredExteriorDistance(q);
  });
  if (first != runs_.end() && first->box.squaredExteriorDistance(q) < least) edges(*first);
  for (const Run& r : runs_)
    if (&r != &*first && r.box.squaredExteriorDistance(q) <= least) edges(r);
  distance = best < 0 ? within : std::sqrt(least);
  if (best < 0) return {-1, -1};
  return {outline_vertex_[static_cast<size_t>(best)], outline_vertex_[static_cast<size_t>(best) + 1]};
}

int PieceShape::edge_face(const std::array<int, 2>& edge) const {
  const Faces& F = piece_.mesh->faces();
  for (int f : piece_.mesh->vertex_faces(edge[0]))
    if (F(f, 0) == edge[1] || F(f, 1) == edge[1] || F(f, 2) == edge[1]) return f;
  return *piece_.mesh->vertex_faces(edge[0]).begin();  // not reached: an outline edge has its face
}

}  // namespace bdinterp::detail
