#include "bdinterp/interpolator.h"

#include <algorithm>
#include <dlfcn.h>

#include <chrono>
#include <cmath>
#include <deque>
#include <exception>
#include <sstream>
#include <thread>

#include "bdinterp/holes.h"
#include "bdinterp/layout.h"
#include "bdinterp/metric_blend.h"
#include "bdinterp/orientation.h"
#include "bdinterp/still.h"
#include "bdinterp/parallel.h"

namespace bdinterp {

namespace {

// Solved frames of one piece, for warm starts: the last few (weights, u) pairs, newest first.
struct History {
  static constexpr size_t kSize = 6;
  std::deque<std::pair<Eigen::VectorXd, Eigen::VectorXd>> solved;

  void add(const Eigen::VectorXd& w, const Eigen::VectorXd& u) {
    if (solved.size() == kSize) {
      solved.back().first = w;  // reuse the oldest entry's storage
      solved.back().second = u;
      solved.push_front(std::move(solved.back()));
      solved.pop_back();
    } else {
      solved.emplace_front(w, u);
    }
  }

  // Initial guess for weights w: polynomial extrapolation (degree <= 5) along the line through the
  // nearest solved frame and w, over the solved frames that lie on that line, as long as the
  // extrapolation is well conditioned (sum of |Lagrange weights| <= 80, which admits degree 5 on
  // equally spaced frames: 63); else the nearest solution; zero (exact at the inputs) without
  // history. On a slider the guess is then limited by the earlier solutions' own tolerance rather
  // than by the truncation error (at 5k vertices: geometric-mean residual of the guess 2.4e-9 at
  // degree 3, 6.8e-10 at degree 5; a quarter of the frames need no CG iteration instead of 7 %).
  void predict(const Eigen::VectorXd& w, Eigen::VectorXd& u) const {
    // An input shape's own metric is flat: u = 0 reproduces it exactly, in no step.
    const bool input_shape = (w.array() == 0.0).count() == w.size() - 1;
    if (solved.empty() || input_shape) {
      u.setZero();
      return;
    }
    size_t nearest = 0;
    for (size_t k = 1; k < solved.size(); ++k)
      if ((solved[k].first - w).squaredNorm() < (solved[nearest].first - w).squaredNorm()) nearest = k;
    const Eigen::VectorXd& w0 = solved[nearest].first;
    const Eigen::VectorXd d = w - w0;
    const double dd = d.squaredNorm();
    u = solved[nearest].second;
    if (dd == 0) return;
    // Parameter s along w0 + s d (w at s = 1) of every solved frame on that line.
    std::vector<std::pair<double, size_t>> nodes{{0.0, nearest}};
    for (size_t k = 0; k < solved.size(); ++k) {
      if (k == nearest) continue;
      const Eigen::VectorXd q = solved[k].first - w0;
      const double sk = q.dot(d) / dd;
      if ((q - sk * d).norm() <= 1e-12 * (1.0 + w0.norm()) && std::abs(sk) > 1e-12) nodes.push_back({sk, k});
    }
    std::sort(nodes.begin(), nodes.end(), [](const auto& a, const auto& b) {
      return std::abs(1.0 - a.first) < std::abs(1.0 - b.first);
    });
    for (size_t m = std::min(nodes.size(), kSize); m >= 2; --m) {
      double L[kSize], total = 0;
      for (size_t i = 0; i < m; ++i) {
        L[i] = 1.0;
        for (size_t j = 0; j < m; ++j)
          if (j != i) L[i] *= (1.0 - nodes[j].first) / (nodes[i].first - nodes[j].first);
        total += std::abs(L[i]);
      }
      if (!(total <= 80.0)) continue;
      u = L[0] * solved[nodes[0].second].second;
      for (size_t i = 1; i < m; ++i) u += L[i] * solved[nodes[i].second].second;
      return;
    }
  }
};

// Statistics over several frames: the worst of each measure, the sum of the work done.
void merge(FrameStats& into, const FrameStats& s) {
  into.iterations = std::max(into.iterations, s.iterations);
  into.residual = std::max(into.residual, s.residual);
  into.broken_triangles = std::max(into.broken_triangles, s.broken_triangles);
  into.max_broken_triangles = std::max(into.max_broken_triangles, s.max_broken_triangles);
  into.flatness = std::max(into.flatness, s.flatness);
  into.factorizations += s.factorizations;
  into.chord_steps += s.chord_steps;
  into.pieces = s.pieces;
  into.hole_closure.resize(std::max(into.hole_closure.size(), s.hole_closure.size()), 0.0);
  for (size_t k = 0; k < s.hole_closure.size(); ++k)
    into.hole_closure[k] = std::max(into.hole_closure[k], s.hole_closure[k]);
}

// OpenBLAS runs threads of its own inside CHOLMOD's supernodal solves; next to one worker per core
// they only compete (measured at 50k vertices: parallel frames 1.0x faster with them, 1.24x without).
// While the workers run, OpenBLAS (if it is the BLAS in use) is limited to one thread.
class SingleThreadedBlas {
 public:
  explicit SingleThreadedBlas(bool active) {
    if (!active) return;
    set_ = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    const auto get = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
    if (set_ && get) {
      saved_ = get();
      set_(1);
    } else {
      set_ = nullptr;
    }
  }
  ~SingleThreadedBlas() {
    if (set_) set_(saved_);
  }
  SingleThreadedBlas(const SingleThreadedBlas&) = delete;
  SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;

