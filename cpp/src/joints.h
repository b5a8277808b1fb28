// Joints between the loose pieces of a cut-out character (issue #20, point 2; docs/JOINTS.md).
//
// Pieces that overlap in the base shape are pinned together there. Each piece is placed on its own
// first (the anchor's geodesic, rigid_motion.h); the joints then move every child rigidly so that
// its joint point stays where its parent's in-between carries that point, turned by the parent's
// angle plus the blend of its angles relative to the parent. The shape of every piece is untouched.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "anchor_frame.h"
#include "bdinterp/types.h"

namespace bdinterp {

// What Joints needs of one piece: its vertices (global indices), its faces (local indices into
// `vertices`), and its anchor frame in every input (angles relative to the base, unwrapped).
struct JointPiece {
  const std::vector<int>* vertices;
  const Faces* faces;
  const std::vector<Frame2>* frames;
};

namespace detail {
class TriangleGrid;  // point location in one piece's triangles (joints.cpp)
}

class Joints {
 public:
  // shapes: the inputs (#V by 2, the Interpolator's normalised frame); base: the base input.
  // Finds the overlaps of the pieces in the base shape, a tree of joints per group of overlapping
  // pieces rooted at the piece that moves least, and each joint's point: the fixed point of the
  // child's motion relative to its parent when every input agrees on it and it lies in the overlap
  // (a pin), else the overlap point nearest to the overlap's centre. root >= 0: that piece (the one
  // holding a vertex anchor) is the root of its group whatever it moves, so it keeps its anchor.
  Joints(const std::vector<Positions>& shapes, int base, const std::vector<JointPiece>& pieces, int root = -1);

  int size() const { return static_cast<int>(joints_.size()); }
  // Joint k as (parent piece, child piece), in the order apply() visits them (parents first).
  std::array<int, 2> link(int k) const { return {joints_[k].parent, joints_[k].child}; }
  // Joint k's point in the base shape (2), and whether it is a pin (else an overlap point).
  Eigen::Vector2d point(int k) const { return joints_[k].point; }
  bool pinned(int k) const { return joints_[k].pin; }

  // Moves the children in `out` (#V by 2, every piece placed on its own) for weights w (#inputs,
  // sum 1). angle (#pieces): the anchor angle each piece was placed at (blend_frames); on return,
  // its angle after the joints. Exact at the inputs when the pieces are (w = e_i).
  void apply(const Eigen::VectorXd& w, std::vector<double>& angle, Eigen::Ref<Positions> out) const;

 private:
  // A point of the base shape in a piece: the face's three global vertices, barycentric weights.
  struct Site {
    std::array<int, 3> v;
    Eigen::Vector3d bary;
    Eigen::Vector2d at(const Eigen::Ref<const Positions>& X) const;
  };
  struct Joint {
    int parent, child;
    Eigen::Vector2d point;
    bool pin;
    Site in_parent, in_child;
    std::vector<double> relative;           // per input: child's angle minus parent's, in (-pi, pi]
    std::vector<double> parent_angle;       // per input: the parent's anchor angle
    std::vector<Eigen::Vector2d> offset;    // per input: child's point minus parent's (0 at a pin)
  };
  // Appends the joint of `child` under `parent`, whose base-shape overlap is `overlap` (vertices).
  void add_joint(const std::vector<Positions>& shapes, int base, double size, int parent, int child,
                 const std::vector<int>& overlap, const detail::TriangleGrid& in_parent,
                 const detail::TriangleGrid& in_child);

  std::vector<Joint> joints_;
  const std::vector<JointPiece> pieces_;
};

}  // namespace bdinterp
