#include "bdinterp/interpolator.h"

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <exception>
#include <sstream>
#include <thread>

#include "bdinterp/folds.h"
#include "bdinterp/geometry.h"
#include "bdinterp/holes.h"
#include "bdinterp/joints.h"
#include "bdinterp/layout.h"
#include "bdinterp/metric_blend.h"
#include "bdinterp/orientation.h"
#include "bdinterp/still.h"
#include "bdinterp/parallel.h"
#include "bdinterp/rigid_motion.h"
#include "detail/validation.h"
#include "detail/warm_start.h"

namespace bdinterp {
namespace {
using detail::check_orientation;
using detail::validate_anchor;
using detail::validate_options;
using detail::weights_text;

// Frames merged: the flattening's reports by their one rule, the worst flatness, the first warning.
void merge(FrameStats& into, const FrameStats& s) {
  merge(static_cast<FlattenReport&>(into), s);
  into.flatness = std::max(into.flatness, s.flatness);
  into.pieces = s.pieces;  // these are the same for every frame of an Interpolator
  into.fold_faces = s.fold_faces, into.fold_free_vertices = s.fold_free_vertices, into.joints = s.joints;
  into.converged = into.converged && s.converged;
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

}  // namespace

// Everything about one disk-shaped piece that does not change: read-only, shared by the workers.
struct Interpolator::PiecePlan {
  Piece piece;
  std::vector<Eigen::VectorXd> l2;  // per input shape: squared edge lengths
  std::shared_ptr<const FlattenPlan> flatten;
  std::shared_ptr<const LayoutPlan> layout;
  AnchorFrame anchor;
  std::vector<Frame2> frames;  // per input shape: its anchor
  bool mirrored;               // the base shape is clockwise: lay out counter-clockwise, then reflect
  std::unique_ptr<const HoleSolver> holes;  // pieces with holes: flattening and layout (holes.h)
  int geodesic_base = -1;      // blend_frames: the anchor on the motions' geodesic from this input

  // still: anchor on the parts that do not move between the inputs (still.h): the default anchor,
  // also the point an anchor path without a vertex moves.
  PiecePlan(Piece p, const std::vector<Positions>& local_shapes, int base, int anchor_vertex, bool still)
      : piece(std::move(p)),
        flatten(std::make_shared<const FlattenPlan>(piece.mesh)),
        layout(std::make_shared<const LayoutPlan>(piece.mesh)),
        anchor(piece.mesh, local_shapes[base], anchor_vertex),
        mirrored(doubled_total_area(local_shapes[base], piece.mesh.faces()) < 0) {
    if (piece.mesh.boundary_loops().size() > 1) holes = std::make_unique<const HoleSolver>(piece.mesh, local_shapes[base]);
    const Eigen::VectorXd region = still ? still_region(piece.mesh, anchor, local_shapes, base) : Eigen::VectorXd();
    if (region.size() > 0) anchor.set_region(region);
    for (const Positions& X : local_shapes) {
      l2.push_back(squared_edge_lengths(piece.mesh, X));
      frames.push_back(anchor.measure_input(X));
    }
    // The default anchor (and a path's point) moves on the geodesic of the rigid motions; the
    // paper's vertex anchor keeps its linear blend; a whole turn with a shift has none (rigid_motion.h).
    if (still && anchor_vertex < 0 && has_geodesic(frames, base)) geodesic_base = base;
  }
};

// What one thread needs to solve frames of one piece: solvers with their own CHOLMOD workspaces
// and the warm-start history.
struct Interpolator::Workspace {
  explicit Workspace(const PiecePlan& p)
      : flattener(p.flatten), layout(p.layout, /*own_system=*/false),
        holes(p.holes ? p.holes->clone() : nullptr), u(Eigen::VectorXd::Zero(p.piece.mesh.num_vertices())) {}

  void forget() {
    history.solved.clear();
    flattener.forget();
    if (holes) holes->forget();
  }

  // The piece's frame at weights w into its rows of out (normalised coordinates).
  FlattenReport solve(const PiecePlan& p, const Eigen::VectorXd& w, const FlattenOptions& opt,
                      const Anchor& anchor_mode, Eigen::Ref<Positions> out, double* flatness,
                      std::vector<double>& closure) {
    l2w = blend_squared_lengths(p.piece.mesh, p.l2, w);
    history.predict(w, u);
    const FlattenReport rep = holes ? holes->solve(l2w, u, X, opt, flatness, closure) : solve_disk(w, opt, flatness);
    if (holes) history.add(w, u);
    if (p.mirrored) X.col(0) *= -1.0;
    const Frame2 frame = blend_frames(p.frames, w, anchor_mode, p.geodesic_base);
    angle = frame.angle;
    p.anchor.place(X, frame);
    for (size_t i = 0; i < p.piece.vertices.size(); ++i) out.row(p.piece.vertices[i]) = X.row(i);
    return rep;
  }

