#include "pipeline/piece_solver.h"

#include <stdexcept>

#include "mesh/geometry.h"
#include "blend/metric_blend.h"
#include "place/rigid_motion.h"
#include "place/still.h"

namespace bdinterp::detail {
namespace {

// A disk (one boundary loop): the Flattener with u = 0 on the boundary, the Layout on its Hessian.
class DiskSolver final : public PieceSolver {
 public:
  explicit DiskSolver(const PiecePlan& plan)
      : PieceSolver(plan), flattener_(plan.flatten), layout_(plan.layout, /*own_system=*/false) {}

  void forget() override {
    PieceSolver::forget();
    flattener_.forget();
  }
  Flattener& flattener() override { return flattener_; }

 private:
  FlattenReport flatten(const Eigen::VectorXd& w, const FlattenOptions& options) override {
    const bool cold = u_.isZero(0.0) && !flattener_.has_reusable_factorization();
    FlattenReport rep = flattener_.solve(l2w_, u_, options);
    if (rep.broken_triangles > 0 && !cold) rep = solve_cold(options, rep);
    if (rep.broken_triangles == 0) history_.add(w, u_);
    return rep;
  }

  // Broken triangles at the solution: the energy is not strictly convex there and the point reached
  // depends on the start. Solved again as a fresh Interpolator would, so the frame does not depend
  // on the frames before it (and it stays out of the warm-start history); the work of both counts.
  FlattenReport solve_cold(const FlattenOptions& options, const FlattenReport& warm) {
    flattener_.forget();
    u_.setZero();
    FlattenReport rep = flattener_.solve(l2w_, u_, options);
    rep.factorizations += warm.factorizations;
    rep.chord_steps += warm.chord_steps;
    rep.line_search_steps += warm.line_search_steps;
    return rep;
  }

  // The layout solves with the flattening's factorised Hessian: no second factorisation. Unless that
  // one needed a diagonal shift (a singular Hessian, e.g. broken triangles around a vertex): refining
  // a shifted singular system fails, so then the uniform Laplacian of its own.
  void lay_out(PieceOutcome& out) override {
    double shift = 0;
    SparseCholesky* W = flattener_.num_interior() > 0 ? &flattener_.factored_hessian(l2w_, u_, &shift) : nullptr;
    if (shift > 0) {
      layout_.ensure_own_system();
      layout_.embed(flattener_.flat_squared_lengths(), X_, &out.flatness);
    } else {
      layout_.embed(flattener_.flat_squared_lengths(), W, shift, X_, &out.flatness);
    }
  }

  Flattener flattener_;
  Layout layout_;
};

// A piece with holes: HoleSolver flattens (one unknown per hole, the periods closed by its dipoles)
// and lays out (the disks' Layout with the holes' vertices free, docs/HOLES.md).
class HoledSolver final : public PieceSolver {
 public:
  explicit HoledSolver(const PiecePlan& plan) : PieceSolver(plan), holes_(plan.holes->clone()) {}

  void forget() override {
    PieceSolver::forget();
    holes_->forget();
  }
  Flattener& flattener() override { return holes_->flattener(); }

 private:
  FlattenReport flatten(const Eigen::VectorXd& w, const FlattenOptions& options) override {
    const FlattenReport rep = holes_->flatten(l2w_, u_, options);
    history_.add(w, u_);
    return rep;
  }

  void lay_out(PieceOutcome& out) override {
    out.flatness = holes_->layout(holes_->flat_squared_lengths(), X_, out.closure);
  }

  std::unique_ptr<HoleSolver> holes_;
};

}  // namespace

PiecePlan::PiecePlan(Piece p, const std::vector<Positions>& local_shapes, int base, int anchor_vertex, bool still,
                     bool joints)
    : piece(std::move(p)),
      anchor(piece.mesh, local_shapes[base], anchor_vertex),
      mirrored(doubled_total_area(local_shapes[base], piece.mesh.faces()) < 0) {
  if (joints) shape.emplace(JointPiece{&piece.vertices, &piece.mesh, &anchor.base(), &frames});
  const Eigen::VectorXd region = still ? still_region(piece.mesh, anchor, local_shapes, base) : Eigen::VectorXd();
  if (region.size() > 0) anchor.set_region(region);
  for (const Positions& X : local_shapes) frames.push_back(anchor.measure_input(X));
  // The default anchor (and a path's point) moves on the geodesic of the rigid motions; the
  // paper's vertex anchor keeps its linear blend; a whole turn with a shift has none (rigid_motion.h).
  if (still && anchor_vertex < 0 && has_geodesic(frames, base)) geodesic_base = base;
}

void PiecePlan::plan_solve(const std::vector<Positions>& local_shapes, int base) {
  // A holed piece flattens and lays out in its HoleSolver: no disk plan or layout for it.
  if (piece.mesh.boundary_loops().size() > 1) {
    holes = std::make_unique<const HoleSolver>(piece.mesh, local_shapes[base]);
  } else {
    flatten = std::make_shared<const FlattenPlan>(piece.mesh);
    layout = std::make_shared<const LayoutPlan>(piece.mesh);
  }
  for (const Positions& X : local_shapes) l2.push_back(squared_edge_lengths(piece.mesh, X));
}

std::unique_ptr<PieceSolver> PieceSolver::make(const PiecePlan& plan) {
  if (!plan.holes && !plan.flatten) throw std::logic_error("PieceSolver: the plan's plan_solve was not called");
  if (plan.holes) return std::make_unique<HoledSolver>(plan);
  return std::make_unique<DiskSolver>(plan);
}

PieceSolver::PieceSolver(const PiecePlan& plan)
    : plan_(plan), u_(Eigen::VectorXd::Zero(plan.piece.mesh.num_vertices())) {}

PieceOutcome PieceSolver::solve(const Eigen::VectorXd& w, const FlattenOptions& options, const Anchor& anchor,
                                Eigen::Ref<Positions> out) {
  PieceOutcome result;
  blend(w);
  predict(w);
  result.report = flatten(w, options);
  lay_out(result);
  place(w, anchor, out, result);
  return result;
}

void PieceSolver::forget() {
  history_.solved.clear();
}

void PieceSolver::continue_from(const PieceSolver& other) {
  forget();
  history_ = other.history_;
}

void PieceSolver::blend(const Eigen::VectorXd& w) { blend_squared_lengths(plan_.piece.mesh, plan_.l2, w, l2w_); }

void PieceSolver::predict(const Eigen::VectorXd& w) { history_.predict(w, u_); }

void PieceSolver::place(const Eigen::VectorXd& w, const Anchor& anchor, Eigen::Ref<Positions> out,
                        PieceOutcome& result) {
  if (plan_.mirrored) X_.col(0) *= -1.0;
  const Frame2 frame = blend_frames(plan_.frames, w, anchor, plan_.geodesic_base);
  result.angle = frame.angle;
  plan_.anchor.place(X_, frame);
  for (size_t i = 0; i < plan_.piece.vertices.size(); ++i) out.row(plan_.piece.vertices[i]) = X_.row(i);
}

}  // namespace bdinterp::detail
