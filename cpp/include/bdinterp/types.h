// Array types and exceptions shared by every unit of bdinterp.
#pragma once

#include <Eigen/Core>
#include <stdexcept>
#include <string>

namespace bdinterp {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kTwoPi = 2 * kPi, kHalfPi = kPi / 2;  // the only other circle constants; exact

// #V by 2 list of vertex positions, one row per vertex (row-major so numpy (n,2) maps without a copy).
using Positions = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;
// #F by 3 list of vertex indices, one triangle per row; counter-clockwise or clockwise, but consistent.
using Faces = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
// #E by 2 list of vertex index pairs (i < j).
using Edges = Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor>;

// Where an InvalidInput points: indices into the caller's arrays, -1 where not applicable.
// shape: into the Interpolator's shapes (0: the first); face: a row of the faces; vertex: a row of
// the positions. Python: the exception's .shape, .face and .vertex (None for -1).
struct Where {
  int shape = -1, face = -1, vertex = -1;
  static Where of_shape(int s) { return {s, -1, -1}; }
  static Where of_face(int f, int shape = -1) { return {shape, f, -1}; }
  static Where of_vertex(int v, int shape = -1) { return {shape, -1, v}; }
  bool empty() const { return shape < 0 && face < 0 && vertex < 0; }
};

// Thrown for input that can never succeed (bad indices, non-manifold topology, invalid metric ...).
// detail(): what is wrong, without the location; where(): the shape/face/vertex it is about (so
// that a caller can name them in its own terms, e.g. Blender's key names and polygons); what():
// the location then the detail, "shape 1, vertex 7: " + detail(), or detail() alone when where()
// is empty. Python: bdinterp.InvalidInputError (a ValueError) with .detail, .shape, .face, .vertex.
class InvalidInput : public std::invalid_argument {
 public:
  explicit InvalidInput(const std::string& detail) : InvalidInput(Where{}, detail) {}
  InvalidInput(const Where& where, const std::string& detail)
      : std::invalid_argument(located(where, detail)), where_(where), detail_(detail) {}
  const Where& where() const { return where_; }
  const std::string& detail() const { return detail_; }

 private:
  static std::string located(const Where& w, const std::string& detail) {
    std::string at;
    if (w.shape >= 0) at += "shape " + std::to_string(w.shape);
    if (w.face >= 0) at += (at.empty() ? "" : ", ") + std::string("face ") + std::to_string(w.face);
    if (w.vertex >= 0) at += (at.empty() ? "" : ", ") + std::string("vertex ") + std::to_string(w.vertex);
    return at.empty() ? detail : at + ": " + detail;
  }
  Where where_;
  std::string detail_;
};

// Thrown when a numerical solve fails on valid input (no convergence, factorisation failure).
// Python: bdinterp.SolverError, a subclass of RuntimeError.
class SolverError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace bdinterp
