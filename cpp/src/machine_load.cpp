// What the thread pool knows of the machine (parallel.h, detail): the cores this process may use,
// how many other threads want them, and the two running means it judges by.
#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "bdinterp/parallel.h"

namespace bdinterp::parallel {
namespace {
// This process's cgroup path for `controller` ("" for v2's unified hierarchy) from /proc/self/cgroup
// ("0::/system.slice/x.service", "1:cpu,cpuacct:/docker/abc"); "/" inside a container's namespace.
std::string cgroup_path(const std::string& controller) {
  std::ifstream in("/proc/self/cgroup");
  for (std::string line; std::getline(in, line);) {
    const size_t a = line.find(':'), b = line.find(':', a + 1);
    if (a == std::string::npos || b == std::string::npos) continue;
    const std::string names = "," + line.substr(a + 1, b - a - 1) + ",";
    if (controller.empty() ? names == ",," : names.find("," + controller + ",") != std::string::npos)
      return line.substr(b + 1);
  }
  return "/";
}

// The cgroup's CPU quota in cores (0: none), v2 (cpu.max) or v1 (cfs_quota_us / cfs_period_us), in
// the process's own cgroup (a systemd unit's CPUQuota, a container's --cpus).
int cgroup_quota_cores() {
  std::ifstream v2("/sys/fs/cgroup" + cgroup_path("") + "/cpu.max");
  std::string line;
  if (v2 && std::getline(v2, line)) return detail::quota_cores(line);
  const std::string v1 = "/sys/fs/cgroup/cpu" + cgroup_path("cpu");
  std::ifstream quota(v1 + "/cpu.cfs_quota_us"), period(v1 + "/cpu.cfs_period_us");
  std::string q, p;
  if (quota >> q && period >> p) return detail::quota_cores(q + " " + p);
  return 0;
}
}  // namespace

int usable_cores() {
  static const int n = [] {
    int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0) cores = std::min(cores, std::max(1, CPU_COUNT(&set)));
    const int quota = cgroup_quota_cores();
    return quota > 0 ? std::min(cores, quota) : cores;
  }();
  return n;
}

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
  // 1.5 cores of quota: two threads can run, but not both all the time; round up, the pool's
  // lateness rule covers the rest.
  return std::max(1, static_cast<int>(std::ceil(q / period - 1e-9)));
}

int detail::runnable_threads() {
  static const int fd = open("/proc/loadavg", O_RDONLY | O_CLOEXEC);
  char buf[128];
  const ssize_t n = fd < 0 ? -1 : pread(fd, buf, sizeof buf - 1, 0);
  if (n <= 0) return -1;
  buf[n] = 0;
  int running = -1;
  // "0.52 0.58 0.59 3/245 12345": the fourth field is runnable/total.
  return std::sscanf(buf, "%*s %*s %*s %d/", &running) == 1 ? running : -1;
}

bool detail::LoadMean::add(int others, int cores) {
  // Busy when the others leave fewer than two cores to this process (one for the caller, one for
  // a worker); without the count, assume busy: running serially is the cautious choice.
  const double excess = others < 0 ? 1.0 : std::max(0, others - (cores - 2));
  mean_ = 0.75 * mean_ + 0.25 * excess;
  return mean_ >= 0.5;
}

bool detail::LateMean::add(bool late) {
  mean_ = 0.875 * mean_ + (late ? 0.125 : 0.0);
  return late && mean_ >= 0.2;
}

double detail::busy_arithmetic(int rounds) {
  // 24 independent chains of a multiply and an add keep the floating-point units busy (2 x 24 operations
  // per ~6 cycles of latency): a few chains would only wait on their own latency and leave room for
  // a hyper-threaded sibling, which could then not be told from a core of its own.
  double a[24];
  for (int j = 0; j < 24; ++j) a[j] = 1.0 + 0.01 * j;
  for (int r = 0; r < rounds; ++r) {
    for (double& x : a) x = x * 0.9999999 + 1e-7;
  }
  double sum = 0;
  for (double x : a) sum += x;
  static std::atomic<double> sink{0};
  sink.store(sum, std::memory_order_relaxed);
  return sum;
}

}  // namespace bdinterp::parallel
