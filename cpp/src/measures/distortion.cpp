#include "bdinterp/distortion.h"

#include <Eigen/Dense>
#include <cfloat>
#include <cmath>
#include <limits>
#include <sstream>

namespace bdinterp {
namespace {

// Calls fn(f, J) with the 2x2 Jacobian of every face after validating the arrays.
template <typename Fn>
void for_each_jacobian(const Eigen::Ref<const Positions>& X0, const Eigen::Ref<const Positions>& X1,
                       const Eigen::Ref<const Faces>& F, Fn fn) {
  if (X0.rows() != X1.rows()) {
    std::ostringstream s;
    s << "source has " << X0.rows() << " vertices, result has " << X1.rows();
    throw InvalidInput(s.str());
  }
  for (int f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      if (F(f, c) < 0 || F(f, c) >= X0.rows()) {
        std::ostringstream s;
        s << "vertex index " << F(f, c) << " out of range [0, " << X0.rows() << ")";
        throw InvalidInput(Where::of_face(f), s.str());
      }
    }
    Eigen::Matrix2d D0, D1;
    D0 << X0(F(f, 1), 0) - X0(F(f, 0), 0), X0(F(f, 2), 0) - X0(F(f, 0), 0),
        X0(F(f, 1), 1) - X0(F(f, 0), 1), X0(F(f, 2), 1) - X0(F(f, 0), 1);
    D1 << X1(F(f, 1), 0) - X1(F(f, 0), 0), X1(F(f, 2), 0) - X1(F(f, 0), 0),
        X1(F(f, 1), 1) - X1(F(f, 0), 1), X1(F(f, 2), 1) - X1(F(f, 0), 1);
    // K and the area ratio do not change when both D0 and D1 are scaled alike: scale by a power of
    // two (exactly) to D0's size, so coordinates of any magnitude (1e-150 .. 1e150) do not overflow.
    const double size = D0.cwiseAbs().maxCoeff();
    if (size > 0 && size <= DBL_MAX) {
      const double scale = std::ldexp(1.0, -std::ilogb(size));
      D0 *= scale;
      D1 *= scale;
    }
    const double det0 = D0.determinant();
    if (!(std::abs(det0) > 0)) {
      std::ostringstream s;
      s << "zero area (or a non-finite vertex) in the source";
      throw InvalidInput(Where::of_face(f), s.str());
    }
    fn(f, D1 * D0.inverse(), D1.determinant() / det0);
  }
}

}  // namespace

Eigen::VectorXd conformal_distortion(const Eigen::Ref<const Positions>& source,
                                     const Eigen::Ref<const Positions>& result,
                                     const Eigen::Ref<const Faces>& F) {
  Eigen::VectorXd K(F.rows());
  for_each_jacobian(source, result, F, [&](int f, const Eigen::Matrix2d& J, double) {
    // Closed-form singular values of a 2x2 matrix: sigma = |q| +- |r| with q, r the conformal and
    // anti-conformal parts.
    const double q = std::hypot(0.5 * (J(0, 0) + J(1, 1)), 0.5 * (J(1, 0) - J(0, 1)));
    const double r = std::hypot(0.5 * (J(0, 0) - J(1, 1)), 0.5 * (J(1, 0) + J(0, 1)));
    const double smin = std::abs(q - r);
    K[f] = smin > 0 ? (q + r) / smin : std::numeric_limits<double>::infinity();
  });
  return K;
}

int flipped_faces(const Eigen::Ref<const Positions>& source, const Eigen::Ref<const Positions>& result,
                  const Eigen::Ref<const Faces>& F) {
  return static_cast<int>((area_ratio(source, result, F).array() <= 0.0).count());
}

Eigen::VectorXd area_ratio(const Eigen::Ref<const Positions>& source, const Eigen::Ref<const Positions>& result,
                           const Eigen::Ref<const Faces>& F) {
  Eigen::VectorXd a(F.rows());
  for_each_jacobian(source, result, F, [&](int f, const Eigen::Matrix2d&, double ratio) { a[f] = ratio; });
  return a;
}

}  // namespace bdinterp
