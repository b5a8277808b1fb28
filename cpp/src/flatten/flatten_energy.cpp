#include "flatten/flatten_energy.h"

#include <algorithm>
#include <cmath>

#include "flatten/lobachevsky.h"
#include "mesh/triangle.h"
#include "mesh/turns.h"

namespace bdinterp::detail {
namespace {
constexpr double kHalfPi = 1.57079632679489661923;
using FaceSlots = FlattenPlan::FaceSlots;

// Adds the cotan weights (cot / 2) of one face to the Hessian values H.
inline void scatter_cotangents(const double cot[3], const FaceSlots& s, double* H) {
  for (int c = 0; c < 3; ++c) {
    if (s.off[c] < 0) continue;
    const double w = 0.5 * cot[c];
    H[s.diag[(c + 1) % 3]] += w;
    H[s.diag[(c + 2) % 3]] += w;
    H[s.off[c]] -= w;
  }
}

// Per-thread accumulators of one pass: half-angle sums (whole turns, broken faces), running
// products, Hessian values.
struct Accumulator {
  double *sum, *re, *im, *h;
  double energy = 0;
  int broken = 0;
};

// One face's share of the angle sums (and the energy, and the Hessian, as asked).
inline void accumulate_face(const FaceSlots& s, const Evaluation& ev, bool want_energy, Accumulator& a) {
  const double l[3] = {ev.scaled_len[s.edge[0]], ev.scaled_len[s.edge[1]], ev.scaled_len[s.edge[2]]};
  const double l2[3] = {ev.scaled_l2[s.edge[0]], ev.scaled_l2[s.edge[1]], ev.scaled_l2[s.edge[2]]};
  double x[3], perimeter;
  const double q = excesses(l, x, &perimeter);
  if (!(q > 0)) {  // broken: (pi, 0, 0), halved; zero cotangents
    const int c = longest_side(l);
    a.sum[s.row[c]] += 0.5 * kPi;
    ++a.broken;
    if (want_energy) {
      for (int m = 0; m < 3; ++m) a.energy += (m == c ? kPi - kHalfPi : -kHalfPi) * std::log(l2[m]);
    }
    return;
  }
  for (int c = 0; c < 3; ++c) turn(a.re[s.row[c]], a.im[s.row[c]], a.sum[s.row[c]], perimeter * x[c], q);
  if (want_energy) {  // the line search's path: the angles themselves are needed
    for (int c = 0; c < 3; ++c) {
      const double angle = 2 * atan_positive(q, perimeter * x[c]);
      const double lambda = std::log(l2[c]);
      a.energy += angle * lambda + 2 * lobachevsky(angle) - kHalfPi * lambda;
    }
  }
  if (a.h) {
    double cot[3];
    cotangents(l2, q, cot);
    scatter_cotangents(cot, s, a.h);
  }
}

}  // namespace

void EnergyEvaluator::scale(const Eigen::VectorXd& l2, const Eigen::VectorXd& u, Evaluation& out) {
  const Edges& E = plan_->mesh.edges();
  const Eigen::Index nv = u.size(), ne = E.rows();
  exp_u_.resize(nv);
  out.scaled_l2.resize(ne);
  out.scaled_len.resize(ne);
  // exp(u_i + u_j) = exp(u_i) exp(u_j): one exp per vertex instead of one per edge.
  parallel::Loop(nv).run([&](int, long v) { exp_u_[v] = u[v] == 0.0 ? 1.0 : std::exp(u[v]); });
  parallel::Loop(ne).run([&](int, long e) {
    out.scaled_l2[e] = l2[e] * (exp_u_[E(e, 0)] * exp_u_[E(e, 1)]);
    out.scaled_len[e] = std::sqrt(out.scaled_l2[e]);
  });
}

void EnergyEvaluator::evaluate(const Eigen::VectorXd& l2, const Eigen::VectorXd& u, bool want_energy,
                               double* H, Evaluation& out) {
  const long nf = static_cast<long>(plan_->slots.size());
  const int n = plan_->num_interior(), rows = n + 1;  // the last row collects the boundary corners
  const parallel::Loop faces(nf);
  const int threads = faces.chunks();
  scale(l2, u, out);
  out.defect.resize(rows);
  corner_re_.resize(rows);
  corner_im_.resize(rows);
  sum_parts_.prepare(threads, rows);
  re_parts_.prepare(threads, rows);
  im_parts_.prepare(threads, rows);
  if (H) hessian_parts_.prepare(threads, plan_->nnz() + 1);
  for (int k = 0; k < threads; ++k) {
    std::fill_n(sum_parts_.buffer(k, out.defect.data()), rows, 0.0);
    std::fill_n(re_parts_.buffer(k, corner_re_.data()), rows, 1.0);
    std::fill_n(im_parts_.buffer(k, corner_im_.data()), rows, 0.0);
    if (H) std::fill_n(hessian_parts_.buffer(k, H), plan_->nnz() + 1, 0.0);
  }
  parallel::PerChunk energies(threads), brokens(threads);
  faces.run([&](int k, long f) {
    Accumulator a{sum_parts_.buffer(k, out.defect.data()), re_parts_.buffer(k, corner_re_.data()),
                  im_parts_.buffer(k, corner_im_.data()), H ? hessian_parts_.buffer(k, H) : nullptr};
    accumulate_face(plan_->slots[f], out, want_energy, a);
    energies.at(k) += a.energy;
    brokens.at(k) += a.broken;
  });
  double energy = energies.sum();
  const int broken = static_cast<int>(brokens.sum());
  // Every thread's share of the half-angle sums, into the gradient target - sum: the chunks' products
  // multiplied together, so one arctangent per vertex however many chunks (two took 5 % of a warm
  // 5k frame run serially on a busy machine).
  const Eigen::VectorXd& target = plan_->target;
  parallel::Loop(n).run([&](int, long i) {
    double sum = out.defect[i], re = corner_re_[i], im = corner_im_[i];
    for (int t = 1; t < threads; ++t) {
      sum += sum_parts_.buffer(t, nullptr)[i];
      combine_turns(re, im, sum, re_parts_.buffer(t, nullptr)[i], im_parts_.buffer(t, nullptr)[i]);
    }
    out.defect[i] = target[i] - 2 * (sum + argument(re, im));
  });
  out.defect[n] = 0;
  if (H) hessian_parts_.add_into(H);
  if (want_energy) {
    for (int i = 0; i < n; ++i) energy += target[i] * u[plan_->pattern.vertex[i]];
  }
  out.broken = broken;
  out.energy = energy;
  out.has_energy = want_energy;
  out.residual = n ? out.defect.head(n).cwiseAbs().maxCoeff() : 0.0;
}

void EnergyEvaluator::assemble_hessian(const Evaluation& at, double* H) {
  const long nf = static_cast<long>(plan_->slots.size());
  const parallel::Loop faces(nf);
  const int size = plan_->nnz() + 1;
  hessian_parts_.prepare(faces.chunks(), size);
  for (int k = 0; k < faces.chunks(); ++k) std::fill_n(hessian_parts_.buffer(k, H), size, 0.0);
  faces.run([&](int k, long f) {
    const FaceSlots& s = plan_->slots[f];
    const double l[3] = {at.scaled_len[s.edge[0]], at.scaled_len[s.edge[1]], at.scaled_len[s.edge[2]]};
    const double l2[3] = {at.scaled_l2[s.edge[0]], at.scaled_l2[s.edge[1]], at.scaled_l2[s.edge[2]]};
    double cot[3];
    if (!triangle_cotangents_from_lengths(l, l2, cot))
      scatter_cotangents(cot, s, hessian_parts_.buffer(k, H));
  });
  hessian_parts_.add_into(H);
}

}  // namespace bdinterp::detail
