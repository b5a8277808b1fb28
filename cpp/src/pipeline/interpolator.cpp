#include "bdinterp/interpolator.h"

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <exception>
#include <sstream>
#include <system_error>
#include <thread>

#include "mesh/orientation.h"
#include "parallel/parallel.h"
#include "pipeline/validation.h"
#include "pipeline/frame_passes.h"
#include "pipeline/piece_solver.h"

namespace bdinterp {
namespace {
using detail::check_orientation;
using detail::FrameInProgress;
using detail::PiecePlan;
using detail::PieceSolver;
using detail::validate_anchor;
using detail::validate_options;

// Frames merged: the flattening's reports by their one rule, the worst flatness, the first warning.
void merge(FrameStats& into, const FrameStats& s) {
  merge(static_cast<FlattenReport&>(into), s);
  into.flatness = std::max(into.flatness, s.flatness);
  into.pieces = s.pieces;  // these are the same for every frame of an Interpolator
  into.fold_faces = s.fold_faces, into.fold_free_vertices = s.fold_free_vertices, into.joints = s.joints;
  into.converged = into.converged && s.converged;
  into.threads = std::max(into.threads, s.threads);
  if (into.warnings.empty()) into.warnings = s.warnings;
  into.hole_closure.resize(std::max(into.hole_closure.size(), s.hole_closure.size()), 0.0);
  for (size_t k = 0; k < s.hole_closure.size(); ++k)
    into.hole_closure[k] = std::max(into.hole_closure[k], s.hole_closure[k]);
}

// The rows of `shapes` of the piece's vertices, in its local order.
std::vector<Positions> local_positions(const std::vector<Positions>& shapes, const Piece& p) {
  std::vector<Positions> local;
  // Both columns: Eigen 3.4 deprecates Eigen::placeholders::all, Eigen 5 has no Eigen::all.
  for (const Positions& X : shapes) local.emplace_back(X(p.vertices, Eigen::seqN(0, 2)));
  return local;
}

// One plan per piece of the solved mesh, with every input's positions of its vertices (its local
// order) for plan_solve; anchor.vertex is global (-1: none); joints: each with its outline for
// the joints.
struct Plans {
  std::vector<std::unique_ptr<PiecePlan>> plans;
  std::vector<std::vector<Positions>> local;
};
Plans plan_pieces(std::vector<Piece> pieces, const std::vector<Positions>& unit, const Anchor& anchor, int base,
                  bool joints) {
  const bool still = anchor.mode == Anchor::Mode::Centroid || (anchor.mode == Anchor::Mode::Path && anchor.vertex < 0);
  Plans out;
  for (Piece& p : pieces) {
    out.local.push_back(local_positions(unit, p));
    const auto it = std::find(p.vertices.begin(), p.vertices.end(), anchor.vertex);
    const int av = anchor.vertex >= 0 && it != p.vertices.end() ? static_cast<int>(it - p.vertices.begin()) : -1;
    out.plans.push_back(std::make_unique<PiecePlan>(std::move(p), out.local.back(), base, av, still, joints));
  }
  return out;
}

// The given joint links with their pieces and points in the normalised frame (InvalidInput naming
// the link for a vertex in no piece or a point that is not finite).
std::vector<detail::GivenJoint> given_joints(const std::vector<std::unique_ptr<PiecePlan>>& plans, int num_vertices,
                                             const InterpolatorOptions& options, const Eigen::RowVector2d& offset,
                                             double scale) {
  std::vector<int> piece_of(static_cast<size_t>(num_vertices), -1);
  for (size_t p = 0; p < plans.size(); ++p)
    for (int v : plans[p]->piece.vertices) piece_of[static_cast<size_t>(v)] = static_cast<int>(p);
  std::vector<detail::GivenJoint> out;
  for (const JointLink& l : options.joint_links) {
    const std::string where = "joint link " + std::to_string(out.size()) + ": ";
    const bool path = l.parent_vertex == -1;  // the child is a root on its given path
    for (int v : path ? std::vector<int>{l.child_vertex} : std::vector<int>{l.parent_vertex, l.child_vertex}) {
      if (v < 0 || v >= num_vertices)
        throw InvalidInput(where + "vertex " + std::to_string(v) + " out of range [0, " + std::to_string(num_vertices) + ")");
      if (piece_of[static_cast<size_t>(v)] < 0) throw InvalidInput(where + "vertex " + std::to_string(v) + " is in no face");
    }
    if (!l.point.allFinite()) throw InvalidInput(where + "its point is not finite");
    out.push_back({l.parent_vertex < 0 ? -1 : piece_of[static_cast<size_t>(l.parent_vertex)],
                   piece_of[static_cast<size_t>(l.child_vertex)],
                   ((l.point.transpose() - offset) / scale).transpose()});
  }
  return out;
}

// The joints between pieces (joints.h); null with one piece or joints off.
std::unique_ptr<const Joints> join_pieces(const std::vector<std::unique_ptr<PiecePlan>>& plans,
                                          const std::vector<Positions>& unit, double size, const Anchor& anchor,
                                          const InterpolatorOptions& options, const std::vector<detail::GivenJoint>& given) {
  if (!options.joints || plans.size() < 2) return nullptr;
  detail::PieceShapes parts;
  int anchored = -1;  // the piece of a vertex anchor roots its tree, so the anchor holds
  for (const auto& p : plans) {
    const auto& vs = p->piece.vertices;
    if (anchor.vertex >= 0 && std::find(vs.begin(), vs.end(), anchor.vertex) != vs.end())
      anchored = static_cast<int>(parts.size());
    parts.push_back(&*p->shape);
  }
  return std::make_unique<const Joints>(unit, options.base, size, parts, anchored, given);
}

// frames()'s workers, at least 1: `threads` asked for, at most one per frame; by default (0) the
// usable cores, at most one per 4 frames, so that each worker warm-starts along a run of frames
// and a short sequence continues the history of the calls before it as one worker would.
int frame_workers(int threads, size_t frames) {
  const size_t most = threads > 0 ? frames : frames / 4;
  return static_cast<int>(std::max<size_t>(1, std::min<size_t>(threads > 0 ? threads : parallel::usable_cores(), most)));
}

// body(k) for every worker k in [0, workers), each on a thread of its own (the caller runs k = 0):
// a worker's frames take milliseconds each, against tens of microseconds to start a thread, and
// every worker asked for runs (the pool's loops are the frames' insides). Where no thread can be
// started, the caller runs the rest.
template <class Body>
void run_workers(int workers, Body&& body) {
  std::vector<std::thread> threads;
  int started = 1;
  try {
    for (; started < workers; ++started) threads.emplace_back([&body, started] { body(started); });
  } catch (const std::system_error&) {
    for (int k = started; k < workers; ++k) body(k);
  }
  body(0);
  for (std::thread& t : threads) t.join();
}

}  // namespace

Interpolator::Interpolator(const std::vector<Positions>& shapes, const Faces& F, const Anchor& anchor,
                           const InterpolatorOptions& options)
    : num_shapes_(static_cast<int>(shapes.size())), anchor_(anchor), options_(options) {
  if (shapes.empty()) throw InvalidInput("need at least one shape");
  validate_options(options, num_shapes());
  num_vertices_ = static_cast<int>(shapes[0].rows());
  const Mesh mesh(F, num_vertices_);
  validate_anchor(anchor, mesh, num_shapes());
  const std::vector<Positions> unit = normalise(shapes, mesh);
  anchor_.path.position /= scale_;  // only differences of path positions matter (see blend_frames)
  folded_ = check_not_mirrored(mesh, unit, options.base);
  std::vector<Piece> pieces = split_into_pieces(mesh);
  for (size_t k = 0; k < pieces.size(); ++k) {
    const std::vector<Positions> local = local_positions(unit, pieces[k]);
    for (int i = 0; i < num_shapes(); ++i) check_orientation(local[i], pieces[k], i, static_cast<int>(k));
  }
  // An input folds: the method solves the rest of the mesh, the fold region is filled (folds.h).
  std::unique_ptr<const FoldFill> folds;
  std::unique_ptr<const Mesh> cut;
  if (options.folds && std::any_of(folded_.begin(), folded_.end(), [](const std::vector<int>& f) { return !f.empty(); })) {
    folds = std::make_unique<const FoldFill>(mesh, unit, options.base, fold_region(mesh, unit, options.base));
    cut = std::make_unique<const Mesh>(folds->region().rest, num_vertices_);
    pieces = split_into_pieces(*cut);  // fold-free in every input: their orientation is checked
  }
  const bool joined = options.joints && pieces.size() > 1;
  Plans planned = plan_pieces(std::move(pieces), unit, anchor, options.base, joined);
  // The joints read the pieces' meshes and base shapes: before the solvers' plans evict them.
  std::unique_ptr<const Joints> joints =
      join_pieces(planned.plans, unit, base_size_, anchor, options,
                  given_joints(planned.plans, num_vertices_, options, offset_, scale_));
  for (size_t p = 0; p < planned.plans.size(); ++p) {
    planned.plans[p]->plan_solve(planned.local[p], options.base);
    planned.local[p].clear();
    plans_.push_back(std::move(planned.plans[p]));
  }
  workers_.resize(1);
  for (const auto& plan : plans_) workers_[0].push_back(PieceSolver::make(*plan));
  passes_ = std::make_unique<const detail::FramePasses>(cut ? *cut : mesh, unit, std::move(folds), std::move(joints),
                                                        offset_, scale_, options);
}

Interpolator::~Interpolator() = default;

std::vector<Interpolator::JointInfo> Interpolator::joints() const {
  std::vector<JointInfo> out;
  const Joints* joints = passes_->joints();
  auto lowest = [&](int piece) { return *std::min_element(plans_[piece]->piece.vertices.begin(),
                                                          plans_[piece]->piece.vertices.end()); };
  for (int k = 0; joints && k < joints->size(); ++k) {
    const auto [parent, child] = joints->link(k);
    const detail::JointEdge& e = joints->edge(k);
    out.push_back({lowest(parent), lowest(child), (e.point.transpose() * scale_ + offset_).transpose(),
                   joints->pinned(k), e.kind, e.fit});
  }
  return out;
}

std::vector<Interpolator::RootInfo> Interpolator::joint_roots() const {
  std::vector<RootInfo> out;
  const Joints* joints = passes_->joints();
  if (!joints) return out;
  for (const detail::JointRoot& r : joints->roots())
    out.push_back({*std::min_element(plans_[r.piece]->piece.vertices.begin(), plans_[r.piece]->piece.vertices.end()),
                   r.reason, (r.point.transpose() * scale_ + offset_).transpose(), r.fit});
  return out;
}

double Interpolator::joints_seconds() const {
  const Joints* joints = passes_->joints();
  return joints ? joints->seconds() : 0.0;
}

FrameStats Interpolator::solve_frame(const Eigen::VectorXd& w, Eigen::Ref<Positions> out, int worker) {
  FrameInProgress frame{w, out, std::vector<double>(plans_.size()), FrameStats()};
  FrameStats& st = frame.stats;
  st.pieces = static_cast<int>(plans_.size());
  for (size_t p = 0; p < plans_.size(); ++p) {
    const detail::PieceOutcome piece = workers_[worker][p]->solve(w, options_.flatten, anchor_, out);
    merge(st, piece.report);
    st.flatness = std::max(st.flatness, piece.flatness);
    st.hole_closure.insert(st.hole_closure.end(), piece.closure.begin(), piece.closure.end());
    frame.angles[p] = piece.angle;
  }
  passes_->run(frame);
  return st;
}

void Interpolator::blend_into(const Eigen::VectorXd& w, Eigen::Ref<Positions> out) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto t0 = std::chrono::steady_clock::now();
  check_weights(w);
  if (out.rows() != num_vertices()) throw InvalidInput("output has the wrong number of rows");
  const parallel::ThreadLimit limit(options_.threads);
  FrameStats st = solve_frame(w, out, 0);
  st.threads = limit.threads_ran();
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  stats_ = st;
}

