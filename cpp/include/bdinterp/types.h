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

// Thrown for input that can never succeed (bad indices, non-manifold topology, invalid metric ...).
// The message names the problem and the offending vertex/face/edge indices. Python: ValueError.
class InvalidInput : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Thrown when a numerical solve fails on valid input (no convergence, factorisation failure).
// Python: bdinterp.SolverError, a subclass of RuntimeError.
class SolverError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace bdinterp
