// The thread pool of the frame loops (parallel.h): every chunk runs exactly once, results do not
// depend on which thread ran what, nested and concurrent use is safe, and idle workers sleep.
#include <gtest/gtest.h>
#ifdef _WIN32
#ifndef WIN32_LEAN_AND_MEAN
#define WIN32_LEAN_AND_MEAN
#endif
#ifndef NOMINMAX
#define NOMINMAX
#endif
#include <windows.h>
#undef far  // windows.h's 16-bit pointer qualifiers: names of variables here
#undef near
#else
#include <sys/resource.h>
#endif

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "parallel/parallel.h"
#include "competitors.h"

namespace bdinterp {
namespace {
// How long competitor processes may take to start (a new process under Wine: ~0.3-1 s).
#ifdef _WIN32
constexpr int kCompetitorStartMs = 4000;
#else
constexpr int kCompetitorStartMs = 500;
#endif

// CPU time of this process (all threads), user and system.
double cpu_seconds() {
#ifdef _WIN32
  FILETIME created, exited, kernel, user;
  GetProcessTimes(GetCurrentProcess(), &created, &exited, &kernel, &user);
  auto seconds = [](const FILETIME& t) { return 1e-7 * ((static_cast<uint64_t>(t.dwHighDateTime) << 32) | t.dwLowDateTime); };
  return seconds(kernel) + seconds(user);
#else
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + 1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
#endif
}

TEST(Parallel, SharesPartitionTheRangeLikeStaticScheduling) {
  for (long n : {0L, 1L, 7L, 100L, 2001L}) {
    for (int chunks : {1, 2, 3, 8}) {
      long next = 0;
      for (int k = 0; k < chunks; ++k) {
        const auto [first, last] = parallel::share(n, k, chunks);
        EXPECT_EQ(first, next);
        EXPECT_GE(last - first, n / chunks);
        EXPECT_LE(last - first, n / chunks + 1);
        next = last;
      }
      EXPECT_EQ(next, n);
    }
  }
}

TEST(Parallel, EveryChunkRunsOnceAndSumsAreReproducible) {
  // Sums of 1/i over per-chunk partials are bit-identical whatever the timing (random work per
  // chunk), and equal to the serial sum of the chunks' sums in chunk order.
  const long n = 200000;
  const parallel::Loop loop(n);
  const int chunks = loop.chunks();
  EXPECT_EQ(chunks, parallel::usable_cores());
  std::vector<double> expected(chunks, 0.0);
  for (int k = 0; k < chunks; ++k) {
    const auto [first, last] = parallel::share(n, k, chunks);
    for (long i = first; i < last; ++i) expected[k] += 1.0 / (i + 1);
  }
  double total = 0;
  for (double e : expected) total += e;
  for (int rep = 0; rep < 50; ++rep) {
    std::vector<std::atomic<long>> runs(chunks);
    parallel::PerChunk part(chunks);
    loop.run([&](int k, long i) {
      ++runs[k];
      if ((k + rep) % 3 == 0 && i % 50000 == 0) std::this_thread::sleep_for(std::chrono::microseconds(50));
      part.at(k) += 1.0 / (i + 1);
    });
    for (int k = 0; k < chunks; ++k) {
      const auto [first, last] = parallel::share(n, k, chunks);
      EXPECT_EQ(runs[k].load(), last - first);
    }
    EXPECT_EQ(part.sum(), total);  // bitwise
  }
}

TEST(Parallel, NestedAndConcurrentRunsComplete) {
  // Four threads each start loops whose chunks start loops: all complete with the right counts
  // (nested and competing calls run serially on their caller instead of waiting for the pool).
  std::atomic<long> count{0};
  std::vector<std::thread> callers;
  for (int c = 0; c < 4; ++c) {
    callers.emplace_back([&] {
      for (int rep = 0; rep < 200; ++rep)
        parallel::Loop(30, 100).run([&](int, long) { parallel::Loop(5, 1000).run([&](int, long) { ++count; }); });
    });
  }
  for (auto& t : callers) t.join();
  EXPECT_EQ(count.load(), 4L * 200 * 30 * 5);
}

TEST(Parallel, IdleWorkersSleep) {
  // After a loop, the workers spin for ~20 us, then block: 0.2 s of idling must cost the process
  // (nearly) no CPU time. A pool that waits actively (OMP_WAIT_POLICY=active) would burn
  // ~0.2 s per worker here; libgomp's default spins 300k rounds after every region.
  // First wait until the process is quiet: OpenBLAS (linked through CHOLMOD) starts its own threads,
  // which spin ~0.1 s after start-up (measured: 0.10 s of CPU in the first 0.2 s) before they sleep.
  for (int k = 0; k < 20; ++k) {
    const double t = cpu_seconds();
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (cpu_seconds() - t < 0.002) break;
  }
  std::vector<double> x(100000, 1.0);
  parallel::Loop(static_cast<long>(x.size())).run([&](int, long i) { x[i] = std::sqrt(x[i] + i); });
  double before = cpu_seconds();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_LT(cpu_seconds() - before, 0.02);
  // Likewise after a frame: inside a ThreadLimit (as every Interpolator call) idle workers of an
  // idle machine spin until the next loop, but not once the frame is over.
  {
    const parallel::ThreadLimit frame(0);
    for (int k = 0; k < 3; ++k)
      parallel::Loop(static_cast<long>(x.size())).run([&](int, long i) { x[i] = std::sqrt(x[i] + i); });
  }
  before = cpu_seconds();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_LT(cpu_seconds() - before, 0.02);
}

TEST(Parallel, OtherProgramsAreCountedBesideAnAwakeWorker) {
  // Twice as many spinning processes as cores, beside one spinning thread of this process (as an
  // awake pool worker): every sample after the first window counts the others on all cores but
  // one at least. Windows and macOS count busy cores; there the pool's own threads used to hide
  // the others (the capped busy-core count minus this process's awake threads read 0).
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  const testing::Competitors others(2 * cores);
  std::atomic<bool> stop{false};
  std::thread worker([&] {
    while (!stop.load(std::memory_order_relaxed)) {
    }
  });
  const int expected = std::max(1, cores - 1);
  parallel::detail::other_threads(2);  // starts a window where counts come from CPU-time counters
  const auto started = std::chrono::steady_clock::now() + std::chrono::milliseconds(kCompetitorStartMs);
  while (std::chrono::steady_clock::now() < started && parallel::detail::other_threads(2) < expected)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // until the competitors run
  int fewest = 1 << 20;
  for (int k = 0; k < 8; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    fewest = std::min(fewest, parallel::detail::other_threads(2));  // this thread and the worker
  }
  stop = true;
  worker.join();
  EXPECT_GE(fewest, expected);
  parallel::detail::LoadMean verdict;
  for (int k = 0; k < 4; ++k) verdict.add(fewest, cores);
  EXPECT_TRUE(verdict.add(fewest, cores));  // the others leave this process one core at most
}

// Samples of `others` on `cores` until the verdict reads `want` (limit + 1: never within limit).
int samples_until(parallel::detail::LoadMean& m, int others, int cores, bool want, int limit = 20) {
  for (int k = 1; k <= limit; ++k)
    if (m.add(others, cores) == want) return k;
  return limit + 1;
}

TEST(Parallel, BusyVerdictFollowsTheOtherProgramsThreads) {
  // Behaviour, not coefficients: the verdict starts busy (the cautious guess), turns idle within a
  // few samples (10 ms apart) of nothing else running, ignores a program that runs for a moment,
  // and turns busy within a few samples of one that keeps a core, idle again once it stops.
  parallel::detail::LoadMean m;
  EXPECT_TRUE(m.add(1, 2));
  EXPECT_LE(samples_until(m, 0, 2, false), 4);
  EXPECT_EQ(samples_until(m, 0, 2, true), 21);  // stays idle
  EXPECT_FALSE(m.add(1, 2));                    // a moment's competitor
  EXPECT_EQ(samples_until(m, 0, 2, true), 21);
  EXPECT_LE(samples_until(m, 1, 2, true), 4);   // a lasting one
  EXPECT_EQ(samples_until(m, 1, 2, false), 21);
  EXPECT_LE(samples_until(m, 0, 2, false), 4);
  parallel::detail::LoadMean unknown;
  EXPECT_EQ(samples_until(unknown, -1, 2, false), 21);  // no count: stays busy
  // 16 cores: 14 others leave this process two cores, not busy; 15 leave one, busy.
  parallel::detail::LoadMean many, full;
  EXPECT_LE(samples_until(many, 14, 16, false), 4);
  EXPECT_EQ(samples_until(many, 14, 16, true), 21);
  EXPECT_EQ(samples_until(full, 15, 16, false), 21);
}

TEST(Parallel, LoopsRunOnTheCallerWhileOtherProgramsTakeTheCores) {
  // Twice as many spinning processes as cores (busy-core counts, which cannot exceed the cores, then
  // still see all cores but one taken) leave this process no core of its own: within a few
  // samples (10 ms apart) the pool judges the machine busy, also while its worker was awake (it
  // spins through a frame on an idle machine), and from then on every chunk runs on the calling
  // thread (no worker is woken to take turns with the caller), with the same chunks as ever.
  const int cores = parallel::usable_cores();
  const parallel::ThreadLimit frame(0);
  // Up to 0.4 s of loops (a worker awake while idle), for the verdict to leave its cautious start.
  for (int k = 0; k < 80 && parallel::machine_busy(); ++k)
    parallel::Loop(2, 1000).run([](int, long) {}), std::this_thread::sleep_for(std::chrono::milliseconds(5));
  // Whether the verdict turns, not only starts, busy: on a busy machine it was busy before.
  std::printf("[ busy before the competitors: %d ]\n", parallel::machine_busy() ? 1 : 0);
  const testing::Competitors others(2 * cores);
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(kCompetitorStartMs);
  while (std::chrono::steady_clock::now() < until && !parallel::machine_busy()) {
    parallel::Loop(2, 1000).run([](int, long) {});
    std::this_thread::sleep_for(std::chrono::milliseconds(12));
  }
  const bool busy = parallel::machine_busy();
  std::vector<std::thread::id> ran(2);
  for (int rep = 0; rep < 20; ++rep) parallel::Loop(2, 1000).run([&](int k, long) { ran[k] = std::this_thread::get_id(); });
  EXPECT_TRUE(busy);
  EXPECT_EQ(ran[0], std::this_thread::get_id());
  EXPECT_EQ(ran[1], std::this_thread::get_id());
}

TEST(Parallel, LoopsGoToTheWorkersWhileTheMachineIsIdle) {
  // The other half of the policy: with nothing else taking the cores, a loop's second chunk runs
  // on a worker (independent check: the thread ids). Only loops judged idle before and after count
  // (the shared CI machine is often busy, and the verdict may turn in the middle). A chunk lasts
  // 1 ms: long enough for a worker that slept through a busy spell, or lost its core a moment, to
  // claim the second chunk before the caller, done with its own, takes the one nobody claimed.
  if (parallel::usable_cores() < 2) GTEST_SKIP() << "one usable core";
  const parallel::ThreadLimit frame(0);
  int idle = 0, elsewhere = 0;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(3);
  while (elsewhere == 0 && idle < 40 && std::chrono::steady_clock::now() < until) {
    const bool idle_before = !parallel::machine_busy();
    std::vector<std::thread::id> ran(2);
    parallel::Loop(2, 50000).run([&](int k, long) {
      ran[k] = std::this_thread::get_id();
      const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(1);
      while (std::chrono::steady_clock::now() < end) {}  // a chunk's work, long enough to be shared
    });
    if (!idle_before || parallel::machine_busy()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));  // let the verdict settle
      continue;
    }
    ++idle;
    elsewhere += ran[0] != ran[1];
  }
  if (elsewhere == 0 && idle < 40) GTEST_SKIP() << "the machine stayed busy (" << idle << " idle loops)";
  EXPECT_GE(elsewhere, 1) << idle << " loops on an idle machine all ran on the caller";
}

