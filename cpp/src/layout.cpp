#include "bdinterp/layout.h"

#include <array>
#include <cmath>
#include <deque>

#include "bdinterp/triangle.h"

namespace bdinterp {
namespace {

// Breadth-first order over the dual graph from `root`, without the root: each face with the parent
// it is reached from and the corners opposite their shared edge.
std::vector<Layout::TreeStep> dual_tree(const Mesh& m, int root) {
  const Faces& FE = m.face_edges();
  const Edges& EF = m.edge_faces();
  std::vector<bool> seen(m.num_faces(), false);
  std::vector<Layout::TreeStep> order;
  order.reserve(m.num_faces());
  std::deque<int> queue{root};
  seen[root] = true;
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop_front();
    for (int c = 0; c < 3; ++c) {
      const int e = FE(f, c);
      const int g = EF(e, 0) == f ? EF(e, 1) : EF(e, 0);
      if (g < 0 || seen[g]) continue;
      seen[g] = true;
      const int cg = FE(g, 0) == e ? 0 : (FE(g, 1) == e ? 1 : 2);
      order.push_back({g, f, cg, c});
      queue.push_back(g);
    }
  }
  return order;
}

// The face farthest (in dual steps) from the boundary: short propagation paths to every face.
int central_face(const Mesh& m) {
  const Edges& EF = m.edge_faces();
  const Faces& FE = m.face_edges();
  std::vector<int> dist(m.num_faces(), -1);
  std::deque<int> queue;
  for (int e = 0; e < m.num_edges(); ++e) {
    if (EF(e, 1) < 0 && dist[EF(e, 0)] < 0) {
      dist[EF(e, 0)] = 0;
      queue.push_back(EF(e, 0));
    }
  }
  int last = 0;
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop_front();
    last = f;
    for (int c = 0; c < 3; ++c) {
      const int e = FE(f, c);
      const int g = EF(e, 0) == f ? EF(e, 1) : EF(e, 0);
      if (g >= 0 && dist[g] < 0) {
        dist[g] = dist[f] + 1;
        queue.push_back(g);
      }
    }
  }
  return last;
}

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

}  // namespace

Layout::Layout(const Mesh& disk, bool own_system) : mesh_(&disk) {
  const Faces& F = disk.faces();
  const Faces& FE = disk.face_edges();
  const Edges& E = disk.edges();
  const Edges& EF = disk.edge_faces();
  root_ = central_face(disk);
  tree_ = dual_tree(disk, root_);
  std::vector<int> col_ptr, rows;
  pattern_ = interior_pattern(disk, col_ptr, rows);
  const int n = pattern_.size();
  auto corner_of_edge = [&](int f, int e) { return FE(f, 0) == e ? 0 : (FE(f, 1) == e ? 1 : 2); };
  // The boundary half-edges (each face's half-edge c runs from corner c+1 to corner c+2, so the
  // interior lies to their left), chained into the loop from its smallest vertex.
  std::vector<HalfEdge> leaving(disk.num_vertices(), HalfEdge{-1, -1, 1.0});
  int start = -1;
  for (int e = 0; e < E.rows(); ++e) {
    if (EF(e, 1) >= 0) continue;
    const int f = EF(e, 0), c = corner_of_edge(f, e), a = F(f, (c + 1) % 3);
    leaving[a] = {f, c, 1.0};
    if (start < 0 || a < start) start = a;
  }
  for (int v = start; v >= 0 && loop_.size() < leaving.size();) {
    loop_.push_back(v);
    loop_edges_.push_back(leaving[v]);
    v = F(leaving[v].face, (leaving[v].corner + 2) % 3);
    if (v == start) break;
  }
  // One tie to the boundary for every interior vertex next to it.
  std::vector<bool> tied(n, false);
  for (int e = 0; e < E.rows(); ++e) {
    const int ia = pattern_.index[E(e, 0)], ib = pattern_.index[E(e, 1)];
    if ((ia >= 0) == (ib >= 0)) continue;
    const int row = ia >= 0 ? ia : ib, boundary = ia >= 0 ? E(e, 1) : E(e, 0);
    if (tied[row]) continue;
    tied[row] = true;
    const int f = EF(e, 0), c = corner_of_edge(f, e);
    ties_.push_back({row, boundary, {f, c, F(f, (c + 1) % 3) == boundary ? 1.0 : -1.0}});
  }
  local_.resize(disk.num_faces(), 3);
  rot_.resize(disk.num_faces(), 2);
  broken_.resize(disk.num_faces());
  rhs_.resize(2 * n);
  row_sum_.resize(n);
  if (!own_system || n == 0) return;
  // The uniform graph Laplacian: weight 1 per edge (boundary edges in the diagonal).
  own_ = std::make_unique<SparseCholesky>(n, col_ptr, rows);
  double* W = own_->values();
  std::fill_n(W, rows.size(), 0.0);
  for (int e = 0; e < E.rows(); ++e) {
    const int ia = pattern_.index[E(e, 0)], ib = pattern_.index[E(e, 1)];
    if (ia >= 0) W[pattern_.diag_pos[ia]] += 1.0;
    if (ib >= 0) W[pattern_.diag_pos[ib]] += 1.0;
    if (pattern_.edge_pos[e] >= 0) W[pattern_.edge_pos[e]] = -1.0;
  }
  own_->factorize();
}

