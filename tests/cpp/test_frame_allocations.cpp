// Warm frames allocate no large block (>= 16 KiB) once an Interpolator's buffers are sized: each
// freed large block costs page faults and, under jemalloc as in Blender 3.4 and 4.3, madvise and a
// TLB flush on every core running the process (docs/BENCHMARKS.md, "Inside Blender").
// Counted by a malloc of this test binary's own (glibc only; sanitizers bring their own malloc):
// it forwards to glibc's and counts the large requests made while `counting` is set, except those of
// a shared CHOLMOD (Debian 12's SuiteSparse 5 reallocates cholmod_solve2's workspace on every call;
// SuiteSparse 7, which the shipped modules link, keeps it).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <utility>

#include "bdinterp/interpolator.h"
#include "test_meshes.h"

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer)
#define BDI_SANITIZED 1
#endif
#endif
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__) && !defined(BDI_SANITIZED)
#define BDI_COUNTS_MALLOC 1
#include <dlfcn.h>
extern "C" void* __libc_malloc(size_t size);
namespace {
std::atomic<bool> counting{false};
std::atomic<long> large{0};
}  // namespace
extern "C" void* malloc(size_t size) {
  if (size >= 16384 && counting.exchange(false)) {
    Dl_info caller{};
    const bool cholmod = dladdr(__builtin_return_address(0), &caller) && caller.dli_fname &&
                         std::strstr(caller.dli_fname, "libcholmod");
    if (!cholmod) large.fetch_add(1, std::memory_order_relaxed);
    counting = true;
  }
  return __libc_malloc(size);
}
#endif

namespace bdinterp {
namespace {

#ifdef BDI_COUNTS_MALLOC
// A test mesh (over 2048 vertices: #V doubles are large blocks) and its image under `map`.
struct Pair {
  testing::TestMesh mesh;
  Positions target;
};
template <class Map>
Pair pair_of(testing::TestMesh mesh, Map map) {
  Pair p{std::move(mesh), {}};
  p.target = testing::apply(p.mesh.V, map);
  return p;
}

// Checks 10 warm slider frames (t = 0.40 .. 0.49) after 10 (t = 0.30 .. 0.39) that size the buffers
// and fill the warm-start history, each into the same array: a frame that does not refactorise
// allocates no large block (CHOLMOD's numeric factorisation allocates its transpose; measured: one
// frame in ten refactorises). Returns the number of frames checked; `last`: the last frame's stats.
int check_warm_frames(const Pair& p, FrameStats& last) {
  Interpolator interp({p.mesh.V, p.target}, p.mesh.F);
  Positions out(p.mesh.V.rows(), 2);
  auto frame = [&](int k) { interp.blend_into(Eigen::Vector2d(0.7 - 0.01 * k, 0.3 + 0.01 * k), out); };
  for (int k = 0; k < 10; ++k) frame(k);
  int checked = 0;
  for (int k = 10; k < 20; ++k) {
    large = 0;
    counting = true;
    frame(k);
    counting = false;
    if (interp.last_stats().factorizations > 0) continue;
    EXPECT_EQ(large.load(), 0) << "frame " << k;
    ++checked;
  }
  EXPECT_TRUE(out.allFinite());
  last = interp.last_stats();
  return checked;
}
#endif

TEST(FrameAllocations, AWarmFrameOfAHoledPieceAllocatesNoLargeBlock) {
#ifndef BDI_COUNTS_MALLOC
  GTEST_SKIP() << "counts glibc's malloc only";
#else
  // An annulus of 2624 vertices bent both ways (no fold: areas change by less than 1.6x).
  const Pair p = pair_of(testing::annulus(40, 64), [](const Eigen::Vector2d& q) {
    return Eigen::Vector2d(q.x() + 0.15 * std::sin(bdinterp::kPi * q.y()), q.y() + 0.3 * std::sin(bdinterp::kPi * q.x()));
  });
  FrameStats stats;
  EXPECT_GE(check_warm_frames(p, stats), 5);  // 1d9d512's parent: 2-4 blocks a frame (the closure's #V vectors)
  EXPECT_EQ(stats.hole_closure.size(), 1u);  // the holes path
  EXPECT_EQ(stats.fold_faces, 0);
#endif
}

TEST(FrameAllocations, AWarmFrameWithAFoldRegionAllocatesNoLargeBlock) {
#ifndef BDI_COUNTS_MALLOC
  GTEST_SKIP() << "counts glibc's malloc only";
#else
  // A Z fold of the jittered unit grid (61 x 41 vertices): the strip 0.5 < x < 0.6 mirrored (its
  // faces folded), the rest shifted to join it, so that every frame runs the fold fill over the
  // strip's fold region (docs/FOLDS.md).
  const Pair p = pair_of(testing::jittered_grid(60, 40), [](const Eigen::Vector2d& q) {
    const double x = q.x() < 0.5 ? q.x() : q.x() < 0.6 ? 1.0 - q.x() : q.x() - 0.2;
    return Eigen::Vector2d(x, q.y());
  });
  FrameStats stats;
  EXPECT_GE(check_warm_frames(p, stats), 5);  // cd6c405's parent: ~10 blocks a frame (FoldFill::fill's)
  EXPECT_GT(stats.fold_faces, 400);  // the strip's ~480 faces and more
#endif
}

}  // namespace
}  // namespace bdinterp
