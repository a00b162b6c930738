// Capacities of one kernel instantiation: the compile-time sizes of its memories and tokens.
// Runtime parameters (StereoParams) must stay within them; software builds use generous caps,
// the HLS export instantiates the kernels with the exact values of one design.
#pragma once

#include "parallax/kernels/access.hpp"
#include "parallax/kernels/params.hpp"
#include "parallax/kernels/store.hpp"

namespace parallax {
namespace kern {

// MAX_W: widest row; MAX_D: most disparities; LANES: largest PU one firing can carry;
// WINDOW_ROWS: line-buffer rows of the cost stage (>= the matching window's height);
// MEDIAN_ROWS: line-buffer rows of the median (>= its k; 1 when the median is off).
// KIND_MASK: the stream path kinds (sgm.hpp, StreamPathKind bits) an aggregation stage may use;
// a kind outside it has no hardware (its row memory is never touched).
// MAX_MIN_D: the largest min_disparity (the right image's columns kept beyond D); when FIXED the
// design's exact min_disparity, 0 unless given.
// FIXED: the capacities are the design's exact structure (the HLS export): D = MAX_D and
// PU = LANES, so the kernels use these constants instead of the runtime values and synthesis
// sees compile-time lane addresses and trip counts. Software instantiations (FIXED = false) take
// D and PU at run time within the capacities.
// COUNT: the kernels' arrays count their accesses per bank and firing (access.hpp; the
// simulator's counting run and the exported C simulation, never synthesis); software
// instantiations then also run their lane loops to PU exactly (no SIMD rounding), as the
// hardware's unrolled copies do.
// STORE: the element types of the kernels' memories and register files (store.hpp): the built-in
// integers of the arithmetic (HostStore), or the export's ap_uint at the model's widths.
template <int MAX_W, int MAX_D, int LANES, int WINDOW_ROWS = kMaxWindow, int MEDIAN_ROWS = kMaxMedian,
          unsigned KIND_MASK = 0xFu, bool FIXED = false, int MAX_MIN_D = (FIXED ? 0 : kMaxMinDisparity),
          bool COUNT = false, class STORE = HostStore>
struct Caps {
  static constexpr bool count_accesses = COUNT;
  typedef STORE store;
  // A member array T[N0][N1]... of a kernel instantiated with these capacities.
  template <class T, int... N>
  using array = typename ArrayOf<COUNT, T, N...>::type;
  static constexpr int max_width_px = MAX_W;
  static constexpr int max_disparities = MAX_D;
  static constexpr int lanes = LANES;
  static constexpr int window_rows = WINDOW_ROWS;
  static constexpr int median_rows = MEDIAN_ROWS;
  static constexpr unsigned kind_mask = KIND_MASK;
  static constexpr bool fixed = FIXED;
  static constexpr int max_min_disparity = MAX_MIN_D;
  // The design's D and PU: the capacities when FIXED, else the runtime values.
  static int disparities(int runtime) { return FIXED ? MAX_D : runtime; }
  static int parallel_units(int runtime) { return FIXED ? LANES : runtime; }
  static int min_disparity(int runtime) { return FIXED ? MAX_MIN_D : runtime; }
  // Trip count of a loop over `runtime` items within `cap`: the compile-time cap when FIXED
  // (bodies guarded where the runtime value may be smaller; synthesis unrolls on it), the
  // runtime value in software instantiations (the same iterations that do anything).
  static constexpr int trip(int runtime, int cap) { return FIXED ? cap : runtime; }
  // The same where the iterations past `runtime` are don't-care: software instantiations round
  // up to whole SIMD vectors of 16 lanes (no scalar remainder), within `cap`.
  static constexpr int simd_trip(int runtime, int cap) {
    return FIXED ? cap : COUNT ? runtime : ((runtime + 15) / 16 * 16 < cap ? (runtime + 15) / 16 * 16 : cap);
  }
  static_assert(!FIXED || MAX_D % LANES == 0, "a fixed design's PU divides its D");
};

}  // namespace kern
}  // namespace parallax
