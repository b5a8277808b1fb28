// The fill of a fold region (folds.h): rotations lifted across the dual graph and extended
// harmonically over R, separated parts turned by the blend of the inputs' rotations, one Poisson
// solve for R's free vertices and those parts' translations, local-global steps that clamp K.
// Reasoning: docs/FOLDS.md.
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <deque>
#include <limits>
#include <functional>
#include <utility>

#include "folds/folds.h"
#include "mesh/geometry.h"
#include "linalg/sparse_cholesky.h"
#include "folds/fold_fill.h"
#include "mesh/turns.h"

namespace bdinterp {
namespace {
using detail::clamp_change;
using detail::distortion;
using detail::face_jacobian;
using detail::polar_angle;
using detail::rotation;
using detail::wrap_angle;
constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();
// The factor of each local-global correction of a target (fill()). Bar at n = 48, 200 deg, the
// largest K excess away from the folds after 10 / 20 steps: 2.1 % / 0.73 % with 1, 0.62 % / 0.11 %
// with 2, 0.15 % / 0.11 % with 3 (docs/FOLDS.md).
constexpr double kOverRelax = 2;

using Entry = std::pair<double, int>;  // (path cost, face) of lift()'s queue

}  // namespace

// fill()'s buffers, kept between frames (under mutex_): a frame allocates nothing large, as every
// freed large block costs page faults and, under jemalloc as in Blender, madvise (docs/BENCHMARKS.md).
struct FoldFill::Work {
  Eigen::VectorXd blend, ang, th, delta, b, x;  // per face; the harmonic system's rhs and solution
  std::vector<double> cost;                     // lift()'s path costs and queue
  std::vector<Entry> heap;
  std::vector<Eigen::Matrix2d> G, target;  // per R face
  Positions X0;
  Eigen::MatrixXd rhs, z;  // the Poisson system's
};

struct FoldFill::Plan {
  Mesh mesh;
  std::vector<Eigen::Matrix2d> base_inverse;  // #F: inverse of the base's edge matrix
  std::vector<double> area;                   // #F: base area
  std::vector<double> weight;                 // #F: the face's weight in the Poisson energy
  std::vector<std::vector<char>> unfolded;    // per input, #F: 1 where it keeps the base's orientation
  std::vector<char> smooth;                   // #F: keeps the harmonic rotation (sheared components)
  std::vector<int> part;                      // #F: part (component) of M', -1 in R
  std::vector<int> part_of_vertex;            // #V: part of an M' vertex, else -1
  std::vector<int> ref;                       // per part: its first face
  std::vector<std::vector<int>> part_faces, part_vertices;  // per part: its faces, its vertices (ascending)
  std::vector<char> in_rest;                  // #F: 1 for the faces of M'
  std::vector<char> main;                     // per part: the largest part of its piece
  std::vector<int> r_index;                   // #F: index among R's faces, else -1
  std::vector<Eigen::VectorXd> theta;         // per input: its rotation field (#F)
  std::vector<std::vector<Eigen::Matrix2d>> J;  // per input, per R face: its Jacobian
  std::vector<int> var;                       // #V: Poisson unknown, -1 for fixed vertices
  int num_free = 0;
  std::vector<int> part_var;                  // per part: its translation's unknown, -1 for main parts
  std::vector<double> bound;                  // per R face: the inputs' largest K; 0: keeps its target
  int iterations = 0;                         // local-global steps after the Poisson solve
  std::unique_ptr<SparseCholesky> harmonic, poisson;

  explicit Plan(const Mesh& m) : mesh(m) {}

