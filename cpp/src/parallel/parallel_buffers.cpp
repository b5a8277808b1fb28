// The per-chunk accumulation buffers of the loops (parallel.h): summed in chunk order, so results
// do not depend on which thread ran which chunk.
#include <algorithm>

#include "parallel/parallel.h"

namespace bdinterp::parallel {

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

double PerChunk::sum() const {
  double s = 0;
  for (const Slot& v : values_) s += v.value;
  return s;
}

double PerChunk::max() const {
  double m = values_[0].value;
  for (const Slot& v : values_) m = std::max(m, v.value);
  return m;
}

}  // namespace bdinterp::parallel
