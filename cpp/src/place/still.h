// The default anchor region: the parts of a piece that do not move between the inputs (docs/ANCHOR.md).
//
// Animators pose a limb and leave the body where it is. The whole-piece centroid and mean rotation
// move with the limb, and blending them linearly drags the body along (a body whose arm rolls up
// turned by 4 degrees and slid by 38 % of its size half way). Anchoring on what stays still keeps it
// still; when everything moves alike (a rigid turn, a translation) the region is the whole piece
// and the anchor is the old one.
#pragma once

#include <vector>

#include "place/anchor_frame.h"

namespace bdinterp {

struct StillOptions {
  // A face belongs to the region in full when its motion (see still_region) exceeds the least
  // motion of any face by at most `band` times the piece's size, with a linear taper to 0 at twice
  // that (1 %: the "still" tolerance on position).
  double band = 0.01;
};

// Per face of the piece (#F): its weight in the anchor region, base area times the taper above.
// The motion of a face is the largest, over the inputs, of |rotation relative to the base| times
// the piece's size (its base bounding-box diagonal) plus the distance its centroid moves from the
// base. Empty when no face is still (the least motion exceeds the band): then the whole piece is
// the region. shapes: the inputs (#V by 2 each), frame: the piece's AnchorFrame (its base shape).
Eigen::VectorXd still_region(const Mesh& piece, const AnchorFrame& frame, const std::vector<Positions>& shapes,
                             int base, const StillOptions& options = {});

}  // namespace bdinterp
