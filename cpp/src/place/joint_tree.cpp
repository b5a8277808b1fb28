// Which piece of a cut-out character holds which (joints.h, docs/JOINTS.md): the kind of each
// overlapping pair from its relative motion between the inputs, and the tree of the best joints.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>
#include <queue>
#include <sstream>

#include "mesh/geometry.h"
#include "place/joints.h"
#include "place/rigid_motion.h"
#include "mesh/turns.h"

namespace bdinterp::detail {
namespace {

// A piece whose anchor moves by at most this fraction of the size in every input is still (the
// float32 keys of a still piece moved by an armature differ by about 1e-7).
constexpr double kStill = 1e-6;

// Piece p's motion from the base to input i (its anchor frames): turn, then base point to point i.
RigidMotion motion(const JointPiece& p, int base, size_t i) {
  const Frame2 &b = (*p.frames)[static_cast<size_t>(base)], &x = (*p.frames)[i];
  const RigidMotion turn{x.angle - b.angle, Eigen::Vector2d::Zero()};
  return {turn.angle, x.point - turn(b.point)};
}

// Per input, the child's motion relative to its parent: mp^-1 after mc.
std::vector<RigidMotion> relative_motions(const JointPiece& parent, const JointPiece& child, int base) {
  std::vector<RigidMotion> rel;
  rel.reserve(parent.frames->size());
  for (size_t i = 0; i < parent.frames->size(); ++i) {
    const RigidMotion mp = motion(parent, base, i), mc = motion(child, base, i);
    const RigidMotion back{-mp.angle, Eigen::Rotation2Dd(-mp.angle) * -mp.shift};
    rel.push_back({mc.angle - mp.angle, back(mc.shift)});
  }
  return rel;
}

// A first guess at the pin: the fixed point of the relative motion in the input that turns the
// child most; false if no input turns it.
bool pin_guess(const std::vector<RigidMotion>& rel, Eigen::Vector2d& q) {
  const auto most = std::max_element(rel.begin(), rel.end(), [](const RigidMotion& a, const RigidMotion& b) {
    return std::abs(std::sin(0.5 * a.angle)) < std::abs(std::sin(0.5 * b.angle));
  });
  const std::complex<double> denom = 1.0 - std::polar(1.0, most->angle);
  if (std::abs(denom) < 1e-6) return false;
  const std::complex<double> z = std::complex<double>(most->shift.x(), most->shift.y()) / denom;
  q = Eigen::Vector2d(z.real(), z.imag());
  return true;
}

// The affine map of face f of a piece from the base shape B to X: x -> J x + c.
void face_map(const PieceShape& piece, int f, const Positions& X, Eigen::Matrix2d& J, Eigen::Vector2d& c) {
  const int a = piece.vertex(f, 0), b = piece.vertex(f, 1), d = piece.vertex(f, 2);
  J = edge_matrix(X, a, b, d) * piece.base_edges(f).inverse();
  c = X.row(a).transpose() - J * piece.base_corner(f, 0);
}

// Refines q to the point that the parent's and the child's triangles carry to the same place in
// every input (least squares over the inputs, per pair of triangles, each piece's triangle holding
// q or, outside it, the one whose affine extension is nearest; until they stay the same). False,
// and no further step, once q lies farther than `leave` from either piece's bounding box.
bool refine_pin(const std::vector<Positions>& shapes, int base, const PieceShape& parent, const PieceShape& child,
                double leave, Eigen::Vector2d& q) {
  int fp = -1, fc = -1, last_p = -2, last_c = -2;
  Eigen::Vector3d bary;
  for (int iteration = 0; iteration < 10 && (fp != last_p || fc != last_c); ++iteration) {
    if (std::max(parent.box_distance(q), child.box_distance(q)) > leave) return false;
    last_p = fp, last_c = fc;
    parent.locate_nearest(q, fp, bary);
    child.locate_nearest(q, fc, bary);
    Eigen::Matrix2d M = Eigen::Matrix2d::Zero();
    Eigen::Vector2d r = Eigen::Vector2d::Zero();
    for (size_t i = 0; i < shapes.size(); ++i) {  // the gap (Jc - Jp) q + (cc - cp) in each input
      if (i == static_cast<size_t>(base)) continue;  // none in the base: both maps are the identity
      Eigen::Matrix2d Jp, Jc;
      Eigen::Vector2d cp, cc;
      face_map(parent, fp, shapes[i], Jp, cp);
      face_map(child, fc, shapes[i], Jc, cc);
      M += (Jc - Jp).transpose() * (Jc - Jp);
      r += (Jc - Jp).transpose() * (cc - cp);
    }
    if (std::abs(M.determinant()) < 1e-24) break;  // the pieces move alike: every point is common
    q = -M.inverse() * r;
  }
  return std::max(parent.box_distance(q), child.box_distance(q)) <= leave;
}

// Whether a turning pair may slide (classify): a vertex moved by at most kSlideMost of the size
// lies within kSlideMost size / (2 |sin(angle / 2)|) of the fixed point of each relative motion,
// and an overlap vertex lies in both pieces' boxes. `fixed`: the most-turning motion's (pin_guess).
bool may_slide(const PieceShape& a, const PieceShape& b, const std::vector<RigidMotion>& rel,
               const Eigen::Vector2d& fixed, double size) {
  double chord = 0;  // the most any motion moves a point at distance 1 from its fixed point
  for (const RigidMotion& m : rel) chord = std::max(chord, 2 * std::abs(std::sin(0.5 * m.angle)));
  const double radius = Joints::kSlideMost * size / chord * (1 + 1e-9);
  return std::max(a.box_distance(fixed), b.box_distance(fixed)) <= radius;
}

// How far a pin's point may lie outside either of its pieces: this fraction of the smaller piece's
// size (painted sprites often leave a knee's pivot just outside the thigh).
double pin_reach(const PieceShape& a, const PieceShape& b) {
  return Joints::kPinReach * std::min(a.diagonal(), b.diagonal());
}

// The vertices of `b` inside `a` (base shape; PieceShape::contains), as global vertices.
std::vector<int> inside(const PieceShape& a, const PieceShape& b) {
  std::vector<int> out;
  if (!a.boxes_meet(b)) return out;
  const Positions& B = *b.piece().base;
  for (Eigen::Index v = 0; v < B.rows(); ++v)
    if (a.in_box(B.row(v).transpose()) && a.contains(B.row(v).transpose())) out.push_back((*b.piece().vertices)[v]);
  return out;
}

// The vertices of either piece inside the other; of a piece that lies wholly inside the other (an
// eye on a head: PieceShape::holds), its own vertices alone, so the overlap is the piece itself
// whatever the other's triangles under it.
std::vector<int> overlap_vertices(const PieceShape& a, const PieceShape& b) {
  if (a.holds(b)) return *b.piece().vertices;
  if (b.holds(a)) return *a.piece().vertices;
  std::vector<int> ov = inside(a, b), ba = inside(b, a);
  ov.insert(ov.end(), ba.begin(), ba.end());
  return ov;
}

// The largest distance any of the motions moves x.
double largest_shift(const std::vector<RigidMotion>& motions, const Eigen::Vector2d& x) {
  double most = 0;
  for (const RigidMotion& m : motions) most = std::max(most, (m(x) - x).norm());
  return most;
}

// A candidate joint between two overlapping pieces; rank orders candidates (smaller is better).
struct Candidate {
  JointEdge edge;
  double rank;
};

// The kind of the joint between pieces a and b, or false when there is none (pieces that only
// come near and make no pin). Glued: no input moves
// b against a by more than kPinGap of the size (turn x size + shift at the overlap's centre). Pin:
// the refined fixed point of the relative motion lies within pin_reach of both pieces and both
// carry it to one place in every input. Slide: b moves against a, turning or not, by at most
// kSlideMost of the size at the overlap's vertex nearest the relative motion's fixed point (a hip
// that the rig translates under the thighs); it sits there. Candidates rank pins first, by the
// larger of their gap (over kPinGap) and distance outside the pieces (over the reach), plus their
// largest relative turn (a joint turns less than a chain through it), then glued, then slides,
// each by its fit.
bool classify(const std::vector<Positions>& shapes, int base, double size, const PieceShape& a,
              const PieceShape& b, Candidate& out) {
  const Positions& X = shapes[static_cast<size_t>(base)];
  const std::vector<RigidMotion> rel = relative_motions(a.piece(), b.piece(), base);
  double turn = 0;
  for (const RigidMotion& m : rel) turn = std::max(turn, std::abs(detail::wrap_angle(m.angle)));
  Eigen::Vector2d q;
  const bool turns = turn > Joints::kPinGap && pin_guess(rel, q);
  if (turns) {
    // Where no vertex can slide, a point that leaves the pins' reach twice over makes no pin.
    const bool slides = may_slide(a, b, rel, q, size);
    const double reach = pin_reach(a, b);
    if (refine_pin(shapes, base, a, b, slides ? HUGE_VAL : 2 * reach, q)) {
      std::array<int, 2> faces;
      const double gap = joint_gap(shapes, base, a, b, q, faces) / size;
      const double out_a = a.outside(q, 2 * reach), out_b = b.outside(q, 2 * reach);
      if (gap <= Joints::kPinGap && out_a <= reach && out_b <= reach) {
        const double fit = std::max(gap / Joints::kPinGap, 0.5 * (out_a + out_b) / reach);  // at most 1
        out = {{-1, -1, q, JointKind::Pin, gap, faces}, fit + turn / kPi};
        return true;
      }
    }
    if (!slides) return false;
  }
  const std::vector<int> overlap = overlap_vertices(a, b);
  if (overlap.empty()) return false;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (int v : overlap) centre += X.row(v).transpose() / static_cast<double>(overlap.size());
  if (!turns) q = centre;
  const int v = *std::min_element(overlap.begin(), overlap.end(), [&](int p, int r) {
    return (X.row(p).transpose() - q).norm() < (X.row(r).transpose() - q).norm();
  });
  const Eigen::Vector2d at = turns ? Eigen::Vector2d(X.row(v).transpose()) : centre;
  double moved = 0;
  for (const RigidMotion& m : rel)
    moved = std::max(moved, std::abs(detail::wrap_angle(m.angle)) * size + (m(at) - at).norm());
  const bool glued = moved <= Joints::kPinGap * size;
  if (turns && largest_shift(rel, X.row(v).transpose()) > Joints::kSlideMost * size) return false;
  out = {{-1, -1, X.row(v).transpose(), glued ? JointKind::Glued : JointKind::Slide, moved / size},
         (glued ? 2.0 : 3.0) + std::min(moved / size, 0.5)};
  return true;
}

// How far each piece's anchor moves from the base in any input (turn x size + shift).
std::vector<double> piece_moves(const PieceShapes& pieces, int base, size_t k, double size) {
  std::vector<double> moves(pieces.size(), 0.0);
  for (size_t p = 0; p < pieces.size(); ++p) {
    const Eigen::Vector2d at = pieces[p]->piece().frames->at(static_cast<size_t>(base)).point;
    for (size_t i = 0; i < k; ++i) {
      const RigidMotion m = motion(pieces[p]->piece(), base, i);
      moves[p] = std::max(moves[p], std::abs(m.angle) * size + (m(at) - at).norm());
    }
  }
  return moves;
}

int find_set(std::vector<int>& up, int x) {
  while (up[x] != x) x = up[x] = up[up[x]];
  return x;
}

// The spanning forest's edges (unoriented, piece a < b) as parents first from `sources`.
std::vector<JointEdge> orient(int n, const std::vector<Candidate>& chosen, const std::vector<int>& sources) {
  std::vector<std::vector<const Candidate*>> adjacent(n);
  for (const Candidate& c : chosen) adjacent[c.edge.parent].push_back(&c), adjacent[c.edge.child].push_back(&c);
  std::vector<bool> seen(n, false);
  std::vector<JointEdge> out;
  std::queue<int> todo;
  for (int s : sources)
    if (!seen[s]) seen[s] = true, todo.push(s);
  while (!todo.empty()) {
    const int u = todo.front();
    todo.pop();
    for (const Candidate* c : adjacent[u]) {
      const int v = c->edge.parent == u ? c->edge.child : c->edge.parent;
      if (seen[v]) continue;
      seen[v] = true;
      JointEdge e = c->edge;
      if (e.parent != u) std::swap(e.faces[0], e.faces[1]);
      e.parent = u, e.child = v;
      out.push_back(e);
      todo.push(v);
    }
  }
  return out;
}

// Piece p's own motion as a turn about a point inside (or nearest to) it, ranked like a pin: the
// distance of its fixed point outside the piece relative to the pins' reach (of the piece's own
// size; a point farther than ten reaches counts as ten), plus its largest turn / pi (of
// two pieces whose fixed points lie inside them, the one that turns less leaves less to the path its
// tree's root takes, which two keys do not fix); a piece that only travels (turns by no more than
// kPinGap) ranks 0.
JointRoot root_rank(const PieceShape& shape, int p, int base, size_t k) {
  std::vector<RigidMotion> own;
  own.reserve(k);
  double turn = 0;
  for (size_t i = 0; i < k; ++i) {
    own.push_back(motion(shape.piece(), base, i));
    turn = std::max(turn, std::abs(own.back().angle));
  }
  Eigen::Vector2d q;
  if (turn <= Joints::kPinGap || !pin_guess(own, q)) return {p, RootReason::Travels, 0.0, Eigen::Vector2d::Zero()};
  const double reach = Joints::kPinReach * shape.diagonal();
  return {p, RootReason::Turns, shape.outside(q, 10 * reach) / reach + turn / kPi, q};
}

// Roots: the anchored piece alone in its tree (so the anchor holds); elsewhere every still piece
// (so none is moved by another); per remaining tree the piece whose own motion is best a turn about
// a point inside it (root_rank; ties: the piece that moves least), so that a chain joined to
// nothing still turns about its shoulder, not about its hand.
std::vector<JointRoot> choose_roots(const std::vector<Positions>& shapes, int base,
                                    const PieceShapes& pieces,
                                    int root, double size, std::vector<int>& up) {
  const int n = static_cast<int>(pieces.size());
  const std::vector<double> moves = piece_moves(pieces, base, shapes.size(), size);
  std::vector<JointRoot> roots;
  const int anchored = root >= 0 ? find_set(up, root) : -1;
  if (root >= 0) roots.push_back({root, RootReason::Anchor, 0.0, Eigen::Vector2d::Zero()});
  for (int p = 0; p < n; ++p)
    if (moves[p] <= kStill * size && find_set(up, p) != anchored)
      roots.push_back({p, RootReason::Still, 0.0, Eigen::Vector2d::Zero()});
  std::vector<bool> rooted(n, false);
  for (const JointRoot& r : roots) rooted[find_set(up, r.piece)] = true;
  std::vector<JointRoot> best(n, {-1, RootReason::Turns, HUGE_VAL, Eigen::Vector2d::Zero()});
  for (int p = 0; p < n; ++p) {
    const int tree = find_set(up, p);
    if (rooted[tree]) continue;
    const JointRoot r = root_rank(*pieces[p], p, base, shapes.size());
    JointRoot& b = best[tree];
    if (b.piece < 0 || r.fit < b.fit || (r.fit == b.fit && moves[p] < moves[b.piece])) b = r;
  }
  for (int t = 0; t < n; ++t)
    if (best[t].piece >= 0) roots.push_back(best[t]);
  return roots;
}

}  // namespace

double joint_gap(const std::vector<Positions>& shapes, int base, const PieceShape& parent, const PieceShape& child,
                 const Eigen::Vector2d& q, std::array<int, 2>& faces) {
  int &fp = faces[0], &fc = faces[1];
  Eigen::Vector3d bary;
  parent.locate_nearest(q, fp, bary);
  child.locate_nearest(q, fc, bary);
  double gap = 0;  // none in the base, where both maps are the identity
  for (size_t i = 0; i < shapes.size(); ++i) {
    if (i == static_cast<size_t>(base)) continue;
    Eigen::Matrix2d Jp, Jc;
    Eigen::Vector2d cp, cc;
    face_map(parent, fp, shapes[i], Jp, cp);
    face_map(child, fc, shapes[i], Jc, cc);
    gap = std::max(gap, ((Jc - Jp) * q + cc - cp).norm());
  }
  return gap;
}

std::vector<JointEdge> find_joint_tree(const std::vector<Positions>& shapes, int base, double size,
                                       const PieceShapes& pieces, int root, std::vector<JointRoot>& roots) {
  const int n = static_cast<int>(pieces.size());
  std::vector<Candidate> candidates;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      if (!pieces[a]->boxes_meet(*pieces[b], pin_reach(*pieces[a], *pieces[b]))) continue;
      Candidate c;
      if (!classify(shapes, base, size, *pieces[a], *pieces[b], c)) continue;
      c.edge.parent = a, c.edge.child = b;
      candidates.push_back(c);
    }
  // Kruskal: the best joints that make no cycle.
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& p, const Candidate& q) { return p.rank < q.rank; });
  std::vector<int> up(n);
  std::iota(up.begin(), up.end(), 0);
  std::vector<Candidate> chosen;
  for (const Candidate& c : candidates) {
    const int ra = find_set(up, c.edge.parent), rb = find_set(up, c.edge.child);
    if (ra != rb) up[ra] = rb, chosen.push_back(c);
  }
  roots = choose_roots(shapes, base, pieces, root, size, up);
  std::vector<int> sources;
  for (const JointRoot& r : roots) sources.push_back(r.piece);
  return orient(n, chosen, sources);
}

