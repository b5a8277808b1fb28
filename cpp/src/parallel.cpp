#include "bdinterp/parallel.h"

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

// Below this many iterations a loop of a frame is not worth splitting. With the worker spinning
// through a frame on an idle machine a fork/join costs about a microsecond, so loops of a few
// hundred faces gain too (warm frames on the idle 2-core VM, default / threads=1, with 500 against
// 2000: 500 vertices 0.79-0.82 against 0.97-1.01, 1k 0.79-0.95 against 1.01-1.10, 2k 0.73 against
// 0.76-0.80).
constexpr long kMinItems = 500;
// How long an idle worker spins before it sleeps. While a frame is being computed on an idle
// machine: until the next loop, however long. A warm frame alternates parallel loops with serial
// Cholesky solves (~0.15 ms each at 5k vertices, milliseconds at 50k): a worker that went to sleep
// during a solve costs a futex wake-up and a scheduling delay at the next loop, about what that
// loop gains on two cores (measured: with 20 us spins only, warm frames on an idle machine were
// 1.01-1.07x the one-thread time). Otherwise (between frames, or on a busy machine) kShortSpin,
// just the gap between the loops of one evaluation: on a busy machine a spinning worker takes the
// core from the frame's own calling thread and from other programs (measured: 300 us spins made
// frames beside busy programs 1.37-1.70x slower than one thread).
constexpr auto kShortSpin = std::chrono::microseconds(20);
// Busy = other programs leave this process fewer than two cores (detail::LoadMean). Sampled every
// kSample by a thread that starts a loop, from the kernel's count of runnable threads
// (/proc/loadavg: one pread, a few us) less this process's running threads (the sampler and the
// awake workers). While busy, loops run serially on their calling thread: beside one busy program
// on two cores a second thread of ours only takes turns with the first on the remaining core
// (measured: warm 5k frames 1.17-1.24x the one-thread time with the pool, beside another bdinterp
// 1.13-1.36x). A competitor that starts or stops is noticed within ~30 ms of frames; after a second
// without loops the verdict goes back to busy until measured again.
constexpr auto kSample = std::chrono::milliseconds(10);
constexpr auto kStale = std::chrono::seconds(1);
// When the caller waited for a chunk that a worker had claimed longer than its own chunks took
// (plus kSlack for wake-up and cache noise), the worker was descheduled mid-chunk. If that happens
// again and again (detail::LateMean: contention the runnable count does not show, such as a CPU
// quota or a noisy host), callers run all chunks themselves for kBackOff (the same chunks and
// partial sums, so the same bits), then try the pool again. Not for one late chunk now and then:
// on the idle VM backing off after every one made warm 5k frames serial ~60 % of the time (47
// back-offs in 4 s: 0.99x the one-thread time; 0.74-0.90x without).
constexpr auto kBackOff = std::chrono::milliseconds(50);
constexpr auto kSlack = std::chrono::microseconds(50);
// Whether a second core pays for small loops, measured every kProbeEvery while a worker spins: the
// round trip of one cache line to it (the fastest of kProbeTrips; beyond far_round_trip_ns the cores
// are far apart) and whether two threads really run at once (concurrent()). This VM's host moves
// its two virtual cores between physical ones within seconds: round trips of 80-110 ns, 200-450 ns
// (far apart) or 60-70 ns (one core's two hyper-threads). In the last two states frames that split
// their loops took 1.2-1.9x the one-thread time at 1k vertices (1.0-1.2x at 5k): every fork/join and
// every line the other core wrote paid for the distance, or two threads shared one core. Then loops
// under kFarMinItems run serially on the calling thread (the same chunks, so the same bits) until
// the next probe. Larger loops still use the pool: their chunks are long and their data is beyond
// the cores' own caches anyway (warm 50k frames 0.68x the one-thread time at a 410 ns round trip,
// against ~1.05x serially).
constexpr auto kProbeEvery = std::chrono::milliseconds(100);
constexpr long kFarMinItems = 20000;
constexpr int kProbeTrips = 16;
constexpr int kProbeRounds = 6000;  // busy_arithmetic: ~11 us
std::atomic<int64_t> far_round_trip_ns{160};
std::atomic<int> concurrent_limit{3};  // two chunks in less than 3/2 of one's time
std::atomic<int64_t> last_round_trip_ns{-1};
std::atomic<bool> last_concurrent{true};
std::atomic<int64_t> serial_until{0};  // steady_clock ticks
std::atomic<bool> busy{true};  // see kSample; until measured, the cautious guess
std::atomic<int> computing{0};  // ThreadLimits alive that allow more than one thread: frames running
std::atomic<int> awake{0};      // pool workers not asleep (spinning or running chunks)

