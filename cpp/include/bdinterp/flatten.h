// Step 2 of the method: make the blended metric flat by a discrete conformal change (CETM,
// Springborn, Schroeder & Pinkall 2008), keeping the boundary fixed (u = 0 there, paper Sec. 3).
//
// Convention: the flattened squared length of edge ij is exp(u_i + u_j) * l2_ij. The convex energy
//   E(u) = sum_faces [ sum_m (alpha_m lambda_m + 2 L(alpha_m)) - pi/2 sum_m lambda_m ] + sum_i 2pi u_i,
// with lambda_m = log of the scaled squared length of edge m, alpha_m the angle opposite it and L
// Lobachevsky's function, has gradient g_i = 2pi - (angle sum at i) at interior vertices and the
// cotan Laplacian (weights (cot a + cot b) / 2) as Hessian. Newton with a line search on E.
#pragma once

#include <Eigen/Sparse>
#include <memory>

#include "bdinterp/mesh.h"
#include "bdinterp/parallel.h"
#include "bdinterp/sparse_cholesky.h"

namespace bdinterp {

struct FlattenOptions {
  double tolerance = 1e-10;  // stop when max |2pi - angle sum| over interior vertices <= tolerance
  int max_iterations = 50;   // Newton steps before giving up with SolverError
  // Allow chord steps: Newton steps with the factorisation of an earlier iterate (of this solve or of
  // the previous solve on this Flattener) instead of a new one, while they contract fast enough.
  // Every step, chord or not, is accepted only if it reduces the residual; the tolerance is the same.
  bool reuse_factorization = true;
};

struct FlattenReport {
  int iterations = 0;            // Newton steps taken
  double residual = 0;           // final max |2pi - angle sum| (radians)
  int broken_triangles = 0;      // faces violating the triangle inequality in the final metric
  int max_broken_triangles = 0;  // the most seen at any Newton iterate
  int line_search_steps = 0;     // step halvings over all iterations
  int factorizations = 0;        // numeric factorisations (Newton steps with a fresh Hessian)
  int chord_steps = 0;           // steps that reused an earlier factorisation (also in iterations)
};

class Flattener {
 public:
  // disk: one connected piece with one boundary loop (see split_into_disks). Builds the sparsity
  // pattern of the interior cotan Laplacian and runs CHOLMOD's symbolic analysis once.
  explicit Flattener(const Mesh& disk);
  Flattener(const Flattener&) = delete;
  Flattener(Flattener&&) noexcept;
  ~Flattener();
  // A copy with its own CHOLMOD workspace, for use on another thread.
  std::unique_ptr<Flattener> clone() const;

  // l2: #E blended squared edge lengths. u: #V conformal factors; on input the initial guess
  // (boundary entries are ignored), on output the solution (0 on the boundary). Throws SolverError
  // if `options.tolerance` is not reached within `options.max_iterations` steps.
  FlattenReport solve(const Eigen::VectorXd& l2, Eigen::VectorXd& u,
                      const FlattenOptions& options = {});

  // The pieces of the solve, exposed for tests and diagnostics (all sized #V; boundary entries of
  // gradients are 0).
  double energy(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) const;
  Eigen::VectorXd gradient(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) const;
  Eigen::SparseMatrix<double> hessian(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) const;
  // max |2pi - angle sum| over interior vertices.
  double residual(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) const;
  // #E flat squared lengths exp(u_i + u_j) l2_ij at the solution of the last solve() (valid until
  // the next call of any evaluating method), so the layout need not recompute them.
  const Eigen::VectorXd& flat_squared_lengths() const { return scaled_l2_; }
  int num_interior() const { return num_interior_; }
  // The interior numbering and Hessian pattern (see interior_pattern).
  const InteriorPattern& pattern() const { return pattern_; }
  // For the layout: a factorised symmetric positive definite matrix over pattern() whose values()
  // are the matrix that was factorised (the Hessian at the last factorisation, plus `*shift` on the
  // diagonal). Factorises the Hessian at (l2, u) if no factorisation is at hand.
  SparseCholesky& factored_hessian(const Eigen::VectorXd& l2, const Eigen::VectorXd& u, double* shift);
  // Benchmarks: loads the Hessian at (l2, u) into the solver (no factorisation) and gives access to
  // it; the next solve() will not reuse the factorisation that was there.
  void assemble_hessian(const Eigen::VectorXd& l2, const Eigen::VectorXd& u);
  SparseCholesky* cholesky() { factor_reusable_ = false; return chol_.get(); }
  // Forgets the reusable factorisation, so the next solve starts with a fresh Newton step.
  void forget() { factor_reusable_ = false; }
  bool is_interior(int v) const { return pattern_.index[v] >= 0; }

