// What the thread pool knows of the machine (parallel.h, detail), the platform-independent part: the
// running means it judges by, CPU quotas, other programs' busy cores from CPU-time counters. What each platform
// reports is in machine_probe_linux.cpp, machine_probe_windows.cpp and machine_probe_macos.cpp.
#include <algorithm>
#include <cmath>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>

#include "parallel/parallel.h"

namespace bdinterp::parallel {
int detail::quota_cores(const std::string& cpu_max) {
  std::istringstream in(cpu_max);
  std::string quota;
  double period = 0;
  if (!(in >> quota >> period) || quota == "max" || period <= 0) return 0;
  double q = 0;
  try {
    q = std::stod(quota);
  } catch (...) {
    return 0;
  }
  if (!(q > 0)) return 0;  // v1 writes -1 for "no quota"
  // 1.5 cores of quota: two threads can run, but not both all the time; round up (a chunk a
  // throttled worker does not claim is run by the caller).
  return std::max(1, static_cast<int>(std::ceil(q / period - 1e-9)));
}

bool detail::LoadMean::add(int others, int cores) {
  // Busy when the others leave fewer than two cores to this process (one for the caller, one for
  // a worker); without the count, assume busy: running serially is the cautious choice.
  const double excess = others < 0 ? 1.0 : std::max(0, others - (cores - 2));
  mean_ = 0.75 * mean_ + 0.25 * excess;
  return mean_ >= 0.5;
}

int detail::OtherCores::add(uint64_t busy, uint64_t own, uint64_t total, int cores, uint64_t min_total) {
  if (!started_) {
    started_ = true;
    busy_ = busy, own_ = own, total_ = total;
    return -1;
  }
  // Counters that went back (a wrapped or reset counter): start a new window.
  if (busy < busy_ || own < own_ || total < total_ || busy - busy_ > total - total_) {
    busy_ = busy, own_ = own, total_ = total;
    return last_;
  }
  // Counters advance by the clock tick (1-16 ms): a shorter window would be mostly rounding.
  if (total - total_ < min_total) return last_;
  // The process's time is counted apart from the machine's, so it can exceed the busy time by a tick.
  const double others = static_cast<double>(busy - busy_) - static_cast<double>(own - own_);
  const double share = std::max(0.0, others) / static_cast<double>(total - total_);
  busy_ = busy, own_ = own, total_ = total;
  last_ = std::min(cores, static_cast<int>(std::lround(share * cores)));
  return last_;
}

int detail::other_cores_now(uint64_t busy, uint64_t own, uint64_t total, int cores, uint64_t min_total) {
  static std::mutex m;
  static OtherCores window;
  const std::lock_guard<std::mutex> lock(m);
  return window.add(busy, own, total, cores, min_total);
}

int detail::cores_within(int limit) {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return limit > 0 ? std::min(cores, limit) : cores;
}

}  // namespace bdinterp::parallel
