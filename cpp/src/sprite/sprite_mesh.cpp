// mesh_from_alpha: checks, then trace -> drop small -> grow -> simplify -> mesh.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "bdinterp/sprite_mesh.h"
#include "bdinterp/types.h"
#include "sprite/outline.h"

namespace bdinterp {
namespace {

void check(bool ok, const std::string& detail) {
  if (!ok) throw InvalidInput(detail);
}

void check_options(const SpriteMeshOptions& o) {
  auto finite = [](double v) { return std::isfinite(v); };
  check(finite(o.threshold) && o.threshold > 0 && o.threshold <= 1,
        "threshold must lie in (0, 1], not " + std::to_string(o.threshold));
  check(finite(o.spacing) && o.spacing >= 0,
        "spacing must be a positive number of pixels (0: chosen from the sprite), not " + std::to_string(o.spacing));
  check(finite(o.spacing_divisions) && o.spacing_divisions >= 1,
        "spacing_divisions must be >= 1, not " + std::to_string(o.spacing_divisions));
  check(finite(o.detail) && o.detail >= 0, "detail must be >= 0 pixels, not " + std::to_string(o.detail));
  check(finite(o.padding) && o.padding >= 0 && o.padding <= 64,
        "padding must lie in [0, 64] pixels, not " + std::to_string(o.padding));
  check(finite(o.min_angle) && o.min_angle > 0 && o.min_angle <= 30,
        "min_angle must lie in (0, 30] degrees, not " + std::to_string(o.min_angle));
  check(finite(o.min_area) && o.min_area >= 0, "min_area must be >= 0 pixels^2, not " + std::to_string(o.min_area));
}

// The first alpha that is NaN or outside [0, 1], and the bounding box of alpha >= threshold.
Eigen::AlignedBox2d check_alpha(const Eigen::Ref<const AlphaImage>& alpha, double threshold) {
  check(alpha.rows() >= 2 && alpha.cols() >= 2,
        "the image is " + std::to_string(alpha.cols()) + "x" + std::to_string(alpha.rows()) +
            " pixels; it needs at least 2x2");
  Eigen::AlignedBox2d box;
  const float th = float(threshold);
  for (Eigen::Index r = 0; r < alpha.rows(); ++r)
    for (Eigen::Index c = 0; c < alpha.cols(); ++c) {
      const float a = alpha(r, c);
      if (!(a >= 0.0f && a <= 1.0f))
        check(false, "alpha at row " + std::to_string(r) + ", column " + std::to_string(c) + " is " +
                         (std::isnan(a) ? std::string("NaN") : std::to_string(a)) + "; it must lie in [0, 1]");
      if (a >= th) box.extend(Eigen::Vector2d(double(c), double(alpha.rows() - 1 - r)));
    }
  check(!box.isEmpty(), "no pixel has alpha >= the threshold " + std::to_string(threshold) + ": nothing to mesh");
  return box;
}

}  // namespace

SpriteMesh mesh_from_alpha(const Eigen::Ref<const AlphaImage>& alpha, const SpriteMeshOptions& o) {
  check_options(o);
  const Eigen::AlignedBox2d box = check_alpha(alpha, o.threshold);
  const double side = box.sizes().maxCoeff() + 1;  // the sprite's larger side, pixels
  const double spacing = o.spacing > 0 ? o.spacing : std::max(2.0, side / o.spacing_divisions);
  sprite::Field field = sprite::alpha_field(alpha, o.threshold, int(std::ceil(o.padding)) + 2);
  std::vector<sprite::Loop> loops = sprite::trace(field);
  sprite::Dropped dropped = sprite::drop_small(field, loops, o.min_area);
  if (o.padding > 0) {  // (grown reads the outline from the field: no trace after the drop)
    field = sprite::grown(std::move(field), o.padding);
    loops = sprite::trace(field);
    const sprite::Dropped closed = sprite::drop_small(field, loops, o.min_area);  // closed by the padding
    dropped.islands += closed.islands, dropped.holes += closed.holes;
  } else if (dropped.islands + dropped.holes > 0) {
    loops = sprite::trace(field);
  }
  check(!loops.empty(), "every island is smaller than min_area " + std::to_string(o.min_area) + " pixels^2");
  double area = 0;
  int islands = 0;
  for (const sprite::Loop& loop : loops) {
    const double a = sprite::signed_area(loop);
    area += a, islands += a > 0;
  }
  SpriteMesh mesh = sprite::triangulate(sprite::simplify(loops, o.detail, o.min_angle), spacing, o.min_angle, area);
  check(mesh.faces.rows() > 0, "the sprite's outline encloses no area to mesh");
  mesh.spacing = spacing;
  mesh.width = int(alpha.cols()), mesh.height = int(alpha.rows());
  mesh.islands = islands, mesh.holes = int(loops.size()) - islands;
  mesh.dropped_islands = dropped.islands, mesh.dropped_holes = dropped.holes;
  mesh.area = 0;
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector2d a = mesh.vertices.row(mesh.faces(f, 0)), b = mesh.vertices.row(mesh.faces(f, 1)),
                          c = mesh.vertices.row(mesh.faces(f, 2));
    mesh.area += 0.5 * ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
  }
  mesh.uvs = mesh.vertices.array().rowwise() / Eigen::Array2d(double(alpha.cols()), double(alpha.rows())).transpose();
  return mesh;
}

}  // namespace bdinterp