Layout::Layout(Layout&&) noexcept = default;
Layout::~Layout() = default;

std::unique_ptr<Layout> Layout::clone() const {
  std::unique_ptr<Layout> copy(new Layout(mesh_));
  copy->pattern_ = pattern_;
  copy->tree_ = tree_;
  copy->root_ = root_;
  copy->loop_ = loop_;
  copy->loop_edges_ = loop_edges_;
  copy->ties_ = ties_;
  if (own_) copy->own_ = std::make_unique<SparseCholesky>(own_->clone());
  copy->local_.resize(local_.rows(), 3);
  copy->rot_.resize(rot_.rows(), 2);
  copy->broken_.resize(broken_.size());
  copy->rhs_.resize(rhs_.size());
  copy->row_sum_.resize(row_sum_.size());
  return copy;
}

Positions Layout::embed(const Eigen::VectorXd& l2, double* flatness) {
  Positions X;
  embed(l2, X, flatness);
  return X;
}

void Layout::embed(const Eigen::VectorXd& l2, Positions& X, double* flatness) {
  if (!own_ && pattern_.size() > 0) throw InvalidInput("layout: built without a system of its own");
  embed(l2, own_.get(), 0.0, X, flatness);
}

void Layout::vector_of(const HalfEdge& h, double* v) const {
  double e[3][2];
  local_half_edges(&local_(h.face, 0), e);
  const double c = rot_(h.face, 0), s = rot_(h.face, 1), *d = e[h.corner];
  v[0] = h.sign * (c * d[0] - s * d[1]);
  v[1] = h.sign * (s * d[0] + c * d[1]);
}

void Layout::embed(const Eigen::VectorXd& l2, SparseCholesky* W, double shift, Positions& X,
                   double* flatness) {
  const Mesh& m = *mesh_;
  const Faces& F = m.faces();
  const Faces& FE = m.face_edges();
  if (l2.size() != m.num_edges()) throw InvalidInput("layout: l2 must have one entry per edge");
  const int nf = static_cast<int>(F.rows()), n = pattern_.size();
  if (n > 0 && (!W || W->size() != n)) throw InvalidInput("layout: the system does not match the mesh");
  const int threads = parallel::loop_threads(nf);
  // Each face in its own frame: corner 0 at the origin, corner 1 at (l01, 0), corner 2 at (cx, cy)
  // with cx = (l01^2 + l02^2 - l12^2) / (2 l01), cy = 4 area / (2 l01) (no trigonometry).
  parallel::for_each(threads, nf, [&](int, long f) {
    const int* fe = &FE(f, 0);
    const double fl2[3] = {l2[fe[0]], l2[fe[1]], l2[fe[2]]};
    const double l[3] = {std::sqrt(fl2[0]), std::sqrt(fl2[1]), std::sqrt(fl2[2])};
    double x[3], perimeter;
    const double q = excesses(l, x, &perimeter);
    broken_[f] = !(q > 0);
    double cx, cy;
    if (!broken_[f]) {
      const double half_inv = 0.5 / l[2];
      cx = (fl2[2] + fl2[1] - fl2[0]) * half_inv;
      cy = q * half_inv;
    } else {  // broken triple (CETM convention of triangle.h): angle pi or 0 at corner 0
      cx = longest_side(l) == 0 ? -l[1] : l[1];
      cy = 0.0;
    }
    local_.row(f) << l[2], cx, cy;
  });
  // Rotations as unit complex numbers (cos, sin), propagated over the dual tree: the shared edge is
  // the same vector seen from both faces, run in opposite directions, so
  // rot_g = -rot_f h_f conj(h_g) / |h_f h_g|, where |h_f| = |h_g| = the edge's length unless a face
  // is broken (its sides then do not close up).
  rot_.row(root_) << 1.0, 0.0;
  for (const TreeStep& st : tree_) {
    double hf[2], hg[2];
    vector_of({st.parent, st.parent_corner, 1.0}, hf);  // rotated by rot_f already
    double local[3][2];
    local_half_edges(&local_(st.face, 0), local);
    hg[0] = local[st.face_corner][0];
    hg[1] = local[st.face_corner][1];
    const double zr = -(hf[0] * hg[0] + hf[1] * hg[1]), zi = hf[0] * hg[1] - hf[1] * hg[0];
    const double inv = broken_[st.face] || broken_[st.parent] ? 1.0 / std::sqrt(zr * zr + zi * zi)
                                                              : 1.0 / l2[FE(st.face, st.face_corner)];
    rot_(st.face, 0) = zr * inv;
    rot_(st.face, 1) = zi * inv;
  }
  // The boundary: walk the loop, then spread the closing gap over it by arc length.
  X.resize(m.num_vertices(), 2);
  X.setZero();
  {
    const size_t nb = loop_.size();
    std::vector<double> arc(nb + 1, 0.0);
    double px = 0, py = 0;
    for (size_t k = 0; k < nb; ++k) {
      X(loop_[k], 0) = px;
      X(loop_[k], 1) = py;
      double v[2];
      vector_of(loop_edges_[k], v);
      px += v[0];
      py += v[1];
      arc[k + 1] = arc[k] + std::sqrt(v[0] * v[0] + v[1] * v[1]);
    }
    for (size_t k = 1; k < nb; ++k) {
      const double a = arc[k] / arc[nb];
      X(loop_[k], 0) -= a * px;
      X(loop_[k], 1) -= a * py;
    }
  }
  if (n > 0) solve_interior(*W, shift, X);
  if (flatness) {
    parallel::PerChunk worst(threads);
    const Edges& E = m.edges();
    parallel::for_each(threads, E.rows(), [&](int k, long e) {
      const double dx = X(E(e, 1), 0) - X(E(e, 0), 0), dy = X(E(e, 1), 1) - X(E(e, 0), 1);
      worst.at(k) = std::max(worst.at(k), std::abs((dx * dx + dy * dy) / l2[e] - 1.0));
    });
    *flatness = worst.max();
  }
}