TEST(Parallel, LoopsOfLittleWorkRunOnTheCaller) {
  // The size rule: under 500 simple iterations of work a fork/join is not worth it, whatever the
  // load; the same loop with more work per iteration is split.
  const parallel::ThreadLimit frame(0);
  std::vector<std::thread::id> ran(2);
  const parallel::Loop small(2, 249);
  EXPECT_EQ(small.chunks(), 1);
  for (int rep = 0; rep < 20; ++rep) small.run([&](int, long i) { ran[i] = std::this_thread::get_id(); });
  EXPECT_EQ(ran[0], std::this_thread::get_id());
  EXPECT_EQ(ran[1], std::this_thread::get_id());
  EXPECT_EQ(parallel::Loop(2, 250).chunks(), std::min(2, parallel::usable_cores()));
  EXPECT_EQ(frame.threads_ran(), 1);
}

TEST(Parallel, CpuQuotasInCores) {
  EXPECT_EQ(parallel::detail::quota_cores("max 100000"), 0);
  EXPECT_EQ(parallel::detail::quota_cores("-1 100000"), 0);  // cgroup v1: no quota
  EXPECT_EQ(parallel::detail::quota_cores("100000 100000"), 1);
  EXPECT_EQ(parallel::detail::quota_cores("150000 100000"), 2);
  EXPECT_EQ(parallel::detail::quota_cores("50000 100000"), 1);
  EXPECT_EQ(parallel::detail::quota_cores("400000 100000\n"), 4);
  EXPECT_EQ(parallel::detail::quota_cores(""), 0);
  EXPECT_EQ(parallel::detail::quota_cores("garbage"), 0);
  EXPECT_EQ(parallel::detail::quota_cores("100000 0"), 0);
  // This process: at least one core, never more than its affinity mask allows.
  const int mask = parallel::detail::affinity_cores();
  ASSERT_GE(mask, 1);
  EXPECT_GE(parallel::usable_cores(), 1);
  EXPECT_LE(parallel::usable_cores(), mask);
}