  // Lifts the principal angles `ang` across the dual graph from the faces already set in theta,
  // through the faces with allow[f]: each reached face takes the branch nearest its neighbour's on
  // the path with the least total turn (Dijkstra), so that the value does not depend on the order
  // of a walk that may cross a collapsed face (where neighbours differ by up to pi).
  // cost, queue: buffers (queue a binary heap, popped in std::priority_queue's order).
  void lift(const Eigen::VectorXd& ang, const std::vector<char>& allow, Eigen::VectorXd& theta,
            std::vector<double>& cost, std::vector<Entry>& queue) const {
    const std::greater<Entry> later;
    cost.assign(theta.size(), std::numeric_limits<double>::infinity());
    queue.clear();
    for (int f = 0; f < theta.size(); ++f)
      if (!std::isnan(theta[f])) cost[f] = 0, queue.emplace_back(0.0, f), std::push_heap(queue.begin(), queue.end(), later);
    while (!queue.empty()) {
      std::pop_heap(queue.begin(), queue.end(), later);
      const auto [c, f] = queue.back();
      queue.pop_back();
      if (c > cost[f]) continue;
      for (int k = 0; k < 3; ++k) {
        const int g = mesh.opposite_face(mesh.face_edges()(f, k), f);
        if (g < 0 || !allow[g] || cost[g] == 0) continue;
        const double step = wrap_angle(ang[g] - theta[f]), total = c + std::abs(step);
        if (total >= cost[g]) continue;
        cost[g] = total;
        theta[g] = theta[f] + step;
        queue.emplace_back(total, g);
        std::push_heap(queue.begin(), queue.end(), later);
      }
    }
  }

  // A separated part turns by the inputs' blend (its mean rotation), about its vertices' mean.
  void turn_separated_parts(const Eigen::VectorXd& blend, Eigen::VectorXd& th, Eigen::Ref<Positions> X) const {
    for (size_t q = 0; q < ref.size(); ++q) {
      if (main[q]) continue;
      double turn = 0, total = 0;
      for (int f : part_faces[q]) turn += area[f] * (blend[f] - th[f]), total += area[f];
      turn /= total;
      Eigen::RowVector2d centre = Eigen::RowVector2d::Zero();
      for (int v : part_vertices[q]) centre += X.row(v);
      centre /= static_cast<double>(part_vertices[q].size());
      const Eigen::Matrix2d R = rotation(turn);
      for (int v : part_vertices[q]) X.row(v) = centre + (X.row(v) - centre) * R.transpose();
      for (int f : part_faces[q]) th[f] += turn;
    }
  }

  // The harmonic extension over R's dual graph of `values` on M' (#F; R rows ignored) into R's rows;
  // b, x: buffers.
  void extend(Eigen::VectorXd& values, Eigen::VectorXd& b, Eigen::VectorXd& x) const {
    const int n = static_cast<int>(harmonic->size());
    b.setZero(n);
    x.resize(n);
    for (int f = 0; f < values.size(); ++f) {
      if (r_index[f] < 0) continue;
      for (int c = 0; c < 3; ++c) {
        const int g = mesh.opposite_face(mesh.face_edges()(f, c), f);
        if (g >= 0 && r_index[g] < 0) b[r_index[f]] += values[g];
      }
    }
    harmonic->solve(b.data(), x.data());
    for (int f = 0; f < values.size(); ++f)
      if (r_index[f] >= 0) values[f] = x[r_index[f]];
  }

  std::array<Eigen::Vector2d, 3> gradients(int f) const {  // of the three hat functions, in the base
    const Eigen::Vector2d b1 = base_inverse[f].row(0).transpose(), b2 = base_inverse[f].row(1).transpose();
    return {-b1 - b2, b1, b2};
  }