  // Steps 2 and 3 on a disk into X.
  FlattenReport solve_disk(const Eigen::VectorXd& w, const FlattenOptions& opt, double* flatness) {
    const bool cold = u.isZero(0.0) && !flattener.has_reusable_factorization();
    FlattenReport rep = flattener.solve(l2w, u, opt);
    if (rep.broken_triangles > 0 && !cold) {
      // Broken triangles at the solution: the energy is not strictly convex there and the point
      // reached depends on the start. Solve again as a fresh Interpolator would, so the frame does
      // not depend on the frames before it, and keep it out of the warm-start history.
      flattener.forget();
      u.setZero();
      const FlattenReport warm = rep;
      rep = flattener.solve(l2w, u, opt);
      rep.factorizations += warm.factorizations;
      rep.chord_steps += warm.chord_steps;
      rep.line_search_steps += warm.line_search_steps;
    }
    if (rep.broken_triangles == 0) history.add(w, u);
    // The layout solves with the flattening's factorised Hessian: no second factor. Unless that
    // factorisation needed a diagonal shift (a singular Hessian, e.g. broken triangles around a
    // vertex): refining a shifted singular system fails (frames 40 % off), so the uniform Laplacian.
    double shift = 0;
    SparseCholesky* W = flattener.num_interior() > 0 ? &flattener.factored_hessian(l2w, u, &shift) : nullptr;
    if (shift > 0) {
      layout.ensure_own_system();
      layout.embed(flattener.flat_squared_lengths(), X, flatness);
    } else {
      layout.embed(flattener.flat_squared_lengths(), W, shift, X, flatness);
    }
    return rep;
  }

  Flattener flattener;
  Layout layout;
  std::unique_ptr<HoleSolver> holes;
  detail::History history;
  Eigen::VectorXd u, l2w;
  Positions X;
  double angle = 0;  // the anchor angle of the last frame (the joints turn children from it)
};

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
  std::unique_ptr<const Mesh> cut;
  if (options.folds && std::any_of(folded_.begin(), folded_.end(), [](const std::vector<int>& f) { return !f.empty(); })) {
    folds_ = std::make_unique<const FoldFill>(mesh, unit, options.base, fold_region(mesh, unit, options.base));
    cut = std::make_unique<const Mesh>(folds_->region().rest, num_vertices_);
    pieces = split_into_pieces(*cut);  // fold-free in every input: their orientation is checked
  }
  for (int v = 0; v < num_vertices_; ++v)
    if ((cut ? *cut : mesh).is_isolated_vertex(v)) isolated_.push_back(v);
  for (const Positions& X : unit) {
    isolated_positions_.emplace_back(isolated_.size(), 2);
    for (size_t k = 0; k < isolated_.size(); ++k) isolated_positions_.back().row(k) = X.row(isolated_[k]);
  }
  workers_.resize(1);
  const bool still = anchor.mode == Anchor::Mode::Centroid || (anchor.mode == Anchor::Mode::Path && anchor.vertex < 0);
  for (Piece& p : pieces) {
    const std::vector<Positions> local = local_positions(unit, p);
    const auto it = std::find(p.vertices.begin(), p.vertices.end(), anchor.vertex);
    const int av = anchor.vertex >= 0 && it != p.vertices.end() ? static_cast<int>(it - p.vertices.begin()) : -1;
    plans_.push_back(std::make_unique<const PiecePlan>(std::move(p), local, options.base, av, still));
    workers_[0].push_back(std::make_unique<Workspace>(*plans_.back()));
  }
  if (options.joints && plans_.size() > 1) {
    std::vector<JointPiece> parts;
    int anchored = -1;  // the piece of a vertex anchor roots its group, so the anchor holds
    for (const auto& p : plans_) {
      const auto& vs = p->piece.vertices;
      if (anchor.vertex >= 0 && std::find(vs.begin(), vs.end(), anchor.vertex) != vs.end())
        anchored = static_cast<int>(parts.size());
      parts.push_back({&vs, &p->piece.mesh.faces(), &p->frames});
    }
    joints_ = std::make_unique<const Joints>(unit, options.base, parts, anchored);
  }
}

Interpolator::~Interpolator() = default;

std::vector<Interpolator::JointInfo> Interpolator::joints() const {
  std::vector<JointInfo> out;
  auto lowest = [&](int piece) { return *std::min_element(plans_[piece]->piece.vertices.begin(),
                                                          plans_[piece]->piece.vertices.end()); };
  for (int k = 0; joints_ && k < joints_->size(); ++k) {
    const auto [parent, child] = joints_->link(k);
    out.push_back({lowest(parent), lowest(child), (joints_->point(k).transpose() * scale_ + offset_).transpose(),
                   joints_->pinned(k)});
  }
  return out;
}

FrameStats Interpolator::solve_frame(const Eigen::VectorXd& w, Eigen::Ref<Positions> out, int worker) {
  FrameStats st;
  st.pieces = static_cast<int>(plans_.size());
  std::vector<double> angles(plans_.size());
  for (size_t p = 0; p < plans_.size(); ++p) {
    double flat = 0;
    merge(st, workers_[worker][p]->solve(*plans_[p], w, options_.flatten, anchor_, out, &flat, st.hole_closure));
    st.flatness = std::max(st.flatness, flat);
    angles[p] = workers_[worker][p]->angle;
  }
  if (joints_) {
    joints_->apply(w, angles, out);
    st.joints = joints_->size();
  }
  for (size_t k = 0; k < isolated_.size(); ++k) {
    out.row(isolated_[k]).setZero();
    for (int i = 0; i < num_shapes(); ++i) out.row(isolated_[k]) += w[i] * isolated_positions_[i].row(k);
  }
  if (folds_) folds_->fill(w, out, &st.fold_faces, &st.fold_free_vertices);
  // Back to the caller's coordinates, checking that every position is finite on the way.
  bool finite = true;
  for (Eigen::Index v = 0; v < out.rows(); ++v) {
    const double x = out(v, 0) * scale_ + offset_[0], y = out(v, 1) * scale_ + offset_[1];
    out(v, 0) = x;
    out(v, 1) = y;
    finite &= std::abs(x) <= DBL_MAX && std::abs(y) <= DBL_MAX;
  }
  if (!finite) throw SolverError("the frame at weights " + weights_text(w) + " is not finite");
  self_check(st, w);
  return st;
}

void Interpolator::blend_into(const Eigen::VectorXd& w, Eigen::Ref<Positions> out) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto t0 = std::chrono::steady_clock::now();
  check_weights(w);
  if (out.rows() != num_vertices()) throw InvalidInput("output has the wrong number of rows");
  const parallel::ThreadLimit limit(options_.threads);
  FrameStats st = solve_frame(w, out, 0);
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
    for (auto& ws : worker) ws->forget();
}

