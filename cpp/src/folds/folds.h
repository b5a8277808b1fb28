// Folded inputs (reasoning and measurements in docs/FOLDS.md): cut, interpolate,
// fill. The faces an input folds or collapses, with their neighbours (the fold region R), are taken
// out; the rest M' is fold-free and flat in every input, so the method interpolates it as usual
// (exact at the inputs). R is then filled by one Poisson solve whose target gradients are the
// inputs' Jacobians with their rotations replaced by the in-between's (a harmonic field over R), and
// parts of M' that R separates from the main part are turned by the blend of the inputs' rotations
// and placed by that same solve; a few local-global steps then clamp K to the inputs' on the faces
// away from the folds. At an input's weights every step returns the input exactly.
#pragma once

#include <memory>
#include <mutex>
#include <vector>

#include "mesh/mesh.h"

namespace bdinterp {

struct FoldOptions {
  // A face whose signed area in some input is below `shrink` times that in another input joins the
  // region's seed (folded faces: ratio < 0). With folded faces only, the skinned joints of
  // tests/python/test_folds.py left M' connected through faces shrunk to 0.05 .. 0.5, whose length
  // blend made the limb lag (46 deg behind the proportional swing at t = 0.5, then a pop). 0.4: at
  // 0.3 the fill's K excess two rings out reached 65 % (bar, n = 48), at 0.5 the body's sheared
  // torso joined R (K 3x the inputs' there); docs/FOLDS.md.
  double shrink = 0.4;
  // A face whose squared-length blend between two inputs at t = 1/2 would have more than
  // `inflation` times the larger of their areas (a shear [[1, s], [0, 1]] gives sqrt(1 + s^2 / 4):
  // 1.6 at K = 8) seeds the region too, though it does not fold: the method inflated the sheared
  // torso of a skinned body up to 3.99 x; in R the fill keeps it within 1.95 x (docs/FOLDS.md).
  // 1.6: at 1.7 one face went out of range (body, n = 48), at 1.5 K rose 12 % above the inputs'.
  double inflation = 1.6;
  // An interior vertex whose unsigned angle sum in some input is off 2 pi by more than this
  // (radians) is a branch point (the faces around it wrap twice) and seeds the region too.
  double angle_tolerance = 1e-6;
  // The weight (times its area) in the Poisson energy of a face some input folds. Its target
  // gradient passes through a singular matrix between the keys; at full weight it pulls its
  // neighbours along: K 53 % above the inputs' three rings from the folds (bar at n = 48, 160 deg),
  // 0.1 % with 0.2 (docs/FOLDS.md). The keys stay exact for any weight (zero energy there).
  double folded_weight = 0.2;
  // At most this many local-global steps after the fill's Poisson solve (docs/FOLDS.md): each face
  // of R outside two vertex rings of the folds whose K is above the inputs' largest adds (x 2) the
  // change that clamps it to its target, and the factorised system solves again; they stop once
  // no face is above. 0: the Poisson fill only, whose K exceeded the inputs' by 10 % (bar at
  // n = 48, 200 deg); 0.62 % after 10 steps, 0.11 % after 20.
  int fill_iterations = 20;
};

// The fold region of a set of inputs.
struct FoldRegion {
  std::vector<char> in_region;     // #F: 1 for the faces of R
  std::vector<int> faces;          // the faces of R, ascending
  std::vector<int> free_vertices;  // ascending: vertices all of whose faces are in R
  Faces rest;                      // the faces of M' = F \ R (rows of F in ascending order)
  int grown = 0;                   // faces added so that M' has no pinch and its loops turn as in the base
};

// R = the faces incident to a seed vertex (a vertex of a face whose area in some input is below
// options.shrink times that in another, or that the length blend inflates beyond
// options.inflation, or a branch point), grown until M' has no pinched vertex (a vertex whose M' faces form
// more than one fan) and every boundary loop of M' turns by the same total in every input as in
// shapes[base] (otherwise the faces at that loop join R). shapes: the inputs (#V by 2 each).
// R is empty when no input folds, shrinks or shears a face that far. Throws InvalidInput when R takes a whole piece.
FoldRegion fold_region(const Mesh& mesh, const std::vector<Positions>& shapes, int base,
                       const FoldOptions& options = {});

// The growth step of fold_region: adds faces to in_region (#F, 1 = in R) until M' has no pinched
// vertex and its loops turn in every input as in shapes[base]. Nothing changes for an empty R.
void close_region(const Mesh& mesh, const std::vector<Positions>& shapes, int base, std::vector<char>& in_region);

// The fill of a fold region, planned once (read-only afterwards; fill() may be called from any
// thread, the solves are serialised by a mutex of its own).
class FoldFill {
 public:
  // mesh: the whole mesh; shapes: the inputs (#V by 2, the coordinates fill() works in); region from
  // fold_region(mesh, shapes, base). Factorises the two constant systems (harmonic rotations over
  // R's dual graph; the Poisson system of R's free vertices and the separated parts' translations).
  FoldFill(const Mesh& mesh, const std::vector<Positions>& shapes, int base, FoldRegion region,
           const FoldOptions& options = {});
  ~FoldFill();

  const FoldRegion& region() const { return region_; }
  // X (#V by 2): on entry the rows of M's vertices hold the method's frame of M' at weights w (#k,
  // sum 1), every part of M' placed by its own anchor; other rows are ignored. On exit: the parts of
  // M' separated from the main part (the largest of its piece) turned by the blend of the inputs'
  // rotations, and the free vertices and those parts' translations from the Poisson solve and its
  // local-global steps (FoldOptions::fill_iterations).
  // faces, free_vertices (optional): receive the sizes of R and of its free vertices.
  void fill(const Eigen::VectorXd& w, Eigen::Ref<Positions> X, int* faces = nullptr, int* free_vertices = nullptr) const;

 private:
  struct Plan;
  struct Work;
  FoldRegion region_;
  std::unique_ptr<Plan> plan_;
  mutable std::mutex mutex_;
  std::unique_ptr<Work> work_;  // fill()'s buffers (under mutex_)
};

}  // namespace bdinterp
