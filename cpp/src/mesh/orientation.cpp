#include "mesh/orientation.h"

#include <sstream>

#include "mesh/geometry.h"

namespace bdinterp {

std::vector<int> folded_faces(const Mesh& mesh, const Positions& base, const Positions& X) {
  const Faces& F = mesh.faces();
  std::vector<int> out;
  for (int f = 0; f < F.rows(); ++f)
    if ((doubled_area(base, F, f) > 0) != (doubled_area(X, F, f) > 0)) out.push_back(f);
  return out;
}

std::vector<std::vector<int>> check_not_mirrored(const Mesh& mesh, const std::vector<Positions>& shapes, int base) {
  std::vector<int> faces_of_piece(mesh.num_pieces(), 0);
  for (int f = 0; f < mesh.num_faces(); ++f) ++faces_of_piece[mesh.piece_of_face(f)];
  std::vector<std::vector<int>> all;
  for (size_t i = 0; i < shapes.size(); ++i) {
    all.push_back(folded_faces(mesh, shapes[base], shapes[i]));
    std::vector<int> folded(mesh.num_pieces(), 0);
    for (int f : all.back()) ++folded[mesh.piece_of_face(f)];
    for (int p = 0; p < mesh.num_pieces(); ++p) {
      if (2 * folded[p] <= faces_of_piece[p]) continue;
      std::ostringstream s;
      s << "a mirror image of the base shape: " << folded[p] << " of " << faces_of_piece[p] << " faces";
      if (mesh.num_pieces() > 1) s << " of piece " << p;
      s << " are reversed (a reflection cannot be reached by rotating; mirror the shape back)";
      throw InvalidInput(Where::of_shape(static_cast<int>(i)), s.str());
    }
  }
  return all;
}

}  // namespace bdinterp