  void find_parts(const std::vector<char>& in_region);
  void plan_bounds(const FoldRegion& region, const FoldOptions& options);
  void rhs(const FoldRegion& region, const std::vector<Eigen::Matrix2d>& G, const Positions& X, Eigen::MatrixXd& b) const;
  void solve(const FoldRegion& region, const std::vector<Eigen::Matrix2d>& G, Work& work, Eigen::Ref<Positions> X) const;
  void plan_rotations(const std::vector<Positions>& shapes, const std::vector<int>& region_faces);
  void to_anchor_branch(Eigen::VectorXd& theta) const;
  void plan_systems(const FoldRegion& region);
};

void FoldFill::Plan::find_parts(const std::vector<char>& in_region) {
  const int nf = mesh.num_faces();
  part.assign(nf, -1);
  part_of_vertex.assign(mesh.num_vertices(), -1);
  std::vector<double> part_area;
  for (int f0 = 0; f0 < nf; ++f0) {
    if (in_region[f0] || part[f0] >= 0) continue;
    const int p = static_cast<int>(ref.size());
    ref.push_back(f0);
    part_area.push_back(0);
    std::deque<int> queue{f0};
    part[f0] = p;
    while (!queue.empty()) {
      const int f = queue.front();
      queue.pop_front();
      part_area[p] += area[f];
      for (int c = 0; c < 3; ++c) {
        part_of_vertex[mesh.faces()(f, c)] = p;
        const int g = mesh.opposite_face(mesh.face_edges()(f, c), f);
        if (g >= 0 && !in_region[g] && part[g] < 0) part[g] = p, queue.push_back(g);
      }
    }
  }
  std::vector<int> largest(mesh.num_pieces(), -1);  // per piece of the mesh: its largest part
  for (size_t p = 0; p < ref.size(); ++p) {
    int& l = largest[mesh.piece_of_face(ref[p])];
    if (l < 0 || part_area[p] > part_area[l]) l = static_cast<int>(p);
  }
  main.assign(ref.size(), 0);
  for (int l : largest)
    if (l >= 0) main[l] = 1;
  part_faces.resize(ref.size());
  part_vertices.resize(ref.size());
  in_rest.assign(nf, 0);
  for (int f = 0; f < nf; ++f)
    if (part[f] >= 0) part_faces[part[f]].push_back(f), in_rest[f] = 1;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (part_of_vertex[v] >= 0) part_vertices[part_of_vertex[v]].push_back(v);
}

void FoldFill::Plan::to_anchor_branch(Eigen::VectorXd& theta) const {
  // The inputs' fields are blended, so a 2 pi k of one input turns the in-between by 2 pi k t.
  // The main part's anchor measures its rotation on the branch of the area-weighted median
  // (AnchorFrame::bulk_rotations); the field of each piece takes that branch too.
  for (size_t q = 0; q < ref.size(); ++q) {
    if (!main[q]) continue;
    std::vector<std::pair<double, double>> rot;  // (angle, area) of the part's faces
    for (int f : part_faces[q]) rot.emplace_back(theta[f], area[f]);
    const double shift = detail::median_turns(std::move(rot));
    const int piece = mesh.piece_of_face(ref[q]);
    for (int f = 0; f < mesh.num_faces(); ++f)
      if (mesh.piece_of_face(f) == piece) theta[f] -= shift;
  }
}

void FoldFill::Plan::plan_rotations(const std::vector<Positions>& shapes, const std::vector<int>& region_faces) {
  const int nf = mesh.num_faces();
  const std::vector<char> all(nf, 1);
  Work work;
  for (size_t i = 0; i < shapes.size(); ++i) {
    const Positions& X = shapes[i];
    const std::vector<char>& unfolded = this->unfolded[i];
    Eigen::VectorXd ang(nf), th = Eigen::VectorXd::Constant(nf, kUnset);
    for (int f = 0; f < nf; ++f) ang[f] = polar_angle(face_jacobian(X, mesh.faces(), f, base_inverse[f]));
    for (size_t p = 0; p < ref.size(); ++p)
      if (main[p]) th[ref[p]] = ang[ref[p]];
    lift(ang, unfolded, th, work.cost, work.heap);  // through the faces this input does not fold, then the rest
    lift(ang, all, th, work.cost, work.heap);
    to_anchor_branch(th);
    // Over R: the harmonic extension of M's field, moved to the face's own rotation where it does
    // not fold (the branch nearest the extension), except in components of R with sheared faces.
    Eigen::VectorXd h = th;
    extend(h, work.b, work.x);
    for (int f : region_faces) th[f] = unfolded[f] && !smooth[f] ? h[f] + wrap_angle(ang[f] - h[f]) : h[f];
    theta.push_back(th);
    J.emplace_back();
    for (int f : region_faces) J.back().push_back(face_jacobian(X, mesh.faces(), f, base_inverse[f]));
  }
}

void FoldFill::Plan::plan_systems(const FoldRegion& region) {
  const int nf = mesh.num_faces();
  r_index.assign(nf, -1);
  for (size_t k = 0; k < region.faces.size(); ++k) r_index[region.faces[k]] = static_cast<int>(k);
  std::vector<SymmetricEntry> h;
  for (int f : region.faces) {
    for (int c = 0; c < 3; ++c) {
      const int g = mesh.opposite_face(mesh.face_edges()(f, c), f);
      if (g < 0) continue;
      h.push_back({r_index[f], r_index[f], 1.0});
      if (r_index[g] >= 0) h.push_back({r_index[f], r_index[g], -1.0});
    }
  }
  harmonic = factorise(static_cast<int>(region.faces.size()), h);
  var.assign(mesh.num_vertices(), -1);
  for (int v : region.free_vertices) var[v] = num_free++;
  part_var.assign(ref.size(), -1);
  int n = num_free;
  for (size_t p = 0; p < ref.size(); ++p)
    if (!main[p]) part_var[p] = n++;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (part_of_vertex[v] >= 0) var[v] = part_var[part_of_vertex[v]];
  std::vector<SymmetricEntry> L;
  for (int f : region.faces) {
    const auto B = gradients(f);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const int va = var[mesh.faces()(f, a)], vb = var[mesh.faces()(f, b)];
        if (va >= 0 && vb >= 0) L.push_back({va, vb, weight[f] * B[a].dot(B[b])});
      }
  }
  if (n > 0) poisson = factorise(n, L);
}

