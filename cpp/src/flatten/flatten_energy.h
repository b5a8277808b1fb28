// Internal: the one pass over the faces that every flattening step needs — the angle sums (the
// energy's gradient), optionally the energy itself and the Hessian values — and the Hessian alone
// from lengths already scaled. Both assemble per face with the same functions.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "flatten/flatten.h"
#include "parallel/parallel.h"

namespace bdinterp::detail {

// What one pass computed at some u.
struct Evaluation {
  Eigen::VectorXd defect;      // #unknowns + 1: target - angle sum, the gradient (last entry: 0)
  Eigen::VectorXd scaled_l2;   // #E: exp(u_i + u_j) l2_ij
  Eigen::VectorXd scaled_len;  // #E: its square roots
  double residual = 0;         // max |defect|
  double energy = 0;           // valid if has_energy
  bool has_energy = false;
  int broken = 0;              // faces violating the triangle inequality
};

// One thread's scratch for evaluations over a shared plan.
class EnergyEvaluator {
 public:
  explicit EnergyEvaluator(const FlattenPlan& plan) : plan_(&plan) {}

  // At (l2, u) (#E, #V): fills `out`; with want_energy also the energy; with H (nnz + 1 values, the
  // last a spare slot) also the Hessian values in the pattern's order. Half of each angle is the
  // argument of p x_c + i q (p the perimeter, x_c Kahan's excess, q = 4 area; accurate for needles):
  // each vertex multiplies its corners' factors and takes one argument at the end, so there is no
  // arctangent per corner. Broken faces count as (pi, 0, 0) with zero cotangents (CETM, Sec. 4.2).
  void evaluate(const Eigen::VectorXd& l2, const Eigen::VectorXd& u, bool want_energy, double* H,
                Evaluation& out);
  // The Hessian values at the scaled lengths of `at` into H (nnz + 1), without angles.
  void assemble_hessian(const Evaluation& at, double* H);

 private:
  void scale(const Eigen::VectorXd& l2, const Eigen::VectorXd& u, Evaluation& out);

  const FlattenPlan* plan_;
  parallel::Partials sum_parts_, re_parts_, im_parts_, hessian_parts_;
  Eigen::VectorXd corner_re_, corner_im_;  // #interior + 1: thread 0's running products
  Eigen::VectorXd exp_u_;                  // #V
};

}  // namespace bdinterp::detail
