// Interpolates a bar and its 270-degree bend with the installed bdinterp library and prints, per t,
// the largest conformal distortion and the Newton statistics. Exits non-zero if a frame has a flipped
// face or exceeds the target's distortion by more than 1%.
#include <bdinterp/distortion.h>
#include <bdinterp/interpolator.h>

#include <cmath>
#include <cstdio>

int main() {
  const int nx = 60, ny = 4;
  const double length = 1.0, width = 0.08, angle = 1.5 * M_PI;
  bdinterp::Positions V((nx + 1) * (ny + 1), 2), T(V.rows(), 2);
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const double x = length * i / nx, y = width * j / ny;
      const double radius = length / angle, r = radius - (y - width / 2), a = x / radius;
      V.row(j * (nx + 1) + i) << x, y;
      T.row(j * (nx + 1) + i) << r * std::sin(a), radius - r * std::cos(a);
    }
  }
  bdinterp::Faces F(2 * nx * ny, 3);
  for (int j = 0, f = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 2, d = a + nx + 1;
      F.row(f++) << a, b, c;
      F.row(f++) << a, c, d;
    }
  }
  bdinterp::Interpolator interp({V, T}, F);
  const double K1 = bdinterp::conformal_distortion(V, T, F).maxCoeff();
  int bad = 0;
  for (double t = 0; t <= 1.0001; t += 0.25) {
    const bdinterp::Positions X = interp.at(t);
    const double K = bdinterp::conformal_distortion(V, X, F).maxCoeff();
    const int flipped = (bdinterp::area_ratio(V, X, F).array() <= 0).count();
    const auto& s = interp.last_stats();
    std::printf("t=%.2f  max K=%.4f (target %.4f)  flipped=%d  Newton steps=%d  residual=%.1e\n", t, K,
                K1, flipped, s.iterations, s.residual);
    bad += flipped > 0 || K > 1.01 * K1;
  }
  return bad ? 1 : 0;
}
