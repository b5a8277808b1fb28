// Step 2 of the method: make the blended metric flat by a discrete conformal change (CETM,
// Springborn, Schroeder & Pinkall 2008), keeping the boundary fixed (u = 0 there, paper Sec. 3).
//
// Convention: the flattened squared length of edge ij is exp(u_i + u_j) * l2_ij. The convex energy
//   E(u) = sum_faces [ sum_m (alpha_m lambda_m + 2 L(alpha_m)) - pi/2 sum_m lambda_m ] + sum_i 2pi u_i,
// with lambda_m = log of the scaled squared length of edge m, alpha_m the angle opposite it and L
// Lobachevsky's function, has gradient g_i = 2pi - (angle sum at i) at interior vertices and the
// cotan Laplacian (weights (cot a + cot b) / 2) as Hessian. Newton with a line search on E.
//
// The unknowns need not be one per interior vertex (FlattenUnknowns): several vertices may share
// one (a hole's loop, docs/HOLES.md), with a target angle sum of its own. The energy restricted to
// that linear subspace stays convex; its Hessian is the cotan Laplacian with the shared rows and
// columns summed (an edge inside one unknown adds w + w - 2w = 0). A disk is the special case.
//
// A FlattenPlan holds what depends on the mesh only (read-only, shared by threads); a Flattener is
// one thread's workspace (scratch, numeric factorisation, the refactorisation policy's state).
#pragma once

#include <Eigen/Sparse>
#include <memory>

#include "bdinterp/flatten_options.h"
#include "mesh/mesh.h"
#include "linalg/sparse_cholesky.h"

namespace bdinterp {

// What a flattening solves for. Every vertex with an unknown moves by that unknown's change (so
// vertices sharing one keep their differences in u: fixed offsets set by the caller); u is 0 at the
// others. Unknown k's condition is: angle sum over its vertices = target[k].
struct FlattenUnknowns {
  std::vector<int> of_vertex;  // #V: the unknown of each vertex in [0, #unknowns), -1 where u = 0
  std::vector<double> target;  // #unknowns: target angle sums (2 pi at an interior vertex)
};
// One unknown per interior vertex (in vertex order), target 2 pi; u = 0 on the boundary (the paper).
FlattenUnknowns interior_unknowns(const Mesh& mesh);

// The mesh-only part of a flattening: the unknowns, where each face's terms go, the symbolic
// analysis of the Hessian. Read-only once built; the mesh must outlive it.
struct FlattenPlan {
  // disk: one connected piece with one boundary loop (see split_into_disks): interior_unknowns.
  explicit FlattenPlan(const Mesh& disk);
  // piece: one connected piece; unknowns as described above (of_vertex sized #V). Throws
  // InvalidInput for sizes that do not match.
  FlattenPlan(const Mesh& piece, FlattenUnknowns unknowns);

  // Per face, where its terms go, with fixed vertices sent to spare slots (row num_interior() of the
  // angle sums, entry nnz() of the Hessian values) so that the face loops need no branches.
  struct FaceSlots {
    int edge[3];  // edge opposite corner c
    int row[3];   // unknown of corner c
    int diag[3];  // Hessian position of corner c's diagonal
    int off[3];   // Hessian position of the entry of edge c; -1: both ends one unknown, no term
  };

  const Mesh& mesh;
  InteriorPattern pattern;       // index: the unknown of each vertex; vertex: one vertex of each
  Eigen::VectorXd target;        // per unknown: its target angle sum
  std::vector<int> moved;        // the vertices with an unknown, ascending
  std::vector<FaceSlots> slots;
  std::shared_ptr<const CholeskyAnalysis> analysis;  // null without unknowns
  int num_interior() const { return pattern.size(); }  // the number of unknowns
  int nnz() const { return analysis ? static_cast<int>(analysis->row_indices().size()) : 0; }
};

class Flattener {
 public:
  // A workspace with a plan of its own.
  explicit Flattener(const Mesh& disk);
  // A workspace over a shared plan (e.g. one per thread).
  explicit Flattener(std::shared_ptr<const FlattenPlan> plan);
  Flattener(Flattener&&) noexcept;
  Flattener& operator=(Flattener&&) noexcept;
  ~Flattener();

  // l2: #E blended squared edge lengths. u: #V conformal factors; on input the initial guess
  // (entries of vertices without an unknown and non-finite entries are set to 0; vertices sharing an
  // unknown keep their differences), on output the solution (0 on the boundary of a disk).
  // Throws InvalidInput for bad options or sizes, SolverError if `options.tolerance` is not reached
  // within `options.max_iterations` steps.
  FlattenReport solve(const Eigen::VectorXd& l2, Eigen::VectorXd& u, const FlattenOptions& options = {});

  // The pieces of the solve, exposed for tests and diagnostics (all sized #V; gradients hold unknown
  // k's entry at vertex pattern().vertex[k], 0 elsewhere). They do not disturb the state solve() leaves.
  double energy(const Eigen::VectorXd& l2, const Eigen::VectorXd& u);
  Eigen::VectorXd gradient(const Eigen::VectorXd& l2, const Eigen::VectorXd& u);
  // The Hessian as Newton assembles it (#V by #V, rows and columns pattern().vertex only).
  Eigen::SparseMatrix<double> hessian(const Eigen::VectorXd& l2, const Eigen::VectorXd& u);
  // max |target - angle sum| over the unknowns.
  double residual(const Eigen::VectorXd& l2, const Eigen::VectorXd& u);
  // #E flat squared lengths exp(u_i + u_j) l2_ij at the solution of the last solve() (valid until
  // the next solve), so the layout need not recompute them.
  const Eigen::VectorXd& flat_squared_lengths() const;
  int num_interior() const { return plan_->num_interior(); }
  const FlattenPlan& plan() const { return *plan_; }
  // The interior numbering and Hessian pattern (see interior_pattern).
  const InteriorPattern& pattern() const { return plan_->pattern; }
  bool is_interior(int v) const { return plan_->pattern.index[v] >= 0; }
  // For the layout: a factorised symmetric positive definite matrix over pattern() whose values()
  // are the matrix that was factorised (the Hessian at the last factorisation, plus `*shift` on the
  // diagonal). Factorises the Hessian at (l2, u) if no factorisation is at hand.
  SparseCholesky& factored_hessian(const Eigen::VectorXd& l2, const Eigen::VectorXd& u, double* shift);
  // Benchmarks: loads the Hessian at (l2, u) into the solver (no factorisation) and gives access to
  // it; the next solve() will not reuse the factorisation that was there.
  void assemble_hessian(const Eigen::VectorXd& l2, const Eigen::VectorXd& u);
  SparseCholesky* cholesky();
  // A factorisation from an earlier solve is at hand for chord steps (see reuse_factorization).
  bool has_reusable_factorization() const;
  // Forgets the reusable factorisation and the cost model's observations, so the next solve
  // starts as a fresh Flattener's would.
  void forget();

  struct State;  // the workspace (flatten.cpp)

 private:
  // The holes' first-order steps at a solution (holes_response.cpp) read and move the workspace.
  friend bool follow_offsets(Flattener&, const Eigen::VectorXd&, Eigen::VectorXd&, double, const FlattenOptions&);
  friend bool offset_response(Flattener&, const Eigen::VectorXd&, double, Eigen::VectorXd&);
  std::shared_ptr<const FlattenPlan> plan_;
  std::unique_ptr<State> state_;
};

// exp(u_i + u_j) * l2_ij for every edge.
Eigen::VectorXd scale_lengths(const Mesh& mesh, const Eigen::VectorXd& l2, const Eigen::VectorXd& u);

}  // namespace bdinterp
