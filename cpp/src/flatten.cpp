#include "bdinterp/flatten.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "bdinterp/lobachevsky.h"
#include "bdinterp/triangle.h"
#include "bdinterp/parallel.h"

namespace bdinterp {
namespace {
constexpr double kTwoPi = 6.28318530717958647692;
constexpr double kHalfPi = 1.57079632679489661923;
constexpr double kMaxStep = 4.0;  // largest change of any u_i in one Newton step
// CG iterations after the chord step that a factor of a neighbouring frame typically needs.
constexpr int kFreshIterations = 1;
}  // namespace

Eigen::VectorXd scale_lengths(const Mesh& mesh, const Eigen::VectorXd& l2, const Eigen::VectorXd& u) {
  const Edges& E = mesh.edges();
  Eigen::VectorXd out(E.rows());
  for (int e = 0; e < E.rows(); ++e) out[e] = l2[e] * std::exp(u[E(e, 0)] + u[E(e, 1)]);
  return out;
}

Flattener::Flattener(const Mesh& disk) : mesh_(&disk) {
  std::vector<int> col_ptr, rows;
  pattern_ = interior_pattern(disk, col_ptr, rows);
  num_interior_ = pattern_.size();
  grad_.resize(num_interior_ + 1);
  scaled_l2_.resize(disk.num_edges());
  if (num_interior_ == 0) return;
  nnz_ = static_cast<int>(rows.size());
  chol_ = std::make_unique<SparseCholesky>(num_interior_, col_ptr, rows);
  hvals_.assign(nnz_ + 1, 0.0);
  const Faces& F = disk.faces();
  const Faces& FE = disk.face_edges();
  slots_.resize(F.rows());
  for (int f = 0; f < F.rows(); ++f) {
    FaceSlots& s = slots_[f];
    for (int c = 0; c < 3; ++c) {
      const int i = pattern_.index[F(f, c)], p = pattern_.edge_pos[FE(f, c)];
      s.edge[c] = FE(f, c);
      s.row[c] = i >= 0 ? i : num_interior_;
      s.diag[c] = i >= 0 ? pattern_.diag_pos[i] : nnz_;
      s.off[c] = p >= 0 ? p : nnz_;
    }
  }
}

Flattener::Flattener(Flattener&&) noexcept = default;
Flattener::~Flattener() = default;

std::unique_ptr<Flattener> Flattener::clone() const {
  std::unique_ptr<Flattener> copy(new Flattener(mesh_));
  copy->nnz_ = nnz_;
  copy->num_interior_ = num_interior_;
  copy->pattern_ = pattern_;
  copy->slots_ = slots_;
  copy->hvals_ = hvals_;
  if (chol_) copy->chol_ = std::make_unique<SparseCholesky>(chol_->clone());
  copy->grad_.resize(num_interior_ + 1);
  copy->scaled_l2_.resize(scaled_l2_.size());
  copy->factor_reusable_ = factor_reusable_ && chol_;
  copy->factor_cost_ = factor_cost_;
  copy->chord_cost_ = chord_cost_;
  copy->stale_cost_ = stale_cost_;
  copy->shift_ = shift_;
  copy->newton_c_ = newton_c_;
  return copy;
}

namespace {

// Adds the cotan weights (cot / 2) of one face to the Hessian values H (zero for a broken face).
inline void scatter_cotangents(const double cot[3], const int diag[3], const int off[3], double* H) {
  for (int c = 0; c < 3; ++c) {
    const double w = 0.5 * cot[c];
    H[diag[(c + 1) % 3]] += w;
    H[diag[(c + 2) % 3]] += w;
    H[off[c]] -= w;
  }
}

}  // namespace

namespace {

// Multiplies the running product (re, im) of a vertex's corner factors by the factor (a, b) of one
// more corner, a, b > 0: its argument, half the corner's angle, is in (0, pi / 2), so the product's
// argument passed a multiple of 2 pi exactly when it moved from the lower half-plane to the upper
// one; whole turns are added to `sum`. The product is rescaled (by a power of two, exactly) before
// it could overflow or underflow.
inline void turn(double& re, double& im, double& sum, double a, double b) {
  constexpr double kTwoPi = 6.28318530717958647692;
  double nr = re * a - im * b, ni = re * b + im * a;
  sum += (im < 0 && !(ni < 0)) ? kTwoPi : 0.0;
  const double size = std::abs(nr) + std::abs(ni);
  if (size > 0x1p500 || size < 0x1p-500) {
    const double scale = size > 1 ? 0x1p-500 : 0x1p500;
    nr *= scale;
    ni *= scale;
  }
  re = nr;
  im = ni;
}

// The argument of (re, im) in [0, 2 pi), classified by the sign of im as turn() does.
inline double argument(double re, double im) {
  constexpr double kTwoPi = 6.28318530717958647692;
  return fast_atan2(im, re) + (im < 0 ? kTwoPi : 0.0);
}

}  // namespace

Flattener::Eval Flattener::evaluate(const Eigen::VectorXd& l2, const Eigen::VectorXd& u,
                                    bool want_energy, bool want_hessian) const {
  constexpr double kPi = 3.14159265358979323846;
  const Edges& E = mesh_->edges();
  const Eigen::Index nv = u.size(), ne = E.rows(), nf = static_cast<Eigen::Index>(slots_.size());
  const int threads = parallel::loop_threads(nf);
  const int rows = num_interior_ + 1;  // the last row collects the boundary corners
  exp_u_.resize(nv);
  scaled_l2_.resize(ne);
  scaled_len_.resize(ne);
  corner_re_.resize(rows);
  corner_im_.resize(rows);
  double* H = want_hessian && chol_ ? hvals_.data() : nullptr;
  sum_parts_.prepare(threads, rows);
  re_parts_.prepare(threads, rows);
  im_parts_.prepare(threads, rows);
  if (H) hessian_parts_.prepare(threads, nnz_ + 1);
  parallel::PerChunk energies(threads), brokens(threads);
  // exp(u_i + u_j) = exp(u_i) exp(u_j): one exp per vertex instead of one per edge.
  parallel::for_each(threads, nv, [&](int, long v) { exp_u_[v] = u[v] == 0.0 ? 1.0 : std::exp(u[v]); });
  parallel::for_each(threads, ne, [&](int, long e) {
    scaled_l2_[e] = l2[e] * (exp_u_[E(e, 0)] * exp_u_[E(e, 1)]);
    scaled_len_[e] = std::sqrt(scaled_l2_[e]);
  });
  parallel::run(threads, [&](int k) {
    double energy = 0;
    int broken = 0;
    // Angle sums without an arctangent per corner: by the half-angle formula, half the angle at
    // corner c is arg(p x_c + i q) (p the perimeter, x_c Kahan's excess, q = 4 area; accurate for
    // needles), so each vertex multiplies its corners' factors and takes one argument at the end
    // (turn() counts the whole turns): the products hold half the angle sums. Broken faces add
    // (pi, 0, 0), halved, directly. Per-thread arrays.
    double* sum = sum_parts_.buffer(k, grad_.data());
    double* re = re_parts_.buffer(k, corner_re_.data());
    double* im = im_parts_.buffer(k, corner_im_.data());
    double* h = H ? hessian_parts_.buffer(k, H) : nullptr;
    std::fill_n(sum, rows, 0.0);
    std::fill_n(re, rows, 1.0);
    std::fill_n(im, rows, 0.0);
    if (h) std::fill_n(h, nnz_ + 1, 0.0);
    const auto [first, last] = parallel::share(nf, k, threads);
    for (Eigen::Index f = first; f < last; ++f) {
      const FaceSlots& s = slots_[f];
      const double l[3] = {scaled_len_[s.edge[0]], scaled_len_[s.edge[1]], scaled_len_[s.edge[2]]};
      const double fl2[3] = {scaled_l2_[s.edge[0]], scaled_l2_[s.edge[1]], scaled_l2_[s.edge[2]]};
      double x[3], perimeter;
      const double q = excesses(l, x, &perimeter);
      if (!(q > 0)) {  // broken: (pi, 0, 0), zero cotangents (CETM, Sec. 4.2)
        const int c = longest_side(l);
        sum[s.row[c]] += 0.5 * kPi;
        ++broken;
        if (want_energy) {
          for (int m = 0; m < 3; ++m) energy += (m == c ? kPi - kHalfPi : -kHalfPi) * std::log(fl2[m]);
        }
        continue;
      }
      if (want_energy) {  // the line search's path: the angles themselves are needed
        for (int c = 0; c < 3; ++c) {
          const double angle = 2 * atan_positive(q, perimeter * x[c]);
          const double lambda = std::log(fl2[c]);
          sum[s.row[c]] += 0.5 * angle;
          energy += angle * lambda + 2 * lobachevsky(angle) - kHalfPi * lambda;
        }
      } else {
        for (int c = 0; c < 3; ++c) turn(re[s.row[c]], im[s.row[c]], sum[s.row[c]], perimeter * x[c], q);
      }
      if (h) {
        double cot[3];
        cotangents(fl2, q, cot);
        scatter_cotangents(cot, s.diag, s.off, h);
      }
    }
    energies.at(k) = energy;
    brokens.at(k) = broken;
  });
  // The angle sums, every chunk's share, into the gradient 2 pi - sum.
  parallel::for_each(threads, num_interior_, [&](int, long i) {
    double total = 0;
    for (int t = 0; t < threads; ++t) {
      total += sum_parts_.buffer(t, grad_.data())[i] +
               argument(re_parts_.buffer(t, corner_re_.data())[i], im_parts_.buffer(t, corner_im_.data())[i]);
    }
    grad_[i] = kTwoPi - 2 * total;  // the products hold half the angle sums
  });
  double energy = energies.sum();
  const int broken = static_cast<int>(brokens.sum());
  grad_[num_interior_] = 0;
  if (H) hessian_parts_.add_into(H);
  if (want_energy) {
    for (int i = 0; i < num_interior_; ++i) energy += kTwoPi * u[pattern_.vertex[i]];
  }
  Eval ev;
  ev.broken = broken;
  ev.energy = energy;
  ev.residual = num_interior_ ? grad_.head(num_interior_).cwiseAbs().maxCoeff() : 0.0;
  return ev;
}

void Flattener::assemble_from_scaled() const {
  double* H = hvals_.data();
  std::fill(hvals_.begin(), hvals_.end(), 0.0);
  double cot[3];
  for (const FaceSlots& s : slots_) {
    const double fl[3] = {scaled_len_[s.edge[0]], scaled_len_[s.edge[1]], scaled_len_[s.edge[2]]};
    const double fl2[3] = {scaled_l2_[s.edge[0]], scaled_l2_[s.edge[1]], scaled_l2_[s.edge[2]]};
    triangle_cotangents_from_lengths(fl, fl2, cot);
    scatter_cotangents(cot, s.diag, s.off, H);
  }
}

void Flattener::load_hessian() { std::copy_n(hvals_.data(), nnz_, chol_->values()); }

void Flattener::assemble_hessian(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) {
  factor_reusable_ = false;
  if (num_interior_ == 0) return;
  evaluate(l2, u, false, true);
  load_hessian();
}

double Flattener::energy(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) const {
  return evaluate(l2, u, true, false).energy;
}

Eigen::VectorXd Flattener::gradient(const Eigen::VectorXd& l2, const Eigen::VectorXd& u) const {
  evaluate(l2, u, false, false);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(mesh_->num_vertices());
  for (int i = 0; i < num_interior_; ++i) g[pattern_.vertex[i]] = grad_[i];
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
    double cot[3];
    if (triangle_cotangents(fl2, cot)) continue;
    for (int c = 0; c < 3; ++c) {
      const int a = F(f, (c + 1) % 3), b = F(f, (c + 2) % 3);
      if (pattern_.index[a] < 0 || pattern_.index[b] < 0) {
        // Boundary rows/columns are fixed (u = 0): keep only the interior diagonal part.
        if (pattern_.index[a] >= 0) trip.emplace_back(a, a, 0.5 * cot[c]);
        if (pattern_.index[b] >= 0) trip.emplace_back(b, b, 0.5 * cot[c]);
        continue;
      }
      const double w = 0.5 * cot[c];
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

void Flattener::factorize_with_shift() {
  // The Hessian is positive definite unless faces degenerate to (pi, 0, 0) around a vertex; then a
  // small diagonal shift keeps the step a descent direction.
  load_hessian();
  double shift = 0;
  for (int attempt = 0;; ++attempt) {
    try {
      chol_->factorize();
      shift_ = shift;
      return;
    } catch (const SolverError&) {
      if (attempt == 3) throw;
      double* H = chol_->values();
      double dmax = 0;
      for (int p : pattern_.diag_pos) dmax = std::max(dmax, std::abs(H[p]));
      const double add = (shift == 0 ? 1e-10 : 99 * shift) * std::max(dmax, 1.0);
      for (int p : pattern_.diag_pos) H[p] += add;
      shift += add;
    }
  }
}

SparseCholesky& Flattener::factored_hessian(const Eigen::VectorXd& l2, const Eigen::VectorXd& u,
                                            double* shift) {
  if (num_interior_ == 0) throw SolverError("factored_hessian: the piece has no interior vertex");
  if (!factor_reusable_) {  // e.g. an input shape, reproduced by u = 0 without any Newton step
    evaluate(l2, u, false, true);
    factorize_with_shift();
    factor_cost_ = chol_->factor_flops();
    stale_cost_ = 0;
    factor_reusable_ = true;
  }
  *shift = shift_;
  return *chol_;
}

void Flattener::hessian_times(const double* x, double* y) const {
  chol_->multiply(hvals_.data(), x, y);
}

int Flattener::preconditioned_cg(double eta, int max_iterations) {
  // Solves H step_ = -grad_ (H: the values in the solver, M: its factorisation) until the max-norm
  // of the linear residual is <= eta. Returns the number of iterations.
  const int n = num_interior_;
  cg_r_.resize(n);
  cg_z_.resize(n);
  cg_p_.resize(n);
  for (int i = 0; i < n; ++i) step_[i] = -grad_[i];
  chol_->solve(step_.data(), step_.data());  // the chord step
  hessian_times(step_.data(), cg_z_.data());
  for (int i = 0; i < n; ++i) cg_r_[i] = -grad_[i] - cg_z_[i];
  int it = 0;
  if (cg_r_.cwiseAbs().maxCoeff() <= eta) return it;
  chol_->solve(cg_r_.data(), cg_z_.data());
  cg_p_ = cg_z_;
  double rz = cg_r_.dot(cg_z_);
  for (it = 1; it <= max_iterations; ++it) {
    hessian_times(cg_p_.data(), cg_z_.data());  // q = H p, in z's storage
    const double pq = cg_p_.dot(cg_z_);
    if (!(pq > 0)) break;
    const double alpha = rz / pq;
    step_ += alpha * cg_p_;
    cg_r_ -= alpha * cg_z_;
    if (cg_r_.cwiseAbs().maxCoeff() <= eta) break;
    chol_->solve(cg_r_.data(), cg_z_.data());
    const double rz_next = cg_r_.dot(cg_z_);
    cg_p_ = cg_z_ + (rz_next / rz) * cg_p_;
    rz = rz_next;
  }
  return it;
}

namespace {

// Operation-count estimate of one evaluation of angles (atan2, sqrt, exp per face): costs are
// estimated, not timed, so that a solve takes the same path on every machine and every run.
constexpr double kFlopsPerFace = 150;

// Expected cost of reaching `tol` from residual r with chord steps contracting by `rate` each.
double chord_cost(double r, double tol, double rate, double step_cost) {
  if (rate >= 0.5) return std::numeric_limits<double>::infinity();
  return std::ceil(std::log(tol / r) / std::log(rate)) * step_cost;
}

// Expected cost with Newton steps r <- c r^2 (a fresh factorisation each), the last Newton step
// possibly replaced by chord steps with the factor it leaves (contraction about c r).
double newton_cost(double r, double tol, double c, double newton_step_cost, double step_cost) {
  double cost = 0;
  for (int k = 0; k < 8 && r > tol; ++k) {
    const double next = std::min(c * r * r, 0.5 * r);
    cost += newton_step_cost;
    if (next <= tol) return cost;
    const double rate = std::min(c * r, 0.5);
    const double chord = chord_cost(next, tol, rate, step_cost);
    if (chord < newton_step_cost) return cost + chord;
    r = next;
  }
  return cost;
}

}  // namespace

double Flattener::evaluation_cost() const { return kFlopsPerFace * mesh_->num_faces(); }

FlattenReport Flattener::solve(const Eigen::VectorXd& l2, Eigen::VectorXd& u,
                               const FlattenOptions& options) {
  const Mesh& m = *mesh_;
  if (l2.size() != m.num_edges()) throw InvalidInput("flatten: l2 must have one entry per edge");
  if (u.size() != m.num_vertices()) u = Eigen::VectorXd::Zero(m.num_vertices());
  for (int v = 0; v < m.num_vertices(); ++v)
    if (pattern_.index[v] < 0 || !std::isfinite(u[v])) u[v] = 0.0;

  FlattenReport rep;
  // One pass gives the residual and, should a step follow, the Hessian at u.
  Eval cur = evaluate(l2, u, false, num_interior_ > 0);  // scaled_l2_, grad_, Hessian describe u
  bool hessian_at_u = num_interior_ > 0;
  rep.max_broken_triangles = cur.broken;
  double cur_energy = std::numeric_limits<double>::quiet_NaN();
  step_.resize(num_interior_);
  trial_ = u;
  // Chord steps are tried first when an earlier factorisation is available (the previous frame's).
  bool try_chord = options.reuse_factorization && factor_reusable_ && num_interior_ > 0;
  bool grad_at_u = true;  // grad_ and scaled_l2_ describe u (else they describe a rejected trial)
  auto fail = [&](const char* what) {
    std::ostringstream s;
    s << what << " (residual " << cur.residual << " > tolerance " << options.tolerance << ")";
    throw SolverError(s.str());
  };
  while (cur.residual > options.tolerance) {
    if (rep.iterations >= options.max_iterations) {
      std::ostringstream s;
      s << "flattening did not converge in " << options.max_iterations << " Newton steps";
      fail(s.str().c_str());
    }
    ++rep.iterations;
    if (try_chord) {
      // Newton step with the Hessian at u, solved by conjugate gradients preconditioned with the
      // earlier factorisation: a few solves instead of a factorisation.
      if (!hessian_at_u) assemble_from_scaled();
      hessian_at_u = true;
      // Inexact Newton: the linear residual need only be small next to the tolerance and to the
      // quadratic error term; solving further costs solves without improving the accepted step.
      const double eta = std::max(0.5 * options.tolerance,
                                  std::min(1e-3 * cur.residual, 0.1 * cur.residual * cur.residual));
      const int cg_iterations = preconditioned_cg(eta, 12);
      for (int i = 0; i < num_interior_; ++i) {
        const int v = pattern_.vertex[i];
        trial_[v] = u[v] + step_[i];
      }
      const Eval next = evaluate(l2, trial_, false, false);
      chord_cost_ = (cg_iterations + 1) * (chol_->solve_flops() + 4.0 * nnz_) + evaluation_cost();
      if (std::isfinite(next.residual) && next.residual <= 0.5 * cur.residual) {
        const double rate = next.residual / cur.residual;
        u.swap(trial_);
        cur = next;
        hessian_at_u = false;
        cur_energy = std::numeric_limits<double>::quiet_NaN();
        ++rep.chord_steps;
        rep.max_broken_triangles = std::max(rep.max_broken_triangles, cur.broken);
        // Ski rental across solves: an aging factor needs more CG iterations than a fresh one
        // would; once those extra iterations have cost as much as a factorisation, factorise the
        // Hessian at hand so that the next solves start fresh. Never worse than twice the better
        // of always and never refactorising.
        stale_cost_ += std::max(0, cg_iterations - kFreshIterations) * (chol_->solve_flops() + 4.0 * nnz_);
        if (stale_cost_ >= factor_cost_) {
          factorize_with_shift();
          ++rep.factorizations;
          stale_cost_ = 0;
        }
        // Keep chording while that is expected to be cheaper than a fresh Newton step.
        const double newton = factor_cost_ + chord_cost_;
        try_chord = chord_cost(cur.residual, options.tolerance, rate, chord_cost_) <=
                    newton_cost(cur.residual, options.tolerance, newton_c_, newton, chord_cost_);
        continue;
      }
      try_chord = false;
      grad_at_u = false;
    }
    // A Newton step with a fresh factorisation at u.
    if (grad_at_u) {
      if (!hessian_at_u) assemble_from_scaled();
    } else {
      evaluate(l2, u, false, true);
      grad_at_u = true;
    }
    factorize_with_shift();
    stale_cost_ = 0;
    factor_cost_ = chol_->factor_flops();
    factor_reusable_ = true;
    ++rep.factorizations;
    for (int i = 0; i < num_interior_; ++i) step_[i] = -grad_[i];
    chol_->solve(step_.data(), step_.data());
    // Far from the solution, faces broken to (pi, 0, 0) make the energy piecewise linear and the
    // Hessian nearly singular: cap the change of the log-scale factors (e^4 ~ 55x a length).
    const double longest = step_.cwiseAbs().maxCoeff();
    if (longest > kMaxStep) step_ *= kMaxStep / longest;
    double slope = 0;  // < 0
    for (int i = 0; i < num_interior_; ++i) slope += grad_[i] * step_[i];
    if (!(slope < 0)) {  // numerically singular Hessian: fall back to steepest descent
      const double gmax = std::max(grad_.head(num_interior_).cwiseAbs().maxCoeff(), 1e-300);
      slope = 0;
      for (int i = 0; i < num_interior_; ++i) {
        step_[i] = -grad_[i] * (kMaxStep / gmax);
        slope += grad_[i] * step_[i];
      }
    }
    double s = 1.0;
    Eval next;
    for (;;) {
      for (int i = 0; i < num_interior_; ++i) {
        const int v = pattern_.vertex[i];
        trial_[v] = u[v] + s * step_[i];
      }
      // Full steps that halve the residual are accepted without the energy (quadratic phase).
      next = evaluate(l2, trial_, false, false);
      bool accept = std::isfinite(next.residual) && next.residual <= 0.5 * cur.residual;
      bool energy_known = false;
      if (!accept && std::isfinite(next.residual)) {
        if (std::isnan(cur_energy)) cur_energy = evaluate(l2, u, true, false).energy;
        next = evaluate(l2, trial_, true, false);
        const double roundoff = 1e-13 * (std::abs(cur_energy) + 1.0);
        accept = next.energy <= cur_energy + 1e-4 * s * slope ||
                 (std::abs(slope) * s < roundoff && next.residual < cur.residual);
        energy_known = accept;
      }
      if (accept) {
        cur_energy = energy_known ? next.energy : std::numeric_limits<double>::quiet_NaN();
        break;
      }
      s *= 0.5;
      ++rep.line_search_steps;
      if (s < 1e-12) fail("flattening line search failed");
    }
    // The last evaluate was at the accepted trial: grad_ and scaled_l2_ describe the new u.
    if (s == 1.0 && cur.residual > 0) newton_c_ = next.residual / (cur.residual * cur.residual);
    const double newton_rate = next.residual / cur.residual;
    u.swap(trial_);
    cur = next;
    hessian_at_u = false;
    rep.max_broken_triangles = std::max(rep.max_broken_triangles, cur.broken);
    // Chord steps with this factor contract about as much as this Newton step did.
    if (options.reuse_factorization && s == 1.0 && cur.residual > options.tolerance) {
      const double step = chord_cost_ > 0 ? chord_cost_ : chol_->solve_flops() + evaluation_cost();
      const double newton = factor_cost_ + step;
      try_chord = chord_cost(cur.residual, options.tolerance, newton_rate, step) <=
                  newton_cost(cur.residual, options.tolerance, newton_c_, newton, step);
    }
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
