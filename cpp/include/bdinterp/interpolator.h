// The stateful tier: precompute once per mesh (topology, pieces, symbolic factorisations, the inputs'
// squared edge lengths and anchors), then produce in-betweens for any t or weights.
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "bdinterp/anchor.h"
#include "bdinterp/flatten_options.h"

namespace bdinterp {

class Mesh;  // mesh.h (private)
namespace detail {
struct PiecePlan;    // piece_solver.h
class PieceSolver;   // piece_solver.h
class FramePasses;   // frame_passes.h
}  // namespace detail

// How a joint holds a child piece to its parent (docs/JOINTS.md): Pin, the child turns against its
// parent about one point inside both pieces in every input; Glued, the child moves with its parent
// (no relative motion in any input); Slide, it slides over its parent without turning against it
// (an eye over a head); Given, a joint of InterpolatorOptions::joint_links.
enum class JointKind { Pin, Glued, Slide, Given };
// Why a piece roots its tree of joints: it holds the vertex anchor; it is still; it only travels
// (no turn); its own motion is a turn about a point inside or near it (the best of its tree); no
// given link holds it; a given link gives its path (JointLink with parent_vertex -1).
enum class RootReason { Anchor, Still, Travels, Turns, Given, Path };

// A joint the caller gives, e.g. a bone of an armature: the piece holding child_vertex hangs from
// the piece holding parent_vertex at `point` (the base shape, caller's coordinates). parent_vertex
// -1: the piece is a root whose `point` travels on the chord between the inputs, turning by its
// blended angle (a root bone's path: offset and angle blended).
struct JointLink {
  int parent_vertex = -1, child_vertex = -1;
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
};

struct InterpolatorOptions {
  FlattenOptions flatten;
  int base = 0;  // which shape is the domain S0 of the maps (paper Sec. 5); any input may be
  // Threads: frames() splits a sequence over this many workers, each on a thread of its own (at
  // most one per frame), and a single frame splits its face loops over up to this many threads
  // (the usable cores at most). 0 = one per usable core (frames(): at most one per 4 frames),
  // 1 = sequential; at most kMaxThreads.
  int threads = 0;
  // The self-check of every frame: the layout's flatness (see Layout::embed) must be at most
  // max_flatness (a converged frame measures 1e-13 .. 1e-9) and the flattened metric must have no
  // broken triangles. A frame failing it is flagged in FrameStats (converged = false, warnings);
  // with `strict` it raises SolverError instead of being returned.
  double max_flatness = 1e-6;
  bool strict = false;
  // Inputs with folded faces (orientation.h): the method solves the mesh without their fold region,
  // which is filled in (folds.h, docs/FOLDS.md), so the folded keys are reached. false: the paper's
  // method on the whole mesh (the keys' folded metric is flattened too, so folded keys are missed).
  bool folds = true;
  // Cut-out characters (joints.h, docs/JOINTS.md): pieces that overlap in the base shape and are
  // held by a pin or glued (found from the inputs' relative motions) stay joined, each child placed
  // by its parent. false: every piece placed on its own.
  bool joints = true;
  // Non-empty (and joints on): the tree of joints as given, one link per child piece, instead of
  // the joints found; InvalidInput for a vertex in no piece, a link within one piece, a piece with
  // two parents or a cycle (naming the link).
  std::vector<JointLink> joint_links;
  static constexpr int kMaxThreads = 1024;
};

// Statistics of the last computed frame or sequence: the flattening's report merged over pieces and
// frames by the one rule of merge(FlattenReport&, ...) (the worst state, the sum of the work), and:
struct FrameStats : FlattenReport {
  double flatness = 0;    // the largest layout residual, see Layout::embed
  int pieces = 0;
  double seconds = 0;     // wall-clock time of the call in C++
  bool converged = true;  // every frame passed the self-check (see InterpolatorOptions)
  std::string warnings;   // why not, naming the first failing frame; empty when converged
  // Per hole (inner boundary loop, pieces in order): the translation period of the flat metric
  // around it relative to the loop's length, which the layout spreads (see holes.h); 0 at inputs.
  std::vector<double> hole_closure;
  // Folded inputs (folds.h): the faces of the fold region and its free vertices (0 when no input folds).
  int fold_faces = 0;
  int fold_free_vertices = 0;
  int joints = 0;  // joints between pieces (joints.h); 0 when InterpolatorOptions::joints is off
  // The threads that ran: frames()'s workers when it had several (a thread each), else the most
  // threads one loop of a frame ran on (1 when serial, e.g. while the machine is busy).
  int threads = 0;
};

// No hidden state: a frame depends on its weights, not on the calls before it: with the default
// options frames after any history equal a fresh Interpolator's to 1e-12 of the size (measured
// 2e-14; the flattening refines below its tolerance, FlattenOptions::refinement), except where the
// frame itself is that ill-conditioned (docs/robustness.md). Frames whose flattening ends with
// broken triangles are solved cold.
// Thread safety: every public member may be called from any thread; calls on one Interpolator are
// serialised by a mutex of its own (one call at a time; frames() parallelises internally). From
// Python the bindings release the GIL before taking it, so the two locks cannot deadlock.
class Interpolator {
 public:
  // shapes: k >= 1 arrays of #V by 2 positions with the connectivity F (#F by 3). Validates everything
  // (throws InvalidInput): sizes, indices, manifoldness, pieces with boundary, finite coordinates, no collapsed
  // faces in any shape, signed face areas that do not cancel, no mirror image of the base (orientation.h), the anchor
  // and the options; pieces may have holes (holes.h). Vertices
  // in no face are blended linearly. Coordinates of any magnitude (1e-150 .. 1e150) are solved
  // alike: the shapes are moved and scaled (by a power of two) to unit size inside.
  Interpolator(const std::vector<Positions>& shapes, const Faces& F, const Anchor& anchor = {},
               const InterpolatorOptions& options = {});
  ~Interpolator();
  Interpolator(const Interpolator&) = delete;
  Interpolator& operator=(const Interpolator&) = delete;

