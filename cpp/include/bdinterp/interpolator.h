// The stateful tier: precompute once per mesh (topology, pieces, symbolic factorisations, the inputs'
// squared edge lengths and anchors), then produce in-betweens for any t or weights.
#pragma once

#include <memory>
#include <vector>

#include "bdinterp/anchor.h"
#include "bdinterp/flatten.h"

namespace bdinterp {

struct InterpolatorOptions {
  FlattenOptions flatten;
  int base = 0;  // which shape is the domain S0 of the maps (paper Sec. 5); any input may be
};

// Statistics of the last computed frame (over all pieces).
struct FrameStats {
  int iterations = 0;            // Newton steps (the most over pieces)
  double residual = 0;           // max |2pi - angle sum| at interior vertices
  int broken_triangles = 0;      // faces violating the triangle inequality at the solution
  int max_broken_triangles = 0;  // the most seen during Newton
  double flatness = 0;           // layout residual, see Layout::embed
  int pieces = 0;
  int factorizations = 0;        // numeric Cholesky factorisations (summed over pieces)
  int chord_steps = 0;           // Newton steps that reused an earlier factorisation (summed)
  double seconds = 0;            // wall-clock time of the frame in C++
  // Per hole (inner boundary loop, pieces in order): the translation period of the flat metric
  // around it relative to the loop's length, which the layout spreads (see holes.h); 0 at inputs.
  std::vector<double> hole_closure;
};

// Not thread-safe: one Interpolator per thread (frames() parallelises internally).
class Interpolator {
 public:
  // shapes: k >= 1 arrays of #V by 2 positions with the connectivity F (#F by 3). Validates everything
  // (throws InvalidInput): sizes, indices, manifoldness, disk pieces, finite coordinates, no collapsed
  // faces in any shape, anchor vertex in range; pieces may have holes (holes.h). Vertices in no face are blended linearly.
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
  // metric stays valid.
  Positions at(double t);
  // k shapes: the bounded-distortion blend for weights w (#k, sum 1; negative entries extrapolate).
  Positions blend(const Eigen::VectorXd& w);
  // Writes frame j (weights (1 - ts[j], ts[j])) into rows [j #V, (j + 1) #V) of out ((#ts #V) by 2).
  // The sequence is cut into contiguous chunks solved in parallel (see set_threads); each frame is
  // warm-started from the frames before it in its chunk. Afterwards last_stats() aggregates over
  // all frames: the largest iterations/residual/flatness, summed factorisations and chord steps,
  // and the wall-clock seconds of the whole call.
  void frames(const std::vector<double>& ts, Eigen::Ref<Positions> out);
  void blend_into(const Eigen::VectorXd& w, Eigen::Ref<Positions> out);

  const FrameStats& last_stats() const { return stats_; }

  // Drops every cached solution (warm-start history, reusable factorisations): the next frame is
  // computed cold, from nothing but the symbolic analysis. For benchmarks and reproducibility.
  void forget();
  // Benchmark floor: median wall-clock seconds (over `repeats`) of one numeric factorisation plus one
  // solve of the interior cotan Laplacian of the base shape, summed over pieces (symbolic analysis
  // reused). Leaves the warm-start history untouched but invalidates reusable factorisations.
  double floor_seconds(int repeats = 5);
  // Threads to use: frames() splits a sequence over this many workers (never more than one per 4
  // frames), and a single frame splits its face loops over this many threads. 0 (default) = one per
  // core, 1 = sequential.
  void set_threads(int n) { threads_ = n; }
  int threads() const { return threads_; }

 private:
  struct PieceSolver;
  void check_weights(const Eigen::VectorXd& w) const;
  void solve_frame(const Eigen::VectorXd& w, Eigen::Ref<Positions> out, int worker, FrameStats& st);

  int num_shapes_ = 0, num_vertices_ = 0;
  Anchor anchor_;
  InterpolatorOptions options_;
  std::vector<std::unique_ptr<PieceSolver>> pieces_;
  std::vector<int> isolated_;
  std::vector<std::vector<int>> folded_;  // per shape: folded_faces
  std::vector<Positions> isolated_positions_;  // per shape: the isolated vertices' positions
  FrameStats stats_;
  int threads_ = 0;  // 0: hardware concurrency
};

// One-off: interpolate between two shapes at t (builds and discards an Interpolator).
Positions interpolate(const Positions& source, const Positions& target, const Faces& F, double t,
                      const Anchor& anchor = {});

}  // namespace bdinterp
