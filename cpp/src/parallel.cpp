#include "bdinterp/parallel.h"

#ifdef _OPENMP
#include <omp.h>
#include <pthread.h>
#endif

namespace bdinterp::parallel {
namespace {
// Below this many iterations a loop of a frame is not worth splitting (measured: a 5k-vertex mesh,
// 10k faces, gains ~1.7x on two cores; a few hundred faces lose to the fork/join).
constexpr long kMinItems = 2000;
thread_local int limit = 0;  // 0: none

#ifdef _OPENMP
// OpenMP's thread pool does not survive fork(): a child that starts a parallel region after its
// parent ran one waits forever for threads that were not copied (e.g. Python's multiprocessing).
// Children run their loops serially instead.
bool forked = false;
void note_fork() { forked = true; }
const bool fork_handler = pthread_atfork(nullptr, nullptr, note_fork) == 0;
#endif
}  // namespace

int loop_threads(long items) {
#ifdef _OPENMP
  if (items < kMinItems || forked) return 1;
  const int all = omp_get_max_threads();
  return limit > 0 && limit < all ? limit : all;
#else
  (void)items;
  return 1;
#endif
}

int thread_index() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

ThreadLimit::ThreadLimit(int threads) : saved_(limit) { limit = threads; }
ThreadLimit::~ThreadLimit() { limit = saved_; }

void Partials::prepare(int threads, long size) {
  threads_ = threads;
  size_ = size;
  if (static_cast<int>(parts_.size()) < threads - 1) parts_.resize(threads - 1);
  for (int k = 0; k + 1 < threads; ++k) parts_[k].resize(size);
}

void Partials::add_into(double* target) const {
  for (int k = 0; k + 1 < threads_; ++k) {
    const double* p = parts_[k].data();
    for (long i = 0; i < size_; ++i) target[i] += p[i];
  }
}

}  // namespace bdinterp::parallel
