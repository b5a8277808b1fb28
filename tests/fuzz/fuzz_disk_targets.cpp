// Fuzz target 2: a valid disk (a jittered 6 x 4 grid, 35 vertices) whose target is the source
// under a random affine map plus per-vertex perturbations from the input, solved at several t
// (at, frames and blend), with the same Interpolator (warm starts, reused factorisations).
// Input: the affine map (4 numbers), a perturbation scale, per-vertex offsets, then a list of t.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "bdinterp/interpolator.h"
#include "fuzz_common.h"
#include "test_meshes.h"

namespace bd = bdinterp;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const bd::testing::TestMesh disk = bd::testing::jittered_grid(6, 4, 1.5, 1.0, 3);
  fuzz::Bytes in(data, size);
  const long nv = disk.V.rows();
  Eigen::Matrix2d A;
  A << 1 + in.number(1.0), in.number(1.0), in.number(1.0), 1 + in.number(1.0);
  const double scale = in.number(0.3);
  bd::Positions target = disk.V * A.transpose();
  for (long v = 0; v < nv; ++v) {
    const double dx = in.number(1.0), dy = in.number(1.0);
    target.row(v) += scale * Eigen::RowVector2d(dx, dy);
  }
  std::vector<double> ts;
  while (!in.empty() && ts.size() < 12) ts.push_back(in.number(1.5));
  if (ts.empty()) ts.push_back(0.5);
  const int threads = static_cast<int>(ts.size() % 3);
  fuzz::check(
      [&](bd::Positions& out) {
        bd::Interpolator I({disk.V, target}, disk.F);
        I.set_threads(threads);
        for (double t : ts) out = I.at(t);  // one Interpolator: warm starts and reuse
        bd::Positions seq(nv * ts.size(), 2);
        I.frames(ts, seq);
        if (!seq.allFinite()) fuzz::finding("non-finite frames()");
      },
      nv);
  return 0;
}
