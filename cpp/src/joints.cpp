#include "joints.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>
#include <queue>

#include "geometry.h"
#include "rigid_motion.h"
#include "detail/turns.h"

namespace bdinterp {
namespace {
// A point counts as inside a triangle when its least barycentric weight is at least this (so
// vertices on a shared outline do not make an overlap).
constexpr double kInside = 1e-9;
}  // namespace

namespace detail {
// Finds the triangle of one piece (in the base shape) that contains a point: a uniform grid of
// about one face per cell over the piece's bounding box.
class TriangleGrid {
 public:
  TriangleGrid(const Positions& X, const JointPiece& piece) : X_(X), piece_(piece) {
    const Faces& F = *piece.faces;
    lo_ = hi_ = X.row((*piece.vertices)[0]).transpose();
    for (int v : *piece.vertices) lo_ = lo_.cwiseMin(X.row(v).transpose()), hi_ = hi_.cwiseMax(X.row(v).transpose());
    n_ = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(F.rows()))));
    cells_.resize(static_cast<size_t>(n_) * n_);
    for (int f = 0; f < F.rows(); ++f) {
      Eigen::Vector2d a = corner(f, 0), b = a;
      for (int c = 1; c < 3; ++c) a = a.cwiseMin(corner(f, c)), b = b.cwiseMax(corner(f, c));
      const auto [i0, j0] = cell(a);
      const auto [i1, j1] = cell(b);
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) cells_[static_cast<size_t>(j) * n_ + i].push_back(f);
    }
  }

  bool boxes_meet(const TriangleGrid& o) const {
    return (lo_.array() <= o.hi_.array()).all() && (o.lo_.array() <= hi_.array()).all();
  }
  bool in_box(const Eigen::Vector2d& q) const {
    return (q.array() >= lo_.array()).all() && (q.array() <= hi_.array()).all();
  }
  // The face holding q with the largest least barycentric weight (-inf and face -1 if q is outside
  // the box); bary gets its weights.
  double locate(const Eigen::Vector2d& q, int& face, Eigen::Vector3d& bary) const {
    face = -1;
    double best = -HUGE_VAL;
    if (!in_box(q)) return best;
    const auto [i, j] = cell(q);
    for (int f : cells_[static_cast<size_t>(j) * n_ + i]) {
      const Eigen::Vector2d a = corner(f, 0), e1 = corner(f, 1) - a, e2 = corner(f, 2) - a, d = q - a;
      const double det = e1.x() * e2.y() - e1.y() * e2.x();
      const double s = (d.x() * e2.y() - d.y() * e2.x()) / det, t = (e1.x() * d.y() - e1.y() * d.x()) / det;
      const Eigen::Vector3d b(1 - s - t, s, t);
      if (b.minCoeff() > best) best = b.minCoeff(), face = f, bary = b;
    }
    return best;
  }
  int vertex(int f, int c) const { return (*piece_.vertices)[(*piece_.faces)(f, c)]; }

 private:
  Eigen::Vector2d corner(int f, int c) const { return X_.row(vertex(f, c)).transpose(); }
  std::pair<int, int> cell(const Eigen::Vector2d& q) const {
    const Eigen::Vector2d r = ((q - lo_).array() / (hi_ - lo_).cwiseMax(1e-300).array() * n_).matrix();
    return {std::clamp(static_cast<int>(r.x()), 0, n_ - 1), std::clamp(static_cast<int>(r.y()), 0, n_ - 1)};
  }
  const Positions& X_;
  const JointPiece& piece_;
  Eigen::Vector2d lo_, hi_;
  int n_;
  std::vector<std::vector<int>> cells_;
};
}  // namespace detail