double Interpolator::floor_seconds(int repeats) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const parallel::ThreadLimit limit(options_.threads);  // factorised as inside a frame
  double total = 0;
  for (size_t p = 0; p < plans_.size(); ++p) {
    Flattener& fl = workers_[0][p]->flattener;
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
  const int threads = options_.threads;
  int workers = threads > 0 ? threads : parallel::usable_cores();
  workers = std::max(1, std::min<int>(workers, static_cast<int>(ts.size() / 4)));
  prepare_workers(workers);
  std::vector<FrameStats> stats(workers);
  std::vector<std::exception_ptr> errors(workers);
  auto run = [&](int k) {
    // One frame per worker: with several workers, the loops inside a frame stay on their thread (and
    // OpenBLAS on one thread, held by the workers together).
    const parallel::ThreadLimit limit(workers > 1 ? 1 : threads);
    const size_t chunk = workers - 1 - k;  // worker 0 does the last chunk
    const size_t begin = ts.size() * chunk / workers, end = ts.size() * (chunk + 1) / workers;
    try {
      for (size_t j = begin; j < end; ++j)
        merge(stats[k], solve_frame(Eigen::Vector2d(1.0 - ts[j], ts[j]), out.middleRows(j * n, n), k));
    } catch (...) {
      errors[k] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (int k = 1; k < workers; ++k) pool.emplace_back(run, k);
  run(0);
  for (auto& th : pool) th.join();
  for (const auto& e : errors) if (e) std::rethrow_exception(e);
  FrameStats st = stats[0];
  for (int k = 1; k < workers; ++k) merge(st, stats[k]);
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  stats_ = st;
}

void Interpolator::prepare_workers(int workers) {
  // Workers 1, 2, ... start from worker 0's history (the frames before the sequence), with no
  // reusable factorisation of their own.
  while (static_cast<int>(workers_.size()) < workers) {
    workers_.emplace_back();
    for (const auto& plan : plans_) workers_.back().push_back(std::make_unique<Workspace>(*plan));
  }
  for (int k = 1; k < workers; ++k) {
    for (size_t p = 0; p < plans_.size(); ++p) {
      workers_[k][p]->forget();
      workers_[k][p]->history = workers_[0][p]->history;
    }
  }
}

}  // namespace bdinterp
