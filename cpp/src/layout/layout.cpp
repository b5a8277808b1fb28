#include "layout/layout.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "parallel/parallel.h"
#include "mesh/triangle.h"

namespace bdinterp {
namespace {
using HalfEdge = LayoutPlan::HalfEdge;

// The half-edges h[c] (from corner c+1 to corner c+2) of a face stored as p = (l01, cx, cy):
// corner 0 at the origin, corner 1 at (l01, 0), corner 2 at (cx, cy).
inline void local_half_edges(const double* p, double h[3][2]) {
  h[0][0] = p[1] - p[0];
  h[0][1] = p[2];
  h[1][0] = -p[1];
  h[1][1] = -p[2];
  h[2][0] = p[0];
  h[2][1] = 0.0;
}

// The free vertices of `piece` (all but those of its loop `outer` and isolated ones), numbered in
// increasing vertex order: a disk's interior numbering, so its pattern is interior_pattern()'s.
std::vector<int> free_vertices(const Mesh& piece, int outer, int& n) {
  const auto& loops = piece.boundary_loops();
  if (outer < 0 || (outer >= static_cast<int>(loops.size()) && !loops.empty()))
    throw InvalidInput("layout: no boundary loop " + std::to_string(outer));
  std::vector<int> index(piece.num_vertices(), 0);
  if (!loops.empty())
    for (int v : loops[outer]) index[v] = -1;
  n = 0;
  for (int v = 0; v < piece.num_vertices(); ++v) index[v] = index[v] < 0 || piece.is_isolated_vertex(v) ? -1 : n++;
  return index;
}

}  // namespace

LayoutPlan::HalfEdge LayoutPlan::half_edge(int e, int from) const {
  const int f = mesh.edge_faces()(e, 0), c = mesh.corner_of_edge(f, e);
  return {f, c, mesh.faces()(f, (c + 1) % 3) == from ? 1.0 : -1.0};
}

LayoutPlan::LayoutPlan(const Mesh& piece, int outer_loop, bool share_analysis) : mesh(piece), outer(outer_loop) {
  const Faces& F = piece.faces();
  const Edges& E = piece.edges();
  const Edges& EF = piece.edge_faces();
  root = piece.central_face();
  tree = piece.dual_walk({root});
  int n = 0;
  const std::vector<int> index = free_vertices(piece, outer, n);
  std::vector<int> col_ptr, rows;  // for the shared analysis (else ensure_own_system builds them again)
  pattern = unknowns_pattern(piece, index, n, col_ptr, rows);
  if (share_analysis && n > 0) uniform = std::make_shared<const CholeskyAnalysis>(n, std::move(col_ptr), std::move(rows));
  for (int e = 0; e < E.rows(); ++e) one_sided |= pattern.edge_pos[e] >= 0 && EF(e, 1) < 0;
  // The boundary half-edges (each face's half-edge c runs from corner c+1 to corner c+2, so the
  // piece lies to their left), chained into the outer loop from its smallest vertex.
  std::vector<HalfEdge> leaving(piece.num_vertices(), HalfEdge{-1, -1, 1.0});
  for (int e = 0; e < E.rows(); ++e) {
    if (EF(e, 1) >= 0) continue;
    const int f = EF(e, 0), c = piece.corner_of_edge(f, e);
    leaving[F(f, (c + 1) % 3)] = {f, c, 1.0};
  }
  const auto& loops = piece.boundary_loops();
  const int start = loops.empty() ? -1 : *std::min_element(loops[outer].begin(), loops[outer].end());
  for (int v = start; v >= 0 && loop.size() < leaving.size();) {
    loop.push_back(v);
    loop_edges.push_back(leaving[v]);
    v = F(leaving[v].face, (leaving[v].corner + 2) % 3);
    if (v == start) break;
  }
  // One tie to the outer loop for every free vertex next to it.
  std::vector<bool> tied(pattern.size(), false);
  for (int e = 0; e < E.rows(); ++e) {
    const int ia = pattern.index[E(e, 0)], ib = pattern.index[E(e, 1)];
    if ((ia >= 0) == (ib >= 0)) continue;
    const int row = ia >= 0 ? ia : ib, boundary = ia >= 0 ? E(e, 1) : E(e, 0);
    if (tied[row]) continue;
    tied[row] = true;
    ties.push_back({row, boundary, half_edge(e, boundary)});
  }
}

// One thread's scratch.
struct Layout::Scratch {
  Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> rot;  // #F: (cos, sin) per face
  // #F: each face in its own frame, corner 0 at the origin, corner 1 at (l01, 0), corner 2 at
  // (cx, cy); rows (l01, cx, cy).
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> local;
  std::vector<char> broken;       // #F: the face's lengths violate the triangle inequality
  Eigen::VectorXd rhs, row_sum;   // 2 #free and #free
  parallel::Partials rhs_parts;   // other threads' shares of the right-hand side
};

Layout::Layout(const Mesh& disk, bool own_system) : Layout(std::make_shared<const LayoutPlan>(disk), own_system) {}

Layout::Layout(std::shared_ptr<const LayoutPlan> plan, bool own_system)
    : plan_(std::move(plan)), scratch_(std::make_unique<Scratch>()) {
  const int nf = plan_->mesh.num_faces(), n = plan_->pattern.size();
  scratch_->local.resize(nf, 3);
  scratch_->rot.resize(nf, 2);
  scratch_->broken.resize(nf);
  scratch_->rhs.resize(2 * n);
  scratch_->row_sum.resize(n);
  if (own_system) ensure_own_system();
}

void Layout::ensure_own_system() {
  const LayoutPlan& p = *plan_;
  const int n = p.pattern.size();
  if (own_ || n == 0) return;
  // The uniform graph Laplacian: weight 1 per edge (edges to the outer loop in the diagonal).
  if (p.uniform) {
    own_ = std::make_unique<SparseCholesky>(p.uniform);
  } else {
    std::vector<int> col_ptr, rows;
    unknowns_pattern(p.mesh, p.pattern.index, n, col_ptr, rows);
    own_ = std::make_unique<SparseCholesky>(n, col_ptr, rows);
  }
  double* W = own_->values();
  const Edges& E = p.mesh.edges();
  for (int e = 0; e < E.rows(); ++e) {
    const int ia = p.pattern.index[E(e, 0)], ib = p.pattern.index[E(e, 1)];
    if (ia >= 0) W[p.pattern.diag_pos[ia]] += 1.0;
    if (ib >= 0) W[p.pattern.diag_pos[ib]] += 1.0;
    if (p.pattern.edge_pos[e] >= 0) W[p.pattern.edge_pos[e]] = -1.0;
  }
  own_->factorize();
}

Layout::Layout(Layout&&) noexcept = default;
Layout& Layout::operator=(Layout&&) noexcept = default;
Layout::~Layout() = default;

Positions Layout::embed(const Eigen::VectorXd& l2, double* flatness) {
  Positions X;
  embed(l2, X, flatness);
  return X;
}

void Layout::embed(const Eigen::VectorXd& l2, Positions& X, double* flatness) {
  if (!own_ && plan_->pattern.size() > 0) throw InvalidInput("layout: built without a system of its own");
  embed(l2, own_.get(), 0.0, X, flatness);
}

void Layout::vector_of(const HalfEdge& h, double* v) const {
  double e[3][2];
  local_half_edges(&scratch_->local(h.face, 0), e);
  const double c = scratch_->rot(h.face, 0), s = scratch_->rot(h.face, 1), *d = e[h.corner];
  v[0] = h.sign * (c * d[0] - s * d[1]);
  v[1] = h.sign * (s * d[0] + c * d[1]);
}

void Layout::embed(const Eigen::VectorXd& l2, SparseCholesky* W, double shift, Positions& X, double* flatness) {
  const Mesh& m = plan_->mesh;
  if (l2.size() != m.num_edges()) throw InvalidInput("layout: l2 must have one entry per edge");
  const int n = plan_->pattern.size();
  if (n > 0 && (!W || W->size() != n)) throw InvalidInput("layout: the system does not match the mesh");
  place_faces(l2);
  X.resize(m.num_vertices(), 2);
  X.setZero();
  place_boundary(X);
  if (n > 0) solve_free(*W, shift, X);
  if (!flatness) return;
  const Edges& E = m.edges();
  const parallel::Loop edges(E.rows());
  parallel::PerChunk worst(edges.chunks());
  edges.run([&](int k, long e) {
    const double dx = X(E(e, 1), 0) - X(E(e, 0), 0), dy = X(E(e, 1), 1) - X(E(e, 0), 1);
    worst.at(k) = std::max(worst.at(k), std::abs((dx * dx + dy * dy) / l2[e] - 1.0));
  });
  *flatness = worst.max();
}

void Layout::place_faces(const Eigen::VectorXd& l2) {
  const Faces& FE = plan_->mesh.face_edges();
  const int nf = static_cast<int>(FE.rows());
  Scratch& s = *scratch_;
  // Each face in its own frame: corner 0 at the origin, corner 1 at (l01, 0), corner 2 at (cx, cy)
  // with cx = (l01^2 + l02^2 - l12^2) / (2 l01), cy = 4 area / (2 l01) (no trigonometry).
  parallel::Loop(nf).run([&](int, long f) {
    const int* fe = &FE(f, 0);
    const double fl2[3] = {l2[fe[0]], l2[fe[1]], l2[fe[2]]};
    const double l[3] = {std::sqrt(fl2[0]), std::sqrt(fl2[1]), std::sqrt(fl2[2])};
    double x[3], perimeter;
    const double q = excesses(l, x, &perimeter);
    s.broken[f] = !(q > 0);
    double cx, cy;
    if (!s.broken[f]) {
      const double half_inv = 0.5 / l[2];
      cx = (fl2[2] + fl2[1] - fl2[0]) * half_inv;
      cy = q * half_inv;
    } else {  // broken triple (CETM convention of triangle.h): angle pi or 0 at corner 0
      cx = longest_side(l) == 0 ? -l[1] : l[1];
      cy = 0.0;
    }
    s.local.row(f) << l[2], cx, cy;
  });
  // Rotations as unit complex numbers (cos, sin), propagated over the dual tree: the shared edge is
  // the same vector seen from both faces, run in opposite directions, so
  // rot_g = -rot_f h_f conj(h_g) / |h_f h_g|, where |h_f| = |h_g| = the edge's length unless a face
  // is broken (its sides then do not close up; the product is normalised instead). The turn
  // rot_g / rot_f comes from the local frames alone, in parallel, into rot_g's row; the walk is then
  // one complex product a face.
  const std::vector<Mesh::DualStep>& tree = plan_->tree;
  parallel::Loop(static_cast<long>(tree.size())).run([&](int, long k) {
    const Mesh::DualStep& st = tree[k];
    double lf[3][2], lg[3][2];
    local_half_edges(&s.local(st.parent, 0), lf);
    local_half_edges(&s.local(st.face, 0), lg);
    const double *hf = lf[st.parent_corner], *hg = lg[st.face_corner];
    const double inv = s.broken[st.face] || s.broken[st.parent] ? 1.0 : 1.0 / l2[FE(st.face, st.face_corner)];
    s.rot(st.face, 0) = -(hf[0] * hg[0] + hf[1] * hg[1]) * inv;
    s.rot(st.face, 1) = (hf[0] * hg[1] - hf[1] * hg[0]) * inv;
  });
  s.rot.row(plan_->root) << 1.0, 0.0;
  for (const Mesh::DualStep& st : tree) {  // breadth-first: the parent's rotation is final
    const double c = s.rot(st.parent, 0), sn = s.rot(st.parent, 1), a = s.rot(st.face, 0), b = s.rot(st.face, 1);
    double re = c * a - sn * b, im = c * b + sn * a;
    if (s.broken[st.face] || s.broken[st.parent]) {
      const double inv = 1.0 / std::sqrt(re * re + im * im);
      re *= inv;
      im *= inv;
    }
    s.rot(st.face, 0) = re;
    s.rot(st.face, 1) = im;
  }
}

void Layout::place_boundary(Positions& X) const {
  const std::vector<int>& loop = plan_->loop;
  const size_t nb = loop.size();
  std::vector<double> arc(nb + 1, 0.0);
  double px = 0, py = 0;
  for (size_t k = 0; k < nb; ++k) {
    X(loop[k], 0) = px;
    X(loop[k], 1) = py;
    double v[2];
    vector_of(plan_->loop_edges[k], v);
    px += v[0];
    py += v[1];
    arc[k + 1] = arc[k] + std::sqrt(v[0] * v[0] + v[1] * v[1]);
  }
  for (size_t k = 1; k < nb; ++k) {
    const double a = arc[k] / arc[nb];
    X(loop[k], 0) -= a * px;
    X(loop[k], 1) -= a * py;
  }
}

void Layout::assemble_rhs(const SparseCholesky& W, double shift, const Positions& X) {
  const Faces& F = plan_->mesh.faces();
  const Faces& FE = plan_->mesh.face_edges();
  const Edges& EF = plan_->mesh.edge_faces();
  const InteriorPattern& pattern = plan_->pattern;
  const int nf = static_cast<int>(F.rows()), n = pattern.size();
  Scratch& s = *scratch_;
  const double* M = W.values();
  const int* col_ptr = W.column_pointers();
  const int* rows = W.row_indices();
  // For an exact layout X, (W X)_i = sum_j w_ij (X_i - X_j) + r_i X_i over the free neighbours j,
  // with w_ij = -W_ij and r_i the row sum of W (the weight of i's edges to the outer loop). The edge
  // differences come from the faces (an inner edge half from either side, a hole's edge whole from
  // its one face), X_i in the last term from an outer-loop neighbour and the edge to it.
  s.row_sum.setZero();
  for (int j = 0; j < n; ++j) {
    s.row_sum[j] += M[col_ptr[j]] - shift;
    for (int p = col_ptr[j] + 1; p < col_ptr[j + 1]; ++p) {
      s.row_sum[j] += M[p];
      s.row_sum[rows[p]] += M[p];
    }
  }
  const parallel::Loop faces(nf);
  const bool one_sided = plan_->one_sided;  // a disk's free edges all have two faces
  s.rhs_parts.prepare(faces.chunks(), 2 * n);
  for (int k = 0; k < faces.chunks(); ++k) std::fill_n(s.rhs_parts.buffer(k, s.rhs.data()), 2 * n, 0.0);
  faces.run([&](int k, long f) {
    double* b = s.rhs_parts.buffer(k, s.rhs.data());
    double local[3][2];
    local_half_edges(&s.local(f, 0), local);
    const double rc = s.rot(f, 0), rs = s.rot(f, 1);
    for (int c = 0; c < 3; ++c) {
      const int p = pattern.edge_pos[FE(f, c)];
      if (p < 0) continue;
      const int i = pattern.index[F(f, (c + 1) % 3)], j = pattern.index[F(f, (c + 2) % 3)];
      // X_j - X_i as this face sees it: its half-edge rotated into the layout frame.
      const double d0 = rc * local[c][0] - rs * local[c][1], d1 = rs * local[c][0] + rc * local[c][1];
      const double w = (one_sided && EF(FE(f, c), 1) < 0 ? 1.0 : 0.5) * M[p];  // -(this face's share)
      b[i] += w * d0;
      b[n + i] += w * d1;
      b[j] -= w * d0;
      b[n + j] -= w * d1;
    }
  });
  s.rhs_parts.add_into(s.rhs.data());
  for (const LayoutPlan::Tie& t : plan_->ties) {
    double d[2];
    vector_of(t.edge, d);
    s.rhs[t.row] += s.row_sum[t.row] * (X(t.boundary, 0) + d[0]);
    s.rhs[n + t.row] += s.row_sum[t.row] * (X(t.boundary, 1) + d[1]);
  }
}

void Layout::solve_free(SparseCholesky& W, double shift, Positions& X) {
  const int n = plan_->pattern.size();
  assemble_rhs(W, shift, X);
  Eigen::VectorXd& x = scratch_->rhs;
  const Eigen::VectorXd b = shift > 0 ? x : Eigen::VectorXd();  // kept only for the refinement
  W.solve(x.data(), x.data(), 2);
  // The factorised matrix is W + shift I: iterative refinement recovers the solution for W.
  for (int it = 0; it < 5 && shift > 0; ++it) {
    Eigen::VectorXd r(2 * n);  // b - (W - shift I) x
    for (int col = 0; col < 2; ++col) W.multiply(W.values(), x.data() + col * n, r.data() + col * n);
    r = b - r + shift * x;
    W.solve(r.data(), r.data(), 2);
    x += r;
    if (r.cwiseAbs().maxCoeff() <= 1e-15 * x.cwiseAbs().maxCoeff()) break;
  }
  for (int i = 0; i < n; ++i) {
    X(plan_->pattern.vertex[i], 0) = x[i];
    X(plan_->pattern.vertex[i], 1) = x[n + i];
  }
}

}  // namespace bdinterp
