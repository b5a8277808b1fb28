// Internal: the Interpolator's checks of its arguments (InvalidInput naming what is wrong).
#pragma once

#include <string>

#include "bdinterp/interpolator.h"
#include "mesh/mesh.h"

namespace bdinterp::detail {

// "(w0, w1, ...)" at full precision, for messages.
std::string weights_text(const Eigen::VectorXd& w);
// Every field of the options, for `num_shapes` inputs; the tolerance also >= 2^-50 (~8.9e-16), the
// smallest angle-sum residual a double can reach on the normalised inputs (InvalidInput naming both).
void validate_options(const InterpolatorOptions& o, int num_shapes);
// The anchor's vertex (-1 or a vertex in a face; InvalidInput at that vertex) and path (finite,
// increasing t; finite positions and angles; two shapes).
void validate_anchor(const Anchor& anchor, const Mesh& mesh, int num_shapes);
// The signed areas of a piece's faces in shape X must not cancel: its centroid (the anchor)
// divides by their sum. Rejected when less than 0.1 % of the faces' total area remains
// (InvalidInput at `shape` and the piece's first face).
void check_orientation(const Positions& X, const Piece& p, int shape, int piece);

}  // namespace bdinterp::detail
