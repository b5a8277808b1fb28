#include "pipeline/frame_passes.h"

#include <cfloat>
#include <cmath>
#include <sstream>

#include "pipeline/validation.h"

namespace bdinterp::detail {

// The order matters: the fill needs every part of the rest placed (the joints' too) and the
// self-check reads what every pass reported.
const FramePasses::Pass FramePasses::kOrder[] = {&FramePasses::join_pieces, &FramePasses::place_isolated,
                                                 &FramePasses::fill_folds, &FramePasses::denormalise,
                                                 &FramePasses::self_check};

FramePasses::FramePasses(const Mesh& solved, const std::vector<Positions>& unit, std::unique_ptr<const FoldFill> folds,
                         std::unique_ptr<const Joints> joints, const Eigen::RowVector2d& offset, double scale,
                         const InterpolatorOptions& options)
    : folds_(std::move(folds)), joints_(std::move(joints)), offset_(offset), scale_(scale),
      max_flatness_(options.max_flatness), strict_(options.strict) {
  for (int v = 0; v < solved.num_vertices(); ++v)
    if (solved.is_isolated_vertex(v)) isolated_.push_back(v);
  for (const Positions& X : unit) {
    isolated_positions_.emplace_back(isolated_.size(), 2);
    for (size_t k = 0; k < isolated_.size(); ++k) isolated_positions_.back().row(k) = X.row(isolated_[k]);
  }
}

void FramePasses::run(FrameInProgress& frame) const {
  for (const Pass pass : kOrder) (this->*pass)(frame);
}

void FramePasses::join_pieces(FrameInProgress& frame) const {
  if (!joints_) return;
  joints_->apply(frame.w, frame.angles, frame.out);
  frame.stats.joints = joints_->size();
}

void FramePasses::place_isolated(FrameInProgress& frame) const {
  for (size_t k = 0; k < isolated_.size(); ++k) {
    frame.out.row(isolated_[k]).setZero();
    for (Eigen::Index i = 0; i < frame.w.size(); ++i) frame.out.row(isolated_[k]) += frame.w[i] * isolated_positions_[i].row(k);
  }
}

void FramePasses::fill_folds(FrameInProgress& frame) const {
  if (folds_) folds_->fill(frame.w, frame.out, &frame.stats.fold_faces, &frame.stats.fold_free_vertices);
}

void FramePasses::denormalise(FrameInProgress& frame) const {
  bool finite = true;
  Eigen::Ref<Positions>& out = frame.out;
  for (Eigen::Index v = 0; v < out.rows(); ++v) {
    const double x = out(v, 0) * scale_ + offset_[0], y = out(v, 1) * scale_ + offset_[1];
    out(v, 0) = x;
    out(v, 1) = y;
    finite &= std::abs(x) <= DBL_MAX && std::abs(y) <= DBL_MAX;
  }
  if (!finite) throw SolverError("the frame at weights " + weights_text(frame.w) + " is not finite");
}

void FramePasses::self_check(FrameInProgress& frame) const {
  FrameStats& st = frame.stats;
  std::ostringstream s;
  if (st.broken_triangles > 0)
    s << st.broken_triangles << " triangles violate the triangle inequality in the flattened metric";
  if (!(st.flatness <= max_flatness_)) {
    s << (st.broken_triangles > 0 ? "; " : "") << "the layout's flatness residual " << st.flatness
      << " exceeds max_flatness " << max_flatness_;
  }
  if (s.tellp() == 0) return;
  st.converged = false;
  st.warnings = "frame at weights " + weights_text(frame.w) + ": " + s.str();
  if (strict_) throw SolverError(st.warnings + " (strict)");
}

}  // namespace bdinterp::detail
