// Internal: intra-frame parallelism. The face and edge loops of one frame are split over the cores
// (OpenMP), except inside Interpolator::frames(), which already solves one frame per core.
#pragma once

#include <vector>

namespace bdinterp::parallel {

// Threads to use for a loop of `items` independent iterations started on the calling thread: 1 for
// small loops (a fork/join costs a few microseconds), 1 on threads marked by SerialLoops, else all.
int loop_threads(long items);
// This thread's index inside a parallel region (0 outside).
int thread_index();

// While alive, loops started on this thread run on it alone.
class SerialLoops {
 public:
  SerialLoops();
  ~SerialLoops();
  SerialLoops(const SerialLoops&) = delete;
  SerialLoops& operator=(const SerialLoops&) = delete;

 private:
  bool saved_;
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
