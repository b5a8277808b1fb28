// Step 3 of the method: lay flat edge lengths out in the plane without accumulated drift.
//
// Each face is built from its three lengths and the faces' rotations are propagated across shared
// edges (exact when the metric is flat, up to its angle-sum residual). The boundary loop is laid
// out by walking its edges, the walk's closing gap (of the order of that residual) spread along it
// by arc length; the interior vertices then solve one sparse symmetric positive definite system
// W x = b that fits every interior edge vector at once, so no error accumulates along paths.
//
// W may be any SPD matrix with the interior vertex-adjacency pattern of interior_pattern(): -W_ij
// weighs the edge ij, and the row sums weigh the edges to the boundary. For consistent edge vectors
// every such W gives the same, exact layout. The interpolator passes the flattening's own
// factorised cotan Laplacian (no second factor); a stand-alone Layout factorises the uniform graph
// Laplacian once.
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
  // disk: one connected piece with one boundary loop (see split_into_disks). With own_system, the
  // uniform graph Laplacian of the interior vertices is factorised here for embed(l2, ...).
  explicit Layout(const Mesh& disk, bool own_system = true);
  Layout(Layout&&) noexcept;
  ~Layout();
  std::unique_ptr<Layout> clone() const;  // own CHOLMOD workspace, for another thread

  // l2: #E flat squared edge lengths. Returns #V by 2 positions whose faces are counter-clockwise in
  // the order given by the face list, in an arbitrary rigid frame. If `flatness` is given it receives
  // max over edges of | |x_i - x_j|^2 / l2_ij - 1 |, which is ~1e-15 for an exactly flat metric.
  // Needs own_system.
  Positions embed(const Eigen::VectorXd& l2, double* flatness = nullptr);
  // The same into X (resized if needed), so that repeated frames allocate nothing.
  void embed(const Eigen::VectorXd& l2, Positions& X, double* flatness = nullptr);
  // The same with the system W: a factorised SparseCholesky over interior_pattern(disk) whose
  // values() are the factorised matrix plus `shift` on the diagonal (the shift is undone by
  // iterative refinement). W may be null when the disk has no interior vertex.
  void embed(const Eigen::VectorXd& l2, SparseCholesky* W, double shift, Positions& X,
             double* flatness = nullptr);

  // One step of the dual spanning tree: `face` is reached from `parent` across the edge opposite
  // corner `face_corner` of face and `parent_corner` of parent.
  struct TreeStep {
    int face, parent, face_corner, parent_corner;
  };
  // A half-edge of face `face`, opposite corner `corner`, taken forwards (sign 1) or backwards (-1).
  struct HalfEdge {
    int face, corner;
    double sign;
  };

 private:
  explicit Layout(const Mesh* mesh) : mesh_(mesh) {}
  // The rotated half-edge vector h in the layout frame.
  void vector_of(const HalfEdge& h, double* v) const;
  // The interior positions into X, the boundary's being there.
  void solve_interior(SparseCholesky& W, double shift, Positions& X);

  const Mesh* mesh_;
  InteriorPattern pattern_;
  std::vector<TreeStep> tree_;  // breadth-first from a central face (the root, not listed)
  int root_ = 0;
  std::vector<int> loop_;              // the boundary vertices in order (interior on the left)
  std::vector<HalfEdge> loop_edges_;   // loop_[k] -> loop_[k + 1]
  // Interior vertices next to the boundary: (interior number, boundary vertex, half-edge from the
  // boundary vertex to the interior one).
  struct Tie {
    int row, boundary;
    HalfEdge edge;
  };
  std::vector<Tie> ties_;
  std::unique_ptr<SparseCholesky> own_;  // the uniform interior Laplacian (own_system)
  Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> rot_;  // #F scratch: (cos, sin) per face
  // #F scratch: each face in its own frame, corner 0 at the origin, corner 1 at (l01, 0), corner 2 at
  // (cx, cy); rows (l01, cx, cy).
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> local_;
  std::vector<char> broken_;        // #F scratch: the face's lengths violate the triangle inequality
  Eigen::VectorXd rhs_, row_sum_;  // 2 #interior and #interior scratch
  parallel::Partials rhs_parts_;    // other threads' shares of the right-hand side
};

}  // namespace bdinterp