 private:
  void (*set_)(int) = nullptr;
  int saved_ = 1;
};

}  // namespace

// Everything about one disk-shaped piece of the mesh.
struct Interpolator::PieceSolver {
  // What one thread needs to solve frames of this piece: solvers with their own CHOLMOD workspaces
  // and the warm-start history.
  struct Workspace {
    Flattener* flattener;
    Layout* layout;
    std::unique_ptr<Flattener> own_flattener;
    std::unique_ptr<Layout> own_layout;
    std::unique_ptr<HoleSolver> holes;  // pieces with holes: flattening and layout (holes.h)
    History history;
    Eigen::VectorXd u, l2w;
    Positions X;
  };

  Piece piece;
  std::vector<Eigen::VectorXd> l2;  // per input shape: squared edge lengths
  Flattener flattener;
  Layout layout;
  AnchorFrame anchor;
  std::vector<Frame2> frames;  // per input shape: its anchor
  bool mirrored;               // the base shape is clockwise: lay out counter-clockwise, then reflect
  Workspace main{&flattener, &layout, nullptr, nullptr, nullptr, {}, {}, {}, {}};
  std::vector<std::unique_ptr<Workspace>> extra;  // workers 1, 2, ... of frames()

  Workspace& worker(int k) { return k == 0 ? main : *extra[k - 1]; }

  // still: anchor on the parts that do not move between the inputs (the default anchor, still.h).
  PieceSolver(Piece p, const std::vector<Positions>& local_shapes, int base, int anchor_vertex, bool still)
      : piece(std::move(p)),
        flattener(piece.mesh),
        layout(piece.mesh, /*own_system=*/false),
        anchor(piece.mesh, local_shapes[base], anchor_vertex) {
    const Eigen::VectorXd region = still ? still_region(piece.mesh, anchor, local_shapes, base) : Eigen::VectorXd();
    if (region.size() > 0) anchor.set_region(region);
    for (const Positions& X : local_shapes) {
      l2.push_back(squared_edge_lengths(piece.mesh, X));
      frames.push_back(anchor.measure_input(X));
    }
    const Positions& B = local_shapes[base];
    double area = 0;
    const Faces& F = piece.mesh.faces();
    for (int f = 0; f < F.rows(); ++f) {
      const Eigen::RowVector2d a = B.row(F(f, 1)) - B.row(F(f, 0)), b = B.row(F(f, 2)) - B.row(F(f, 0));
      area += a.x() * b.y() - a.y() * b.x();
    }
    mirrored = area < 0;
    main.u = Eigen::VectorXd::Zero(piece.mesh.num_vertices());
    if (piece.mesh.boundary_loops().size() > 1) main.holes = std::make_unique<HoleSolver>(piece.mesh, B);
  }

  // A workspace for another thread, starting from this one's history and reusable factorisation.
  std::unique_ptr<Workspace> clone_workspace() const {
    auto ws = std::make_unique<Workspace>();
    ws->own_flattener = main.flattener->clone();
    ws->own_layout = main.layout->clone();
    ws->flattener = ws->own_flattener.get();
    ws->layout = ws->own_layout.get();
    if (main.holes) ws->holes = main.holes->clone();
    ws->history = main.history;
    ws->u = Eigen::VectorXd::Zero(piece.mesh.num_vertices());
    return ws;
  }

  void forget() {
    main.history.solved.clear();
    main.flattener->forget();
  }