int64_t ticks() { return std::chrono::steady_clock::now().time_since_epoch().count(); }
template <class Duration>
int64_t ticks_of(Duration d) {
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(d).count();
}

thread_local int limit = 0;        // 0: none
thread_local bool inside = false;  // running a chunk or a run(): nested runs are serial

// The pool does not survive fork(): a child (e.g. of Python's multiprocessing) runs serially.
std::atomic<bool> forked{false};
#ifndef _WIN32
void note_fork() { forked.store(true); }
const bool fork_handler = pthread_atfork(nullptr, nullptr, note_fork) == 0;
#endif  // Windows has no fork()

// The busy verdict (see kSample), updated by whichever thread starts a loop when the last sample is
// older than kSample (one at a time).
class LoadProbe {
 public:
  void sample() {
    const int64_t now = ticks();
    int64_t last = last_.load(std::memory_order_relaxed);
    if (now - last < ticks_of(kSample) || !last_.compare_exchange_strong(last, now)) return;
    const int others = detail::other_threads(1 + awake.load(std::memory_order_relaxed));
    const std::lock_guard<std::mutex> lock(m_);
    if (now - last > ticks_of(kStale)) verdict_ = detail::LoadMean();  // old news: the cautious guess
    busy.store(verdict_.add(others, usable_cores()), std::memory_order_relaxed);
  }