  int num_shapes() const { return num_shapes_; }
  int num_vertices() const { return num_vertices_; }
  // Faces (ascending) of input `shape` folded relative to the base shape (orientation.h); empty for
  // the base. Inputs with more than half of a piece's faces folded are refused as mirror images.
  const std::vector<int>& folded_faces(int shape) const { return folded_.at(shape); }

  // Two shapes: the in-between at t (weights (1 - t, t)); t outside [0, 1] extrapolates while the
  // metric stays valid. InvalidInput for a non-finite t.
  Positions at(double t);
  // k shapes: the bounded-distortion blend for weights w (#k, sum 1; negative entries extrapolate).
  Positions blend(const Eigen::VectorXd& w);
  // Writes frame j (weights (1 - ts[j], ts[j])) into rows [j #V, (j + 1) #V) of out ((#ts #V) by 2).
  // The sequence is cut into contiguous chunks, one per worker, each on a thread of its own (see
  // InterpolatorOptions::threads); each frame is warm-started from the frames before it in its
  // chunk. Afterwards last_stats() merges all frames, with the wall-clock seconds of the whole call.
  void frames(const std::vector<double>& ts, Eigen::Ref<Positions> out);
  void blend_into(const Eigen::VectorXd& w, Eigen::Ref<Positions> out);

  FrameStats last_stats() const;

  // Drops every cached solution (warm-start history, reusable factorisations): the next frame is
  // computed cold, from nothing but the symbolic analysis. For benchmarks and reproducibility.
  void forget();
  // Benchmark floor: median wall-clock seconds (over `repeats`) of one numeric factorisation plus one
  // solve of the interior cotan Laplacian of the base shape, summed over pieces (symbolic analysis
  // reused), with the thread settings of a frame. Leaves the warm-start history untouched but
  // invalidates reusable factorisations.
  double floor_seconds(int repeats = 5);
  // Sets options().threads (InvalidInput outside [0, kMaxThreads]) for the calls after it: for C++
  // benchmarks and fuzzers. Python's `threads` property is read-only (threads= of the constructor).
  void set_threads(int n);
  int threads() const;
  const InterpolatorOptions& options() const { return options_; }

  // A joint between two pieces (InterpolatorOptions::joints, joints.h): the pieces by their lowest
  // vertex, the joint point in the base shape (caller's coordinates), its kind, whether it is a
  // pin (both pieces carry the point to one place in every input, to 0.1 % of the size) and fit:
  // that largest gap over the inputs relative to the size (for Glued: the largest relative motion).
  struct JointInfo {
    int parent_vertex, child_vertex;
    Eigen::Vector2d point;
    bool pin;
    JointKind kind;
    double fit;
  };
  // The joints, parents before children; empty when joints are off or no piece is joined.
  std::vector<JointInfo> joints() const;
  // The root of every tree of joints (a piece in no joint is a tree of its own): the piece by its
  // lowest vertex, why it is the root, and for RootReason::Turns the fixed point of its own motion
  // (caller's coordinates) and its rank (distance outside the piece / (Joints' reach x its size)
  // + its largest turn / pi). Empty when joints are off.
  struct RootInfo {
    int vertex;
    RootReason reason;
    Eigen::Vector2d point;
    double rank;
  };
  std::vector<RootInfo> joint_roots() const;
  // Wall-clock seconds the joints took when the Interpolator was made (the tree found or the
  // given links checked, each joint's sites and offsets); 0 when joints are off. For benchmarks.
  double joints_seconds() const;

 private:
  // The shapes moved and scaled to unit size (sets offset_, scale_ and base_size_), validated.
  std::vector<Positions> normalise(const std::vector<Positions>& shapes, const Mesh& mesh);
  void check_weights(const Eigen::VectorXd& w) const;
  // Solvers for `workers` workers, workers 1, 2, ... continuing from worker 0's history.
  void prepare_workers(int workers);
  // One frame into out (in the caller's coordinates): every piece, then the frame passes; `worker`
  // selects the piece solvers.
  FrameStats solve_frame(const Eigen::VectorXd& w, Eigen::Ref<Positions> out, int worker);

  int num_shapes_ = 0, num_vertices_ = 0;
  Anchor anchor_;  // in the normalised frame
  InterpolatorOptions options_;
  Eigen::RowVector2d offset_;  // caller's = scale_ * normalised + offset_
  double scale_ = 1;
  double base_size_ = 0;  // the normalised base shape's bounding box diagonal
  std::vector<std::unique_ptr<const detail::PiecePlan>> plans_;
  // workers_[k][p]: worker k's solver of piece p (worker 0 serves at/blend and keeps history).
  std::vector<std::vector<std::unique_ptr<detail::PieceSolver>>> workers_;
  std::vector<std::vector<int>> folded_;  // per shape: folded_faces
  std::unique_ptr<const detail::FramePasses> passes_;  // joints, isolated vertices, fold fill, ...
  FrameStats stats_;
  mutable std::mutex mutex_;
};

// (#V) the piece of every vertex as Interpolator splits the mesh (faces joined through shared
// edges), numbered 0, 1, ... in order of each piece's lowest vertex; a vertex in no face is a piece
// of its own. Throws InvalidInput as the Interpolator does for its mesh: no vertices or no faces, an
// index outside [0, num_vertices), a face repeating a vertex, a non-manifold mesh.
Eigen::VectorXi piece_labels(const Faces& F, int num_vertices);

}  // namespace bdinterp
