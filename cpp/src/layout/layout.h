// Step 3 of the method: lay flat edge lengths out in the plane without accumulated drift.
//
// Each face is built from its three lengths and the faces' rotations are propagated across shared
// edges (exact when the metric is flat, up to its angle-sum residual). The outer boundary loop is
// laid out by walking its edges, the walk's closing gap (of the order of that residual) spread along
// it by arc length; every other vertex (the interior and, on a piece with holes, the holes' loops) is
// free and solves one sparse symmetric positive definite system W x = b that fits every edge vector
// between free vertices at once, so no error accumulates along paths.
//
// W may be any SPD matrix with the free vertices' adjacency pattern (LayoutPlan::pattern; for a disk
// interior_pattern()'s): -W_ij weighs the edge ij, and the row sums weigh the edges to the outer
// loop. For consistent edge vectors every such W gives the same, exact layout. The interpolator
// passes a disk the flattening's own factorised cotan Laplacian (no second factor); a holed piece,
// whose Hessian has one row per hole rather than per hole vertex, and a stand-alone Layout factorise
// the uniform graph Laplacian once per workspace.
//
// A LayoutPlan holds what depends on the mesh only (read-only, shared by threads); a Layout is one
// thread's workspace.
#pragma once

#include <memory>
#include <vector>

#include "mesh/mesh.h"
#include "linalg/sparse_cholesky.h"

namespace bdinterp {

// The mesh-only part of a layout; `piece` must outlive it.
struct LayoutPlan {
  // piece: one connected piece with a boundary (split_into_pieces); outer: the index in its
  // boundary_loops() of the loop walked (a disk's only loop), the others' vertices are free. With
  // share_analysis, the workspaces' uniform Laplacians share one symbolic analysis made here (a
  // holed piece's, whose layout always uses it). Throws InvalidInput for an outer index out of range.
  explicit LayoutPlan(const Mesh& piece, int outer = 0, bool share_analysis = false);

  // A half-edge of face `face`, opposite corner `corner`, taken forwards (sign 1) or backwards (-1).
  struct HalfEdge {
    int face, corner;
    double sign;
  };
  // A free vertex next to the outer loop: its free number, an outer-loop neighbour and the
  // half-edge from that loop vertex to it.
  struct Tie {
    int row, boundary;
    HalfEdge edge;
  };
  // Edge e run from its end `from`, as its first face (edge_faces()(e, 0)) sees it.
  HalfEdge half_edge(int e, int from) const;

  const Mesh& mesh;
  int outer = 0;                    // the index in mesh.boundary_loops() of the loop walked
  InteriorPattern pattern;          // over the free vertices (numbered in increasing vertex order)
  bool one_sided = false;           // some edge between free vertices has one face (a hole's)
  int root = 0;                     // the central face, in the layout frame's orientation
  std::vector<Mesh::DualStep> tree;  // breadth-first from the root (not listed)
  std::vector<int> loop;            // the outer loop's vertices in order (the piece on the left)
  std::vector<HalfEdge> loop_edges;  // loop[k] -> loop[k + 1]
  std::vector<Tie> ties;            // one per free vertex next to the outer loop
  std::shared_ptr<const CholeskyAnalysis> uniform;  // with share_analysis: the pattern's analysis
};

class Layout {
 public:
  // disk: one connected piece with one boundary loop (see split_into_disks). With own_system, the
  // uniform graph Laplacian of the free vertices is factorised here for embed(l2, ...).
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
  // The same with the system W: a factorised SparseCholesky over plan().pattern whose values() are
  // the factorised matrix plus `shift` on the diagonal (the shift is undone by iterative
  // refinement). W may be null when the piece has no free vertex.
  void embed(const Eigen::VectorXd& l2, SparseCholesky* W, double shift, Positions& X,
             double* flatness = nullptr);

  // Factorises the uniform graph Laplacian for embed(l2, X) if not done yet (a Layout built without
  // own_system, whose caller's system turned out singular).
  void ensure_own_system();

  const LayoutPlan& plan() const { return *plan_; }
  // The half-edge h's vector in the last embed()'s frame (its face placed and rotated): the holes'
  // closure is the gap of their loops developed by these.
  void vector_of(const LayoutPlan::HalfEdge& h, double* v) const;

 private:
  struct Scratch;
  void place_faces(const Eigen::VectorXd& l2);      // each face in its own frame, then rotated
  void place_boundary(Positions& X) const;          // the outer loop, its closing gap spread by arc length
  // The right-hand side of the free vertices' system into the scratch, the outer loop's being in X.
  void assemble_rhs(const SparseCholesky& W, double shift, const Positions& X);
  // The free vertices' positions into X.
  void solve_free(SparseCholesky& W, double shift, Positions& X);

  std::shared_ptr<const LayoutPlan> plan_;
  std::unique_ptr<SparseCholesky> own_;  // the free vertices' uniform Laplacian (own_system)
  std::unique_ptr<Scratch> scratch_;
};

}  // namespace bdinterp
