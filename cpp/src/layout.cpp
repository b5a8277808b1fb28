#include "bdinterp/layout.h"

#include <array>
#include <cmath>
#include <deque>

#include "bdinterp/triangle.h"

namespace bdinterp {
namespace {

// Breadth-first order over the dual graph from `root`; entries (face, parent, shared edge).
std::vector<std::array<int, 3>> dual_tree(const Mesh& m, int root) {
  const Faces& FE = m.face_edges();
  const Edges& EF = m.edge_faces();
  std::vector<bool> seen(m.num_faces(), false);
  std::vector<std::array<int, 3>> order;
  order.reserve(m.num_faces());
  std::deque<int> queue{root};
  seen[root] = true;
  order.push_back({root, -1, -1});
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop_front();
    for (int c = 0; c < 3; ++c) {
      const int e = FE(f, c);
      const int g = EF(e, 0) == f ? EF(e, 1) : EF(e, 0);
      if (g < 0 || seen[g]) continue;
      seen[g] = true;
      order.push_back({g, f, e});
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

  local_.resize(disk.num_faces(), 3);
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

  copy->local_.resize(local_.rows(), 3);
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
  // Corner coordinates of each face in its own frame: corner 0 at the origin, corner 1 on +x.
  // No trigonometry: corner 2 = (l02 cos a0, l02 sin a0) = ((l01^2 + l02^2 - l12^2), 4 area) / (2 l01).
  for (int f = 0; f < F.rows(); ++f) {
    const double fl2[3] = {l2[FE(f, 0)], l2[FE(f, 1)], l2[FE(f, 2)]};
    const double l[3] = {std::sqrt(fl2[0]), std::sqrt(fl2[1]), std::sqrt(fl2[2])};
    double x[3];
    const int longest = excesses(l, x);
    double cx, cy;
    if (x[0] > 0 && x[1] > 0 && x[2] > 0) {
      const double half_inv = 0.5 / l[2];
      cx = (fl2[2] + fl2[1] - fl2[0]) * half_inv;
      cy = std::sqrt((l[0] + l[1] + l[2]) * x[0] * x[1] * x[2]) * half_inv;
    } else {  // broken triple (CETM convention of triangle.h): angle pi or 0 at corner 0
      cx = longest == 0 ? -l[1] : l[1];
      cy = 0.0;
    }
    local_.row(f) << l[2], cx, cy;
  }
  auto corner = [&](int f, int c) {
    return c == 0 ? Eigen::Vector2d(0.0, 0.0)
                  : (c == 1 ? Eigen::Vector2d(local_(f, 0), 0.0) : Eigen::Vector2d(local_(f, 1), local_(f, 2)));
  };
  auto corner_of = [&](int f, int v) {
    return F(f, 0) == v ? 0 : (F(f, 1) == v ? 1 : 2);
  };
  // Rotations as unit complex numbers (cos, sin): the shared edge a->b must point the same way seen
  // from both faces, i.e. rot_g = rot_f * df * conj(dg) / (|df| |dg|).
  rot_.resize(F.rows(), 2);
  rot_.row(root_) << 1.0, 0.0;
  for (size_t k = 1; k < tree_.size(); ++k) {
    const auto [g, f, e] = tree_[k];
    const int a = m.edges()(e, 0), b = m.edges()(e, 1);
    const Eigen::Vector2d df = corner(f, corner_of(f, b)) - corner(f, corner_of(f, a));
    const Eigen::Vector2d dg = corner(g, corner_of(g, b)) - corner(g, corner_of(g, a));
    // q = df * conj(dg)
    const double qr = df.x() * dg.x() + df.y() * dg.y(), qi = df.y() * dg.x() - df.x() * dg.y();
    const double fr = rot_(f, 0), fi = rot_(f, 1);
    double zr = fr * qr - fi * qi, zi = fr * qi + fi * qr;
    const double inv = 1.0 / std::sqrt(zr * zr + zi * zi);
    rot_.row(g) << zr * inv, zi * inv;
  }
  X.resize(m.num_vertices(), 2);
  X.row(0).setZero();
  const int n = m.num_vertices() - 1;
  if (n > 0) {
    rhs_.setZero();
    for (int f = 0; f < F.rows(); ++f) {
      const double c = rot_(f, 0), s = rot_(f, 1);
      for (int k = 0; k < 3; ++k) {
        const int ka = (k + 1) % 3, kb = (k + 2) % 3;
        const Eigen::Vector2d d = corner(f, kb) - corner(f, ka);
        const double vx = c * d.x() - s * d.y(), vy = s * d.x() + c * d.y();
        const int a = F(f, ka) - 1, b = F(f, kb) - 1;
        if (b >= 0) {
          rhs_[b] += vx;
          rhs_[n + b] += vy;
        }
        if (a >= 0) {
          rhs_[a] -= vx;
          rhs_[n + a] -= vy;
        }
      }
    }
    chol_->solve(rhs_.data(), rhs_.data(), 2);
    for (int v = 1; v <= n; ++v) X.row(v) << rhs_[v - 1], rhs_[n + v - 1];
  }
  if (flatness) {
    double worst = 0;
    const Edges& E = m.edges();
    for (int e = 0; e < E.rows(); ++e) {
      const double d2 = (X.row(E(e, 1)) - X.row(E(e, 0))).squaredNorm();
      worst = std::max(worst, std::abs(d2 / l2[e] - 1.0));
    }
    *flatness = worst;
  }
}

}  // namespace bdinterp
