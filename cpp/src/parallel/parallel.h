// Internal: intra-frame parallelism. The face and edge loops of one frame are split into a few
// chunks run by a small pool of its own (std::thread; idle workers spin through a frame while the
// machine is idle, else 20 us, then sleep), except inside Interpolator::frames(), whose workers
// each solve frames on a thread of their own. The triangular solves split the same way
// (src/detail/tree_solve.h).
// A Loop is split only when it is worth a fork/join; the LoopPolicy (parallel.cpp) runs a split
// loop serially on its calling thread, with the same chunks, while other programs take the cores
// (machine_busy).
// Why not OpenMP: beside another busy program libgomp's fixed split made every loop wait for the
// thread that shared its core (docs/BENCHMARKS.md, "Busy machine"); here the caller takes chunks
// too, so a frame is never slower than the serial loop by more than the wake-up.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace bdinterp::parallel {

// The cores this process may use: the online CPUs, limited by its affinity mask (taskset, a farm's
// cpuset) and by its cgroup's CPU quota (cpu.max: docker --cpus, a Kubernetes limit), which
// std::thread::hardware_concurrency() ignores. The pool's chunks and frames()'s default workers.
// Windows: the process's affinity mask only (a job object's CPU rate limit is not read); macOS: the
// active CPUs (it has neither masks nor cgroups). See detail::affinity_cores.
int usable_cores();

// Whether the pool judges the machine busy (other programs leave this process fewer than two
// cores, sampled by the threads that start loops, see detail::other_threads; true until
// measured): loops then run serially on their calling thread, and idle workers sleep. Diagnostics.
bool machine_busy();

// The contiguous share [first, second) of chunk `chunk` out of `chunks` of n iterations (the
// split of OpenMP's schedule(static): the first n % chunks chunks get one iteration more).
std::pair<long, long> share(long n, int chunk, int chunks);

namespace detail {
using ChunkFn = void (*)(void* context, int chunk);
// fn(context, chunk) for every chunk, on the pool unless the machine is busy; returns the threads
// that ran chunks (1 when the caller ran them all).
int run(int chunks, ChunkFn fn, void* context);
// The chunks of a loop of `work` simple iterations: 1 under 500 (a fork/join costs about a
// microsecond), else the usable cores up to this thread's ThreadLimit; 1 in a child after fork().
int chunks_for(double work);
// Records that a loop started on this thread ran on `threads` threads (ThreadLimit::threads_ran).
void note_threads(int threads);
// Threads of other programs that want a core now, or -1 if unknown. Linux: the kernel's runnable
// count (/proc/loadavg) minus `own_running` (this process's running threads: the caller and the
// pool's awake workers), at least 0. Windows and macOS have no such count: the cores that other
// programs kept busy since the previous sample (at least ~20 ms before), i.e. the machine's busy
// CPU time minus this process's (OtherCores), -1 at the first sample; `own_running` is not used,
// and demand beyond the cores goes unseen. One file per platform:
// machine_probe_linux.cpp, _windows.cpp, _macos.cpp.
int other_threads(int own_running);
// The processors this process may run on: Linux's affinity mask (taskset, a cpuset), Windows' process
// affinity mask (its processor group), macOS's active CPUs (it has no masks); -1 if unknown.
int affinity_cores();
// hardware_concurrency() (at least 1), limited to `limit` if that is positive.
int cores_within(int limit);
// The cores other programs kept busy over a window, from cumulative CPU-time counters in one unit:
// the machine's busy and total time summed over its `cores`, and this process's CPU time (own).
class OtherCores {
 public:
  // (busy - own) / total x cores over the window since the last one of at least `min_total`,
  // rounded, within [0, cores]: the previous answer while the window is shorter, and when a
  // counter went back (a new window starts); -1 at the first call.
  int add(uint64_t busy, uint64_t own, uint64_t total, int cores, uint64_t min_total);

 private:
  bool started_ = false;
  uint64_t busy_ = 0, own_ = 0, total_ = 0;
  int last_ = -1;
};
// OtherCores::add on the process's one window (thread-safe).
int other_cores_now(uint64_t busy, uint64_t own, uint64_t total, int cores, uint64_t min_total);
// Cores of a cgroup CPU quota, "QUOTA PERIOD" as in cpu.max ("150000 100000" -> 2, rounded up);
// 0 for none ("max 100000", v1's "-1 100000") or an unreadable line.
int quota_cores(const std::string& cpu_max);
// omp_set_dynamic(value) on the OpenMP runtime CHOLMOD uses, for the calling thread; returns the
// previous value, or -1 (and does nothing) without one.
int swap_omp_dynamic(int value);
// The busy verdict from successive samples of the other programs' runnable threads (the count
// minus this process's own running ones): busy while the running mean (weight 1/4 on the newest)
// of max(0, others - (cores - 2)) is at least 0.5, i.e. the others leave fewer than two cores on
// average over the last ~4 samples; a program that runs for a moment does not count. Starts as
// busy (mean 1); an unknown count (-1) counts as an excess of 1.
class LoadMean {
 public:
  bool add(int others, int cores);

 private:
  double mean_ = 1.0;
};
}  // namespace detail

