// What each platform reports of the machine (parallel.h: machine_probe_linux.cpp, _windows.cpp,
// _macos.cpp) and the window of other programs' busy cores that Windows' and macOS's load is judged by.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "parallel/parallel.h"

namespace bdinterp {
namespace {

TEST(MachineProbe, OtherProgramsCoresFromCpuTimeCounters) {
  parallel::detail::OtherCores w;
  EXPECT_EQ(w.add(100, 0, 1000, 4, 400), -1);     // the first reading only starts a window
  EXPECT_EQ(w.add(150, 0, 1200, 4, 400), -1);     // 200 ticks: too short a window yet
  EXPECT_EQ(w.add(700, 50, 1800, 4, 400), 3);     // 600 of 800 ticks busy on 4 cores, none ours
  EXPECT_EQ(w.add(1500, 450, 2600, 4, 400), 2);   // 800 busy, 400 of them ours: the others' 2 cores
  EXPECT_EQ(w.add(2300, 1250, 3400, 4, 400), 0);  // all busy, all ours: no other program
  EXPECT_EQ(w.add(2300, 1250, 3600, 4, 400), 0);  // too short: the previous answer
  EXPECT_EQ(w.add(2600, 1700, 4200, 4, 400), 0);  // ours counted a tick more than the machine's busy
  EXPECT_EQ(w.add(3400, 1700, 5000, 4, 400), 4);  // all busy, none ours
  EXPECT_EQ(w.add(10, 5, 100, 4, 400), 4);        // counters reset: a new window from here
  EXPECT_EQ(w.add(260, 5, 600, 4, 400), 2);       // 250 of 500
  EXPECT_EQ(w.add(260, 2, 900, 4, 50), 2);        // our counter went back: not a reading
}

TEST(MachineProbe, CoresAndLoadAreKnown) {
  const int mask = parallel::detail::affinity_cores();
  EXPECT_GE(mask, 1);
  EXPECT_LE(parallel::usable_cores(), mask);
  EXPECT_EQ(parallel::detail::cores_within(0), static_cast<int>(std::thread::hardware_concurrency()));
  EXPECT_EQ(parallel::detail::cores_within(1), 1);
  // Two samples 50 ms apart: the second is a count on every platform (the first may only start the
  // window where the load comes from CPU-time counters).
  parallel::detail::other_threads(1);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const int others = parallel::detail::other_threads(1);
  EXPECT_GE(others, 0);
#ifndef __linux__
  EXPECT_LE(others, static_cast<int>(std::thread::hardware_concurrency()));  // busy cores
#endif
}

}  // namespace
}  // namespace bdinterp
