#include "place/rigid_motion.h"

#include <cmath>
#include <complex>

#include "place/anchor_frame.h"
#include "bdinterp/types.h"

namespace bdinterp {
namespace {
using Complex = std::complex<double>;

// V(a) = (e^{ia} - 1) / (ia) = sinc(a / 2) e^{ia / 2}: the factor from v to the shift.
Complex v_factor(double a) {
  const double h = 0.5 * a;
  // sin(h) / h loses no digits for |h| > 1e-4; below, the series (error < h^4 / 120 < 1e-18).
  const double sinc = std::abs(h) > 1e-4 ? std::sin(h) / h : 1.0 - h * h / 6.0;
  return sinc * std::polar(1.0, h);
}

Complex c(const Eigen::Vector2d& x) { return {x.x(), x.y()}; }
Eigen::Vector2d vec(Complex z) { return {z.real(), z.imag()}; }
}  // namespace

Eigen::Vector2d RigidMotion::operator()(const Eigen::Vector2d& x) const {
  return vec(std::polar(1.0, angle) * c(x) + c(shift));
}

Twist log_motion(const RigidMotion& m) {
  const Complex f = v_factor(m.angle);
  // |f| = |sinc(a / 2)| is 0 only at a = 2 pi k, k != 0; tiny values mean a fixed point at ~1/|f|.
  if (std::abs(f) < 1e-12) {
    if (m.shift.norm() == 0) return {m.angle, Eigen::Vector2d::Zero()};
    throw InvalidInput("rigid motion: a whole turn with a shift has no geodesic (fixed point at infinity)");
  }
  return {m.angle, vec(c(m.shift) / f)};
}

RigidMotion exp_twist(const Twist& xi) { return {xi.angle, vec(v_factor(xi.angle) * c(xi.v))}; }

namespace {
// M_i: the base's frame onto the input's: turn by a_i - a_b, the base point onto the input's point.
RigidMotion relative_motion(const Frame2& base, const Frame2& input) {
  RigidMotion m;
  m.angle = input.angle - base.angle;
  m.shift = input.point - RigidMotion{m.angle, Eigen::Vector2d::Zero()}(base.point);
  return m;
}
}  // namespace

bool has_geodesic(const std::vector<Frame2>& inputs, int base) {
  for (const Frame2& f : inputs) {
    try {
      log_motion(relative_motion(inputs[static_cast<size_t>(base)], f));
    } catch (const InvalidInput&) {
      return false;
    }
  }
  return true;
}

Frame2 geodesic_blend(const std::vector<Frame2>& inputs, const Eigen::VectorXd& w, int base) {
  const Frame2& b = inputs[static_cast<size_t>(base)];
  Twist sum;
  for (size_t i = 0; i < inputs.size(); ++i) {
    const Twist xi = log_motion(relative_motion(b, inputs[i]));
    const double wi = w[static_cast<Eigen::Index>(i)];
    sum.angle += wi * xi.angle;
    sum.v += wi * xi.v;
  }
  const RigidMotion m = exp_twist(sum);
  return {m(b.point), b.angle + sum.angle};
}

}  // namespace bdinterp
