// Steps 2 and 3 of the method on a piece with holes (a multiply connected domain; docs/HOLES.md).
//
// The paper flattens with u = 0 on the boundary, which needs one boundary loop. With holes, u = 0 is
// kept on the outer loop only; each inner loop gets ONE unknown conformal scale whose angle
// condition is the loop's total turning: the domain's angles along a hole of n vertices sum to
// (n + 2) pi, so the hole's boundary turns once and the developed loop closes in rotation. That is
// the disks' Flattener with other unknowns (FlattenUnknowns, flatten.h): the same energy, Newton,
// warm start, refactorisation policy and parallel loops.
//
// One scale per hole does not close the translation period (two numbers per hole): the developed
// hole boundary may miss its start. Two more unknowns per hole close it: u along hole k is
// c_k + a_k cos s + b_k sin s (s: the arc-length angle along the loop in the blended metric). This
// class is that outer step: for fixed dipoles (a, b) the Flattener solves for the c_k (the dipole
// terms are its fixed offsets), and Newton on the dipoles (the Jacobian from the Flattener's linear
// response, Broyden updates; each step by the first of kPeriodSteps that applies) drives every
// period to zero. At an input's own metric the
// periods vanish with zero dipoles: no extra solve, inputs exact. The layout is the disks' Layout
// with the holes' vertices free (its own uniform Laplacian); the remaining period is reported per
// hole, relative to the loop's length.
#pragma once

#include <array>
#include <complex>
#include <memory>
#include <utility>
#include <vector>

#include "flatten/flatten.h"
#include "layout/layout.h"
#include "mesh/mesh.h"

namespace bdinterp {

// The ways a Newton step on the dipoles is taken, tried in this order (HoleSolver::close_periods):
//   Linear: u += S delta with the sensitivity S = du/d dipoles, free (no solve); applies while S is
//           young, the move tiny and the periods it leaves closed (its u is not the Flattener's
//           solution, so no step can follow it);
//   Follow: the Flattener's solution moved by one linear solve (follow_offsets), for small moves;
//   Convex: the dipoles set and a convex solve from u (always applies).
enum class PeriodStep { Linear, Follow, Convex };
inline constexpr PeriodStep kPeriodSteps[] = {PeriodStep::Linear, PeriodStep::Follow, PeriodStep::Convex};

// After f.solve(), u being its solution: the solution for fixed offsets changed by `offset` (#V,
// zero where a vertex has no unknown), to first order and without evaluating the angles again:
// u += offset + the unknowns' response, from one linear solve (CG with the Hessian at the solution,
// preconditioned by the reusable factorisation) whose right-hand side is the defects plus the
// cotan Laplacian of the offsets. What it leaves in the defects is that solve's residual (<= half
// of tolerance * refinement) plus second order in the move, which must be <= max_move in every u.
// Returns false and changes nothing without a reusable factorisation, with broken faces, if the
// solve does not converge or the move is larger. f.flat_squared_lengths() follows u.
bool follow_offsets(Flattener& f, const Eigen::VectorXd& offset, Eigen::VectorXd& u, double max_move,
                    const FlattenOptions& options);
// d u / d offsets at the solution of f's last solve() (and follow_offsets), applied to `offset`
// (#V, zero where a vertex has no unknown): move (#V) = offset + the unknowns' first-order
// response, its linear solve to max |residual| <= relative * max |right-hand side|. Changes no
// state. Returns false without a reusable factorisation, with broken faces or if the solve stalls.
bool offset_response(Flattener& f, const Eigen::VectorXd& offset, double relative, Eigen::VectorXd& move);

struct HolesReport {
  FlattenReport flatten;             // iterations, residual (max over vertices and loops), broken
  std::vector<double> closure;       // per inner loop: |translation period| / loop length
  double flatness = 0;               // max over edges | |x_i - x_j|^2 / l2_ij - 1 | of the layout
};

class HoleSolver {
 public:
  // piece: one connected piece with >= 1 boundary loop; base: its base shape (#V by 2), which only
  // decides which loop is the outer one (the largest enclosed area). Throws InvalidInput for a piece
  // without boundary.
  HoleSolver(const Mesh& piece, const Positions& base);
  ~HoleSolver();
  std::unique_ptr<HoleSolver> clone() const;  // own workspaces (shared plans), for another thread

