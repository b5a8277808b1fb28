// What each platform reports of the machine (parallel.h: machine_probe_linux.cpp, _windows.cpp,
// _macos.cpp) and the busy-core window that Windows' and macOS's load is judged by.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "bdinterp/parallel.h"

namespace bdinterp {
namespace {

TEST(MachineProbe, BusyCoresFromCpuTimeCounters) {
  parallel::detail::BusyCores w;
  EXPECT_EQ(w.add(100, 1000, 4, 400), -1);  // the first reading only starts a window
  EXPECT_EQ(w.add(150, 1200, 4, 400), -1);  // 200 ticks: too short a window yet
  EXPECT_EQ(w.add(700, 1800, 4, 400), 3);   // 600 of 800 ticks busy on 4 cores
  EXPECT_EQ(w.add(700, 2000, 4, 400), 3);   // too short: the previous answer
  EXPECT_EQ(w.add(700, 2600, 4, 400), 0);   // 800 idle ticks since 1800
  EXPECT_EQ(w.add(1500, 3400, 4, 400), 4);  // all busy
  EXPECT_EQ(w.add(10, 100, 4, 400), 4);     // counters reset: a new window from here
  EXPECT_EQ(w.add(260, 600, 4, 400), 2);    // 250 of 500
  EXPECT_EQ(w.add(900, 700, 4, 50), 2);     // more busy than total ticks: not a reading
}

TEST(MachineProbe, CoresAndLoadAreKnown) {
  const int mask = parallel::detail::affinity_cores();
  EXPECT_GE(mask, 1);
  EXPECT_LE(parallel::usable_cores(), mask);
  EXPECT_EQ(parallel::detail::cores_within(0), static_cast<int>(std::thread::hardware_concurrency()));
  EXPECT_EQ(parallel::detail::cores_within(1), 1);
  // Two samples 50 ms apart: the second is a count on every platform (the first may only start the
  // window where the load comes from CPU-time counters).
  parallel::detail::runnable_threads();
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const int runnable = parallel::detail::runnable_threads();
  EXPECT_GE(runnable, 1);
#ifndef __linux__
  EXPECT_LE(runnable, static_cast<int>(std::thread::hardware_concurrency()));  // busy cores
#endif
}

}  // namespace
}  // namespace bdinterp
