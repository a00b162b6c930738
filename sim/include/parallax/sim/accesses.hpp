// The counting run (issue 41): the design's kernels, instantiated with counted arrays
// (kernels/access.hpp), fired over one frame by the func run's scheduler. Every access to every
// bank of every kernel array is recorded per firing; the report is csim_accesses.json, the same
// file the exported project's `make csim` writes from its own C simulation.
#pragma once

#include <string>
#include <vector>

#include "parallax/kernels/access.hpp"
#include "parallax/kernels/params.hpp"
#include "parallax/sim/func.hpp"

namespace parallax::sim {

struct AccessRunOptions {
  std::string design;  // the design's name, for the report
  double clock_hz = 200e6;
  kern::RectifyParams rectify{};  // recurrences of the rectify stages (the counting run itself takes rectified images)
};

// The design's memories as the counting run counts them on a probe frame: a generated pair,
// seeded, as narrow and short as the design's window, disparity range and median allow (every
// chunk of a pixel, every slot of a line buffer and every row memory are reached within it; the
// banking a site shows does not depend on the frame's size or content). Per stage and memory
// (kern::MemoryAccesses). Memoised per design: the stage schedules of a sweep ask once each.
// Aborts on parameters rejected by func_param_errors (callers validate).
std::vector<kern::MemoryAccesses> probe_memory_accesses(const kern::StereoParams& p);

// The declared half of csim_accesses.json: each kernel stage's II (stage_schedules: the probe's
// counts and the declared recurrences at clock_hz) and its recurrences with the delay of their
// operator chains, the budget and the II each forces. The exported testbench carries this table
// and adds its own C simulation's counts.
std::vector<kern::AccessStage> access_stages(const kern::StereoParams& p, const kern::RectifyParams& rectify,
                                             double clock_hz);

// Runs the counting instantiation on one frame (left and right of the design's size) and
// returns csim_accesses.json: per stage the II it declares (access_stages), its firings, every
// counted memory with its banks, ports, largest reads and writes per bank and firing, the sites
// banked at run time and the II the counts force, and the declared recurrences with theirs.
// Aborts on parameters rejected by func_param_errors (callers validate).
std::string count_accesses_json(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                                const AccessRunOptions& opt);

}  // namespace parallax::sim
