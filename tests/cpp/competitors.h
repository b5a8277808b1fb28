// Spinning processes that stand for other programs on the machine. They must be other processes:
// on Windows and macOS the pool's load probe leaves out every thread of its own process.
#pragma once

#include <cstdint>
#include <vector>

namespace bdinterp::testing {

class Competitors {
 public:
  // Starts `processes` children that each spin on one core until this object is destroyed (at most
  // 30 s). POSIX: fork(); Windows: this executable again, running only Competitors.DISABLED_Spin.
  explicit Competitors(int processes);
  ~Competitors();
  Competitors(const Competitors&) = delete;
  Competitors& operator=(const Competitors&) = delete;

 private:
  std::vector<intptr_t> children_;  // POSIX: process ids; Windows: process handles
};

}  // namespace bdinterp::testing
