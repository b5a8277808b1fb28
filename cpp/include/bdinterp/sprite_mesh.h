// A triangle mesh from a sprite's alpha: the outline of alpha >= threshold traced at sub-pixel
// accuracy (marching squares), simplified within `detail` pixels, grown by `padding` pixels, then
// filled by Delaunay refinement (CGAL's 2D conforming Delaunay mesher) with no angle below
// `min_angle` and no edge longer than `spacing` pixels.
#pragma once

#include <Eigen/Core>

namespace bdinterp {

struct SpriteMeshOptions {
  double threshold = 0.5;  // alpha >= threshold is the sprite; in (0, 1]
  double spacing = 0.0;    // the longest edge in pixels; 0: the sprite's larger side / spacing_divisions
  double spacing_divisions = 12;  // >= 1; used when spacing is 0 (the spacing is at least 2 pixels)
  double detail = 1.0;     // how far (pixels) the simplified outline may stray from the traced one
  double padding = 1.0;    // how far (pixels) the outline grows outwards
  double min_angle = 20.0; // degrees, in (0, 30]
  double min_area = 4.0;   // islands and holes smaller than this (pixels^2) are dropped
};

// Row-major alpha in [0, 1], row 0 the image's top row (as images are stored).
using AlphaImage = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct SpriteMesh {
  // Pixels, x to the right, y up, origin at the image's bottom-left corner.
  Eigen::Matrix<double, Eigen::Dynamic, 2> vertices;
  Eigen::Matrix<int, Eigen::Dynamic, 3> faces;  // counter-clockwise
  Eigen::Matrix<double, Eigen::Dynamic, 2> uvs;  // vertices / (width, height)
  double spacing = 0.0;          // the edge bound used
  int outline_vertices = 0;      // vertices of the simplified, grown outline
  int islands = 0, holes = 0;    // kept
  int dropped_islands = 0, dropped_holes = 0;  // smaller than min_area (or closed by the padding)
  double area = 0.0;             // of the mesh, pixels^2
  int width = 0, height = 0;     // the image's size in pixels
};

// Throws InvalidInput for an image smaller than 2x2, NaN or out-of-range alpha, options out of
// range, or nothing at or above the threshold; SolverError if the refinement does not finish.
SpriteMesh mesh_from_alpha(const Eigen::Ref<const AlphaImage>& alpha, const SpriteMeshOptions& options = {});

}  // namespace bdinterp