void Layout::solve_interior(SparseCholesky& W, double shift, Positions& X) {
  const Faces& F = mesh_->faces();
  const Faces& FE = mesh_->face_edges();
  const int nf = static_cast<int>(F.rows()), n = pattern_.size();
  const double* M = W.values();
  const int* col_ptr = W.column_pointers();
  const int* rows = W.row_indices();
  // For an exact layout X, (W X)_i = sum_j w_ij (X_i - X_j) + r_i X_i over the interior neighbours
  // j, with w_ij = -W_ij and r_i the row sum of W (the weight of i's boundary edges). The edge
  // differences come from the faces (each interior edge half from either side), X_i in the last
  // term from a boundary neighbour and the edge to it.
  row_sum_.setZero();
  for (int j = 0; j < n; ++j) {
    row_sum_[j] += M[col_ptr[j]] - shift;
    for (int p = col_ptr[j] + 1; p < col_ptr[j + 1]; ++p) {
      row_sum_[j] += M[p];
      row_sum_[rows[p]] += M[p];
    }
  }
  const int threads = parallel::loop_threads(nf);
  rhs_.setZero();
  rhs_parts_.prepare(threads, 2 * n);
  parallel::run(threads, [&](int k) {
    double* b = rhs_parts_.buffer(k, rhs_.data());
    if (b != rhs_.data()) std::fill_n(b, 2 * n, 0.0);
    const auto [first, last] = parallel::share(nf, k, threads);
    for (int f = first; f < last; ++f) {
      double h[3][2];  // the face's half-edges, rotated into the layout frame
      double local[3][2];
      local_half_edges(&local_(f, 0), local);
      const double rc = rot_(f, 0), rs = rot_(f, 1);
      for (int c = 0; c < 3; ++c) {
        h[c][0] = rc * local[c][0] - rs * local[c][1];
        h[c][1] = rs * local[c][0] + rc * local[c][1];
      }
      for (int c = 0; c < 3; ++c) {
        const int p = pattern_.edge_pos[FE(f, c)];
        if (p < 0) continue;
        const int i = pattern_.index[F(f, (c + 1) % 3)], j = pattern_.index[F(f, (c + 2) % 3)];
        const double* d = h[c];  // X_j - X_i as this face sees it
        const double w = 0.5 * M[p];  // = -(half the weight)
        b[i] += w * d[0];
        b[n + i] += w * d[1];
        b[j] -= w * d[0];
        b[n + j] -= w * d[1];
      }
    }
  });
  rhs_parts_.add_into(rhs_.data());
  for (const Tie& t : ties_) {
    double d[2];
    vector_of(t.edge, d);
    rhs_[t.row] += row_sum_[t.row] * (X(t.boundary, 0) + d[0]);
    rhs_[n + t.row] += row_sum_[t.row] * (X(t.boundary, 1) + d[1]);
  }
  const Eigen::VectorXd b = shift > 0 ? rhs_ : Eigen::VectorXd();  // kept only for the refinement
  Eigen::VectorXd& x = rhs_;
  W.solve(x.data(), x.data(), 2);
  // The factorised matrix is W + shift I: iterative refinement recovers the solution for W.
  for (int it = 0; it < 5 && shift > 0; ++it) {
    Eigen::VectorXd r(2 * n);  // b - (W - shift I) x
    for (int col = 0; col < 2; ++col) W.multiply(M, x.data() + col * n, r.data() + col * n);
    r = b - r + shift * x;
    W.solve(r.data(), r.data(), 2);
    x += r;
    if (r.cwiseAbs().maxCoeff() <= 1e-15 * x.cwiseAbs().maxCoeff()) break;
  }
  for (int i = 0; i < n; ++i) {
    X(pattern_.vertex[i], 0) = x[i];
    X(pattern_.vertex[i], 1) = x[n + i];
  }
}

}  // namespace bdinterp
