// The fold region (folds.h): seeds, growth until the rest is a manifold whose loops turn as in the
// base. Reasoning and measurements: docs/FOLDS.md.
#include "folds/folds.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "mesh/geometry.h"
#include "folds/fold_fill.h"

namespace bdinterp {
namespace {
using detail::corner_angle;

// Seed vertices: those of faces whose signed area in some input is below options.shrink times
// that in another (folded faces included: their ratio is negative), and interior vertices whose
// unsigned angle sum in some input is off 2 pi. The ratio between inputs, not to the base, so that
// the region does not depend on which input is the base (with the base's ratio only, the pair
// reversed found 34 faces instead of 78 on the bar at 160 degrees, and its swing lagged).
std::vector<char> seed_vertices(const Mesh& mesh, const std::vector<Positions>& shapes, int base,
                                const FoldOptions& options) {
  const Faces& F = mesh.faces();
  std::vector<char> seed(mesh.num_vertices(), 0);
  // Per face: the least and largest signed area relative to the base (never collapsed: validated).
  Eigen::VectorXd lo = Eigen::VectorXd::Constant(F.rows(), HUGE_VAL), hi = -lo;
  for (const Positions& X : shapes) {
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(mesh.num_vertices());
    for (int f = 0; f < F.rows(); ++f) {
      const double r = doubled_area(X, F, f) / doubled_area(shapes[base], F, f);
      lo[f] = std::min(lo[f], r), hi[f] = std::max(hi[f], r);
      for (int c = 0; c < 3; ++c) sum[F(f, c)] += corner_angle(X, F, f, c);
    }
    for (int v = 0; v < mesh.num_vertices(); ++v)
      if (!mesh.is_boundary_vertex(v) && !mesh.is_isolated_vertex(v) &&
          std::abs(sum[v] - kTwoPi) > options.angle_tolerance)
        seed[v] = 1;
  }
  for (int f = 0; f < F.rows(); ++f)
    if (lo[f] < options.shrink * hi[f] || detail::blend_inflation(shapes, F, f) > options.inflation)
      for (int c = 0; c < 3; ++c) seed[F(f, c)] = 1;
  return seed;
}

Faces rest_faces(const Faces& F, const std::vector<char>& in_region) {
  Faces rest(F.rows() - std::count(in_region.begin(), in_region.end(), 1), 3);
  for (int f = 0, r = 0; f < F.rows(); ++f)
    if (!in_region[f]) rest.row(r++) = F.row(f);
  return rest;
}

// Adds to R the faces of the vertices of every boundary loop of M' whose total turning in some input
// differs from the base's (a loop the input winds around twice, or not at all). True if any.
bool grow_at_loops(const Mesh& mesh, const std::vector<Positions>& shapes, int base, std::vector<char>& in_region) {
  const Faces faces = rest_faces(mesh.faces(), in_region);
  if (faces.rows() == 0) return false;  // nothing left: check_pieces_remain names the piece
  const Mesh rest(faces, mesh.num_vertices());
  std::vector<Eigen::VectorXd> sums;
  for (const Positions& X : shapes) {
    sums.push_back(Eigen::VectorXd::Zero(mesh.num_vertices()));
    for (int f = 0; f < rest.num_faces(); ++f)
      for (int c = 0; c < 3; ++c) sums.back()[rest.faces()(f, c)] += corner_angle(X, rest.faces(), f, c);
  }
  bool grown = false;
  for (const std::vector<int>& loop : rest.boundary_loops()) {
    auto turning = [&](size_t i) {
      double t = 0;
      for (int v : loop) t += kPi - sums[i][v];
      return t;
    };
    bool same = true;
    for (size_t i = 0; i < shapes.size(); ++i) same = same && std::abs(turning(i) - turning(base)) < kPi;
    if (same) continue;
    for (int v : loop)
      for (int f : mesh.vertex_faces(v)) in_region[f] = 1;
    grown = true;
  }
  return grown;
}

void check_pieces_remain(const Mesh& mesh, const std::vector<char>& in_region) {
  std::vector<int> left(mesh.num_pieces(), 0);
  for (int f = 0; f < mesh.num_faces(); ++f) left[mesh.piece_of_face(f)] += !in_region[f];
  for (int p = 0; p < mesh.num_pieces(); ++p) {
    if (left[p] > 0) continue;
    int v = -1;
    for (int f = 0; f < mesh.num_faces() && v < 0; ++f)
      if (mesh.piece_of_face(f) == p) v = mesh.faces()(f, 0);
    std::ostringstream s;
    s << "the inputs fold or shrink (below half the base area) the faces of piece " << p
      << " (the piece of this vertex) everywhere: no fold-free part is left to interpolate";
    throw InvalidInput(Where::of_vertex(v), s.str());
  }
}

}  // namespace

void close_region(const Mesh& mesh, const std::vector<Positions>& shapes, int base, std::vector<char>& in_region) {
  const auto outside = [&](int f) { return !in_region[f]; };
  for (bool changed = std::count(in_region.begin(), in_region.end(), 1) > 0; changed;) {
    changed = false;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (mesh.one_fan_at(v, outside)) continue;  // v's faces outside R are not pinched into two fans
      for (int f : mesh.vertex_faces(v)) in_region[f] = 1;
      changed = true;
    }
    if (!changed) changed = grow_at_loops(mesh, shapes, base, in_region);
  }
}

FoldRegion fold_region(const Mesh& mesh, const std::vector<Positions>& shapes, int base, const FoldOptions& options) {
  const Faces& F = mesh.faces();
  const std::vector<char> seed = seed_vertices(mesh, shapes, base, options);
  FoldRegion r;
  r.in_region.assign(F.rows(), 0);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (seed[v])
      for (int f : mesh.vertex_faces(v)) r.in_region[f] = 1;
  const long seeded = std::count(r.in_region.begin(), r.in_region.end(), 1);
  close_region(mesh, shapes, base, r.in_region);
  check_pieces_remain(mesh, r.in_region);
  for (int f = 0; f < F.rows(); ++f)
    if (r.in_region[f]) r.faces.push_back(f);
  r.grown = static_cast<int>(r.faces.size() - seeded);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    bool all = mesh.vertex_faces(v).size() > 0;
    for (int f : mesh.vertex_faces(v)) all = all && r.in_region[f];
    if (all) r.free_vertices.push_back(v);
  }
  r.rest = rest_faces(F, r.in_region);
  return r;
}

// See detail/folds.h: the fill's sheared components (docs/FOLDS.md).
std::vector<char> detail::smooth_faces(const Mesh& mesh, const std::vector<Positions>& shapes, const FoldRegion& region,
                               const std::vector<char>& unfolded, const FoldOptions& options) {
  const Faces& F = mesh.faces();
  std::vector<char> out(F.rows(), 0);
  std::vector<int> comp(F.rows(), -1);
  for (int f0 : region.faces) {
    if (comp[f0] >= 0) continue;
    std::vector<int> members{f0};
    comp[f0] = f0;
    bool sheared = false;
    for (size_t k = 0; k < members.size(); ++k) {
      const int f = members[k];
      sheared = sheared || (unfolded[f] && detail::blend_inflation(shapes, F, f) > options.inflation);
      for (int c = 0; c < 3; ++c) {
        const int g = mesh.opposite_face(mesh.face_edges()(f, c), f);
        if (g >= 0 && region.in_region[g] && comp[g] < 0) comp[g] = f0, members.push_back(g);
      }
    }
    for (int f : members) out[f] = sheared && unfolded[f];
  }
  return out;
}

}  // namespace bdinterp
