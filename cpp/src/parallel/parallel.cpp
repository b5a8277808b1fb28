// The pool of parallel.h: one job at a time, chunks claimed by the caller and the workers; the
// LoopPolicy decides whether a loop uses it. Measurements: docs/BENCHMARKS.md, "Busy machine".
#include "parallel/parallel.h"

#ifndef _WIN32
#include <pthread.h>  // pthread_atfork
#endif

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>

#ifdef __SSE2__
#include <immintrin.h>  // _mm_pause
#endif

namespace bdinterp::parallel {
namespace {
// The spin-wait hint: tells the core (and its hyper-thread sibling) that this thread only waits.
inline void pause_cpu() {
#ifdef __SSE2__
  _mm_pause();
#else
  std::this_thread::yield();
#endif
}

// Below this much work (simple iterations) a loop is not split: a fork/join with a spinning
// worker costs ~1 us.
constexpr double kMinItems = 500;
// An idle worker's spin between frames or on a busy machine: the gap between one evaluation's
// loops. Longer, it takes the core from the frame's own thread and from other programs.
constexpr auto kShortSpin = std::chrono::microseconds(20);
// The busy verdict is sampled this often by a thread that starts a loop, and forgotten (back to
// the cautious guess) after kStale without loops.
constexpr auto kSample = std::chrono::milliseconds(10);
constexpr auto kStale = std::chrono::seconds(1);

int64_t ticks() { return std::chrono::steady_clock::now().time_since_epoch().count(); }
template <class Duration>
int64_t ticks_of(Duration d) {
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(d).count();
}

std::atomic<int> computing{0};  // ThreadLimits alive that allow more than one thread: frames running
std::atomic<int> awake{0};      // pool workers not asleep (spinning or running chunks)
thread_local int limit = 0;        // 0: none
thread_local int most_ran = 1;     // the most threads a loop started on this thread ran on
thread_local bool inside = false;  // running a chunk or a run(): nested runs are serial

// The pool does not survive fork(): a child (e.g. of Python's multiprocessing) runs serially.
std::atomic<bool> forked{false};
#ifndef _WIN32
void note_fork() { forked.store(true); }
const bool fork_handler = pthread_atfork(nullptr, nullptr, note_fork) == 0;
#endif  // Windows has no fork()

// Whether a split loop's chunks go to the pool or run on its calling thread (the same chunks
// either way, so the same bits): on the pool unless the machine is busy (detail::LoadMean over
// samples of detail::other_threads).
class LoopPolicy {
 public:
  bool use_pool() {
    sample();
    return !busy_.load(std::memory_order_relaxed);
  }
  // Whether idle workers keep spinning: a frame is being computed with the pool in use.
  bool keep_spinning() const {
    return computing.load(std::memory_order_relaxed) > 0 && !busy_.load(std::memory_order_relaxed);
  }
  bool busy() const { return busy_.load(std::memory_order_relaxed); }

 private:
  // Updates the verdict when the last sample is older than kSample (one thread at a time).
  void sample() {
    const int64_t now = ticks();
    int64_t last = last_.load(std::memory_order_relaxed);
    if (now - last < ticks_of(kSample) || !last_.compare_exchange_strong(last, now)) return;
    const int others = detail::other_threads(1 + awake.load(std::memory_order_relaxed));
    const std::lock_guard<std::mutex> lock(m_);
    if (now - last > ticks_of(kStale)) load_ = detail::LoadMean();  // old news: the cautious guess
    busy_.store(load_.add(others, usable_cores()), std::memory_order_relaxed);
  }

  std::atomic<bool> busy_{true};  // until measured, the cautious guess
  std::atomic<int64_t> last_{0};
  std::mutex m_;
  detail::LoadMean load_;
};
LoopPolicy policy;

// Spins up to `spin`, checking `ready` between pauses; true once it holds.
template <class Ready>
bool spin_until(std::chrono::microseconds spin, Ready&& ready) {
  const auto until = std::chrono::steady_clock::now() + spin;
  for (int k = 0;; ++k) {
    if (ready()) return true;
    pause_cpu();
    if ((k & 63) == 63 && std::chrono::steady_clock::now() > until) return ready();
  }
}

// One job at a time. Its state is one atomic word: generation (32 bits) | chunks (16) | next chunk
// (16); a thread claims a chunk by a compare-exchange that also checks the generation, so a worker
// that wakes late can never claim a chunk of a later job. fn_/context_ are read only after a
// successful claim, and the caller does not start another job before every claimed chunk is done.
class Pool {
 public:
  static Pool& instance() {
    static Pool* pool = new Pool;  // never destroyed: workers sleep until the process ends
    return *pool;
  }

  // Runs the job on the caller and the workers; returns the threads that ran chunks, 0 if another
  // thread is using the pool (the caller then runs the chunks itself).
  int run(int chunks, detail::ChunkFn fn, void* context) {
    std::unique_lock<std::mutex> job(dispatch_, std::try_to_lock);
    if (!job.owns_lock()) return 0;
    grow(std::min(chunks, usable_cores()) - 1);
    fn_ = fn;
    context_ = context;
    done_.store(0);
    ran_.store(0);
    const uint64_t gen = (state_.load() >> 32) + 1;
    state_.store(gen << 32 | static_cast<uint64_t>(chunks) << 16);
    if (sleepers_.load() > 0) {
      { std::lock_guard<std::mutex> lock(m_); }
      wake_.notify_all();
    }
    work(static_cast<uint32_t>(gen));
    if (!spin_until(kShortSpin, [&] { return done_.load(std::memory_order_acquire) == chunks; })) {
      std::unique_lock<std::mutex> lock(m_);
      caller_waiting_ = true;
      finished_.wait(lock, [&] { return done_.load() == chunks; });
      caller_waiting_ = false;
    }
    return ran_.load();
  }

