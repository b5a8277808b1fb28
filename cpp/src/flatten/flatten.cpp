#include "flatten/flatten.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "flatten/flatten_state.h"

namespace bdinterp {

void validate(const FlattenOptions& o) {
  if (!(o.tolerance >= 0) || !std::isfinite(o.tolerance)) {
    std::ostringstream s;
    s << "flatten options: tolerance must be finite and >= 0 (got " << o.tolerance << ")";
    throw InvalidInput(s.str());
  }
  if (!(o.refinement >= 0 && o.refinement <= 1)) {
    std::ostringstream s;
    s << "flatten options: refinement must be in [0, 1] (got " << o.refinement << ")";
    throw InvalidInput(s.str());
  }
  if (o.max_iterations < 0) {
    throw InvalidInput("flatten options: max_iterations must be >= 0 (got " + std::to_string(o.max_iterations) +
                       ")");
  }
}

void merge(FlattenReport& into, const FlattenReport& other) {
  into.iterations = std::max(into.iterations, other.iterations);
  into.residual = std::max(into.residual, other.residual);
  into.broken_triangles = std::max(into.broken_triangles, other.broken_triangles);
  into.max_broken_triangles = std::max(into.max_broken_triangles, other.max_broken_triangles);
  into.line_search_steps += other.line_search_steps;
  into.factorizations += other.factorizations;
  into.chord_steps += other.chord_steps;
  into.convex_solves += other.convex_solves;
}

Eigen::VectorXd scale_lengths(const Mesh& mesh, const Eigen::VectorXd& l2, const Eigen::VectorXd& u) {
  const Edges& E = mesh.edges();
  // exp(u_i + u_j) = exp(u_i) exp(u_j), as the flattening's evaluation scales: one exp per vertex.
  const Eigen::VectorXd exp_u = u.array().exp();
  Eigen::VectorXd out(E.rows());
  for (int e = 0; e < E.rows(); ++e) out[e] = l2[e] * (exp_u[E(e, 0)] * exp_u[E(e, 1)]);
  return out;
}

FlattenUnknowns interior_unknowns(const Mesh& mesh) {
  FlattenUnknowns u;
  u.of_vertex.assign(mesh.num_vertices(), -1);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.is_boundary_vertex(v) || mesh.is_isolated_vertex(v)) continue;
    u.of_vertex[v] = static_cast<int>(u.target.size());
    u.target.push_back(2 * kPi);
  }
  return u;
}

FlattenPlan::FlattenPlan(const Mesh& disk) : FlattenPlan(disk, interior_unknowns(disk)) {}

FlattenPlan::FlattenPlan(const Mesh& piece, FlattenUnknowns unknowns) : mesh(piece) {
  const int n = static_cast<int>(unknowns.target.size());
  if (static_cast<int>(unknowns.of_vertex.size()) != piece.num_vertices())
    throw InvalidInput("flatten: of_vertex must have one entry per vertex");
  for (int k : unknowns.of_vertex)
    if (k < -1 || k >= n) throw InvalidInput("flatten: unknown " + std::to_string(k) + " out of range");
  std::vector<int> col_ptr, rows;
  pattern = unknowns_pattern(piece, unknowns.of_vertex, n, col_ptr, rows);
  target = Eigen::Map<const Eigen::VectorXd>(unknowns.target.data(), n);
  for (int v = 0; v < piece.num_vertices(); ++v)
    if (pattern.index[v] >= 0) moved.push_back(v);
  const int nnz = static_cast<int>(rows.size());
  if (n > 0) analysis = std::make_shared<const CholeskyAnalysis>(n, std::move(col_ptr), std::move(rows));
  const Faces& F = piece.faces();
  const Faces& FE = piece.face_edges();
  slots.resize(F.rows());
  for (int f = 0; f < F.rows(); ++f) {
    FaceSlots& s = slots[f];
    for (int c = 0; c < 3; ++c) {
      const int i = pattern.index[F(f, c)], p = pattern.edge_pos[FE(f, c)];
      const int a = pattern.index[F(f, (c + 1) % 3)], b = pattern.index[F(f, (c + 2) % 3)];
      s.edge[c] = FE(f, c);
      s.row[c] = i >= 0 ? i : n;
      s.diag[c] = i >= 0 ? pattern.diag_pos[i] : nnz;
      // Both ends one unknown (a hole's loop): w + w - 2w = 0, so no term at all.
      s.off[c] = a >= 0 && a == b ? -1 : (p >= 0 ? p : nnz);
    }
  }
}

