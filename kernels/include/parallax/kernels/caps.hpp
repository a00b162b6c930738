// Capacities of one kernel instantiation: the compile-time sizes of its memories and tokens.
// Runtime parameters (StereoParams) must stay within them; software builds use generous caps,
// the HLS export instantiates the kernels with the exact values of one design.
#pragma once

#include "parallax/kernels/params.hpp"

namespace parallax {
namespace kern {

// Right-image codes and pending left disparities are kept in rings indexed by column modulo
// Caps::column_ring; this is its default, which holds kMaxDisparities (docs/kernels.md).
constexpr int kColumnRing = 512;

// MAX_W: widest row; MAX_D: most disparities; LANES: largest PU one firing can carry;
// WINDOW_ROWS: line-buffer rows of the cost stage (>= the matching window's height);
// MEDIAN_ROWS: line-buffer rows of the median (>= its k; 1 when the median is off).
// COLUMN_RING: entries of the per-column rings of the Census and WTA/LR stages, a power of two
// above 2 * MAX_D - 1; ROW_KINDS: path-cost row memories of one aggregation stage (its path kinds
// other than the pixel path, 1 to 3).
template <int MAX_W, int MAX_D, int LANES, int WINDOW_ROWS = kMaxWindow, int MEDIAN_ROWS = kMaxMedian,
          int COLUMN_RING = kColumnRing, int ROW_KINDS = 3>
struct Caps {
  static constexpr int max_width_px = MAX_W;
  static constexpr int max_disparities = MAX_D;
  static constexpr int lanes = LANES;
  static constexpr int window_rows = WINDOW_ROWS;
  static constexpr int median_rows = MEDIAN_ROWS;
  static constexpr int column_ring = COLUMN_RING;
  static constexpr int row_kinds = ROW_KINDS;
  static_assert((COLUMN_RING & (COLUMN_RING - 1)) == 0 && COLUMN_RING > 2 * MAX_D - 1,
                "the column ring must be a power of two above 2 * MAX_D - 1");
  static_assert(ROW_KINDS >= 1 && ROW_KINDS <= 3, "an aggregation stage has 1 to 3 row memories");
};

}  // namespace kern
}  // namespace parallax