  FlattenReport solve(Workspace& ws, const Eigen::VectorXd& w, const FlattenOptions& opt,
                      const Anchor& anchor_mode, Eigen::Ref<Positions> out, double* flatness,
                      std::vector<double>& closure) const {
    ws.l2w = blend_squared_lengths(piece.mesh, l2, w);
    ws.history.predict(w, ws.u);
    Positions& X = ws.X;
    FlattenReport rep;
    if (ws.holes) {
      const HolesReport hr = ws.holes->solve(ws.l2w, ws.u, X, opt);
      rep = hr.flatten;
      *flatness = hr.flatness;
      closure.insert(closure.end(), hr.closure.begin(), hr.closure.end());
      ws.history.add(w, ws.u);
    } else {
      rep = ws.flattener->solve(ws.l2w, ws.u, opt);
      ws.history.add(w, ws.u);
      // The layout solves with the flattening's factorised Hessian: no second factor.
      double shift = 0;
      SparseCholesky* W = ws.flattener->num_interior() > 0 ? &ws.flattener->factored_hessian(ws.l2w, ws.u, &shift) : nullptr;
      ws.layout->embed(ws.flattener->flat_squared_lengths(), W, shift, X, flatness);
    }
    if (mirrored) X.col(0) *= -1.0;
    anchor.place(X, blend_frames(frames, w, anchor_mode));
    for (size_t i = 0; i < piece.vertices.size(); ++i) out.row(piece.vertices[i]) = X.row(i);
    return rep;
  }
};

Interpolator::Interpolator(const std::vector<Positions>& shapes, const Faces& F, const Anchor& anchor,
                           const InterpolatorOptions& options)
    : num_shapes_(static_cast<int>(shapes.size())), anchor_(anchor), options_(options) {
  if (shapes.empty()) throw InvalidInput("need at least one shape");
  num_vertices_ = static_cast<int>(shapes[0].rows());
  if (options.base < 0 || options.base >= num_shapes()) {
    std::ostringstream s;
    s << "base shape index " << options.base << " out of range [0, " << num_shapes() << ")";
    throw InvalidInput(s.str());
  }
  const int nv = static_cast<int>(shapes[0].rows());
  const Mesh mesh(F, nv);
  for (int i = 0; i < num_shapes(); ++i) check_shape(mesh, shapes[i], "shape " + std::to_string(i));
  check_orientation(mesh, shapes, options.base);
  for (const Positions& X : shapes) folded_.push_back(bdinterp::folded_faces(mesh, shapes[options.base], X));
  if (anchor.mode != Anchor::Mode::Centroid && anchor.vertex >= 0) {
    if (anchor.vertex >= nv || mesh.is_isolated_vertex(anchor.vertex)) {
      std::ostringstream s;
      s << "anchor vertex " << anchor.vertex << " is " << (anchor.vertex >= nv ? "out of range" : "in no face");
      throw InvalidInput(s.str());
    }
  }
  if (anchor.mode == Anchor::Mode::Vertex && anchor.vertex < 0)
    throw InvalidInput("vertex anchor needs a vertex index");
  if (anchor.mode == Anchor::Mode::Path) {
    const AnchorPath& p = anchor.path;
    if (num_shapes() != 2) throw InvalidInput("an anchor path needs exactly two shapes");
    if (p.t.empty() || p.angle.size() != p.t.size() || p.position.rows() != static_cast<int>(p.t.size()))
      throw InvalidInput("anchor path: t, positions and angles must have the same non-zero length");
    for (size_t k = 1; k < p.t.size(); ++k)
      if (!(p.t[k] > p.t[k - 1])) throw InvalidInput("anchor path: t must be strictly increasing");
    if (!p.position.allFinite()) throw InvalidInput("anchor path: positions must be finite");
  }
  for (int v = 0; v < nv; ++v)
    if (mesh.is_isolated_vertex(v)) isolated_.push_back(v);
  for (const Positions& X : shapes) {
    isolated_positions_.emplace_back(isolated_.size(), 2);
    for (size_t k = 0; k < isolated_.size(); ++k) isolated_positions_.back().row(k) = X.row(isolated_[k]);
  }
  for (Piece& p : split_into_pieces(mesh)) {
    std::vector<Positions> local(shapes.size(), Positions(p.vertices.size(), 2));
    for (size_t i = 0; i < shapes.size(); ++i)
      for (size_t k = 0; k < p.vertices.size(); ++k) local[i].row(k) = shapes[i].row(p.vertices[k]);
    int av = -1;
    if (anchor.vertex >= 0) {
      const auto it = std::find(p.vertices.begin(), p.vertices.end(), anchor.vertex);
      if (it != p.vertices.end()) av = static_cast<int>(it - p.vertices.begin());
    }
    // The default anchor point (also the one an anchor path moves) is the still parts' centroid.
    const bool still = anchor.mode == Anchor::Mode::Centroid || (anchor.mode == Anchor::Mode::Path && anchor.vertex < 0);
    pieces_.push_back(std::make_unique<PieceSolver>(std::move(p), local, options.base, av, still));
  }
}

Interpolator::~Interpolator() = default;

void Interpolator::check_weights(const Eigen::VectorXd& w) const {
  if (w.size() != num_shapes()) {
    std::ostringstream s;
    s << "got " << w.size() << " weights for " << num_shapes() << " shapes";
    throw InvalidInput(s.str());
  }
  if (!w.allFinite()) throw InvalidInput("weights must be finite");
  if (std::abs(w.sum() - 1.0) > 1e-9) {
    std::ostringstream s;
    s.precision(17);
    s << "weights must sum to 1 (they sum to " << w.sum() << ")";
    throw InvalidInput(s.str());
  }
}

void Interpolator::solve_frame(const Eigen::VectorXd& w, Eigen::Ref<Positions> out, int worker,
                               FrameStats& st) {
  st = FrameStats{};
  st.pieces = static_cast<int>(pieces_.size());
  for (auto& p : pieces_) {
    double flat = 0;
    const FlattenReport r = p->solve(p->worker(worker), w, options_.flatten, anchor_, out, &flat, st.hole_closure);
    st.iterations = std::max(st.iterations, r.iterations);
    st.residual = std::max(st.residual, r.residual);
    st.broken_triangles += r.broken_triangles;
    st.max_broken_triangles += r.max_broken_triangles;
    st.flatness = std::max(st.flatness, flat);
    st.factorizations += r.factorizations;
    st.chord_steps += r.chord_steps;
  }
  for (size_t k = 0; k < isolated_.size(); ++k) {
    out.row(isolated_[k]).setZero();
    for (int i = 0; i < num_shapes(); ++i) out.row(isolated_[k]) += w[i] * isolated_positions_[i].row(k);
  }
}

void Interpolator::blend_into(const Eigen::VectorXd& w, Eigen::Ref<Positions> out) {
  const auto t0 = std::chrono::steady_clock::now();
  check_weights(w);
  if (out.rows() != num_vertices()) throw InvalidInput("output has the wrong number of rows");
  FrameStats st;
  const parallel::ThreadLimit limit(threads_);
  solve_frame(w, out, 0, st);
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  stats_ = st;
}

void Interpolator::forget() {
  for (auto& p : pieces_) p->forget();
}

double Interpolator::floor_seconds(int repeats) {
  double total = 0;
  for (auto& p : pieces_) {
    Flattener& fl = *p->main.flattener;
    if (fl.num_interior() == 0) continue;
    const Eigen::VectorXd& l2 = p->l2[options_.base];
    fl.assemble_hessian(l2, Eigen::VectorXd::Zero(p->piece.mesh.num_vertices()));
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
  if (!std::isfinite(t)) throw InvalidInput("t must be finite");
  return blend(Eigen::Vector2d(1.0 - t, t));
}

void Interpolator::frames(const std::vector<double>& ts, Eigen::Ref<Positions> out) {
  const auto t0 = std::chrono::steady_clock::now();
  if (num_shapes() != 2) throw InvalidInput("frames(ts) needs exactly two shapes");
  const Eigen::Index n = num_vertices();
  if (out.rows() != n * static_cast<Eigen::Index>(ts.size()))
    throw InvalidInput("frames: output must have len(ts) * num_vertices rows");
  for (size_t j = 0; j < ts.size(); ++j)
    if (!std::isfinite(ts[j])) throw InvalidInput("t must be finite (entry " + std::to_string(j) + ")");
  // Contiguous chunks of the sequence, one per worker (each warm-starts along its own chunk); worker 0
  // takes the last chunk so that this Interpolator's warm-start state ends at ts.back().
  int workers = threads_ > 0 ? threads_ : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  workers = std::max(1, std::min<int>(workers, static_cast<int>(ts.size() / 4)));
  for (auto& p : pieces_)
    for (int k = 1; k < workers; ++k) p->extra.push_back(p->clone_workspace());
  std::vector<FrameStats> stats(workers);
  std::vector<std::exception_ptr> errors(workers);
  auto run = [&](int k) {
    // One frame per worker: with several workers, the loops inside a frame stay on their thread.
    const parallel::ThreadLimit limit(workers > 1 ? 1 : threads_);
    const size_t chunk = workers - 1 - k;  // worker 0 does the last chunk
    const size_t begin = ts.size() * chunk / workers, end = ts.size() * (chunk + 1) / workers;
    FrameStats st;
    try {
      for (size_t j = begin; j < end; ++j) {
        solve_frame(Eigen::Vector2d(1.0 - ts[j], ts[j]), out.middleRows(j * n, n), k, st);
        merge(stats[k], st);
      }
    } catch (...) {
      errors[k] = std::current_exception();
    }
  };
  {
    const SingleThreadedBlas blas(workers > 1);
    std::vector<std::thread> threads;
    for (int k = 1; k < workers; ++k) threads.emplace_back(run, k);
    run(0);
    for (auto& th : threads) th.join();
  }
  for (auto& p : pieces_) p->extra.clear();
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
  FrameStats st = stats[0];
  for (int k = 1; k < workers; ++k) merge(st, stats[k]);
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  stats_ = st;
}

Positions interpolate(const Positions& source, const Positions& target, const Faces& F, double t,
                      const Anchor& anchor) {
  Interpolator I({source, target}, F, anchor);
  return I.at(t);
}

}  // namespace bdinterp
