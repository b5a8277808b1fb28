// Internal: intra-frame parallelism. The face and edge loops of one frame are split over the cores
// (OpenMP), except inside Interpolator::frames(), which already solves one frame per core.
#pragma once

#include <vector>

namespace bdinterp::parallel {

// Threads to use for a loop of `items` independent iterations started on the calling thread: 1 for
// small loops (a fork/join costs a few microseconds), else all cores up to this thread's limit.
int loop_threads(long items);
// This thread's index inside a parallel region (0 outside).
int thread_index();

// While alive, loops started on this thread use at most `threads` threads (0: no limit).
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

 private:
  int saved_;
};

// Per-thread accumulation buffers for scatter-adds (thread 0 writes into the caller's array, the
// others into their own, summed afterwards in a fixed order, so results do not depend on timing).
class Partials {
 public:
  // Buffers of `size` for threads 1 .. threads-1 (kept between calls).
  void prepare(int threads, long size);
  double* buffer(int thread, double* own) { return thread == 0 ? own : parts_[thread - 1].data(); }
  // target[i] += sum of the other threads' buffers.
  void add_into(double* target) const;

 private:
  int threads_ = 1;
  long size_ = 0;
  std::vector<std::vector<double>> parts_;
};

}  // namespace bdinterp::parallel