// A loop over [0, n), in the manner of libigl's parallel_for: the loop's size is given once, and
// `cost` is one iteration's work in simple iterations (a face's terms: 1; a hole walked: its
// corners), which decides whether the loop is split (chunks_for(n cost)). The chunks are
// contiguous shares (share()) run on the calling thread and the pool's workers; a body(chunk, i)
// must only depend on its chunk and i (results are then bit-identical for a given chunk count,
// whichever thread ran what) and must not throw. Nested or concurrent loops run their chunks
// serially on the calling thread.
class Loop {
 public:
  explicit Loop(long n, double cost = 1.0)
      : n_(n), chunks_(static_cast<int>(std::min<double>(std::max(n, 1L), detail::chunks_for(n * cost)))) {}
  // The chunks: 1 for a loop not worth splitting, else one per usable core up to this thread's
  // ThreadLimit, at most n. Per-chunk buffers (Partials, PerChunk) are sized by it.
  int chunks() const { return chunks_; }
  // body(chunk, i) for every i in [0, n); returns when all have returned.
  template <class Body>
  void run(Body&& body) const {
    auto chunk = [&](int k) {
      const auto [first, last] = share(n_, k, chunks_);
      for (long i = first; i < last; ++i) body(k, i);
    };
    if (chunks_ <= 1) {
      chunk(0);
      return;
    }
    using Chunk = decltype(chunk);
    detail::note_threads(detail::run(chunks_, [](void* c, int k) { (*static_cast<Chunk*>(c))(k); }, &chunk));
  }

 private:
  long n_;
  int chunks_;
};

// While alive (and `active`), OpenBLAS (which CHOLMOD's supernodal factorisations call) runs on one
// thread: the pool already splits a frame's loops, and OpenBLAS's idle threads yield-spin after
// each call, taking the pool's core and making an idle machine look busy (docs/BENCHMARKS.md).
// Every ThreadLimit holds one. The setting is process-wide: the first object alive saves the
// count and sets 1, the last restores it (so numpy in another thread of the same process runs on
// one BLAS thread for that moment). No-op where CHOLMOD's BLAS is not OpenBLAS.
class SingleThreadedBlas {
 public:
  explicit SingleThreadedBlas(bool active = true);
  ~SingleThreadedBlas();
  SingleThreadedBlas(const SingleThreadedBlas&) = delete;
  SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;

 private:
  bool active_;
};

// The thread settings of one bdinterp call (every Interpolator call holds one). While alive: loops
// started on this thread use at most `threads` chunks (0: no limit); with more than one allowed, the
// pool's idle workers keep spinning between loops while the machine is idle (a frame is being
// computed: the next loop follows within milliseconds); OpenMP regions that CHOLMOD starts on this
// thread may use fewer threads than they ask for when the machine is busy (omp_set_dynamic(1));
// and OpenBLAS runs on one thread (SingleThreadedBlas). Each is restored afterwards.
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  // The most threads one loop started on this thread ran on while this object lives (1: serial).
  int threads_ran() const;
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

 private:
  int saved_;
  int saved_ran_;           // the enclosing ThreadLimit's threads_ran, merged back at the end
  bool counted_;            // counted among the frames being computed (threads != 1)
  int saved_dynamic_ = -1;  // the thread's omp_get_dynamic() before (-1: no OpenMP runtime)
  SingleThreadedBlas blas_;
};

// Diagnostics: the libraries CHOLMOD's calls bind to in this process. blas: the file of its BLAS
// (dgemm_; empty if none is loaded), blas_threads: it is OpenBLAS, whose thread count
// SingleThreadedBlas sets (a reference BLAS, as inside Blender 4.3, has no threads to set); openmp:
// the file of its OpenMP runtime with omp_set_dynamic (empty if none).
struct Runtimes {
  std::string blas, openmp;
  bool blas_threads = false;
};
Runtimes runtimes();

// Per-chunk accumulation buffers for scatter-adds and reductions (chunk 0 writes into the caller's
// array, the others into their own, summed afterwards in chunk order, so results do not depend on
// timing).
class Partials {
 public:
  // Buffers of `size` for chunks 1 .. chunks-1 (kept between calls).
  void prepare(int chunks, long size);
  double* buffer(int chunk, double* own) { return chunk == 0 ? own : parts_[chunk - 1].data(); }
  // target[i] += sum of the other chunks' buffers, in chunk order.
  void add_into(double* target) const;

 private:
  int threads_ = 1;
  long size_ = 0;
  std::vector<std::vector<double>> parts_;
};

// One value per chunk (a reduction without atomics), starting at 0: updated through at(chunk),
// combined in chunk order. Each value has a cache line of its own, so chunks running at the same
// time do not invalidate each other's line on every update.
class PerChunk {
 public:
  explicit PerChunk(int chunks) : values_(chunks > 1 ? chunks : 1) {}
  double& at(int chunk) { return values_[chunk].value; }
  double sum() const;
  double max() const;

 private:
  struct alignas(64) Slot {
    double value = 0;
  };
  std::vector<Slot> values_;
};

}  // namespace bdinterp::parallel
