#include "busy.h"

#include "parallel/parallel.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace bench {
namespace {

using Clock = std::chrono::steady_clock;

// A slider dragged back and forth by 0.005 per frame over [0.2, 0.8].
struct Slider {
  double t = 0.2, dt = 0.005;
  double next() {
    if (t + dt > 0.8 || t + dt < 0.2) dt = -dt;
    return t += dt;
  }
};

// Milliseconds per warm frame over `frames` frames.
double warm_ms(bdinterp::Interpolator& I, Slider& s, int frames) {
  bdinterp::Positions out(I.num_vertices(), 2);
  const auto t0 = Clock::now();
  for (int k = 0; k < frames; ++k) {
    const double t = s.next();
    I.blend_into(Eigen::Vector2d(1 - t, t), out);
  }
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count() / frames;
}

// Milliseconds per frame of a cold bake of 101 frames.
double bake_ms(bdinterp::Interpolator& I) {
  std::vector<double> ts(101);
  for (int j = 0; j < 101; ++j) ts[j] = j / 100.0;
  bdinterp::Positions out(I.num_vertices() * 101, 2);
  I.forget();
  const auto t0 = Clock::now();
  I.frames(ts, out);
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count() / 101;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// The median of a[r] / b[r]: each repetition runs both modes back to back, so a ratio compares them
// under the same load; the load of a shared machine drifts over seconds, and with three busy loops
// on two cores the ratio of the two medians moved by +-0.2 between runs of 9 repetitions.
double paired_ratio(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> r(a.size());
  for (size_t k = 0; k < a.size(); ++k) r[k] = a[k] / b[k];
  return median(r);
}

// Competing processes: busy loops, or this program re-executed with --compete=n.
std::vector<pid_t> start(int busy, int compete_n) {
  std::vector<pid_t> pids;
  for (int k = 0; k < busy; ++k) {
    const pid_t pid = fork();
    if (pid == 0) {
      for (volatile unsigned long x = 0;; x = x + 1) {
      }
    }
    pids.push_back(pid);
  }
  if (compete_n > 0) {
    const pid_t pid = fork();
    if (pid == 0) {
      const std::string arg = "--compete=" + std::to_string(compete_n);
      execl("/proc/self/exe", "bdinterp_bench", arg.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    pids.push_back(pid);
  }
  return pids;
}

void stop(const std::vector<pid_t>& pids) {
  for (pid_t p : pids) kill(p, SIGKILL);
  for (pid_t p : pids) waitpid(p, nullptr, 0);
}

struct Condition {
  const char* name;
  int busy, compete;  // busy loops; size of a competing bdinterp (0: none)
};

}  // namespace

void print_busy_rows(const std::vector<int>& sizes, int reps, const MakeInterpolator& make) {
  std::printf("\nBusy machine (ms per frame, medians of %d interleaved runs; ratio = default / threads=1, the"
              " median of each run's ratio; target <= 1.3 when busy, < 1 idle)\n", reps);
  std::printf("%9s  %-26s %9s %9s %7s %11s %11s %7s %10s\n", "vertices", "competing", "warm", "warm_t1", "ratio",
              "bake/frame", "bake_t1", "ratio", "pool_busy");
  const Condition conditions[] = {{"none (idle)", 0, 0}, {"1 busy loop", 1, 0}, {"3 busy loops", 3, 0},
                                  {"bdinterp, default threads", 0, 5000}};
  for (int n : sizes) {
    std::unique_ptr<bdinterp::Interpolator> I = make(n);
    Slider slider;
    // Short runs (~0.1 s), alternated: the load of a shared machine drifts within seconds.
    const int frames = std::max(3, std::min(50, 100000 / n));
    for (const Condition& c : conditions) {
      const std::vector<pid_t> pids = start(c.busy, c.compete);
      usleep(200000);  // let the competitors get going
      std::vector<double> warm[2], bake[2];
      int judged_busy = 0;  // default-thread runs after which the pool judged the machine busy
      for (int r = 0; r < reps; ++r) {
        // Which mode goes first alternates, so neither always follows the other's bake.
        for (int k = 0; k < 2; ++k) {
          const int one = (k + r) % 2;
          I->set_threads(one);
          warm_ms(*I, slider, 3);  // back on the slider after a bake (not timed)
          warm[one].push_back(warm_ms(*I, slider, frames));
          if (one == 0) judged_busy += bdinterp::parallel::machine_busy();
          if (n <= 20000) bake[one].push_back(bake_ms(*I));
        }
      }
      I->set_threads(0);
      stop(pids);
      const double b0 = bake[0].empty() ? NAN : median(bake[0]), b1 = bake[1].empty() ? NAN : median(bake[1]);
      std::printf("%9d  %-26s %9.3f %9.3f %7.2f %11.3f %11.3f %7.2f %9.0f%%\n", I->num_vertices(), c.name,
                  median(warm[0]), median(warm[1]), paired_ratio(warm[0], warm[1]), b0, b1,
                  bake[0].empty() ? NAN : paired_ratio(bake[0], bake[1]), 100.0 * judged_busy / reps);
      std::fflush(stdout);
    }
  }
}

void compete(int argc, char** argv, const MakeInterpolator& make) {
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--compete=", 10) != 0) continue;
    std::unique_ptr<bdinterp::Interpolator> I = make(std::atoi(argv[i] + 10));
    Slider slider;
    for (;;) warm_ms(*I, slider, 100);
  }
}

}  // namespace bench
