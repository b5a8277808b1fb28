// Internal: where a point lies in one piece of a cut-out character, in the base shape (joints.h).
//
// Nothing is done per face or per vertex when a piece is set up: the joints of a character read
// a few points per pair of pieces, so their cost follows the pieces' outlines, not their faces. A
// point is inside the piece when its outline winds round it; its face is found by walking across
// the piece's faces from the last face found (or from its outline); its distance outside is the
// distance to the outline, whose edges are read in runs with their bounding boxes.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <vector>

#include "bdinterp/types.h"
#include "mesh/mesh.h"

namespace bdinterp {

// What the joints need of one piece: its vertices (global indices), its own mesh (faces in local
// indices into `vertices`), its base shape (#vertices by 2, local order), and its anchor frame in
// every input (angles relative to the base, unwrapped).
struct Frame2;
struct JointPiece {
  const std::vector<int>* vertices;
  const Mesh* mesh;
  const Positions* base;
  const std::vector<Frame2>* frames;
};

namespace detail {

// A point lies in a triangle when its least barycentric weight is at least -kInside.
constexpr double kInside = 1e-9;
// A point this fraction of a piece's size from its outline, or nearer, is on the outline, not
// inside (so vertices on a shared outline do not make an overlap).
constexpr double kOnOutline = 1e-9;

// One piece in its base shape (JointPiece::base). Not thread-safe: a query remembers the face it
// ended in.
class PieceShape {
 public:
  // What the piece points to must outlive the PieceShape. Reads its outline (boundary loops) only.
  explicit PieceShape(const JointPiece& piece);

  // Whether the two pieces' bounding boxes meet once each is grown by `margin`.
  bool boxes_meet(const PieceShape& o, double margin = 0) const {
    return (lo_.array() <= o.hi_.array() + 2 * margin).all() && (o.lo_.array() <= hi_.array() + 2 * margin).all();
  }
  bool in_box(const Eigen::Vector2d& q) const {
    return (q.array() >= lo_.array()).all() && (q.array() <= hi_.array()).all();
  }
  // How far q lies from the bounding box (0 inside it).
  double box_distance(const Eigen::Vector2d& q) const {
    return (lo_ - q).cwiseMax(q - hi_).cwiseMax(0.0).norm();
  }
  // The piece's size: its bounding box's diagonal (the outline's, which bounds a locally
  // injective piece).
  double diagonal() const { return (hi_ - lo_).norm(); }
  // How far q lies outside the piece (0 inside or on its outline), exact below `within`; `within`
  // when it lies that far or farther.
  double outside(const Eigen::Vector2d& q, double within) const;
  // Whether q lies inside the piece, farther than kOnOutline of its size from the outline.
  bool contains(const Eigen::Vector2d& q) const;
  // Whether every point of `other` (its outline and all it winds round) is inside this piece as
  // contains() has it: its outline comes within that margin of no edge of this outline (tested
  // conservatively: false when unsure), no point of this outline lies inside `other`, and one
  // point of `other` is inside. So contains() holds at each of `other`'s vertices, unasked: a
  // point it winds round reaches this outline only across its own, which keeps the margin.
  bool holds(const PieceShape& other) const;
  // A face holding q (least barycentric weight >= -kInside) and that weight; bary gets the face's
  // weights. Face -1 and -inf when q is outside the piece.
  double locate(const Eigen::Vector2d& q, int& face, Eigen::Vector3d& bary) const;
  // As locate(), but a point outside the piece gets the face on the outline edge nearest to it
  // (extended by its affine map), so the face is never -1.
  double locate_nearest(const Eigen::Vector2d& q, int& face, Eigen::Vector3d& bary) const;
  // The barycentric weights of q in face f (extended outside it).
  Eigen::Vector3d barycentric(const Eigen::Vector2d& q, int f) const;
  // Face f's corner c and its edge matrix (corners 1 and 2 minus corner 0) in the base shape.
  Eigen::Vector2d base_corner(int f, int c) const { return corner(f, c); }
  Eigen::Matrix2d base_edges(int f) const {
    Eigen::Matrix2d E;
    E << corner(f, 1) - corner(f, 0), corner(f, 2) - corner(f, 0);
    return E;
  }
  // Global vertex of corner c of face f.
  int vertex(int f, int c) const { return (*piece_.vertices)[piece_.mesh->faces()(f, c)]; }
  const JointPiece& piece() const { return piece_; }

 private:
  // A run of consecutive outline edges (edge k joins outline_[k] and outline_[k + 1]) within one
  // loop, and their bounding box: queries read the edges of the runs whose box can matter (a
  // one-level bounding volume hierarchy, made in one pass over the outline).
  struct Run {
    Eigen::AlignedBox2d box;
    int begin, end;
  };
  static constexpr int kRunEdges = 8;
  // Faces a walk from the last face found may cross before it starts again from the outline.
  static constexpr int kNearWalk = 8;
  Eigen::Vector2d corner(int f, int c) const { return piece_.base->row(piece_.mesh->faces()(f, c)).transpose(); }
  // The face a walk from face f towards q ends in within `steps` faces (-1 where the outline stops
  // it or it takes more steps: a walk that turns back on itself ends too).
  int walk(const Eigen::Vector2d& q, int f, Eigen::Vector3d& bary, int steps) const;
  // The face holding q with the largest least weight, over every face (-1 if none holds it).
  int scan(const Eigen::Vector2d& q, Eigen::Vector3d& bary) const;
  // The outline's winding number round q (holes wind back); 0 and near = true where an edge lies
  // within sqrt(margin2) of q.
  int winding(const Eigen::Vector2d& q, double margin2, bool& near) const;
  // Whether the outline winds round q.
  bool winds(const Eigen::Vector2d& q) const {
    bool near;
    return winding(q, 0, near) != 0;
  }
  // The outline edge nearest q as its two local vertices, and its distance ({-1, -1} and `within`
  // if none is nearer).
  std::array<int, 2> nearest_edge(const Eigen::Vector2d& q, double within, double& distance) const;
  // The face on an outline edge.
  int edge_face(const std::array<int, 2>& edge) const;

  const JointPiece piece_;  // four pointers, kept by value
  Eigen::Vector2d lo_, hi_;
  // The outline's loops one after another, each closed by its first point again, in the base
  // shape (read in order, where the loops would be read through the mesh's vertex order), and
  // their local vertices.
  std::vector<Eigen::Vector2d> outline_;
  std::vector<int> outline_vertex_;
  std::vector<Run> runs_;
  mutable int hint_ = 0;  // the face the last query ended in: the next walk starts there
};

// The pieces of a character as the joints read them (each made with its piece's plan, while the
// piece's base shape is in the cache).
using PieceShapes = std::vector<const PieceShape*>;

}  // namespace detail
}  // namespace bdinterp