  // Drops the warm-start state (the Jacobian and the factorisation): the next solve is cold.
  void forget();
  int num_holes() const { return static_cast<int>(loops_.size()); }
  // The convex solve's Flattener (one unknown per interior vertex and per hole).
  Flattener& flattener() { return flattener_; }
  // Vertices of inner loop k in the order of the mesh's boundary loop.
  const std::vector<int>& hole(int k) const { return loops_[k]; }

  // Step 2 on the piece: l2: #E blended squared lengths; u: #V initial guess (outer-loop entries
  // ignored; along inner loop k its least-squares fit c_k + a_k cos s + b_k sin s is the start; all
  // zero: a cold start), on output the solution (0 on the outer loop, c_k plus the dipole terms
  // along inner loop k). Throws InvalidInput for bad sizes or options, SolverError if the tolerance
  // is not reached. The report counts the convex solves (the first and the closure's), sums their
  // work (factorizations, ...) and gives the most Newton steps of any one as iterations; residual
  // and broken_triangles are the final u's. The flat squared lengths stay in flat_squared_lengths().
  FlattenReport flatten(const Eigen::VectorXd& l2, Eigen::VectorXd& u, const FlattenOptions& options = {});
  // #E flat squared lengths of the last flatten() (valid until the next call).
  const Eigen::VectorXd& flat_squared_lengths() const { return *flat_result_; }
  // flatten() then layout(): X (#V by 2) with counter-clockwise faces in an arbitrary rigid frame.
  HolesReport solve(const Eigen::VectorXd& l2, Eigen::VectorXd& u, Positions& X,
                    const FlattenOptions& options = {});

  // For tests: energy and gradient in the reduced unknowns (one per interior vertex, one per inner
  // loop; u sized #V); the gradient is target angle sum - angle sum, 2 pi at vertices, (n + 2) pi
  // at loops, indexed by unknown.
  double energy(const Eigen::VectorXd& l2, const Eigen::VectorXd& u);
  Eigen::VectorXd gradient(const Eigen::VectorXd& l2, const Eigen::VectorXd& u);
  // Unknown of vertex v: -1 on the outer loop.
  int unknown(int v) const { return plan_->pattern.index[v]; }

  // Lays out flat squared lengths l2 (#E) by the Layout (X as above) and returns its flatness;
  // closure per inner loop: the gap of the loop developed by the Layout's faces / its length.
  double layout(const Eigen::VectorXd& l2, Positions& X, std::vector<double>& closure);
  // The holes' translation periods of flat lengths l2 (#E), relative to each loop's length: (re, im)
  // of hole k at 2k, 2k + 1, in a frame along the loop's first edge. Intrinsic: walking the hole, the
  // direction turns by pi - (the domain's angle) at each vertex (no development of the faces).
  Eigen::VectorXd periods(const Eigen::VectorXd& l2) const;

