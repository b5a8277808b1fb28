// The machine as Linux reports it (parallel.h): the affinity mask, the cgroup's CPU quota, and the
// kernel's count of runnable threads in /proc/loadavg.
#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>

#include "parallel/parallel.h"

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
    const int cores = detail::cores_within(detail::affinity_cores());
    const int quota = cgroup_quota_cores();
    return quota > 0 ? std::min(cores, quota) : cores;
  }();
  return n;
}

int detail::affinity_cores() {
  cpu_set_t set;
  return sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : -1;
}

int detail::other_threads(int own_running) {
  static const int fd = open("/proc/loadavg", O_RDONLY | O_CLOEXEC);
  char buf[128];
  const ssize_t n = fd < 0 ? -1 : pread(fd, buf, sizeof buf - 1, 0);
  if (n <= 0) return -1;
  buf[n] = 0;
  int running = -1;
  // "0.52 0.58 0.59 3/245 12345": the fourth field is runnable/total.
  if (std::sscanf(buf, "%*s %*s %*s %d/", &running) != 1) return -1;
  return std::max(0, running - own_running);
}

}  // namespace bdinterp::parallel
