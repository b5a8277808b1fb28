// The sprite mesher on analytic shapes: a disc's and an annulus's areas, the angle and edge bounds,
// and its InvalidInput for each bad input.
#ifdef BDINTERP_SPRITE
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "bdinterp/sprite_mesh.h"
#include "bdinterp/types.h"

namespace bdinterp {
namespace {


// Alpha of an annulus (radii r0 < r1) about the image's centre, antialiased by 8 x 8 sub-samples.
AlphaImage annulus(int size, double r0, double r1) {
  AlphaImage a(size, size);
  for (int r = 0; r < size; ++r)
    for (int c = 0; c < size; ++c) {
      int in = 0;
      for (int k = 0; k < 64; ++k) {
        const double x = c + (k % 8 + 0.5) / 8 - size / 2.0, y = r + (k / 8 + 0.5) / 8 - size / 2.0;
        const double d = std::hypot(x, y);
        in += d <= r1 && d >= r0;
      }
      a(r, c) = float(in / 64.0);
    }
  return a;
}

double smallest_angle(const SpriteMesh& m, Eigen::Index f) {
  double out = 180;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d p = m.vertices.row(m.faces(f, k)), q = m.vertices.row(m.faces(f, (k + 1) % 3)),
                          s = m.vertices.row(m.faces(f, (k + 2) % 3));
    out = std::min(out, std::acos((q - p).normalized().dot((s - p).normalized())) * 180 / kPi);
  }
  return out;
}

TEST(SpriteMesh, AnnulusAreaHoleAndBounds) {
  SpriteMeshOptions o;
  o.padding = 0, o.detail = 0.1, o.spacing = 10;
  const SpriteMesh m = mesh_from_alpha(annulus(200, 30, 80), o);
  EXPECT_NEAR(m.area, kPi * (80 * 80 - 30 * 30), 2e-3 * m.area);
  EXPECT_EQ(m.islands, 1);
  EXPECT_EQ(m.holes, 1);
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f) {
    EXPECT_GE(smallest_angle(m, f), 20.0 - 1e-9);
    for (int k = 0; k < 3; ++k)
      EXPECT_LE((m.vertices.row(m.faces(f, k)) - m.vertices.row(m.faces(f, (k + 1) % 3))).norm(), 10 + 1e-9);
  }
}

TEST(SpriteMesh, PaddingGrowsTheDisc) {
  // A disc of radius 40 grown by 3 pixels: area pi 43^2 (the outline within detail 0.1).
  SpriteMeshOptions o;
  o.padding = 3, o.detail = 0.1;
  const SpriteMesh m = mesh_from_alpha(annulus(120, 0, 40), o);
  EXPECT_NEAR(m.area, kPi * 43 * 43, 4e-3 * m.area);
  EXPECT_EQ(m.holes, 0);
}

std::string error_of(const AlphaImage& a, const SpriteMeshOptions& o) {
  try {
    mesh_from_alpha(a, o);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "no InvalidInput";
}

TEST(SpriteMesh, BadInput) {
  const AlphaImage ones = AlphaImage::Ones(8, 8);
  SpriteMeshOptions o;
  EXPECT_NE(error_of(AlphaImage::Zero(8, 8), o).find("no pixel has alpha >="), std::string::npos);
  EXPECT_NE(error_of(AlphaImage::Ones(1, 1), o).find("1x1"), std::string::npos);
  AlphaImage nan = ones;
  nan(3, 5) = std::nanf("");
  EXPECT_NE(error_of(nan, o).find("row 3, column 5 is NaN"), std::string::npos);
  o.threshold = 0;
  EXPECT_NE(error_of(ones, o).find("threshold"), std::string::npos);
  o.threshold = 0.5, o.spacing = -1;
  EXPECT_NE(error_of(ones, o).find("spacing"), std::string::npos);
}

}  // namespace
}  // namespace bdinterp
#endif
