#include "place/still.h"

#include <algorithm>
#include <cmath>

#include "mesh/geometry.h"

namespace bdinterp {

Eigen::VectorXd still_region(const Mesh& piece, const AnchorFrame& frame, const std::vector<Positions>& shapes,
                             int base, const StillOptions& options) {
  const Faces& F = piece.faces();
  const Positions& B = shapes[base];
  const double size = (B.colwise().maxCoeff() - B.colwise().minCoeff()).norm();
  auto centroid = [&](const Positions& X, int f) {
    return ((X.row(F(f, 0)) + X.row(F(f, 1)) + X.row(F(f, 2))) / 3.0).eval();
  };
  Eigen::VectorXd motion = Eigen::VectorXd::Zero(F.rows());
  for (const Positions& X : shapes) {
    // The bulk branch: a limb turned past 180 degrees keeps its large rotation, the body ~0.
    const Eigen::VectorXd rot = frame.bulk_rotations(X);
    for (int f = 0; f < F.rows(); ++f) {
      const double m = std::abs(rot[f]) * size + (centroid(X, f) - centroid(B, f)).norm();
      motion[f] = std::max(motion[f], m);
    }
  }
  const double least = motion.minCoeff(), band = options.band * size;
  // Nothing still (every face moves by more than the band): the whole piece, as before. The
  // folded example (examples/folded) moves everywhere, its least-moving face by 3.7 % of its size.
  if (least > band) return {};
  Eigen::VectorXd w(F.rows());
  for (int f = 0; f < F.rows(); ++f) {
    const double area = 0.5 * std::abs(doubled_area(B, F, f));
    const double excess = (motion[f] - least) / band;  // the face with the least motion has 0
    w[f] = area * std::clamp(2.0 - excess, 0.0, 1.0);
  }
  return w;
}

}  // namespace bdinterp
