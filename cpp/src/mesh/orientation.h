// Orientation of the inputs relative to the base shape: folded faces, and mirror images.
//
// A face is folded in an input when its signed area has the opposite sign to the same face in the
// base shape (an inverted triangle, as skinned joints produce). A few are a valid pose; most of them
// mean the input is a reflection of the base, which no rotation reaches: without the check the
// in-betweens end at the rotated base instead of the key.
#pragma once

#include <vector>

#include "mesh/mesh.h"

namespace bdinterp {

// Faces (ascending) of X (#V by 2) whose orientation is opposite to that of base (#V by 2).
std::vector<int> folded_faces(const Mesh& mesh, const Positions& base, const Positions& X);

// The folded faces of every shape (folded_faces against shapes[base]). Throws InvalidInput naming
// the shape when more than half of its faces (of one piece) are folded relative to shapes[base]:
// "shape 1 is a mirror image of shape 0: 380 of 384 faces are reversed ...".
std::vector<std::vector<int>> check_not_mirrored(const Mesh& mesh, const std::vector<Positions>& shapes, int base);

}  // namespace bdinterp
