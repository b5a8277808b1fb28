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

}  // namespace

Layout::Layout(const Mesh& disk) : mesh_(&disk) {
  root_ = central_face(disk);
  tree_ = dual_tree(disk, root_);
  const int n = disk.num_vertices() - 1;  // vertex 0 is pinned at the origin

  half_.resize(disk.num_faces(), 6);
  rhs_.resize(2 * std::max(n, 0));
  if (n <= 0) return;
  // Half-edge Laplacian: every half-edge (a, b) adds (x_b - x_a)^2; interior edges count twice.
  std::vector<std::vector<std::pair<int, double>>> below(n);
  std::vector<double> diag(n, 0.0);
  const Edges& E = disk.edges();
  const Edges& EF = disk.edge_faces();
  for (int e = 0; e < E.rows(); ++e) {
    const double w = EF(e, 1) >= 0 ? 2.0 : 1.0;
    const int a = E(e, 0) - 1, b = E(e, 1) - 1;  // a < b
    if (a >= 0) diag[a] += w;
    if (b >= 0) diag[b] += w;
    if (a >= 0) below[a].push_back({b, -w});
  }
  std::vector<int> col_ptr(n + 1, 0), rows;
  std::vector<double> vals;
  for (int j = 0; j < n; ++j) {
    std::sort(below[j].begin(), below[j].end());
    rows.push_back(j);
    vals.push_back(diag[j]);
    for (const auto& [i, w] : below[j]) {
      rows.push_back(i);
      vals.push_back(w);
    }
    col_ptr[j + 1] = static_cast<int>(rows.size());
  }
  chol_ = std::make_unique<SparseCholesky>(n, col_ptr, rows);
  std::copy(vals.begin(), vals.end(), chol_->values());
  chol_->factorize();
}

Layout::Layout(Layout&&) noexcept = default;
Layout::~Layout() = default;

std::unique_ptr<Layout> Layout::clone() const {
  std::unique_ptr<Layout> copy(new Layout(mesh_));
  copy->tree_ = tree_;
  copy->root_ = root_;
  if (chol_) copy->chol_ = std::make_unique<SparseCholesky>(chol_->clone());

  copy->half_.resize(half_.rows(), 6);
  copy->rhs_.resize(rhs_.size());
  return copy;
}

Positions Layout::embed(const Eigen::VectorXd& l2, double* flatness) {
  Positions X;
  embed(l2, X, flatness);
  return X;
}

