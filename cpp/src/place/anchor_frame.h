// Step 4 of the method, the measuring side: the anchors of the inputs (AnchorFrame) and the anchor of
// an in-between (blend_frames). The user's choice of anchor (Anchor, AnchorPath) is public: anchor.h.
#pragma once

#include <array>
#include <vector>

#include "bdinterp/anchor.h"
#include "mesh/mesh.h"

namespace bdinterp {

// Rigid placement data of one shape of one disk.
struct Frame2 {
  Eigen::Vector2d point;
  double angle;
};

// Measures anchors of shapes of one disk relative to its base shape.
class AnchorFrame {
 public:
  // disk: the piece; base: its base shape (#V by 2); vertex: the anchor vertex in local numbering,
  // or -1 for the centroid.
  AnchorFrame(const Mesh& disk, const Positions& base, int vertex);

  // Replaces the region (whole piece or the anchor vertex's faces) by face weights (#F, >= 0, not
  // all 0): the anchor point becomes the weighted mean of the face centroids, the angle the weighted
  // mean rotation. Call before measuring the inputs. Throws InvalidInput for bad weights.
  void set_region(const Eigen::VectorXd& face_weight);
  // Anchor of input shape X: the angle is on the branch where the bulk turns least.
  Frame2 measure_input(const Positions& X) const;
  // The base shape it was made with (#V by 2, the piece's local order).
  const Positions& base() const { return base_; }
  // Rigidly moves X so that its anchor becomes `target` (its own branch is irrelevant here).
  void place(Positions& X, const Frame2& target) const;
  // Per-face rotation of X relative to the base (closest rotation of the affine map), unwrapped
  // across neighbouring faces; branch as it falls.
  Eigen::VectorXd face_rotations(const Positions& X) const;
  // face_rotations shifted by a multiple of 2 pi so that the base-area-weighted median face turns by
  // at most pi: the branch on which the bulk of the shape turns least.
  Eigen::VectorXd bulk_rotations(const Positions& X) const;

 private:
  // One pass over the faces: the unwrapped rotations in tree order into rot[0, #F) (rot[#F, 2 #F)
  // is scratch); returns the anchor point (the vertex, or the area-weighted centroid).
  Eigen::Vector2d measure(const Positions& X, double* rot) const;
  double base_area(int f) const;

  const Mesh* mesh_;
  int vertex_;
  Positions base_;                        // the base shape (#V by 2)
  std::vector<std::array<int, 2>> tree_;  // dual breadth-first order: (face, parent's slot in tree_)
  Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> base_edges_;  // per slot: s b1, s b2
  Eigen::VectorXd weight_;                // per slot: share of the region's base area (sums to 1)
  bool region_ = false;                   // weight_ set by set_region (a weighted point, too)
};

// The anchor of an in-between for weights w (#inputs, sum 1). geodesic_base >= 0 (the default
// anchor, and a path without a vertex): on the geodesic of the rigid motions relative to that input
// (geodesic_blend in rigid_motion.h), so a piece that turns about a pin keeps the pin. -1 (a vertex
// anchor, the paper's): the weighted blend of the inputs' points and angles. In Path mode the path's
// deviation from its own chord between t = 0 and 1 is added (so the inputs stay exact).
Frame2 blend_frames(const std::vector<Frame2>& inputs, const Eigen::VectorXd& w, const Anchor& anchor,
                    int geodesic_base = -1);

}  // namespace bdinterp