FrameStats Interpolator::last_stats() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

void Interpolator::set_threads(int n) {
  const std::lock_guard<std::mutex> lock(mutex_);
  InterpolatorOptions o = options_;
  o.threads = n;
  validate_options(o, num_shapes());
  options_ = o;
}

int Interpolator::threads() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return options_.threads;
}

void Interpolator::forget() {
  const std::lock_guard<std::mutex> lock(mutex_);
  for (auto& worker : workers_)
    for (auto& solver : worker) solver->forget();
}

double Interpolator::floor_seconds(int repeats) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const parallel::ThreadLimit limit(options_.threads);  // factorised as inside a frame
  double total = 0;
  for (size_t p = 0; p < plans_.size(); ++p) {
    Flattener& fl = workers_[0][p]->flattener();
    if (fl.num_interior() == 0) continue;
    fl.assemble_hessian(plans_[p]->l2[options_.base], Eigen::VectorXd::Zero(plans_[p]->piece.mesh.num_vertices()));
    SparseCholesky& chol = *fl.cholesky();
    Eigen::VectorXd b = Eigen::VectorXd::Ones(fl.num_interior()), x(fl.num_interior());
    std::vector<double> times;
    for (int r = 0; r < std::max(repeats, 1); ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      chol.factorize();
      chol.solve(b.data(), x.data());
      times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
    total += times[times.size() / 2];
  }
  return total;
}