void Layout::embed(const Eigen::VectorXd& l2, Positions& X, double* flatness) {
  const Mesh& m = *mesh_;
  const Faces& F = m.faces();
  const Faces& FE = m.face_edges();
  if (l2.size() != m.num_edges()) throw InvalidInput("layout: l2 must have one entry per edge");
  const int nf = static_cast<int>(F.rows()), ne = static_cast<int>(l2.size());
  const int n = m.num_vertices() - 1;  // vertex 0 is pinned at the origin
  const int threads = parallel::loop_threads(nf);
  length_.resize(ne);
  broken_.resize(nf);
  rot_.resize(nf, 2);
  X.resize(m.num_vertices(), 2);
  X.setZero();
  rhs_parts_.prepare(threads, X.size());
#pragma omp parallel num_threads(threads) if (threads > 1)
  {
#pragma omp for schedule(static)
    for (int e = 0; e < ne; ++e) length_[e] = std::sqrt(l2[e]);
    // Each face in its own frame: corner 0 at the origin, corner 1 at (l01, 0), corner 2 at
    // (cx, cy) with cx = (l01^2 + l02^2 - l12^2) / (2 l01), cy = 4 area / (2 l01) (no
    // trigonometry). Stored as its three half-edge vectors, h_k running from corner k+1 to k+2.
#pragma omp for schedule(static)
    for (int f = 0; f < nf; ++f) {
      const int* fe = &FE(f, 0);
      const double fl2[3] = {l2[fe[0]], l2[fe[1]], l2[fe[2]]};
      const double l[3] = {length_[fe[0]], length_[fe[1]], length_[fe[2]]};
      const double q = four_area(l);
      double cx, cy;
      broken_[f] = !(q > 0);
      if (!broken_[f]) {
        const double half_inv = 0.5 / l[2];
        cx = (fl2[2] + fl2[1] - fl2[0]) * half_inv;
        cy = q * half_inv;
      } else {  // broken triple (CETM convention of triangle.h): angle pi or 0 at corner 0
        cx = l[0] >= l[1] && l[0] >= l[2] ? -l[1] : l[1];
        cy = 0.0;
      }
      double* h = &half_(f, 0);
      h[0] = cx - l[2];
      h[1] = cy;
      h[2] = -cx;
      h[3] = -cy;
      h[4] = l[2];
      h[5] = 0.0;
    }
    // Rotations as unit complex numbers (cos, sin), propagated over the dual tree: the shared edge
    // is the same vector seen from both faces, run in opposite directions, so
    // rot_g = -rot_f h_f conj(h_g) / |h_f h_g|, where |h_f| = |h_g| = the edge's length unless a
    // face is broken (its sides then do not close up).
#pragma omp single
    {
      rot_.row(root_) << 1.0, 0.0;
      for (const TreeStep& st : tree_) {
        const double* hf = &half_(st.parent, 2 * st.parent_corner);
        const double* hg = &half_(st.face, 2 * st.face_corner);
        const double qr = -(hf[0] * hg[0] + hf[1] * hg[1]), qi = hf[0] * hg[1] - hf[1] * hg[0];
        const double fr = rot_(st.parent, 0), fi = rot_(st.parent, 1);
        const double zr = fr * qr - fi * qi, zi = fr * qi + fi * qr;
        const double inv = broken_[st.face] || broken_[st.parent] ? 1.0 / std::sqrt(zr * zr + zi * zi)
                                                                  : 1.0 / l2[FE(st.face, st.face_corner)];
        rot_(st.face, 0) = zr * inv;
        rot_(st.face, 1) = zi * inv;
      }
    }
    // Least squares over all half-edge vectors: the right-hand side gathers, per vertex, the
    // rotated half-edges arriving minus those leaving (per-thread arrays, summed below).
    double* acc = rhs_parts_.buffer(parallel::thread_index(), X.data());  // (x, y) per vertex
    if (acc != X.data()) std::fill_n(acc, X.size(), 0.0);
#pragma omp for schedule(static)
    for (int f = 0; f < nf; ++f) {
      const double c = rot_(f, 0), s = rot_(f, 1);
      const double* h = &half_(f, 0);
      double v[3][2];
      for (int k = 0; k < 3; ++k) {
        v[k][0] = c * h[2 * k] - s * h[2 * k + 1];
        v[k][1] = s * h[2 * k] + c * h[2 * k + 1];
      }
      for (int k = 0; k < 3; ++k) {  // corner k: h_{k+2} arrives, h_{k+1} leaves
        const int in = (k + 2) % 3, out = (k + 1) % 3;
        acc[2 * F(f, k)] += v[in][0] - v[out][0];
        acc[2 * F(f, k) + 1] += v[in][1] - v[out][1];
      }
    }
  }
  rhs_parts_.add_into(X.data());
  if (n > 0) {
    for (int v = 1; v <= n; ++v) {
      rhs_[v - 1] = X(v, 0);
      rhs_[n + v - 1] = X(v, 1);
    }
    chol_->solve(rhs_.data(), rhs_.data(), 2);
    for (int v = 1; v <= n; ++v) X.row(v) << rhs_[v - 1], rhs_[n + v - 1];
  }
  X.row(0).setZero();
  if (flatness) {
    double worst = 0;
    const Edges& E = m.edges();
#pragma omp parallel for num_threads(threads) if (threads > 1) schedule(static) reduction(max : worst)
    for (int e = 0; e < E.rows(); ++e) {
      const double dx = X(E(e, 1), 0) - X(E(e, 0), 0), dy = X(E(e, 1), 1) - X(E(e, 0), 1);
      worst = std::max(worst, std::abs((dx * dx + dy * dy) / l2[e] - 1.0));
    }
    *flatness = worst;
  }
}

}  // namespace bdinterp
