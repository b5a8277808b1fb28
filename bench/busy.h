// Busy-machine rows of bdinterp_bench: frame times with the default threading against one thread,
// in the same run, while competing programs (started and stopped here) occupy the cores.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "bdinterp/interpolator.h"

namespace bench {

// Builds the Interpolator of the benchmark's n-vertex mesh (bending a bar, as everywhere in the
// benchmark).
using MakeInterpolator = std::function<std::unique_ptr<bdinterp::Interpolator>(int n)>;

// Prints, for each size, warm slider frames and baked frames (frames(), 101 t) with the default
// threads and with threads=1, on an idle machine, with 1 and 3 busy loops, and with another
// bdinterp process running warm frames with its default threads (the program re-executes itself
// with --compete=n, handled by compete()). Each ratio is default / threads=1 from interleaved runs.
void print_busy_rows(const std::vector<int>& sizes, int reps, const MakeInterpolator& make);

// If argv holds --compete=n: runs warm frames of the n-vertex case forever (never returns).
void compete(int argc, char** argv, const MakeInterpolator& make);

}  // namespace bench