 private:
  std::atomic<int64_t> last_{0};
  std::mutex m_;
  detail::LoadMean verdict_;
};
LoadProbe load_probe;

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

  // False if another thread is using the pool (the caller then runs the chunks itself).
  bool run(int chunks, detail::ChunkFn fn, void* context, long items) {
    std::unique_lock<std::mutex> job(dispatch_, std::try_to_lock);
    if (!job.owns_lock()) return false;
    grow(std::min(chunks, usable_cores()) - 1);
    if (!cores_pay() && items < kFarMinItems) return false;
    const auto [own, waited] = dispatch(chunks, fn, context);
    if (late_.add(waited > own + ticks_of(kSlack)))
      serial_until.store(ticks() + ticks_of(kBackOff), std::memory_order_relaxed);
    return true;
  }

 private:
  // Runs a job on the caller and the workers; returns the time of the caller's own chunks and of
  // its wait for the others' (ticks). The caller spins `spin` before it sleeps.
  std::pair<int64_t, int64_t> dispatch(int chunks, detail::ChunkFn fn, void* context,
                                       std::chrono::microseconds spin = kShortSpin) {
    fn_ = fn;
    context_ = context;
    done_.store(0);
    const uint64_t gen = (state_.load() >> 32) + 1;
    state_.store(gen << 32 | static_cast<uint64_t>(chunks) << 16);
    if (sleepers_.load() > 0) {
      { std::lock_guard<std::mutex> lock(m_); }
      wake_.notify_all();
    }
    const int64_t t0 = ticks();
    work(static_cast<uint32_t>(gen));
    const int64_t t1 = ticks();
    if (!spin_until(spin, [&] { return done_.load(std::memory_order_acquire) == chunks; })) {
      std::unique_lock<std::mutex> lock(m_);
      caller_waiting_ = true;
      finished_.wait(lock, [&] { return done_.load() == chunks; });
      caller_waiting_ = false;
    }
    return {t1 - t0, ticks() - t1};
  }

  // Whether splitting small loops pays (see kProbeEvery): the cores are near, and two of them
  // really run at once. Probes when due (dispatch_ held, so no job is running). A probe needs a
  // spinning worker: if none is, after a verdict "pays" this job runs on the pool (waking one) and
  // the next call probes; after "does not pay" the workers are woken without a job and loops stay
  // serial for another millisecond.
  bool cores_pay() {
    const int64_t now = ticks(), soon = now + ticks_of(std::chrono::milliseconds(1));
    if (now < apart_until_) return false;
    if (now < next_probe_) return true;
    if (awake.load() == 0 || sleepers_.load() > 0) {
      if (pay_) return true;
      wake_workers();  // rather than jobs waking it one by one, a futex call each
      next_probe_ = apart_until_ = soon;
      return false;
    }
    const int64_t rt = round_trip_ns();
    next_probe_ = rt < 0 ? soon : now + ticks_of(kProbeEvery);
    if (rt < 0) return pay_;  // unanswered (the worker was descheduled): again in a millisecond
    last_round_trip_ns.store(rt, std::memory_order_relaxed);
    pay_ = rt <= far_round_trip_ns.load(std::memory_order_relaxed) && concurrent();
    if (!pay_) apart_until_ = next_probe_;
    return pay_;
  }

  // Publishes a job without chunks: sleeping workers wake up and spin (for a probe).
  void wake_workers() {
    state_.store(((state_.load() >> 32) + 1) << 32);
    { std::lock_guard<std::mutex> lock(m_); }
    wake_.notify_all();
  }

  // Whether two chunks of arithmetic, on the caller and a worker, take less than 1.5x as long as one
  // on the caller (the best of two tries each, ~10 us a chunk): not so when the two cores are one
  // physical core's two hyper-threads, as this VM's host sometimes makes them (round trips of 60-70
  // ns then, against 80-110 ns; warm 1k frames split over them took 1.6-1.8x the one-thread time).
  bool concurrent() {
    int64_t one = INT64_MAX, two = INT64_MAX;
    for (int k = 0; k < 2; ++k) {
      int64_t t = ticks();
      detail::busy_arithmetic(kProbeRounds);
      one = std::min(one, ticks() - t);
      t = ticks();
      // Spinning: a caller put to sleep on a VM can wait milliseconds for its core (seen once per
      // probe as 1.3-1.4x slower 1k frames while the cores were hyper-threads).
      dispatch(2, [](void*, int) { detail::busy_arithmetic(kProbeRounds); }, nullptr, std::chrono::microseconds(500));
      two = std::min(two, ticks() - t);
    }
    const bool at_once = two * 2 < one * concurrent_limit.load(std::memory_order_relaxed);
    last_concurrent.store(at_once, std::memory_order_relaxed);
    return at_once;
  }

  // The fastest of kProbeTrips round trips of ping_ to a spinning worker and back, in ns; -1 if
  // one went unanswered for 20 us.
  int64_t round_trip_ns() {
    int64_t best = -1;
    for (int k = 0; k < kProbeTrips; ++k) {
      const uint32_t v = ping_.load();
      const auto t0 = std::chrono::steady_clock::now();
      ping_.store(v + 1);  // odd: a worker answers with v + 2
      const bool answered = spin_until(std::chrono::microseconds(20),
                                       [&] { return ping_.load(std::memory_order_acquire) != v + 1; });
      const int64_t ns = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0).count();
      if (!answered) {
        ping_.store(v + 2);  // withdrawn (a late answer's CAS then fails)
        return -1;
      }
      best = best < 0 ? ns : std::min(best, ns);
    }
    return best;
  }

  // A spinning worker's side of round_trip_ns().
  void answer_ping() {
    uint32_t v = ping_.load(std::memory_order_relaxed);
    if (v & 1) ping_.compare_exchange_strong(v, v + 1);
  }

  // Claims and runs chunks of job `gen` until none is left.
  void work(uint32_t gen) {
    uint64_t s = state_.load(std::memory_order_acquire);
    for (;;) {
      if (static_cast<uint32_t>(s >> 32) != gen) return;
      const int chunks = static_cast<int>((s >> 16) & 0xffff), next = static_cast<int>(s & 0xffff);
      if (next >= chunks) return;
      if (!state_.compare_exchange_weak(s, s + 1, std::memory_order_acq_rel)) continue;
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

  // Spins until `fresh` (true) or for kShortSpin after the last moment a frame was being computed on
  // an idle machine with the pool in use (false: go to sleep; while callers back off, see kBackOff,
  // a spinning worker would only take a core). Counting the short spin from
  // that moment, not from the last job, keeps a worker awake across the gap between back-to-back
  // frames (a slider drag, a script's loop) instead of waking it at the next frame's first loop.
  template <class Fresh>
  bool wait_for_job(Fresh&& fresh) {
    auto since = std::chrono::steady_clock::now();
    for (int k = 0;; ++k) {
      if (fresh()) return true;
      answer_ping();
      pause_cpu();
      if ((k & 63) != 63) continue;
      const auto now = std::chrono::steady_clock::now();
      const bool keep = computing.load(std::memory_order_relaxed) > 0 && !busy.load(std::memory_order_relaxed) &&
                        now.time_since_epoch().count() >= serial_until.load(std::memory_order_relaxed);
      if (keep) since = now;
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
  alignas(64) std::atomic<uint32_t> ping_{0};  // odd: a round trip waiting for a worker's answer
  alignas(64) int64_t next_probe_ = 0;  // ticks (guarded by dispatch_, as are the next two)
  int64_t apart_until_ = 0;
  bool pay_ = true;  // the last probe's verdict
  std::atomic<int> done_{0}, sleepers_{0};
  bool caller_waiting_ = false;  // guarded by m_
  detail::ChunkFn fn_ = nullptr;
  void* context_ = nullptr;
  unsigned count_ = 0;  // workers started (guarded by dispatch_)
  detail::LateMean late_;  // guarded by dispatch_
};

}  // namespace

bool machine_busy() { return busy.load(std::memory_order_relaxed); }

int64_t detail::core_round_trip_ns() { return last_round_trip_ns.load(std::memory_order_relaxed); }

int64_t detail::swap_far_round_trip_ns(int64_t ns) { return far_round_trip_ns.exchange(ns); }

bool detail::cores_run_at_once() { return last_concurrent.load(std::memory_order_relaxed); }

int detail::swap_concurrent_limit(int twice_ratio) { return concurrent_limit.exchange(twice_ratio); }

int loop_threads(long items) {
  if (items < kMinItems || forked.load(std::memory_order_relaxed)) return 1;
  const int all = std::min(usable_cores(), 0xffff);
  return limit > 0 && limit < all ? limit : all;
}

std::pair<long, long> share(long n, int chunk, int chunks) {
  const long q = n / chunks, r = n % chunks;
  const long first = chunk * q + std::min<long>(chunk, r);
  return {first, first + q + (chunk < r ? 1 : 0)};
}

void detail::run(int chunks, ChunkFn fn, void* context, long items) {
  if (inside || forked.load(std::memory_order_relaxed)) {
    for (int k = 0; k < chunks; ++k) fn(context, k);
    return;
  }
  load_probe.sample();
  if (!busy.load(std::memory_order_relaxed) && ticks() >= serial_until.load(std::memory_order_relaxed)) {
    inside = true;
    const bool ran = Pool::instance().run(std::min(chunks, 0xffff), fn, context, items);
    inside = false;
    if (ran) return;
  }
  for (int k = 0; k < chunks; ++k) fn(context, k);
}

ThreadLimit::ThreadLimit(int threads) : saved_(limit), counted_(threads != 1) {
  limit = threads;
  if (counted_) computing.fetch_add(1, std::memory_order_relaxed);
  saved_dynamic_ = detail::swap_omp_dynamic(1);
}

ThreadLimit::~ThreadLimit() {
  limit = saved_;
  if (counted_) computing.fetch_sub(1, std::memory_order_relaxed);
  if (saved_dynamic_ >= 0) detail::swap_omp_dynamic(saved_dynamic_);
}

}  // namespace bdinterp::parallel