namespace {
using detail::TriangleGrid;

// The vertices of `b` strictly inside `a` (base shape).
std::vector<int> inside(const Positions& X, const TriangleGrid& a, const JointPiece& b) {
  std::vector<int> out;
  int f;
  Eigen::Vector3d bary;
  for (int v : *b.vertices)
    if (a.locate(X.row(v).transpose(), f, bary) >= kInside) out.push_back(v);
  return out;
}

// Piece p's motion from the base to input i (its anchor frames): turn, then base point to point i.
RigidMotion motion(const JointPiece& p, int base, size_t i) {
  const Frame2 &b = (*p.frames)[static_cast<size_t>(base)], &x = (*p.frames)[i];
  const RigidMotion turn{x.angle - b.angle, Eigen::Vector2d::Zero()};
  return {turn.angle, x.point - turn(b.point)};
}

// A first guess at the pin: the fixed point of the child's motion relative to its parent (from
// their anchor frames) in the input that turns it most; false if no input turns it.
bool pin_guess(const JointPiece& parent, const JointPiece& child, int base, Eigen::Vector2d& q) {
  std::vector<RigidMotion> rel;
  for (size_t i = 0; i < parent.frames->size(); ++i) {
    const RigidMotion mp = motion(parent, base, i), mc = motion(child, base, i);
    // mp^-1 after mc: x -> R(-ap) (mc(x) - shift_p)
    const RigidMotion back{-mp.angle, Eigen::Rotation2Dd(-mp.angle) * -mp.shift};
    rel.push_back({mc.angle - mp.angle, back(mc.shift)});
  }
  const auto most = std::max_element(rel.begin(), rel.end(), [](const RigidMotion& a, const RigidMotion& b) {
    return std::abs(std::sin(0.5 * a.angle)) < std::abs(std::sin(0.5 * b.angle));
  });
  const std::complex<double> denom = 1.0 - std::polar(1.0, most->angle);
  if (std::abs(denom) < 1e-6) return false;  // no input turns the child against its parent
  const std::complex<double> z = std::complex<double>(most->shift.x(), most->shift.y()) / denom;
  q = Eigen::Vector2d(z.real(), z.imag());
  return true;
}

// The affine map of face f of a piece from the base shape to X: x -> J x + c.
void face_map(const TriangleGrid& piece, int f, const Positions& B, const Positions& X, Eigen::Matrix2d& J,
              Eigen::Vector2d& c) {
  const int a = piece.vertex(f, 0), b = piece.vertex(f, 1), d = piece.vertex(f, 2);
  J = edge_matrix(X, a, b, d) * edge_matrix(B, a, b, d).inverse();
  c = X.row(a).transpose() - J * B.row(a).transpose();
}

// Refines q to the point that the parent's and the child's triangles carry to the same place in
// every input (least squares over the inputs, per pair of triangles, until they stay the same);
// returns the largest remaining gap over the inputs, infinite if q leaves either piece.
double refine_pin(const std::vector<Positions>& shapes, int base, const TriangleGrid& parent,
                  const TriangleGrid& child, Eigen::Vector2d& q) {
  const Positions& B = shapes[static_cast<size_t>(base)];
  int fp = -1, fc = -1, last_p = -2, last_c = -2;
  Eigen::Vector3d bary;
  for (int iteration = 0; iteration < 10 && (fp != last_p || fc != last_c); ++iteration) {
    last_p = fp, last_c = fc;
    if (parent.locate(q, fp, bary) < -kInside || child.locate(q, fc, bary) < -kInside) return HUGE_VAL;
    Eigen::Matrix2d M = Eigen::Matrix2d::Zero();
    Eigen::Vector2d r = Eigen::Vector2d::Zero();
    for (const Positions& X : shapes) {  // the gap (Jc - Jp) q + (cc - cp) in each input
      Eigen::Matrix2d Jp, Jc;
      Eigen::Vector2d cp, cc;
      face_map(parent, fp, B, X, Jp, cp);
      face_map(child, fc, B, X, Jc, cc);
      M += (Jc - Jp).transpose() * (Jc - Jp);
      r += (Jc - Jp).transpose() * (cc - cp);
    }
    if (std::abs(M.determinant()) < 1e-24) break;  // the pieces move alike: every point is common
    q = -M.inverse() * r;
  }
  double gap = 0;
  for (const Positions& X : shapes) {
    Eigen::Matrix2d Jp, Jc;
    Eigen::Vector2d cp, cc;
    face_map(parent, fp, B, X, Jp, cp);
    face_map(child, fc, B, X, Jc, cc);
    gap = std::max(gap, ((Jc - Jp) * q + cc - cp).norm());
  }
  return gap;
}

// The overlap graph of the pieces in the base shape X: per piece, (neighbour, the vertices of
// either piece strictly inside the other).
std::vector<std::vector<std::pair<int, std::vector<int>>>> overlap_graph(const Positions& X,
                                                                         const std::vector<JointPiece>& pieces,
                                                                         const std::vector<TriangleGrid>& loc) {
  const int n = static_cast<int>(pieces.size());
  std::vector<std::vector<std::pair<int, std::vector<int>>>> overlaps(n);
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      if (!loc[a].boxes_meet(loc[b])) continue;
      std::vector<int> ov = inside(X, loc[a], pieces[b]), ba = inside(X, loc[b], pieces[a]);
      ov.insert(ov.end(), ba.begin(), ba.end());
      if (ov.empty()) continue;
      overlaps[a].emplace_back(b, ov);
      overlaps[b].emplace_back(a, std::move(ov));
    }
  }
  return overlaps;
}

// How far each piece's anchor moves from the base in any of the k inputs (turn x size + shift).
std::vector<double> piece_moves(const std::vector<JointPiece>& pieces, int base, size_t k, double size) {
  std::vector<double> moves(pieces.size(), 0.0);
  for (size_t p = 0; p < pieces.size(); ++p) {
    const Eigen::Vector2d at = pieces[p].frames->at(static_cast<size_t>(base)).point;
    for (size_t i = 0; i < k; ++i) {
      const RigidMotion m = motion(pieces[p], base, i);
      moves[p] = std::max(moves[p], std::abs(m.angle) * size + (m(at) - at).norm());
    }
  }
  return moves;
}

}  // namespace

Eigen::Vector2d Joints::Site::at(const Eigen::Ref<const Positions>& X) const {
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  for (int c = 0; c < 3; ++c) p += bary[c] * X.row(v[c]).transpose();
  return p;
}

