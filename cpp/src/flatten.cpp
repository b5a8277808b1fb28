#include "bdinterp/flatten.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "bdinterp/lobachevsky.h"
#include "bdinterp/triangle.h"

namespace bdinterp {
namespace {
constexpr double kTwoPi = 6.28318530717958647692;
constexpr double kHalfPi = 1.57079632679489661923;
}  // namespace

Eigen::VectorXd scale_lengths(const Mesh& mesh, const Eigen::VectorXd& l2, const Eigen::VectorXd& u) {
  const Edges& E = mesh.edges();
  Eigen::VectorXd out(E.rows());
  for (int e = 0; e < E.rows(); ++e) out[e] = l2[e] * std::exp(u[E(e, 0)] + u[E(e, 1)]);
  return out;
}

Flattener::Flattener(const Mesh& disk) : mesh_(&disk) {
  const int nv = disk.num_vertices();
  interior_index_.assign(nv, -1);
  for (int v = 0; v < nv; ++v) {
    if (!disk.is_boundary_vertex(v) && !disk.is_isolated_vertex(v)) {
      interior_index_[v] = num_interior_++;
      interior_vertex_.push_back(v);
    }
  }
  grad_.resize(num_interior_);
  scaled_l2_.resize(disk.num_edges());
  if (num_interior_ == 0) return;

  // Lower-triangle pattern: column j holds the diagonal and the interior neighbours i > j.
  const Edges& E = disk.edges();
  std::vector<std::vector<std::pair<int, int>>> below(num_interior_);  // (row, edge)
  for (int e = 0; e < E.rows(); ++e) {
    const int a = interior_index_[E(e, 0)], b = interior_index_[E(e, 1)];
    if (a < 0 || b < 0) continue;
    below[std::min(a, b)].push_back({std::max(a, b), e});
  }
  std::vector<int> col_ptr(num_interior_ + 1, 0), rows;
  diag_pos_.resize(num_interior_);
  edge_pos_.assign(E.rows(), -1);
  for (int j = 0; j < num_interior_; ++j) {
    std::sort(below[j].begin(), below[j].end());
    diag_pos_[j] = static_cast<int>(rows.size());
    rows.push_back(j);
    for (const auto& [i, e] : below[j]) {
      edge_pos_[e] = static_cast<int>(rows.size());
      rows.push_back(i);
    }
    col_ptr[j + 1] = static_cast<int>(rows.size());
  }
  nnz_ = static_cast<int>(rows.size());
  chol_ = std::make_unique<SparseCholesky>(num_interior_, col_ptr, rows);
}

Flattener::Flattener(Flattener&&) noexcept = default;
Flattener::~Flattener() = default;

std::unique_ptr<Flattener> Flattener::clone() const {
  std::unique_ptr<Flattener> copy(new Flattener(mesh_));
  copy->nnz_ = nnz_;
  copy->num_interior_ = num_interior_;
  copy->interior_index_ = interior_index_;
  copy->interior_vertex_ = interior_vertex_;
  copy->diag_pos_ = diag_pos_;
  copy->edge_pos_ = edge_pos_;
  if (chol_) copy->chol_ = std::make_unique<SparseCholesky>(chol_->clone());
  copy->grad_.resize(num_interior_);
  copy->scaled_l2_.resize(scaled_l2_.size());
  return copy;
}

Flattener::Eval Flattener::evaluate(const Eigen::VectorXd& l2, const Eigen::VectorXd& u,
                                    bool want_energy, bool want_hessian) const {
  const Mesh& m = *mesh_;
  const Faces& F = m.faces();
  const Faces& FE = m.face_edges();
  const Edges& E = m.edges();
  for (int e = 0; e < E.rows(); ++e) scaled_l2_[e] = l2[e] * std::exp(u[E(e, 0)] + u[E(e, 1)]);
  Eval ev;
  grad_.setConstant(kTwoPi);
  double* H = want_hessian ? chol_->values() : nullptr;
  if (H) std::fill_n(H, nnz_, 0.0);
  double energy = 0;
  for (int f = 0; f < F.rows(); ++f) {
    const double fl2[3] = {scaled_l2_[FE(f, 0)], scaled_l2_[FE(f, 1)], scaled_l2_[FE(f, 2)]};
    const TriangleAngles t = triangle_angles(fl2);
    ev.broken += t.broken;
    for (int c = 0; c < 3; ++c) {
      const int vi = interior_index_[F(f, c)];
      if (vi >= 0) grad_[vi] -= t.angle[c];
    }
    if (want_energy) {
      for (int c = 0; c < 3; ++c) {
        const double lambda = std::log(fl2[c]);
        energy += t.angle[c] * lambda + 2 * lobachevsky(t.angle[c]) - kHalfPi * lambda;
      }
    }
    if (H && !t.broken) {
      for (int c = 0; c < 3; ++c) {
        const double w = 0.5 * t.cot[c];
        const int a = interior_index_[F(f, (c + 1) % 3)], b = interior_index_[F(f, (c + 2) % 3)];
        if (a >= 0) H[diag_pos_[a]] += w;
        if (b >= 0) H[diag_pos_[b]] += w;
        const int p = edge_pos_[FE(f, c)];
        if (p >= 0) H[p] -= w;
      }
    }
  }
  if (want_energy) {
    for (int i = 0; i < num_interior_; ++i) energy += kTwoPi * u[interior_vertex_[i]];
  }
  ev.energy = energy;
  ev.residual = num_interior_ ? grad_.cwiseAbs().maxCoeff() : 0.0;
  return ev;
}

double Flattener::energy(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) const {
  return evaluate(l2, u, true, false).energy;
}

Eigen::VectorXd Flattener::gradient(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) const {
  evaluate(l2, u, false, false);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(mesh_->num_vertices());
  for (int i = 0; i < num_interior_; ++i) g[interior_vertex_[i]] = grad_[i];
  return g;
}

double Flattener::residual(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) const {
  return evaluate(l2, u, false, false).residual;
}

Eigen::SparseMatrix<double> Flattener::hessian(const Eigen::VectorXd& l2,
                                               const Eigen::VectorXd& u) const {
  const Mesh& m = *mesh_;
  const Faces& F = m.faces();
  const Faces& FE = m.face_edges();
  const Eigen::VectorXd s = scale_lengths(m, l2, u);
  std::vector<Eigen::Triplet<double>> trip;
  for (int f = 0; f < F.rows(); ++f) {
    const double fl2[3] = {s[FE(f, 0)], s[FE(f, 1)], s[FE(f, 2)]};
    const TriangleAngles t = triangle_angles(fl2);
    if (t.broken) continue;
    for (int c = 0; c < 3; ++c) {
      const int a = F(f, (c + 1) % 3), b = F(f, (c + 2) % 3);
      if (interior_index_[a] < 0 || interior_index_[b] < 0) {
        // Boundary rows/columns are fixed (u = 0): keep only the interior diagonal part.
        if (interior_index_[a] >= 0) trip.emplace_back(a, a, 0.5 * t.cot[c]);
        if (interior_index_[b] >= 0) trip.emplace_back(b, b, 0.5 * t.cot[c]);
        continue;
      }
      const double w = 0.5 * t.cot[c];
      trip.emplace_back(a, a, w);
      trip.emplace_back(b, b, w);
      trip.emplace_back(a, b, -w);
      trip.emplace_back(b, a, -w);
    }
  }
  Eigen::SparseMatrix<double> Hm(m.num_vertices(), m.num_vertices());
  Hm.setFromTriplets(trip.begin(), trip.end());
  return Hm;
}

FlattenReport Flattener::solve(const Eigen::VectorXd& l2, Eigen::VectorXd& u,
                               const FlattenOptions& options) {
  const Mesh& m = *mesh_;
  if (l2.size() != m.num_edges()) throw InvalidInput("flatten: l2 must have one entry per edge");
  if (u.size() != m.num_vertices()) u = Eigen::VectorXd::Zero(m.num_vertices());
  for (int v = 0; v < m.num_vertices(); ++v)
    if (interior_index_[v] < 0 || !std::isfinite(u[v])) u[v] = 0.0;

  FlattenReport rep;
  Eval cur = evaluate(l2, u, false, true);
  rep.max_broken_triangles = cur.broken;
  double cur_energy = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd step(num_interior_), g(num_interior_), trial = u;
  while (cur.residual > options.tolerance) {
    if (rep.iterations >= options.max_iterations) {
      std::ostringstream s;
      s << "flattening did not converge in " << options.max_iterations
        << " Newton steps (residual " << cur.residual << " > tolerance " << options.tolerance << ")";
      throw SolverError(s.str());
    }
    ++rep.iterations;
    g = grad_;
    // The Hessian is positive definite unless faces degenerate to (pi, 0, 0) around a vertex; then a
    // small diagonal shift keeps the step a descent direction.
    double shift = 0;
    for (int attempt = 0;; ++attempt) {
      try {
        chol_->factorize();
        break;
      } catch (const SolverError&) {
        if (attempt == 3) throw;
        double* H = chol_->values();
        double dmax = 0;
        for (int p : diag_pos_) dmax = std::max(dmax, std::abs(H[p]));
        const double add = (shift == 0 ? 1e-10 : 99 * shift) * std::max(dmax, 1.0);
        for (int p : diag_pos_) H[p] += add;
        shift += add;
      }
    }
    step = -g;
    chol_->solve(step.data(), step.data());
    const double slope = g.dot(step);  // < 0
    double s = 1.0;
    bool energy_known = false;
    for (;;) {
      trial = u;
      for (int i = 0; i < num_interior_; ++i) trial[interior_vertex_[i]] += s * step[i];
      // Full steps that halve the residual are accepted without the energy (quadratic phase).
      Eval next = evaluate(l2, trial, false, false);
      bool accept = std::isfinite(next.residual) && next.residual <= 0.5 * cur.residual;
      energy_known = false;
      if (!accept && std::isfinite(next.residual)) {
        if (std::isnan(cur_energy)) cur_energy = evaluate(l2, u, true, false).energy;
        next = evaluate(l2, trial, true, false);
        const double roundoff = 1e-13 * (std::abs(cur_energy) + 1.0);
        accept = next.energy <= cur_energy + 1e-4 * s * slope ||
                 (std::abs(slope) * s < roundoff && next.residual < cur.residual);
        if (accept) {
          cur_energy = next.energy;
          energy_known = true;
        }
      }
      if (accept) break;
      s *= 0.5;
      ++rep.line_search_steps;
      if (s < 1e-12) {
        std::ostringstream e;
        e << "flattening line search failed (residual " << cur.residual << ")";
        throw SolverError(e.str());
      }
    }
    if (!energy_known) cur_energy = std::numeric_limits<double>::quiet_NaN();
    u.swap(trial);
    cur = evaluate(l2, u, false, true);
    rep.max_broken_triangles = std::max(rep.max_broken_triangles, cur.broken);
  }
  rep.residual = cur.residual;
  rep.broken_triangles = cur.broken;
  return rep;
}

Eigen::VectorXd flatten(const Mesh& disk, const Eigen::VectorXd& l2, const FlattenOptions& options,
                        FlattenReport* report) {
  Flattener fl(disk);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(disk.num_vertices());
  const FlattenReport r = fl.solve(l2, u, options);
  if (report) *report = r;
  return scale_lengths(disk, l2, u);
}

}  // namespace bdinterp
