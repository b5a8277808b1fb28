// Internal: one piece of the mesh solved frame by frame, in the method's named stages
//   blend -> predict -> flatten -> lay out -> place
// (paper Sec. 4: step 1 blends the metric, 2 flattens it, 3 lays it out, 4 places it by the anchor;
// predict is the warm start from the frames solved before). One kind per piece topology: a disk
// (one boundary loop) or a piece with holes (holes.h). The Interpolator runs one PieceSolver per
// piece and worker, then its frame passes (frame_passes.h) on the whole frame.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "place/anchor_frame.h"
#include "flatten/flatten.h"
#include "flatten/holes.h"
#include "layout/layout.h"
#include "mesh/mesh.h"
#include "place/piece_shape.h"
#include "flatten/warm_start.h"

namespace bdinterp::detail {

// Everything about one piece that does not change between frames: read-only, shared by the workers.
struct PiecePlan {
  Piece piece;
  std::vector<Eigen::VectorXd> l2;  // per input shape: squared edge lengths (#E)
  std::shared_ptr<const FlattenPlan> flatten;  // disks only (a holed piece's is its HoleSolver's)
  std::shared_ptr<const LayoutPlan> layout;    // disks only
  AnchorFrame anchor;
  std::vector<Frame2> frames;  // per input shape: its anchor
  bool mirrored;               // the base shape is clockwise: lay out counter-clockwise, then reflect
  std::unique_ptr<const HoleSolver> holes;  // set for pieces with holes (more than one boundary loop)
  int geodesic_base = -1;      // blend_frames: the anchor on the motions' geodesic from this input
  // The piece's outline for the joints (set when asked for): it points into this plan, which is
  // therefore never moved; its queries are not thread-safe (only the Joints' constructor makes them).
  std::optional<detail::PieceShape> shape;

  // The piece's placement: its anchor, its frame in every input and (joints) its `shape`; the
  // solvers' part follows with plan_solve. local_shapes: every input's positions of the piece's
  // vertices (its local order); base: the domain shape; anchor_vertex: the anchor's local index, -1
  // for none; still: anchor on the parts that do not move between the inputs (still.h; the default
  // anchor, also the point an anchor path without a vertex moves); joints: make `shape`.
  PiecePlan(Piece p, const std::vector<Positions>& local_shapes, int base, int anchor_vertex, bool still, bool joints);
  // The solvers' part: `flatten` and `layout` (or `holes`) and `l2`, from the same local_shapes and
  // base. Made after the joints, which read what the constructor left in the cache (the symbolic
  // analyses here would evict it).
  void plan_solve(const std::vector<Positions>& local_shapes, int base);
  PiecePlan(const PiecePlan&) = delete;
  PiecePlan& operator=(const PiecePlan&) = delete;
};

// What one piece adds to its frame's statistics.
struct PieceOutcome {
  FlattenReport report;
  double flatness = 0;          // the layout's residual (Layout::embed)
  std::vector<double> closure;  // pieces with holes: per hole, its relative translation period
  double angle = 0;             // the anchor angle the piece was placed at (the joints turn from it)
};

// The frames of one piece on one thread: its own solvers (CHOLMOD workspaces) and warm-start history.
// Not thread-safe; one per piece and worker, all reading the same PiecePlan (which must outlive it).
class PieceSolver {
 public:
  // The solver of the plan's kind: HoledSolver when plan.holes is set, else DiskSolver (std::logic_error
  // before the plan's plan_solve).
  static std::unique_ptr<PieceSolver> make(const PiecePlan& plan);
  virtual ~PieceSolver() = default;

  // The piece's frame at weights w (#shapes, sum 1) written into its rows of out (#V by 2, the
  // normalised frame), by the stages in order. Throws SolverError when the flattening fails.
  PieceOutcome solve(const Eigen::VectorXd& w, const FlattenOptions& options, const Anchor& anchor,
                     Eigen::Ref<Positions> out);

  // Drops the warm-start history and reusable factorisations: the next frame is solved cold.
  virtual void forget();
  // Starts from other's warm-start history (the frames before a chunk of frames()), with no
  // reusable factorisation of its own.
  void continue_from(const PieceSolver& other);
  // The flattener of the piece's unknowns (a holed piece's is its HoleSolver's), for
  // Interpolator::floor_seconds.
  virtual Flattener& flattener() = 0;

 protected:
  explicit PieceSolver(const PiecePlan& plan);
  // Step 1: l2w_ = the input metrics blended at w (metric_blend.h).
  void blend(const Eigen::VectorXd& w);
  // The warm start: u_ extrapolated from the frames solved before (detail::History).
  void predict(const Eigen::VectorXd& w);
  // Step 2: u_ flattens l2w_; records the frames worth warm-starting from in history_.
  virtual FlattenReport flatten(const Eigen::VectorXd& w, const FlattenOptions& options) = 0;
  // Step 3: X_ = the flat metric laid out with counter-clockwise faces (any rigid frame).
  virtual void lay_out(PieceOutcome& out) = 0;
  // Step 4: X_ reflected back if mirrored, moved to the blended anchor, into the piece's rows of out.
  void place(const Eigen::VectorXd& w, const Anchor& anchor, Eigen::Ref<Positions> out, PieceOutcome& result);

  const PiecePlan& plan_;
  History history_;
  Eigen::VectorXd u_, l2w_;  // #V log scale factors, #E blended squared lengths
  Positions X_;              // #V by 2, the piece's layout
};

}  // namespace bdinterp::detail
