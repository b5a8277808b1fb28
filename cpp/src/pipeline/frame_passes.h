// Internal: what the Interpolator does to a whole frame once every piece is placed (piece_solver.h),
// as an ordered list of passes, each a short member of FramePasses:
//   join pieces -> place isolated vertices -> fill folds -> denormalise -> self-check
#pragma once

#include <memory>
#include <vector>

#include "folds/folds.h"
#include "bdinterp/interpolator.h"
#include "place/joints.h"

namespace bdinterp::detail {

// One frame on its way through the passes.
struct FrameInProgress {
  const Eigen::VectorXd& w;     // the weights (#shapes, sum 1)
  Eigen::Ref<Positions> out;    // #V by 2: normalised coordinates, the caller's after denormalise
  std::vector<double> angles;   // per piece: the anchor angle it was placed at (the joints turn from it)
  FrameStats stats;             // the pieces' statistics; each pass adds its own
};

// The frame passes of one Interpolator: read-only after construction, shared by the workers.
class FramePasses {
 public:
  // solved: the mesh the pieces solve (without a fold region); unit: the inputs in the normalised
  // frame (#V by 2 each); folds, joints: null when the frame has none; caller = scale * unit +
  // offset; options: max_flatness and strict for the self-check.
  FramePasses(const Mesh& solved, const std::vector<Positions>& unit, std::unique_ptr<const FoldFill> folds,
              std::unique_ptr<const Joints> joints, const Eigen::RowVector2d& offset, double scale,
              const InterpolatorOptions& options);

  // Every pass in order. Throws SolverError for a non-finite frame, and (strict) for one failing
  // the self-check.
  void run(FrameInProgress& frame) const;
  const Joints* joints() const { return joints_.get(); }

 private:
  using Pass = void (FramePasses::*)(FrameInProgress&) const;
  static const Pass kOrder[];
  // Children turned and moved by their parents' joints (joints.h).
  void join_pieces(FrameInProgress& frame) const;
  // Vertices in no solved face: the linear blend of their input positions.
  void place_isolated(FrameInProgress& frame) const;
  // The fold region, filled around the solved rest (folds.h).
  void fill_folds(FrameInProgress& frame) const;
  // Back to the caller's coordinates; SolverError if a position is not finite.
  void denormalise(FrameInProgress& frame) const;
  // Flags (or, strict, raises on) broken triangles and a large flatness residual.
  void self_check(FrameInProgress& frame) const;

  std::vector<int> isolated_;
  std::vector<Positions> isolated_positions_;  // per shape: the isolated vertices' positions
  std::unique_ptr<const FoldFill> folds_;
  std::unique_ptr<const Joints> joints_;
  Eigen::RowVector2d offset_;
  double scale_;
  double max_flatness_;
  bool strict_;
};

}  // namespace bdinterp::detail
