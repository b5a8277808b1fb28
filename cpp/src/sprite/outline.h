// The steps of mesh_from_alpha before the mesher: the sampled alpha, its traced outline (marching
// squares), small islands and holes dropped, the outline grown and simplified.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "bdinterp/sprite_mesh.h"

namespace bdinterp::sprite {

using Point = Eigen::Vector2d;
// A closed polyline (last point joins the first) with the sprite on its left: islands run
// counter-clockwise, holes clockwise.
using Loop = std::vector<Point>;

// Values at pixel centres, inside where >= 0, with `margin` samples of outside around the image.
// Sample (i, j) (column i, row j counted from the bottom) sits at (i - margin + 0.5, j - margin + 0.5).
struct Field {
  int width = 0, height = 0, margin = 0;
  std::vector<float> value;
  int lo_i = 0, hi_i = 0, lo_j = 0, hi_j = 0;  // the samples that may be inside: lo <= i, j <= hi
  float at(int i, int j) const { return value[static_cast<size_t>(j) * width + i]; }
  float& at(int i, int j) { return value[static_cast<size_t>(j) * width + i]; }
  Point position(double i, double j) const { return {i - margin + 0.5, j - margin + 0.5}; }
};

// alpha - threshold on the pixel centres (exact zeros nudged inside so no crossing sits on a sample).
Field alpha_field(const Eigen::Ref<const AlphaImage>& alpha, double threshold, int margin);

// The zero level of the field as closed loops; a saddle joins the inside when its centre is inside.
std::vector<Loop> trace(const Field& field);

double signed_area(const Loop& loop);

struct Dropped {
  int islands = 0, holes = 0;
};

// Removes the loops smaller than min_area from `loops` and from `field` (their samples flipped).
Dropped drop_small(Field& field, std::vector<Loop>& loops, double min_area);

// The field whose zero level lies `padding` pixels outside the zero level of `field` (a distance
// field near it); padding > 0.
Field grown(Field field, double padding);

// Douglas-Peucker within `detail` per loop, convex corners sharper than min_angle blunted within
// `detail`, loops kept simple and apart (a loop that would cross is simplified less).
std::vector<Loop> simplify(const std::vector<Loop>& loops, double detail, double min_angle);

// The CGAL mesh of the region the loops bound (result's vertices, faces; nothing else filled).
SpriteMesh triangulate(const std::vector<Loop>& loops, double spacing, double min_angle, double area);

}  // namespace bdinterp::sprite
