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
//
// A LayoutPlan holds what depends on the mesh only (read-only, shared by threads); a Layout is one
// thread's workspace.
#pragma once

#include <memory>
#include <vector>

#include "mesh.h"
#include "sparse_cholesky.h"

namespace bdinterp {

// The mesh-only part of a layout; `disk` must outlive it.
struct LayoutPlan {
  // disk: one connected piece with one boundary loop (see split_into_disks).
  explicit LayoutPlan(const Mesh& disk);

  // A half-edge of face `face`, opposite corner `corner`, taken forwards (sign 1) or backwards (-1).
  struct HalfEdge {
    int face, corner;
    double sign;
  };
  // An interior vertex next to the boundary: its interior number, a boundary neighbour and the
  // half-edge from that boundary vertex to it.
  struct Tie {
    int row, boundary;
    HalfEdge edge;
  };

  const Mesh& mesh;
  InteriorPattern pattern;
  int root = 0;                     // the central face, in the layout frame's orientation
  std::vector<Mesh::DualStep> tree;  // breadth-first from the root (not listed)
  std::vector<int> loop;            // the boundary vertices in order (interior on the left)
  std::vector<HalfEdge> loop_edges;  // loop[k] -> loop[k + 1]
  std::vector<Tie> ties;            // one per interior vertex next to the boundary
};

class Layout {
 public:
  // disk: one connected piece with one boundary loop (see split_into_disks). With own_system, the
  // uniform graph Laplacian of the interior vertices is factorised here for embed(l2, ...).
  explicit Layout(const Mesh& disk, bool own_system = true);
  // A workspace over a shared plan.
  explicit Layout(std::shared_ptr<const LayoutPlan> plan, bool own_system = true);
  Layout(Layout&&) noexcept;
  Layout& operator=(Layout&&) noexcept;
  ~Layout();

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

  // Factorises the uniform graph Laplacian for embed(l2, X) if not done yet (a Layout built without
  // own_system, whose caller's system turned out singular).
  void ensure_own_system();

  const LayoutPlan& plan() const { return *plan_; }

 private:
  struct Scratch;
  // The rotated half-edge vector h in the layout frame.
  void vector_of(const LayoutPlan::HalfEdge& h, double* v) const;
  void place_faces(const Eigen::VectorXd& l2);      // each face in its own frame, then rotated
  void place_boundary(Positions& X) const;          // the loop, its closing gap spread by arc length
  // The right-hand side of the interior system into the scratch, the boundary's positions being in X.
  void assemble_rhs(const SparseCholesky& W, double shift, const Positions& X);
  // The interior positions into X.
  void solve_interior(SparseCholesky& W, double shift, Positions& X);

  std::shared_ptr<const LayoutPlan> plan_;
  std::unique_ptr<SparseCholesky> own_;  // the uniform interior Laplacian (own_system)
  std::unique_ptr<Scratch> scratch_;
};

}  // namespace bdinterp