 private:
  // Claims and runs chunks of job `gen` until none is left.
  void work(uint32_t gen) {
    uint64_t s = state_.load(std::memory_order_acquire);
    for (bool claimed = false;;) {
      if (static_cast<uint32_t>(s >> 32) != gen) return;
      const int chunks = static_cast<int>((s >> 16) & 0xffff), next = static_cast<int>(s & 0xffff);
      if (next >= chunks) return;
      if (!state_.compare_exchange_weak(s, s + 1, std::memory_order_acq_rel)) continue;
      if (!claimed) claimed = true, ran_.fetch_add(1, std::memory_order_relaxed);
      fn_(context_, next);
      if (done_.fetch_add(1, std::memory_order_acq_rel) + 1 == chunks) {
        std::lock_guard<std::mutex> lock(m_);
        if (caller_waiting_) finished_.notify_one();
      }
      s = state_.load(std::memory_order_acquire);
    }
  }

  void worker() {
    inside = true;
    awake.fetch_add(1);
    uint32_t seen = static_cast<uint32_t>(state_.load() >> 32);
    for (;;) {
      auto fresh = [&] { return static_cast<uint32_t>(state_.load() >> 32) != seen; };
      if (!wait_for_job(fresh)) {
        std::unique_lock<std::mutex> lock(m_);
        sleepers_.fetch_add(1);
        awake.fetch_sub(1);
        wake_.wait(lock, fresh);
        awake.fetch_add(1);
        sleepers_.fetch_sub(1);
      }
      seen = static_cast<uint32_t>(state_.load() >> 32);
      work(seen);
    }
  }

  // Spins until `fresh` (true) or for kShortSpin after the policy last wanted spinning workers
  // (false: go to sleep). Counted from that moment, not from the last job, a worker stays awake
  // across the gap between back-to-back frames (a slider drag) instead of being woken per frame.
  template <class Fresh>
  bool wait_for_job(Fresh&& fresh) {
    auto since = std::chrono::steady_clock::now();
    for (int k = 0;; ++k) {
      if (fresh()) return true;
      pause_cpu();
      if ((k & 63) != 63) continue;
      const auto now = std::chrono::steady_clock::now();
      if (policy.keep_spinning()) since = now;
      else if (now - since > kShortSpin) return fresh();
    }
  }

  void grow(int workers) {
    while (static_cast<int>(count_) < workers) {
      std::thread([this] { worker(); }).detach();
      ++count_;
    }
  }

  std::mutex dispatch_;  // held by the thread whose job is running
  std::mutex m_;         // for the sleeping side of the waits
  std::condition_variable wake_, finished_;
  std::atomic<uint64_t> state_{0};
  std::atomic<int> done_{0}, sleepers_{0}, ran_{0};  // ran_: threads that claimed chunks of the job
  bool caller_waiting_ = false;  // guarded by m_
  detail::ChunkFn fn_ = nullptr;
  void* context_ = nullptr;
  unsigned count_ = 0;  // workers started (guarded by dispatch_)
};

}  // namespace

bool machine_busy() { return policy.busy(); }

int detail::chunks_for(double work) {
  if (!(work >= kMinItems) || forked.load(std::memory_order_relaxed)) return 1;
  const int all = std::min(usable_cores(), 0xffff);
  return limit > 0 && limit < all ? limit : all;
}

void detail::note_threads(int threads) { most_ran = std::max(most_ran, threads); }

std::pair<long, long> share(long n, int chunk, int chunks) {
  const long q = n / chunks, r = n % chunks;
  const long first = chunk * q + std::min<long>(chunk, r);
  return {first, first + q + (chunk < r ? 1 : 0)};
}

int detail::run(int chunks, ChunkFn fn, void* context) {
  if (!inside && !forked.load(std::memory_order_relaxed) && policy.use_pool()) {
    inside = true;
    const int ran = Pool::instance().run(std::min(chunks, 0xffff), fn, context);
    inside = false;
    if (ran > 0) return ran;
  }
  for (int k = 0; k < chunks; ++k) fn(context, k);
  return 1;
}

ThreadLimit::ThreadLimit(int threads) : saved_(limit), saved_ran_(most_ran), counted_(threads != 1) {
  limit = threads;
  most_ran = 1;
  if (counted_) computing.fetch_add(1, std::memory_order_relaxed);
  saved_dynamic_ = detail::swap_omp_dynamic(1);
}

int ThreadLimit::threads_ran() const { return most_ran; }

ThreadLimit::~ThreadLimit() {
  limit = saved_;
  most_ran = std::max(saved_ran_, most_ran);
  if (counted_) computing.fetch_sub(1, std::memory_order_relaxed);
  if (saved_dynamic_ >= 0) detail::swap_omp_dynamic(saved_dynamic_);
}

}  // namespace bdinterp::parallel
