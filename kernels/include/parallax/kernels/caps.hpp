// Capacities of one kernel instantiation: the compile-time sizes of its memories and tokens.
// Runtime parameters (StereoParams) must stay within them; software builds use generous caps,
// the HLS export instantiates the kernels with the exact values of one design.
#pragma once

#include "parallax/kernels/params.hpp"

namespace parallax {
namespace kern {

// MAX_W: widest row; MAX_D: most disparities; LANES: largest PU one firing can carry;
// WINDOW_ROWS: line-buffer rows of the cost stage (>= the matching window's height);
// MEDIAN_ROWS: line-buffer rows of the median (>= its k; 1 when the median is off).
template <int MAX_W, int MAX_D, int LANES, int WINDOW_ROWS = kMaxWindow, int MEDIAN_ROWS = kMaxMedian>
struct Caps {
  static constexpr int max_width_px = MAX_W;
  static constexpr int max_disparities = MAX_D;
  static constexpr int lanes = LANES;
  static constexpr int window_rows = WINDOW_ROWS;
  static constexpr int median_rows = MEDIAN_ROWS;
};

// Right-image codes and pending left disparities are kept in rings indexed by column modulo
// this size; it must exceed 2 * kMaxDisparities - 1 (docs/kernels.md, WTA/LR stage).
constexpr int kColumnRing = 512;

}  // namespace kern
}  // namespace parallax
