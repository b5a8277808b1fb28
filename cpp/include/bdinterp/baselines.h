// Baseline interpolation methods the paper compares against (Sec. 6.3), with the same calling shape
// as Interpolator::at so results can be compared face by face.
#pragma once

#include <memory>
#include <vector>

#include "bdinterp/types.h"

namespace bdinterp {

// (1 - t) source + t target. Both #V by 2.
Positions linear_interpolate(const Positions& source, const Positions& target, double t);

// As-rigid-as-possible interpolation (Alexa, Cohen-Or & Levin 2000): each face's affine map
// A = R(theta) S is interpolated as R(t theta) ((1 - t) I + t S), with the angles theta unwrapped
// across neighbouring faces (Baxter et al. 2008) on the branch where the bulk turns least, and the
// vertex positions fit these Jacobians in the least-squares sense (area-weighted). The Poisson matrix
// (cotan Laplacian of the source) is factorised once per piece. The area-weighted centroid is blended
// linearly. Requires disk-shaped pieces like Interpolator.
class ArapInterpolator {
 public:
  ArapInterpolator(const Positions& source, const Positions& target, const Faces& F);
  ~ArapInterpolator();
  Positions at(double t);

 private:
  struct PieceData;
  Positions source_, target_;
  std::vector<std::unique_ptr<PieceData>> pieces_;
  std::vector<int> isolated_;
};

}  // namespace bdinterp
