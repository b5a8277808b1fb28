// Step 3 of the method: lay flat edge lengths out in the plane without accumulated drift.
//
// Each face is built from its three lengths; the faces' rotations are propagated across shared edges
// (exact when the metric is flat: the rotations are consistent up to the angle-sum residual), and the
// positions then solve one least-squares problem that fits every half-edge vector at once. The system
// matrix depends only on the connectivity, so it is factorised once per mesh.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "bdinterp/mesh.h"
#include "bdinterp/parallel.h"
#include "bdinterp/sparse_cholesky.h"

namespace bdinterp {

class Layout {
 public:
  // disk: one connected piece (see split_into_disks). Factorises the half-edge Laplacian once.
  explicit Layout(const Mesh& disk);
  Layout(Layout&&) noexcept;
  ~Layout();
  std::unique_ptr<Layout> clone() const;  // own CHOLMOD workspace, for another thread

  // l2: #E flat squared edge lengths. Returns #V by 2 positions whose faces are counter-clockwise in
  // the order given by the face list, in an arbitrary rigid frame. If `flatness` is given it receives
  // max over edges of | |x_i - x_j|^2 / l2_ij - 1 |, which is ~1e-15 for an exactly flat metric.
  Positions embed(const Eigen::VectorXd& l2, double* flatness = nullptr);
  // The same into X (resized if needed), so that repeated frames allocate nothing.
  void embed(const Eigen::VectorXd& l2, Positions& X, double* flatness = nullptr);

 // One step of the dual spanning tree: `face` is reached from `parent` across the edge opposite
  // corner `face_corner` of face and `parent_corner` of parent.
  struct TreeStep {
    int face, parent, face_corner, parent_corner;
  };

 private:
  explicit Layout(const Mesh* mesh) : mesh_(mesh) {}

  const Mesh* mesh_;
  std::vector<TreeStep> tree_;  // breadth-first from a central face (the root, not listed)
  int root_ = 0;
  std::unique_ptr<SparseCholesky> chol_;  // half-edge Laplacian with vertex 0 removed
  Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> rot_;  // #F scratch: (cos, sin) per face
  // #F scratch: each face in its own frame as its half-edge vectors (x, y) from corner k+1 to k+2.
  Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor> half_;
  Eigen::VectorXd rhs_;     // 2 (#V - 1) scratch
  Eigen::VectorXd length_;  // #E scratch: edge lengths
  std::vector<char> broken_;  // #F scratch: the face's lengths violate the triangle inequality
  parallel::Partials rhs_parts_;  // other threads' shares of the right-hand side
};

}  // namespace bdinterp