void Flattener::State::factorize_with_shift() {
  const std::vector<int>& diag = plan.pattern.diag_pos;
  double* H = factor->values();
  std::copy_n(hessian.data(), plan.nnz(), H);
  double total = 0;
  for (int attempt = 0;; ++attempt) {
    try {
      factor->factorize();
      shift = total;
      return;
    } catch (const SolverError&) {
      if (attempt == 3) throw;
      double dmax = 0;
      for (int p : diag) dmax = std::max(dmax, std::abs(H[p]));
      const double add = (total == 0 ? 1e-10 : 99 * total) * std::max(dmax, 1.0);
      for (int p : diag) H[p] += add;
      total += add;
    }
  }
}

Flattener::Flattener(const Mesh& disk) : Flattener(std::make_shared<const FlattenPlan>(disk)) {}
Flattener::Flattener(std::shared_ptr<const FlattenPlan> plan)
    : plan_(std::move(plan)), state_(std::make_unique<State>(*plan_)) {}
Flattener::Flattener(Flattener&&) noexcept = default;
Flattener& Flattener::operator=(Flattener&&) noexcept = default;
Flattener::~Flattener() = default;

namespace {

void check_sizes(const Mesh& m, const Eigen::VectorXd& l2, const Eigen::VectorXd& u) {
  if (l2.size() != m.num_edges() || u.size() != m.num_vertices()) {
    std::ostringstream s;
    s << "flatten: got " << l2.size() << " squared lengths and " << u.size() << " factors for a mesh with "
      << m.num_edges() << " edges and " << m.num_vertices() << " vertices";
    throw InvalidInput(s.str());
  }
}

}  // namespace

double Flattener::energy(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) {
  check_sizes(plan_->mesh, l2, u);
  state_->evaluate(l2, u, true, false, state_->trial);
  return state_->trial.energy;
}

Eigen::VectorXd Flattener::gradient(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) {
  check_sizes(plan_->mesh, l2, u);
  state_->evaluate(l2, u, false, false, state_->trial);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(plan_->mesh.num_vertices());
  for (int i = 0; i < num_interior(); ++i) g[plan_->pattern.vertex[i]] = state_->trial.defect[i];
  return g;
}

double Flattener::residual(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) {
  check_sizes(plan_->mesh, l2, u);
  state_->evaluate(l2, u, false, false, state_->trial);
  return state_->trial.residual;
}

Eigen::SparseMatrix<double> Flattener::hessian(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) {
  check_sizes(plan_->mesh, l2, u);
  const int nv = plan_->mesh.num_vertices();
  Eigen::SparseMatrix<double> Hm(nv, nv);
  if (!plan_->analysis) return Hm;
  std::vector<double> H(plan_->nnz() + 1);
  state_->evaluator.evaluate(l2, u, false, H.data(), state_->trial);
  const std::vector<int>& col_ptr = plan_->analysis->column_pointers();
  const std::vector<int>& rows = plan_->analysis->row_indices();
  const std::vector<int>& vertex = plan_->pattern.vertex;
  std::vector<Eigen::Triplet<double>> trip;
  for (int j = 0; j < num_interior(); ++j) {
    for (int p = col_ptr[j]; p < col_ptr[j + 1]; ++p) {
      trip.emplace_back(vertex[rows[p]], vertex[j], H[p]);
      if (rows[p] != j) trip.emplace_back(vertex[j], vertex[rows[p]], H[p]);
    }
  }
  Hm.setFromTriplets(trip.begin(), trip.end());
  return Hm;
}

const Eigen::VectorXd& Flattener::flat_squared_lengths() const { return state_->cur.scaled_l2; }

SparseCholesky& Flattener::factored_hessian(const Eigen::VectorXd& l2, const Eigen::VectorXd& u, double* shift) {
  State& s = *state_;
  if (!s.factor) throw SolverError("factored_hessian: the piece has no interior vertex");
  if (!s.factor_reusable) {  // e.g. an input shape, reproduced by u = 0 without any Newton step
    check_sizes(plan_->mesh, l2, u);
    s.evaluate(l2, u, false, true, s.trial);
    s.hessian_at_cur = false;
    s.hessian_drift = HUGE_VAL;  // assembled elsewhere
    s.factorize_with_shift();
    s.policy.refactorised();
    s.factor_reusable = true;
  }
  *shift = s.shift;
  return *s.factor;
}

void Flattener::assemble_hessian(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) {
  State& s = *state_;
  s.factor_reusable = false;
  if (!s.factor) return;
  check_sizes(plan_->mesh, l2, u);
  s.evaluate(l2, u, false, true, s.trial);
  s.hessian_at_cur = false;
  s.hessian_drift = HUGE_VAL;
  std::copy_n(s.hessian.data(), plan_->nnz(), s.factor->values());
}

SparseCholesky* Flattener::cholesky() {
  state_->factor_reusable = false;
  return state_->factor ? &*state_->factor : nullptr;
}

bool Flattener::has_reusable_factorization() const { return state_->factor_reusable; }

void Flattener::forget() {
  state_->factor_reusable = false;
  state_->policy = State::fresh_policy(*plan_);
}

}  // namespace bdinterp
