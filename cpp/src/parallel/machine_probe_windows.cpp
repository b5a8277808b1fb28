// The machine as Windows reports it (parallel.h). Run under Wine by `make test-windows`.
// Windows has no count of runnable threads and no cgroups: the load is the cores other programs kept
// busy since the previous sample (GetSystemTimes minus GetProcessTimes: the pool's own threads are
// not counted; it cannot exceed the core count, so demand beyond the cores is not seen: every core
// busy already makes the verdict busy), and a job object's CPU rate limit is not read (plain fallback:
// the affinity mask and the processor count only).
#include "parallel/windows.h"

#include <bitset>
#include <cstdint>

#include "parallel/parallel.h"

namespace bdinterp::parallel {
namespace {
uint64_t ticks_of(const FILETIME& t) { return (static_cast<uint64_t>(t.dwHighDateTime) << 32) | t.dwLowDateTime; }

// All logical processors of the machine (every processor group), which GetSystemTimes sums over.
int machine_cores() {
  const DWORD n = GetActiveProcessorCount(ALL_PROCESSOR_GROUPS);
  return n > 0 ? static_cast<int>(n) : detail::cores_within(0);
}
}  // namespace

int usable_cores() {
  static const int n = detail::cores_within(detail::affinity_cores());
  return n;
}

int detail::affinity_cores() {
  // The mask of the process's processor group (at most 64 processors: a process starts in one group).
  DWORD_PTR process = 0, system = 0;
  if (!GetProcessAffinityMask(GetCurrentProcess(), &process, &system) || process == 0) return -1;
  return static_cast<int>(std::bitset<64>(static_cast<uint64_t>(process)).count());
}

int detail::other_threads(int) {
  FILETIME idle, kernel, user;  // 100 ns units summed over all processors; kernel time includes idle
  FILETIME created, exited, own_kernel, own_user;  // this process's threads, the same units
  if (!GetSystemTimes(&idle, &kernel, &user) ||
      !GetProcessTimes(GetCurrentProcess(), &created, &exited, &own_kernel, &own_user))
    return -1;
  const uint64_t total = ticks_of(kernel) + ticks_of(user);
  const int cores = machine_cores();
  // A window of at least 20 ms per core: the counters advance by the clock tick (~16 ms).
  return other_cores_now(total - ticks_of(idle), ticks_of(own_kernel) + ticks_of(own_user), total, cores,
                         200000ull * cores);
}

}  // namespace bdinterp::parallel
