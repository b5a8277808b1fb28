// Rigid motions of the plane and their geodesics: the anchor of an in-between
// moves on the path of the motion between the keys, not on the chord between the anchor points.
//
// A rigid motion M(x) = R(angle) x + shift. Its logarithm in se(2) is (angle, v) with
// shift = V(angle) v, V(a) = sinc(a / 2) e^{i a / 2} (as a complex factor); exp(s log M) turns by
// s * angle about M's fixed point (a translation by s * shift when angle = 0). The angle is kept
// as given (unwrapped), so a turn by 540 degrees is 3 pi, not pi.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace bdinterp {

struct Frame2;

struct RigidMotion {
  double angle = 0;                                // radians, counter-clockwise, any branch
  Eigen::Vector2d shift = Eigen::Vector2d::Zero();  // M(0)

  // M(x) = R(angle) x + shift for a point x (2).
  Eigen::Vector2d operator()(const Eigen::Vector2d& x) const;
};

// The Lie-algebra element (angle, v) of M: M = exp(log). v is finite unless M turns by a non-zero
// multiple of 2 pi while it moves (its fixed point is then at infinity): throws InvalidInput there.
struct Twist {
  double angle = 0;                             // radians, as the motion's (not wrapped)
  Eigen::Vector2d v = Eigen::Vector2d::Zero();  // shift = V(angle) v
};
// log: the twist of m (throws InvalidInput as above); exp: the motion of a twist (exp(log m) = m).
Twist log_motion(const RigidMotion& m);
RigidMotion exp_twist(const Twist& xi);

// The anchor frames of the inputs (point, angle) blended on the geodesic relative to the base
// input: with M_i the motion carrying the base's frame onto input i's (turn a_i - a_base, base point
// onto point i), the result is exp(sum_i w_i log M_i) applied to the base's frame. Exact at every
// input (w = e_i), continuous in w; for two inputs w = (1 - t, t) it turns by t (a_1 - a_0) about
// M_1's fixed point, and swapping the inputs (t -> 1 - t) gives the same frame. With three or more
// inputs it depends on which input is the base (docs/JOINTS.md). Sizes: inputs k >= 1, w (k).
// Precondition: has_geodesic(inputs, base).
Frame2 geodesic_blend(const std::vector<Frame2>& inputs, const Eigen::VectorXd& w, int base);

// False when some input's motion from the base turns by a whole non-zero number of turns while it
// moves (no geodesic; the anchor then blends linearly, see blend_frames).
bool has_geodesic(const std::vector<Frame2>& inputs, int base);

}  // namespace bdinterp
