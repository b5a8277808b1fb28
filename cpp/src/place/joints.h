// Joints between the loose pieces of a cut-out character (docs/JOINTS.md).
//
// Each piece is placed on its own first (the anchor's geodesic, rigid_motion.h); the joints then
// move every child rigidly so that its joint point stays where its parent's in-between carries that
// point, turned by the parent's angle plus the blend of its angles relative to the parent. The
// shape of every piece is untouched. Which pieces hold which is a tree: found from the relative
// motions of overlapping pieces (joint_tree.cpp), or given (an armature's bones).
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "place/anchor_frame.h"
#include "bdinterp/interpolator.h"
#include "bdinterp/types.h"
#include "place/piece_shape.h"

namespace bdinterp {

namespace detail {
// One joint of the tree: the pieces, its point in the base shape, its kind and fit (JointInfo),
// and the faces of the parent and the child that carry the point (-1: not yet located).
struct JointEdge {
  int parent = -1, child = -1;
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  JointKind kind = JointKind::Pin;
  double fit = 0;
  std::array<int, 2> faces = {-1, -1};
};
// The root of a tree of joints: the piece, why it roots its tree, and for RootReason::Turns the
// fixed point of its own motion (base shape) and its rank (root_rank in joint_tree.cpp).
struct JointRoot {
  int piece;
  RootReason reason;
  double fit;
  Eigen::Vector2d point;
};
// A given link with its pieces (indices into the pieces) and point in the base shape; parent -1:
// the child is a root whose point travels on the chord between the inputs (a root bone's path).
struct GivenJoint {
  int parent, child;
  Eigen::Vector2d point;
};

// The tree found from the overlaps of the pieces in the base shape (joint_tree.cpp), parents
// first: each overlapping pair is a pin, glued or no joint; a maximum spanning forest keeps the
// best (pins before glued, each by its fit), rooted at the still pieces, the anchored piece
// (root >= 0), else the piece whose own motion is best a turn about a point inside it; `roots`
// gets each tree's root (a piece in no joint is a tree of its own).
std::vector<JointEdge> find_joint_tree(const std::vector<Positions>& shapes, int base, double size,
                                       const PieceShapes& pieces, int root, std::vector<JointRoot>& roots);
// The given links in tree order, parents first (InvalidInput naming link k for two parents of one
// piece, a link within one piece or a cycle); the fit is measured as for a pin. `roots` gets the
// pieces with no parent (RootReason::Path for those a link with parent -1 gives a path).
std::vector<JointEdge> given_joint_tree(const std::vector<Positions>& shapes, int base, double size,
                                        const std::vector<GivenJoint>& links, const PieceShapes& pieces,
                                        std::vector<JointRoot>& roots);
// The largest gap over the inputs between where the two pieces' triangles carry q (q located in
// each, extended by the nearest triangle's affine map outside it); `faces` gets the two faces.
double joint_gap(const std::vector<Positions>& shapes, int base, const PieceShape& parent,
                 const PieceShape& child, const Eigen::Vector2d& q, std::array<int, 2>& faces);
}  // namespace detail

class Joints {
 public:
  // shapes: the inputs (#V by 2, the Interpolator's normalised frame); base: the base input;
  // size: its bounding box diagonal, which the tolerances scale; pieces: each piece's shape (made
  // with its plan). given empty: the tree found (find_joint_tree; root >= 0 is the piece holding a
  // vertex anchor); else the given links (points in the normalised frame).
  Joints(const std::vector<Positions>& shapes, int base, double size, const detail::PieceShapes& pieces, int root,
         const std::vector<detail::GivenJoint>& given);

  int size() const { return static_cast<int>(joints_.size()); }
  // Joint k as (parent piece, child piece), in the order apply() visits them (parents first).
  std::array<int, 2> link(int k) const { return {joints_[k].edge.parent, joints_[k].edge.child}; }
  // Joint k's point in the base shape (2), its kind, whether it is a pin and its fit (JointInfo).
  const detail::JointEdge& edge(int k) const { return joints_[k].edge; }
  bool pinned(int k) const {
    const detail::JointEdge& e = joints_[k].edge;
    return e.kind == JointKind::Pin || (e.kind == JointKind::Given && e.fit <= kPinGap);
  }

  // Moves the children in `out` (#V by 2, every piece placed on its own) for weights w (#inputs,
  // sum 1). angle (#pieces): the anchor angle each piece was placed at (blend_frames); on return,
  // its angle after the joints. Exact at the inputs when the pieces are (w = e_i).
  void apply(const Eigen::VectorXd& w, std::vector<double>& angle, Eigen::Ref<Positions> out) const;

  // A point both pieces carry to one place in every input to this fraction of the size is a pin.
  static constexpr double kPinGap = 1e-3;
  // A pin's point may lie outside either piece by this fraction of the smaller piece's size.
  static constexpr double kPinReach = 0.03;
  // A joint that turns and slides (a pivot the rig translates on its parent) moves its point
  // against the parent by at most this fraction of the size.
  static constexpr double kSlideMost = 0.05;
  // Each tree's root (find_joint_tree, given_joint_tree).
  const std::vector<detail::JointRoot>& roots() const { return roots_; }
  // Wall-clock seconds the constructor took.
  double seconds() const { return seconds_; }

 private:
  // A point of the base shape in a piece: the face's three global vertices, barycentric weights.
  struct Site {
    std::array<int, 3> v;
    Eigen::Vector3d bary;
    Eigen::Vector2d at(const Eigen::Ref<const Positions>& X) const;
  };
  struct Joint {
    detail::JointEdge edge;
    Site in_parent, in_child;
    std::vector<double> relative;           // per input: child's angle minus parent's, in (-pi, pi]
    std::vector<double> parent_angle;       // per input: the parent's anchor angle
    std::vector<Eigen::Vector2d> offset;    // per input: child's point minus parent's (0 at a pin)
  };
  // Where q (base shape) lies in the piece: in `face` if given (>= 0), else its triangle or the
  // one whose extension is nearest.
  static Site site(const detail::PieceShape& piece, const Eigen::Vector2d& q, int face = -1);
  void add_joint(const std::vector<Positions>& shapes, int base, const detail::JointEdge& edge,
                 const detail::PieceShape& in_parent, const detail::PieceShape& in_child);

  // A root that travels on its given path: its point in the piece and where each input puts it.
  struct Path {
    int piece;
    Site at;
    std::vector<Eigen::Vector2d> point;
  };

  std::vector<Joint> joints_;
  std::vector<Path> paths_;
  std::vector<detail::JointRoot> roots_;
  const detail::PieceShapes pieces_;
  double seconds_ = 0;
};

}  // namespace bdinterp