// Per R face: the largest K of the inputs (at least 1, the base's), or 0 for the faces within two
// vertex rings of a face some input folds: those keep their target (they may fold as the pose does).
void FoldFill::Plan::plan_bounds(const FoldRegion& region, const FoldOptions& options) {
  const Faces& F = mesh.faces();
  iterations = options.fill_iterations;
  std::vector<char> near(mesh.num_faces(), 0);
  for (size_t k = 0; k < region.faces.size(); ++k)
    for (const auto& Ji : J) near[region.faces[k]] = near[region.faces[k]] || Ji[k].determinant() <= 0;
  for (int ring = 0; ring < 2; ++ring) {
    std::vector<char> hit(mesh.num_vertices(), 0);
    for (int f = 0; f < F.rows(); ++f)
      if (near[f]) hit[F(f, 0)] = hit[F(f, 1)] = hit[F(f, 2)] = 1;
    for (int f = 0; f < F.rows(); ++f) near[f] = near[f] || hit[F(f, 0)] || hit[F(f, 1)] || hit[F(f, 2)];
  }
  bound.assign(region.faces.size(), 0);
  for (size_t k = 0; k < region.faces.size(); ++k) {
    if (near[region.faces[k]]) continue;
    bound[k] = 1;
    for (const auto& Ji : J) bound[k] = std::max(bound[k], distortion(Ji[k]));
  }
}

FoldFill::FoldFill(const Mesh& mesh, const std::vector<Positions>& shapes, int base, FoldRegion region,
                   const FoldOptions& options)
    : region_(std::move(region)), plan_(std::make_unique<Plan>(mesh)), work_(std::make_unique<Work>()) {
  Plan& p = *plan_;
  const Faces& F = mesh.faces();
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Matrix2d E = edge_matrix(shapes[base], F, f);
    p.base_inverse.push_back(E.inverse());
    p.area.push_back(0.5 * std::abs(E.determinant()));
  }
  std::vector<char> never_folded(F.rows(), 1);  // by any input
  p.weight = p.area;
  for (const Positions& X : shapes) {
    p.unfolded.emplace_back(F.rows());
    for (int f = 0; f < F.rows(); ++f) {
      p.unfolded.back()[f] = doubled_area(X, F, f) * p.base_inverse[f].determinant() > 0;
      if (!p.unfolded.back()[f]) never_folded[f] = 0, p.weight[f] = options.folded_weight * p.area[f];
    }
  }
  p.smooth = detail::smooth_faces(mesh, shapes, region_, never_folded, options);
  p.find_parts(region_.in_region);
  p.plan_systems(region_);
  p.plan_rotations(shapes, region_.faces);
  p.plan_bounds(region_, options);
}

FoldFill::~FoldFill() = default;

