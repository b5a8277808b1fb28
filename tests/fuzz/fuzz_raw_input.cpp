// Fuzz target 1: raw bytes -> mesh, coordinates of two or three shapes, t / weights, options and
// anchor. Layout of the input (all little-endian, read until the bytes run out; see fuzz_common.h):
//   nv (1 byte, <= 64), nf (1 byte, <= 96), shapes (2 or 3), face corners (2 bytes each: an index
//   modulo nv + 2 and a shift of 0 or -1, so out-of-range indices occur), coordinates, flatten
//   options and base, anchor, a mode byte (set_threads, strict, options.threads), then t.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "bdinterp/interpolator.h"
#include "fuzz_common.h"

namespace bd = bdinterp;

namespace {

bd::Anchor read_anchor(fuzz::Bytes& in, int nv) {
  const uint8_t mode = in.byte() % 4;
  if (mode == 1) return bd::Anchor::at_vertex(static_cast<int>(in.byte()) - 2);  // may be out of range
  if (mode != 2) return bd::Anchor::centroid();
  bd::AnchorPath p;
  const int n = in.byte() % 5;
  p.position.resize(n, 2);
  for (int k = 0; k < n; ++k) {
    p.t.push_back(in.number(2.0));
    p.position.row(k) << in.number(10.0), in.number(10.0);
    p.angle.push_back(in.number(7.0));
  }
  if (in.byte() & 1 && !p.angle.empty()) p.angle.pop_back();  // mismatched lengths
  return bd::Anchor::along(p, static_cast<int>(in.byte() % (nv + 2)) - 1);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fuzz::Bytes in(data, size);
  const int nv = in.byte() % 65, nf = in.byte() % 97, shapes = 2 + in.byte() % 2;
  bd::Faces F(nf, 3);
  for (int f = 0; f < nf; ++f)
    for (int c = 0; c < 3; ++c) {
      const int index = in.byte() % (nv + 2), shift = in.byte() & 1;  // -1 .. nv + 1
      F(f, c) = index - shift;
    }
  std::vector<bd::Positions> X(shapes, bd::Positions(nv, 2));
  for (auto& P : X)
    for (int v = 0; v < nv; ++v) P.row(v) << in.number(4.0), in.number(4.0);
  bd::InterpolatorOptions opt;
  if (in.byte() & 1) opt.flatten.tolerance = in.number(1e-6);
  if (in.byte() & 1) opt.flatten.max_iterations = static_cast<int>(in.raw<int16_t>());
  opt.flatten.reuse_factorization = in.byte() & 1;
  opt.base = in.byte() % 5 - 1;  // -1 .. 3, sometimes beyond the shapes
  const bd::Anchor anchor = read_anchor(in, nv);
  const uint8_t mode = in.byte();  // bits 0-1: threads; 2: strict; 3: threads in the options
  const int threads = mode & 3;
  opt.strict = mode & 4;
  if (mode & 8) opt.threads = static_cast<int>(in.raw<int16_t>());  // negative, huge: rejected?
  const double t = in.number(1.5);
  fuzz::check(
      [&](bd::Positions& out) {
        bd::Interpolator I(X, F, anchor, opt);
        I.set_threads(threads);
        if (shapes == 2) {
          out = I.at(t);
        } else {
          Eigen::Vector3d w(1 - t, t * 0.5, t * 0.5);
          out = I.blend(w);
        }
      },
      nv);
  return 0;
}