 private:
  HoleSolver(const HoleSolver&);
  // The convex solve for the unknowns at fixed dipoles (the Flattener), its work added to report.
  void convex_solve(const Eigen::VectorXd& l2, Eigen::VectorXd& u, const FlattenOptions& options,
                    FlattenReport& report);
  // Hole k's period of flat lengths l2 (periods()).
  std::complex<double> hole_period(int k, const Eigen::VectorXd& l2) const;
  // The periods of the last convex solve's flat lengths.
  Eigen::VectorXd solved_periods() const { return periods(flattener_.flat_squared_lengths()); }
  // The dipoles' shape on each hole (loop_xy_) from the blended lengths l2.
  void set_dipole_shapes(const Eigen::VectorXd& l2);
  // The dipoles (a_k, b_k at 2k, 2k + 1) of u's least-squares fit c_k + a_k cos s + b_k sin s along
  // each hole (loop_xy_ set); u along hole k is set to c_k.
  Eigen::VectorXd fit_dipoles(Eigen::VectorXd& u) const;
  // Sets the dipoles (a_k, b_k at 2k, 2k + 1) to ab, keeping each hole's unknown, in u and dipole_.
  void set_dipoles(const Eigen::VectorXd& ab, Eigen::VectorXd& u);
  // d periods / d dipoles at u (whose periods are `period`) by finite differences, and the
  // sensitivity; the Flattener is left at u.
  Eigen::MatrixXd dipole_jacobian(const Eigen::VectorXd& l2, Eigen::VectorXd& u, const Eigen::VectorXd& period,
                                  const FlattenOptions& options, FlattenReport& report);
  // trial_flat_ = flat (#E) times 1 + h (move_i + move_j): the lengths moved by h move_ to first order.
  void move_lengths(const Eigen::VectorXd& flat, double h);
  // offset (#V): the dipoles' change delta along each hole (loop_xy_), 0 elsewhere.
  void dipole_offsets(const Eigen::VectorXd& delta, Eigen::VectorXd& offset) const;
  // jacobian_ and sensitivity_ from the Flattener's first-order response at its solution (a linear
  // solve per dipole, no convex solve); false if the Flattener cannot give it.
  bool linear_jacobian();
  // jacobian_ and sensitivity_ anew at the solved u (periods `period`): linear_jacobian, else by
  // finite differences.
  void refresh_jacobian(const Eigen::VectorXd& l2, Eigen::VectorXd& u, const Eigen::VectorXd& period,
                        const FlattenOptions& options, FlattenReport& report);
  // The dipoles' step delta from the solved u by follow_offsets (one linear solve, no convex
  // solve); false, nothing changed, if the Flattener cannot take it (e.g. a move too large).
  bool follow(const Eigen::VectorXd& delta, Eigen::VectorXd& u, const FlattenOptions& options);
  // The dipoles' step delta taken to first order from the Flattener's solution u (u +=
  // sensitivity_ * delta, no convex solve): kept, with its periods in next and its flat lengths in
  // flat_, if they are finite and below aim; else u, dipole_ and flat_ are unchanged.
  bool linear_step(const Eigen::VectorXd& delta, double aim, Eigen::VectorXd& u, Eigen::VectorXd& next);
  // The Newton step delta on the dipoles by `step`; false, nothing changed, if it does not apply.
  // next: the periods after it.
  bool try_step(PeriodStep step, const Eigen::VectorXd& l2, const Eigen::VectorXd& delta, double aim,
                Eigen::VectorXd& u, Eigen::VectorXd& next, const FlattenOptions& options, FlattenReport& report);
  // Newton on the dipoles from the solved u until the periods are closed (holes.cpp); returns the
  // flat squared lengths of the final u (the Flattener's or flat_).
  const Eigen::VectorXd& close_periods(const Eigen::VectorXd& l2, Eigen::VectorXd& u, const FlattenOptions& options,
                     FlattenReport& report);

  const Mesh* mesh_;
  // The layout's plan (the outer loop walked, every other vertex free; its uniform Laplacian's
  // analysis), shared by copies; before loops_, which are the loops it does not walk.
  std::shared_ptr<const LayoutPlan> layout_plan_;
  std::vector<std::vector<int>> loops_;  // the inner loops
  std::vector<std::vector<std::pair<int, double>>> loop_edges_;  // per inner loop: (edge, +-1)
  // Per inner loop: (position in the loop, face, corner) of every face corner at its vertices.
  std::vector<std::vector<std::array<int, 3>>> loop_corners_;
  mutable std::vector<std::vector<double>> half_turns_;  // per inner loop: hole_period's 2 n doubles
  std::vector<Eigen::MatrixX2d> loop_xy_;  // per inner loop and vertex: the dipoles' shape (cos, sin)
  Eigen::VectorXd dipole_;                // the dipoles in the u of the last solve
  Eigen::MatrixXd jacobian_;              // d periods / d dipoles, kept across frames (Broyden)
  Eigen::MatrixXd sensitivity_;           // #V by 2 #holes: d u / d dipoles of the convex solution, too
  int sensitivity_age_ = 0;               // first-order steps taken since sensitivity_ was last updated
  Eigen::VectorXd flat_;                  // flat squared lengths of a u the Flattener did not solve
  Eigen::VectorXd trial_flat_;            // linear_step's candidate for flat_
  // #V workspaces of the closure, kept: a frame allocates nothing large (freed large blocks cost
  // page faults and, under jemalloc as in Blender, madvise and TLB flushes on every core).
  Eigen::VectorXd move_, before_;
  Eigen::VectorXd offset_;  // #V: follow()'s and linear_jacobian()'s dipole offsets, 0 off the holes
  const Eigen::VectorXd* flat_result_ = nullptr;  // the last flatten()'s: the Flattener's or flat_
  // The plans are shared by copies (one per thread); the workspaces and factors are each copy's own.
  std::shared_ptr<const FlattenPlan> plan_;
  Flattener flattener_;
  Layout layout_;  // over layout_plan_, its uniform Laplacian factorised once per copy
};

}  // namespace bdinterp
