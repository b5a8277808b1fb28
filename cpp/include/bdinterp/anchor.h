// Step 4 of the method: the three rigid degrees of freedom (paper Sec. 3) that the metric leaves open.
//
// An anchor is a point of the shape (its area-weighted centroid, or one vertex) and an orientation
// (the base-area-weighted mean of the per-face rotations relative to the base shape, over the whole
// piece or the anchor vertex's faces). Per-face rotations are unwrapped across neighbouring faces, so a
// limb turned by 540 degrees measures 3 pi, not -pi/2; the whole-shape branch is the one in which the
// area-weighted median face turns by at most pi (the bulk of the shape turns least). In-betweens get
// the weighted blend of the inputs' anchors, which keeps every input exact and is continuous.
#pragma once

#include <vector>

#include "bdinterp/types.h"

namespace bdinterp {

// A user-given anchor trajectory for two-shape interpolation: at t[k] the anchor point is at
// position.row(k) and turned by angle[k] radians (piecewise linear in between, clamped outside).
// What counts is the path's deviation from its chord between t = 0 and t = 1: it is added to the
// anchor's own motion (the geodesic for the centroid, the chord for a vertex, see blend_frames), so
// the source and target stay exact whatever the path's ends.
struct AnchorPath {
  std::vector<double> t;  // strictly increasing
  Positions position;     // t.size() by 2
  std::vector<double> angle;
};

struct Anchor {
  enum class Mode { Centroid, Vertex, Path };
  Mode mode = Mode::Centroid;
  int vertex = -1;  // Vertex mode; in Path mode the vertex that follows the path (-1: the centroid)
  AnchorPath path;

  static Anchor centroid() { return {}; }
  static Anchor at_vertex(int v) { return {Mode::Vertex, v, {}}; }
  static Anchor along(AnchorPath p, int v = -1) { return {Mode::Path, v, std::move(p)}; }
};

}  // namespace bdinterp