Joints::Joints(const std::vector<Positions>& shapes, int base, const std::vector<JointPiece>& pieces, int root)
    : pieces_(pieces) {
  const Positions& X = shapes[static_cast<size_t>(base)];
  const double size = (X.colwise().maxCoeff() - X.colwise().minCoeff()).norm();
  const int n = static_cast<int>(pieces_.size());
  std::vector<TriangleGrid> loc;
  for (const JointPiece& p : pieces_) loc.emplace_back(X, p);
  auto overlaps = overlap_graph(X, pieces_, loc);
  std::vector<double> moves = piece_moves(pieces_, base, shapes.size(), size);
  if (root >= 0) moves[static_cast<size_t>(root)] = -1;  // first in its group
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return moves[a] < moves[b]; });
  // A tree per group of overlapping pieces from the one that moves least, breadth first.
  std::vector<bool> seen(n, false);
  for (int first : order) {
    if (seen[first]) continue;
    seen[first] = true;
    std::queue<int> todo;
    todo.push(first);
    while (!todo.empty()) {
      const int u = todo.front();
      todo.pop();
      auto& next = overlaps[u];
      std::stable_sort(next.begin(), next.end(),
                       [&](const auto& a, const auto& b) { return moves[a.first] < moves[b.first]; });
      for (const auto& [v, ov] : next) {
        if (seen[v]) continue;
        seen[v] = true;
        add_joint(shapes, base, size, u, v, ov, loc[u], loc[v]);
        todo.push(v);
      }
    }
  }
}

void Joints::add_joint(const std::vector<Positions>& shapes, int base, double size, int parent, int child,
                       const std::vector<int>& overlap, const TriangleGrid& in_parent,
                       const TriangleGrid& in_child) {
  const Positions& X = shapes[static_cast<size_t>(base)];
  Joint j{parent, child, {}, false, {}, {}, {}, {}, {}};
  int fp = -1, fc = -1;
  Eigen::Vector3d bp = Eigen::Vector3d::Zero(), bc = bp;
  // A pin: the child turns against its parent about one point inside both pieces (the overlap),
  // which both carry to the same place in every input (to 0.1 % of the size).
  const bool pin = pin_guess(pieces_[parent], pieces_[child], base, j.point) &&
                   refine_pin(shapes, base, in_parent, in_child, j.point) <= 1e-3 * size &&
                   in_parent.locate(j.point, fp, bp) >= -kInside && in_child.locate(j.point, fc, bc) >= -kInside;
  j.pin = pin;
  if (!pin) {
    // Else the overlap's vertex nearest to the overlap's centre (inside both pieces).
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (int v : overlap) centre += X.row(v).transpose() / static_cast<double>(overlap.size());
    const int v = *std::min_element(overlap.begin(), overlap.end(), [&](int a, int b) {
      return (X.row(a).transpose() - centre).norm() < (X.row(b).transpose() - centre).norm();
    });
    j.point = X.row(v).transpose();
    in_parent.locate(j.point, fp, bp);
    in_child.locate(j.point, fc, bc);
  }
  j.in_parent = {{in_parent.vertex(fp, 0), in_parent.vertex(fp, 1), in_parent.vertex(fp, 2)}, bp};
  j.in_child = {{in_child.vertex(fc, 0), in_child.vertex(fc, 1), in_child.vertex(fc, 2)}, bc};
  const std::vector<Frame2>&P = *pieces_[parent].frames, &C = *pieces_[child].frames;
  const size_t b = static_cast<size_t>(base);
  for (size_t i = 0; i < shapes.size(); ++i) {
    j.parent_angle.push_back(P[i].angle);
    // The keys' turn of the child against its parent, the short way (a joint does not wind up).
    const double turn = (C[i].angle - C[b].angle) - (P[i].angle - P[b].angle);
    j.relative.push_back(C[b].angle - P[b].angle + detail::wrap_angle(turn));
    j.offset.push_back(j.in_child.at(shapes[i]) - j.in_parent.at(shapes[i]));
  }
  joints_.push_back(std::move(j));
}

void Joints::apply(const Eigen::VectorXd& w, std::vector<double>& angle, Eigen::Ref<Positions> out) const {
  for (const Joint& j : joints_) {
    double turn = 0;  // the child's angle: the parent's plus the blend of their relative angles
    Eigen::Vector2d offset = Eigen::Vector2d::Zero();  // the keys' offsets blended in the parent's frame
    for (Eigen::Index i = 0; i < w.size(); ++i) {
      turn += w[i] * j.relative[static_cast<size_t>(i)];
      offset += w[i] * (Eigen::Rotation2Dd(angle[j.parent] - j.parent_angle[static_cast<size_t>(i)]) *
                        j.offset[static_cast<size_t>(i)]);
    }
    turn += angle[j.parent];
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(turn - angle[j.child]).toRotationMatrix();
    angle[j.child] = turn;
    const Eigen::Vector2d from = j.in_child.at(out), to = j.in_parent.at(out) + offset;
    for (int v : *pieces_[j.child].vertices) out.row(v) = (R * (out.row(v).transpose() - from) + to).transpose();
  }
}

}  // namespace bdinterp
