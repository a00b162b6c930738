// The counting run (issue 41): the design's kernels, instantiated with counted arrays
// (kernels/access.hpp), fired over one frame by the func run's scheduler. Every access to every
// bank of every kernel array is recorded per firing; the report is csim_accesses.json, the same
// file the exported project's `make csim` writes from its own C simulation.
#pragma once

#include <string>

#include "parallax/kernels/params.hpp"
#include "parallax/sim/func.hpp"

namespace parallax::sim {

struct AccessRunOptions {
  std::string design;  // the design's name, for the report
  double clock_hz = 200e6;
  kern::RectifyParams rectify{};  // recurrences of the rectify stages (the counting run itself takes rectified images)
};

// Runs the counting instantiation on one frame (left and right of the design's size) and
// returns csim_accesses.json: per stage the II it declares (stage_schedules), its firings, every
// counted memory with its banks, ports, largest reads and writes per bank and firing, the sites
// banked at run time and the II the counts force, and the declared recurrences with theirs.
// Aborts on parameters rejected by func_param_errors (callers validate).
std::string count_accesses_json(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                                const AccessRunOptions& opt);

}  // namespace parallax::sim
