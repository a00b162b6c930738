// The kernels' type header: the runtime parameters of one disparity pipeline and the bit
// widths derived from them. C++14, no STL, no heap: this header is shared by the kernels, the
// golden model and every tool, and it is the only thing the kernels depend on.
#pragma once

#include <stdint.h>

namespace parallax {
namespace kern {

enum CostKind : int { kCostCensus = 0, kCostSad = 1 };

// Census variants (docs/algorithm.md §2): every tap against the centre; every second tap in
// raster order against the centre; each tap of the first half against its mirror image through
// the centre (centre-symmetric).
enum CensusKind : int { kCensusFull = 0, kCensusSparse = 1, kCensusSymmetric = 2 };

// Aggregation along a path (docs/algorithm.md §3): SGM takes one predecessor per step; MGM
// (Facciolo et al., BMVC 2015) averages the steps from two, the path's predecessor and the one
// across it (mgm_second_predecessor).
enum AggregationKind : int { kAggregationSgm = 0, kAggregationMgm = 1 };

// One bit per SGM path direction. Angles are the direction of travel (docs/algorithm.md §3).
enum PathBit : unsigned {
  kPath0 = 1u << 0,    // predecessor (x-1, y)
  kPath45 = 1u << 1,   // predecessor (x-1, y-1)
  kPath90 = 1u << 2,   // predecessor (x,   y-1)
  kPath135 = 1u << 3,  // predecessor (x+1, y-1)
  kPath180 = 1u << 4,  // predecessor (x+1, y)
  kPath225 = 1u << 5,  // predecessor (x+1, y+1)
  kPath270 = 1u << 6,  // predecessor (x,   y+1)
  kPath315 = 1u << 7,  // predecessor (x-1, y+1)
};
constexpr unsigned kForwardPaths = kPath0 | kPath45 | kPath90 | kPath135;
constexpr unsigned kBackwardPaths = kPath180 | kPath225 | kPath270 | kPath315;
constexpr unsigned kAllPaths = kForwardPaths | kBackwardPaths;

// The 180-degree path alone among the backward paths runs in the one raster pass, on a row
// memory after each row is complete (row_reverse.hpp); any other backward path needs the
// second pass over the reversed frame through DDR (frame_buffer.hpp), which then also takes 180.
constexpr bool row_reverse_paths(unsigned path_mask) {
  return (path_mask & kBackwardPaths) == kPath180;
}
constexpr bool two_pass_paths(unsigned path_mask) {
  return (path_mask & kBackwardPaths) != 0 && (path_mask & kBackwardPaths) != kPath180;
}
// MGM needs every path's second predecessor computed before the pixel: in the forward raster
// pass (and the reversed second pass) it is; the one-pass 180-degree path's, (x, y+1), is not.
constexpr bool mgm_paths_supported(unsigned path_mask) {
  return !row_reverse_paths(path_mask);
}

// Hard limits of the software instantiations (the HLS export replaces them by the exact values).
constexpr int kMaxWidthPx = 4096;
constexpr int kMaxHeightPx = 4096;
constexpr int kMaxDisparities = 256;
constexpr int kMaxMinDisparity = 256;  // min_disparity: the right image's extra columns kept
constexpr int kMaxWindow = 9;          // census/SAD window side; census also needs w*h-1 <= 64
constexpr int kMaxCensusBits = 64;
constexpr int kMaxMedian = 7;

// Runtime parameters of the disparity pipeline. Structure fields (sizes, D, PU, paths, windows)
// and registers (p1, p2, lr_tolerance) are all runtime values in software; the HLS export turns
// the structure fields into compile-time constants.
struct StereoParams {
  int width_px;
  int height_px;
  int cost;            // CostKind
  int window_w;        // odd
  int window_h;        // odd
  int disparities;     // D: disparities [0, D)
  int parallel_units;  // PU: disparities computed per firing; divides D
  unsigned path_mask;  // PathBit set
  int p1;              // register, 0 <= p1 < p2
  int p2;              // register
  bool lr_check;
  int lr_tolerance;       // register
  int median;             // 0 = off, 3, 5, 7
  int uniqueness_pct;     // register, 0..100: uniqueness margin in percent (0 = off)
  int census;             // CensusKind (cost = census only)
  int min_disparity = 0;  // m, 0 <= m <= kMaxMinDisparity: the codes d in [0, D) are disparities m + d
  int p2_adaptive = 0;    // a, 0..kMaxP2Adaptive: P2 shrinks by (a |dI|) >> 4 (0 = off); a constant of the design
  int aggregation = 0;    // AggregationKind: SGM or MGM; a constant of the design
  int subpixel_bits = 0;  // f, 0..kMaxSubpixelBits: fraction bits of the codes (parabola fit); a constant
};

// The register fields of StereoParams on their own: the values a hardware register holds, which
// may change between frames without resynthesis (the HLS top's AXI4-Lite ports). Each has one
// reader: p1 and p2 the SGM aggregation (sgm.hpp), lr_tolerance and uniqueness_pct the WTA /
// left-right check (wta_lr.hpp); no other kernel reads a register.
struct StereoRegisters {
  int p1;  // 0 <= p1 < p2
  int p2;
  int lr_tolerance;    // >= 0
  int uniqueness_pct;  // 0..100
};

// p with its register fields set to r (the structure fields unchanged).
inline void set_registers(StereoParams& p, const StereoRegisters& r) {
  p.p1 = r.p1;
  p.p2 = r.p2;
  p.lr_tolerance = r.lr_tolerance;
  p.uniqueness_pct = r.uniqueness_pct;
}

// Largest uniqueness margin (percent) the register accepts: 7 bits.
constexpr int kMaxUniquenessPct = 100;
constexpr int kUniquenessBits = 7;

// Intensity-adaptive P2 (docs/algorithm.md §3): along path r into p from q, with a = p2_adaptive
// and the left image's step dI = |I(p) - I(q)|, P2' = max(P1 + 1, P2 - ((a * dI) >> 4)); a = 0
// keeps P2. A structure constant (the export multiplies by it as a constant), 8 bits.
constexpr int kMaxP2Adaptive = 255;
// Sub-pixel refinement (docs/algorithm.md §4): at most 4 fraction bits in a code.
constexpr int kMaxSubpixelBits = 4;
constexpr int kP2AdaptiveBits = 8;
constexpr int kP2AdaptiveShift = 4;
inline int adaptive_p2(int p1, int p2, int a, int i_p, int i_q) {
  const int step = i_p > i_q ? i_p - i_q : i_q - i_p;
  const int lowered = p2 - ((a * step) >> kP2AdaptiveShift);
  return lowered > p1 + 1 ? lowered : p1 + 1;
}

// --- StereoParams as a table: who reads each field, registers, limits ---
//
// One description that the sharing keys of every engine (which recording a design may replay),
// the configuration's field table (models/config), the exported design's structure constants
// and the parameter check (param_table.hpp) all read. A field added to StereoParams is added to
// for_each_param too (tests/sim/sharing_keys_test.cpp fails otherwise).

// The stages that read a field (a bit set). Sharing contract: two designs whose fields read by
// a stage and the stages before it are equal compute the same values up to that stage's output.
enum ParamReader : unsigned {
  kReadByCost = 1u << 0,       // the matching cost (census or SAD over the window, D, m)
  kReadByAggregate = 1u << 1,  // the SGM / MGM path recursion and the sum of the paths
  kReadBySelect = 1u << 2,     // winner-take-all, left-right check, uniqueness, sub-pixel fit
  kReadByMedian = 1u << 3,     // the median filter of the codes
  kReadBySystem = 1u << 4,     // only the hardware's structure: no output value depends on it
};
constexpr unsigned kReadByEveryStage = kReadByCost | kReadByAggregate | kReadBySelect | kReadByMedian;

// The readers of a stage's output: every stage up to and including `stage` (a ParamReader bit).
constexpr unsigned readers_up_to(unsigned stage) {
  return stage == kReadBySystem ? kReadByEveryStage | kReadBySystem : (stage | (stage - 1u)) & kReadByEveryStage;
}

// One field as the visitor sees it: the value as a wide integer (bool 0/1, the path mask as
// its bits), the stages that read it in this design (0 when none does: a census kind of a SAD
// design), whether it is a run-time register, and its limits [lo, hi] as one field alone.
struct ParamField {
  const char* name;
  long long value;
  unsigned readers;
  bool is_register;
  long long lo;
  long long hi;
};

// Calls v(const ParamField&) for every field of p, in declaration order. A field added to
// StereoParams is added here (tests/kernels/param_table_test.cpp counts them).
template <class Visitor>
void for_each_param(const StereoParams& p, Visitor&& v) {
  const unsigned all = kReadByEveryStage;
  const bool census = p.cost == kCostCensus;
  v(ParamField{"width_px", p.width_px, all, false, 1, kMaxWidthPx});
  v(ParamField{"height_px", p.height_px, all, false, 1, kMaxHeightPx});
  v(ParamField{"cost", p.cost, kReadByCost, false, kCostCensus, kCostSad});
  v(ParamField{"window_w", p.window_w, kReadByCost, false, 1, kMaxWindow});
  v(ParamField{"window_h", p.window_h, kReadByCost, false, 1, kMaxWindow});
  v(ParamField{"disparities", p.disparities, kReadByCost | kReadByAggregate | kReadBySelect, false, 1,
               kMaxDisparities});
  v(ParamField{"parallel_units", p.parallel_units, kReadBySystem, false, 1, kMaxDisparities});
  v(ParamField{"path_mask", p.path_mask, kReadByAggregate, false, 1, kAllPaths});
  v(ParamField{"p1", p.p1, kReadByAggregate, true, 0, 65534});
  v(ParamField{"p2", p.p2, kReadByAggregate, true, 1, 65535});
  v(ParamField{"lr_check", p.lr_check ? 1 : 0, kReadBySelect, false, 0, 1});
  v(ParamField{"lr_tolerance", p.lr_tolerance, kReadBySelect, true, 0, 255});
  v(ParamField{"median", p.median, kReadByMedian, false, 0, kMaxMedian});
  v(ParamField{"uniqueness_pct", p.uniqueness_pct, kReadBySelect, true, 0, kMaxUniquenessPct});
  v(ParamField{"census", p.census, census ? unsigned(kReadByCost) : 0u, false, kCensusFull, kCensusSymmetric});
  v(ParamField{"min_disparity", p.min_disparity, kReadByCost, false, 0, kMaxMinDisparity});
  v(ParamField{"p2_adaptive", p.p2_adaptive, kReadByAggregate, false, 0, kMaxP2Adaptive});
  v(ParamField{"aggregation", p.aggregation, kReadByAggregate, false, kAggregationSgm, kAggregationMgm});
  v(ParamField{"subpixel_bits", p.subpixel_bits, kReadBySelect, false, 0, kMaxSubpixelBits});
}
constexpr int kParamFieldCount = 19;

// Whether two names are the same text.
constexpr bool same_name(const char* a, const char* b) {
  while (*a != 0 && *a == *b) ++a, ++b;
  return *a == *b;
}

// The limits of the field named `name` (a name of for_each_param): {lo, hi}, or {1, 0} when no
// field has that name.
struct ParamLimits {
  long long lo;
  long long hi;
};
inline ParamLimits param_limits(const char* name) {
  ParamLimits l{1, 0};
  const StereoParams any{1, 1, 0, 1, 1, 1, 1, 1u, 0, 1, false, 0, 0, 0, 0};
  for_each_param(any, [&](const ParamField& f) {
    if (same_name(f.name, name)) l = ParamLimits{f.lo, f.hi};
  });
  return l;
}

enum RectifyMode : int { kRectifyNone = 0, kRectifyNearest = 1, kRectifyBilinear = 2 };

// Rectification by remap tables (docs/algorithm.md §1).
struct RectifyParams {
  int width_px;
  int height_px;
  int mode;         // RectifyMode
  int frac_bits;    // F: fractional bits of the map entries (0 for nearest)
  int buffer_rows;  // R: line-buffer rows
};

// Number of bits needed to store v (>= 1). Loops, not recursion, because HLS rejects recursive
// calls; unlabelled, because C++14 forbids labels in constexpr functions.
constexpr int bits_for(uint64_t v) {
  int n = 1;
  for (; v > 1; v >>= 1) ++n;
  return n;
}

// ceil(log2 n) for n >= 1: the levels of a balanced binary tree over n inputs.
constexpr int ceil_log2(uint64_t n) {
  int levels = 0;
  for (uint64_t span = 1; span < n; span *= 2) ++levels;
  return levels;
}

constexpr int popcount_u32(unsigned v) {
  int n = 0;
  for (; v != 0; v >>= 1) n += int(v & 1u);
  return n;
}

inline int path_count(const StereoParams& p) {
  return popcount_u32(p.path_mask);
}

// Census tap selection of a window of `taps` taps (raster order, centre tap taps / 2): whether
// tap k gives a bit, and its rank among those that do (rank 0 is the code's most significant bit).
constexpr bool census_tap_used(int kind, int k, int taps) {
  return kind == kCensusSymmetric ? k < taps / 2 : kind == kCensusSparse ? k % 2 == 0 && k != taps / 2 : k != taps / 2;
}
constexpr int census_tap_rank(int kind, int k, int taps) {
  return kind == kCensusSymmetric ? k
         : kind == kCensusSparse  ? k / 2 - ((taps / 2) % 2 == 0 && k > taps / 2 ? 1 : 0)
                                  : k - (k > taps / 2 ? 1 : 0);
}
// Bits of the census code of a w x h window.
constexpr int census_bits(int kind, int w, int h) {
  return kind == kCensusSymmetric ? (w * h) / 2
         : kind == kCensusSparse  ? (w * h + 1) / 2 - (((w * h) / 2) % 2 == 0 ? 1 : 0)
                                  : w * h - 1;
}

inline uint32_t cost_max(const StereoParams& p) {
  return p.cost == kCostCensus ? uint32_t(census_bits(p.census, p.window_w, p.window_h))
                               : uint32_t(255 * p.window_w * p.window_h);
}

// Largest value the P2 register can hold at the width needed for the configured P2.
inline uint32_t p2_register_max(const StereoParams& p) {
  return (uint32_t(1) << bits_for(uint64_t(p.p2 < 0 ? 0 : p.p2))) - 1u;
}

inline int cost_bits(const StereoParams& p) {
  return bits_for(cost_max(p));
}
inline int penalty_bits(const StereoParams& p) {
  return bits_for(uint64_t(p.p2 < 0 ? 0 : p.p2));
}
// Lr <= cost_max + P2 (docs/algorithm.md §3).
inline int path_bits(const StereoParams& p) {
  return bits_for(uint64_t(cost_max(p)) + p2_register_max(p));
}
inline int aggregate_bits(const StereoParams& p) {
  return bits_for(uint64_t(path_count(p)) * (uint64_t(cost_max(p)) + p2_register_max(p)));
}
// Disparity codes are [0, D * 2^f]; the code D * 2^f means invalid; a valid code c is the
// disparity min_disparity + c / 2^f, f = subpixel_bits (docs/algorithm.md §4, §5).
inline int disparity_bits(const StereoParams& p) {
  return bits_for(uint64_t(p.disparities) << p.subpixel_bits);
}
inline int invalid_code(const StereoParams& p) {
  return p.disparities << p.subpixel_bits;
}
// The integer disparities' width (the WTA's candidates and the LR check): bits(D).
inline int disparity_int_bits(const StereoParams& p) {
  return bits_for(uint64_t(p.disparities));
}

}  // namespace kern
}  // namespace parallax