#ifdef BDINTERP_TESTS_CHOLMOD_NO_BLAS
TEST(Parallel, BlasRunsOnOneThreadWhileAFrameIsComputed) {
  // CHOLMOD built from source without a BLAS (simplicial factors only) calls no BLAS.
  EXPECT_TRUE(parallel::runtimes().blas.empty());
  GTEST_SKIP() << "CHOLMOD was built without a BLAS: no BLAS threads to hold";
}
#else
extern "C" int openblas_get_num_threads() __attribute__((weak));
extern "C" void openblas_set_num_threads(int) __attribute__((weak));

TEST(Parallel, BlasRunsOnOneThreadWhileAFrameIsComputed) {
  // The BLAS and OpenMP runtime that CHOLMOD calls are found (this test links Debian's CHOLMOD,
  // which calls OpenBLAS and libgomp); SingleThreadedBlas holds OpenBLAS at one thread while any is
  // alive, on any thread, and restores the count the last one found.
  const parallel::Runtimes r = parallel::runtimes();
  EXPECT_NE(r.openmp.find("libgomp"), std::string::npos) << r.openmp;
  EXPECT_FALSE(r.blas.empty());
  if (!openblas_get_num_threads || !r.blas_threads) GTEST_SKIP() << "CHOLMOD's BLAS is not OpenBLAS: " << r.blas;
  openblas_set_num_threads(2);
  {
    const parallel::SingleThreadedBlas a(true);
    EXPECT_EQ(openblas_get_num_threads(), 1);
    std::thread other([] {
      const parallel::SingleThreadedBlas b(true);
      EXPECT_EQ(openblas_get_num_threads(), 1);
    });
    other.join();
    EXPECT_EQ(openblas_get_num_threads(), 1);  // b's end does not restore while a lives
  }
  EXPECT_EQ(openblas_get_num_threads(), 2);
  {
    const parallel::SingleThreadedBlas off(false);
    EXPECT_EQ(openblas_get_num_threads(), 2);
  }
}
#endif

TEST(Parallel, SmallLoopsAndLimitsStaySerial) {
  EXPECT_EQ(parallel::Loop(10).chunks(), 1);
  EXPECT_EQ(parallel::Loop(3, 1e6).chunks(), std::min(3, parallel::usable_cores()));  // at most n
  const parallel::ThreadLimit one(1);
  EXPECT_EQ(parallel::Loop(1000000).chunks(), 1);
  {
    const parallel::ThreadLimit two(2);
    EXPECT_LE(parallel::Loop(1000000).chunks(), 2);
  }
  EXPECT_EQ(parallel::Loop(1000000).chunks(), 1);
}

}  // namespace
}  // namespace bdinterp