std::vector<JointEdge> given_joint_tree(const std::vector<Positions>& shapes, int base, double size,
                                        const std::vector<GivenJoint>& links, const PieceShapes& pieces,
                                        std::vector<JointRoot>& roots) {
  const int n = static_cast<int>(pieces.size());
  std::vector<int> parent_link(n, -1), path_link(n, -1);
  for (size_t k = 0; k < links.size(); ++k) {
    std::ostringstream s;
    s << "joint link " << k << ": ";
    if (links[k].parent == links[k].child)
      throw InvalidInput(s.str() + "its parent and child vertices are in one piece");
    std::vector<int>& slot = links[k].parent < 0 ? path_link : parent_link;
    if (parent_link[links[k].child] >= 0 || path_link[links[k].child] >= 0)
      throw InvalidInput(s.str() + "its child piece already hangs from link " +
                         std::to_string(std::max(parent_link[links[k].child], path_link[links[k].child])));
    slot[links[k].child] = static_cast<int>(k);
  }
  for (int p = 0; p < n; ++p)
    if (parent_link[p] < 0)
      roots.push_back({p, path_link[p] >= 0 ? RootReason::Path : RootReason::Given, 0.0,
                       path_link[p] >= 0 ? links[path_link[p]].point : Eigen::Vector2d::Zero()});
  std::vector<JointEdge> out;
  std::vector<int> depth(n, -1);  // parents first: walk up each piece's chain to a root
  for (int p = 0; p < n; ++p) {
    std::vector<int> chain;
    for (int q = p; depth[q] < 0; q = links[parent_link[q]].parent) {
      if (std::find(chain.begin(), chain.end(), q) != chain.end())
        throw InvalidInput("joint link " + std::to_string(parent_link[q]) + ": the links make a cycle");
      chain.push_back(q);
      if (parent_link[q] < 0) break;
    }
    std::array<int, 2> faces;
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const int q = *it, k = parent_link[q];
      depth[q] = 0;
      if (k < 0) continue;
      const GivenJoint& g = links[k];
      const double gap = joint_gap(shapes, base, *pieces[g.parent], *pieces[g.child], g.point, faces);
      out.push_back({g.parent, g.child, g.point, JointKind::Given, gap / size, faces});
    }
  }
  return out;
}

}  // namespace bdinterp::detail