Positions Interpolator::blend(const Eigen::VectorXd& w) {
  Positions out(num_vertices(), 2);
  blend_into(w, out);
  return out;
}

Positions Interpolator::at(double t) {
  if (num_shapes() != 2) {
    std::ostringstream s;
    s << "at(t) needs exactly two shapes (have " << num_shapes() << "); use blend(weights)";
    throw InvalidInput(s.str());
  }
  if (!std::isfinite(t)) throw InvalidInput("t must be finite (got " + std::to_string(t) + ")");
  return blend(Eigen::Vector2d(1.0 - t, t));
}

void Interpolator::frames(const std::vector<double>& ts, Eigen::Ref<Positions> out) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto t0 = std::chrono::steady_clock::now();
  if (num_shapes() != 2) throw InvalidInput("frames(ts) needs exactly two shapes");
  const Eigen::Index n = num_vertices();
  if (out.rows() != n * static_cast<Eigen::Index>(ts.size()))
    throw InvalidInput("frames: output must have len(ts) * num_vertices rows");
  for (size_t j = 0; j < ts.size(); ++j)
    if (!std::isfinite(ts[j])) throw InvalidInput("t must be finite (entry " + std::to_string(j) + ")");
  // Contiguous chunks of the sequence, one per worker (each warm-starts along its own chunk); worker 0
  // takes the last chunk so that this Interpolator's warm-start state ends at ts.back().
  const int workers = frame_workers(options_.threads, ts.size());
  prepare_workers(workers);
  std::vector<FrameStats> stats(workers);
  std::vector<std::exception_ptr> errors(workers);
  run_workers(workers, [&](int k) {
    // With several workers, the loops inside a frame stay on their thread (and OpenBLAS on one thread).
    const parallel::ThreadLimit limit(workers > 1 ? 1 : options_.threads);
    const size_t chunk = workers - 1 - k;
    const size_t begin = ts.size() * chunk / workers, end = ts.size() * (chunk + 1) / workers;
    try {
      for (size_t j = begin; j < end; ++j)
        merge(stats[k], solve_frame(Eigen::Vector2d(1.0 - ts[j], ts[j]), out.middleRows(j * n, n), k));
      stats[k].threads = limit.threads_ran();
    } catch (...) {
      errors[k] = std::current_exception();  // rethrown on the calling thread
    }
  });
  for (const auto& e : errors) if (e) std::rethrow_exception(e);
  FrameStats st = stats[0];
  for (int k = 1; k < workers; ++k) merge(st, stats[k]);
  if (workers > 1) st.threads = workers;  // one thread each (their loops stay on it)
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  stats_ = st;
}

void Interpolator::prepare_workers(int workers) {
  // Workers 1, 2, ... start from worker 0's history (the frames before the sequence), with no
  // reusable factorisation of their own.
  while (static_cast<int>(workers_.size()) < workers) {
    workers_.emplace_back();
    for (const auto& plan : plans_) workers_.back().push_back(PieceSolver::make(*plan));
  }
  for (int k = 1; k < workers; ++k)
    for (size_t p = 0; p < plans_.size(); ++p) workers_[k][p]->continue_from(*workers_[0][p]);
}

Eigen::VectorXi piece_labels(const Faces& F, int num_vertices) {
  const Mesh mesh(F, num_vertices);
  std::vector<int> label_of(mesh.num_pieces(), -1);
  Eigen::VectorXi labels(num_vertices);
  int next = 0;
  for (int v = 0; v < num_vertices; ++v) {
    const int p = mesh.piece_of_vertex(v);
    if (p < 0) labels[v] = next++;
    else labels[v] = label_of[p] >= 0 ? label_of[p] : (label_of[p] = next++);
  }
  return labels;
}

}  // namespace bdinterp
