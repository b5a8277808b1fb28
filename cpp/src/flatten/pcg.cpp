#include "flatten/pcg.h"

namespace bdinterp::detail {

int preconditioned_cg(SparseCholesky& M, const double* A_values, const Eigen::VectorXd& b, double eta,
                      int max_iterations, Eigen::VectorXd& x, PcgScratch& s) {
  const int n = M.size();
  s.r.resize(n);
  s.z.resize(n);
  s.p.resize(n);
  x.resize(n);
  M.precondition(b.data(), x.data());  // the chord step
  M.multiply(A_values, x.data(), s.z.data());
  s.r = b - s.z;
  int it = 0;
  if (s.r.cwiseAbs().maxCoeff() <= eta) return it;
  M.precondition(s.r.data(), s.z.data());
  s.p = s.z;
  double rz = s.r.dot(s.z);
  for (it = 1; it <= max_iterations; ++it) {
    M.multiply(A_values, s.p.data(), s.z.data());  // q = A p, in z's storage
    const double pq = s.p.dot(s.z);
    if (!(pq > 0)) break;
    const double alpha = rz / pq;
    x += alpha * s.p;
    s.r -= alpha * s.z;
    if (s.r.cwiseAbs().maxCoeff() <= eta) break;
    M.precondition(s.r.data(), s.z.data());
    const double rz_next = s.r.dot(s.z);
    s.p = s.z + (rz_next / rz) * s.p;
    rz = rz_next;
  }
  return it;
}

}  // namespace bdinterp::detail
