// The machine as macOS reports it (parallel.h).
// NOT RUN: no Mac was at hand. `make test-libcxx` only compiles this file (clang, libc++,
// -fsyntax-only against declarations of the Apple calls in tests/cpp/macos_sdk, written from
// Apple's headers); its behaviour on a Mac is untested.
// macOS has no count of runnable threads, no affinity masks (thread affinity tags are hints) and
// no cgroups: usable cores are the active CPUs (sysctl hw.activecpu), and the load is the cores other
// programs kept busy since the previous sample (host_processor_info's tick counters minus this
// process's getrusage time: the pool's own threads are not counted; it cannot exceed the core count,
// so demand beyond the cores is not seen: every core busy already makes the verdict busy).
#include <mach/mach.h>
#include <sys/resource.h>
#include <sys/sysctl.h>
#include <sys/types.h>
#include <unistd.h>

#include <cstdint>

#include "parallel/parallel.h"

namespace bdinterp::parallel {
namespace {
uint64_t microseconds(const timeval& t) { return static_cast<uint64_t>(t.tv_sec) * 1000000u + static_cast<uint64_t>(t.tv_usec); }
}  // namespace

int usable_cores() {
  static const int n = detail::cores_within(detail::affinity_cores());
  return n;
}

int detail::affinity_cores() {
  int active = 0;
  size_t size = sizeof active;
  return sysctlbyname("hw.activecpu", &active, &size, nullptr, 0) == 0 ? active : -1;
}

int detail::other_threads(int) {
  natural_t cpus = 0;
  processor_info_array_t info = nullptr;
  mach_msg_type_number_t count = 0;
  rusage self{};
  if (getrusage(RUSAGE_SELF, &self) != 0 ||
      host_processor_info(mach_host_self(), PROCESSOR_CPU_LOAD_INFO, &cpus, &info, &count) != KERN_SUCCESS)
    return -1;
  uint64_t busy = 0, total = 0;
  for (natural_t c = 0; c < cpus; ++c) {
    const integer_t* ticks = info + CPU_STATE_MAX * c;
    const uint64_t b = static_cast<uint64_t>(ticks[CPU_STATE_USER]) + ticks[CPU_STATE_SYSTEM] + ticks[CPU_STATE_NICE];
    busy += b;
    total += b + ticks[CPU_STATE_IDLE];
  }
  vm_deallocate(mach_task_self(), reinterpret_cast<vm_address_t>(info), count * sizeof(integer_t));
  // The process's user and system time (all its threads) in the processor counters' clock ticks.
  const long hz = sysconf(_SC_CLK_TCK);
  const uint64_t us = microseconds(self.ru_utime) + microseconds(self.ru_stime);
  const uint64_t own = hz > 0 ? us * static_cast<uint64_t>(hz) / 1000000u : 0;
  // A window of at least 2 ticks (10 ms each) per core.
  return other_cores_now(busy, own, total, static_cast<int>(cpus), 2ull * cpus);
}

}  // namespace bdinterp::parallel
