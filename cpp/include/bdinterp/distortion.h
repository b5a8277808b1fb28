// Per-face distortion of the affine map that takes each face of `source` to the same face of `result`.
#pragma once

#include "bdinterp/types.h"

namespace bdinterp {

// #F conformal distortion K = sigma_max / sigma_min of the per-face Jacobian (paper Sec. 2.1:
// sqrt of the pullback metric's eigenvalue ratio). K >= 1, 1 for a similarity; +inf when the result
// face is collapsed. A flipped face gets the K of its reflection (see area_ratio for the sign).
// Throws InvalidInput for mismatched sizes, bad indices or a collapsed source face.
Eigen::VectorXd conformal_distortion(const Eigen::Ref<const Positions>& source,
                                     const Eigen::Ref<const Positions>& result,
                                     const Eigen::Ref<const Faces>& F);

// Number of faces whose orientation in `result` is opposite to (or collapsed from) that in `source`.
int flipped_faces(const Eigen::Ref<const Positions>& source, const Eigen::Ref<const Positions>& result,
                  const Eigen::Ref<const Faces>& F);

// #F signed area ratio area(result) / area(source); negative where the result face is flipped.
Eigen::VectorXd area_ratio(const Eigen::Ref<const Positions>& source, const Eigen::Ref<const Positions>& result,
                           const Eigen::Ref<const Faces>& F);

}  // namespace bdinterp