void FoldFill::fill(const Eigen::VectorXd& w, Eigen::Ref<Positions> X, int* faces, int* free_vertices) const {
  if (faces) *faces = static_cast<int>(region_.faces.size());
  if (free_vertices) *free_vertices = static_cast<int>(region_.free_vertices.size());
  const std::lock_guard<std::mutex> lock(mutex_);
  const Plan& p = *plan_;
  Work& work = *work_;
  const Faces& F = p.mesh.faces();
  const int nf = p.mesh.num_faces();
  Eigen::VectorXd &blend = work.blend, &ang = work.ang, &th = work.th, &delta = work.delta;
  blend.setZero(nf), ang.resize(nf), th.setConstant(nf, kUnset);
  for (size_t i = 0; i < p.theta.size(); ++i) blend += w[static_cast<Eigen::Index>(i)] * p.theta[i];
  for (int f = 0; f < nf; ++f)
    if (p.part[f] >= 0) ang[f] = polar_angle(face_jacobian(X, F, f, p.base_inverse[f]));
  // The frame's rotations on each part, from the branch nearest the blend at its first face (one walk: R parts them).
  for (int r : p.ref) th[r] = blend[r] + wrap_angle(ang[r] - blend[r]);
  p.lift(ang, p.in_rest, th, work.cost, work.heap);
  p.turn_separated_parts(blend, th, X);
  // Rotations over R: the blend plus the harmonic extension of the frame's difference (0 at inputs).
  delta = th - blend;
  p.extend(delta, work.b, work.x);
  std::vector<Eigen::Matrix2d>& G = work.G;
  G.assign(region_.faces.size(), Eigen::Matrix2d::Zero());
  for (size_t k = 0; k < region_.faces.size(); ++k) {
    const int f = region_.faces[k];
    for (size_t i = 0; i < p.theta.size(); ++i)
      G[k] += w[static_cast<Eigen::Index>(i)] * rotation(blend[f] + delta[f] - p.theta[i][f]) * p.J[i][k];
  }
  if (!p.poisson) return;
  work.X0 = X;
  p.solve(region_, G, work, X);
  // Local-global steps (docs/FOLDS.md): the least-squares fill misses incompatible targets, so each
  // face above its K bound adds kOverRelax times its clamping change to its target and the same
  // factorisation solves again; no face above its bound is a fixed point (inputs: no step at all).
  std::vector<Eigen::Matrix2d>& target = (work.target = G);
  for (int it = 0; it < p.iterations; ++it) {
    bool changed = false;
    for (size_t k = 0; k < region_.faces.size(); ++k) {
      const int f = region_.faces[k];
      if (p.bound[k] <= 0) continue;
      const Eigen::Matrix2d J = face_jacobian(X, F, f, p.base_inverse[f]);
      if (J.determinant() <= 0) continue;
      const Eigen::Matrix2d D = clamp_change(J, p.bound[k]);
      if (D.isZero(0)) continue;
      target[k] += kOverRelax * D;
      changed = true;
    }
    if (!changed) break;
    p.solve(region_, target, work, X);
  }
}

void FoldFill::Plan::rhs(const FoldRegion& region, const std::vector<Eigen::Matrix2d>& G, const Positions& X,
                         Eigen::MatrixXd& b) const {
  const Faces& F = mesh.faces();
  b.setZero(poisson->size(), 2);
  for (size_t k = 0; k < region.faces.size(); ++k) {
    const int f = region.faces[k];
    const auto B = gradients(f);
    for (int a = 0; a < 3; ++a) {
      const int va = var[F(f, a)];
      if (va < 0) continue;
      Eigen::Vector2d r = weight[f] * G[k] * B[a];
      for (int c = 0; c < 3; ++c)  // the known positions move to the right-hand side
        if (part_of_vertex[F(f, c)] >= 0) r -= weight[f] * B[a].dot(B[c]) * X.row(F(f, c)).transpose();
      b.row(va) += r.transpose();
    }
  }
}

// X: the free vertices and the separated parts' translations (from work.X0) solved for the targets G
// (per R face), in work's buffers.
void FoldFill::Plan::solve(const FoldRegion& region, const std::vector<Eigen::Matrix2d>& G, Work& work,
                           Eigen::Ref<Positions> X) const {
  const Positions& X0 = work.X0;
  Eigen::MatrixXd &b = work.rhs, &z = work.z;
  rhs(region, G, X0, b);
  z.resize(b.rows(), 2);
  poisson->solve(b.data(), z.data(), 2);
  for (int v = 0; v < X.rows(); ++v) {
    if (var[v] < 0) continue;
    if (part_of_vertex[v] < 0) X.row(v) = z.row(var[v]);
    else X.row(v) = X0.row(v) + z.row(var[v]);
  }
}

}  // namespace bdinterp