 private:
  struct Eval {
    double energy = 0;
    double residual = 0;
    int broken = 0;
  };
  // One pass over the faces: angle sums into grad_ (interior numbering), optionally the energy and
  // the Hessian values into hvals_.
  Eval evaluate(const Eigen::VectorXd& l2, const Eigen::VectorXd& u, bool want_energy,
                bool want_hessian) const;
  // The Hessian values at the scaled lengths left by the last evaluate (no angles).
  void assemble_from_scaled() const;
  void load_hessian();  // hvals_ into the solver's matrix
  void factorize_with_shift();
  void hessian_times(const double* x, double* y) const;  // y = H x with H = hvals_
  int preconditioned_cg(double eta, int max_iterations);

  explicit Flattener(const Mesh* mesh) : mesh_(mesh) {}

  const Mesh* mesh_;
  int num_interior_ = 0;
  int nnz_ = 0;
  InteriorPattern pattern_;
  // Per face, where its terms go, with the boundary sent to spare slots (row num_interior_ of grad_,
  // entry nnz_ of hvals_) so that the face loops need no branches.
  struct FaceSlots {
    int edge[3];  // edge opposite corner c
    int row[3];   // interior index of corner c
    int diag[3];  // Hessian position of corner c's diagonal
    int off[3];   // Hessian position of the entry of edge c
  };
  std::vector<FaceSlots> slots_;
  // Other threads' shares of an evaluation: angle sums (whole turns, broken faces), running
  // products of the corners' half-angle factors, Hessian values.
  mutable parallel::Partials sum_parts_, re_parts_, im_parts_, hessian_parts_;
  mutable Eigen::VectorXd corner_re_, corner_im_;  // #interior + 1: thread 0's running products
  mutable std::vector<double> hvals_;  // nnz_ + 1: the Hessian at the last evaluated u, in the
                                       // solver's order (the shifted copy lives in the solver)
  std::unique_ptr<SparseCholesky> chol_;
  mutable Eigen::VectorXd grad_;      // #interior + 1, scratch
  mutable Eigen::VectorXd scaled_l2_; // #E, scratch
  mutable Eigen::VectorXd scaled_len_;  // #E, scratch
  mutable Eigen::VectorXd exp_u_;     // #V, scratch
  double shift_ = 0;                  // diagonal shift of the factorisation in chol_
  bool factor_reusable_ = false;      // chol_ holds a factorisation usable for chord steps
  double factor_cost_ = 0;            // estimated flops of a factorisation and of a chord step
  double chord_cost_ = 0;
  double stale_cost_ = 0;             // flops spent on CG iterations a fresh factor would not need
  double evaluation_cost() const;
  double newton_c_ = 1.0;             // last observed r_new / r_old^2 of a full Newton step
  Eigen::VectorXd step_, trial_;      // scratch
  Eigen::VectorXd cg_r_, cg_z_, cg_p_;  // H p shares cg_z_ (never both alive)
};

// One-off convenience: the flat squared edge lengths exp(u_i + u_j) l2_ij of a disk.
Eigen::VectorXd flatten(const Mesh& disk, const Eigen::VectorXd& l2,
                        const FlattenOptions& options = {}, FlattenReport* report = nullptr);

// exp(u_i + u_j) * l2_ij for every edge.
Eigen::VectorXd scale_lengths(const Mesh& mesh, const Eigen::VectorXd& l2, const Eigen::VectorXd& u);

}  // namespace bdinterp
