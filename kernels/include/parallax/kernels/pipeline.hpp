// The pipeline, described once (issue 14): every stage and every FIFO of each variant (one pass,
// two passes through a DDR frame buffer, with or without rectification), with the FIFOs'
// producer, consumer and token, and how each stage's kernel is configured (issue 43:
// stage_setup(), for_each_stage()). The cycle model's graph (sim/src/engine.hpp), the schedule
// (sim/src/schedule.cpp), the configuration's stage names (models/config), the resource model's
// inventory and FIFOs (models/resources) and the HLS export's streams and stage functions (hls/)
// all read these tables; none keeps a list or a configure() argument of its own. C++14, no STL.
#pragma once

#include "parallax/kernels/params.hpp"
#include "parallax/kernels/sgm_kinds.hpp"

namespace parallax {
namespace kern {

// Which variants an entry belongs to: a mask of the conditions below, all of which must hold.
enum PipelineWhen : unsigned {
  kWhenAlways = 0,
  kWhenOnePass = 1u << 0,       // no backward paths but 180
  kWhenTwoPass = 1u << 1,       // backward paths: a second, reversed pass through DDR
  kWhenRectify = 1u << 2,       // rectification in front of the cost stage
  kWhenNoRectify = 1u << 3,     // no rectification
  kWhenRowReverse = 1u << 4,    // one pass with the 180-degree path on reversed rows
  kWhenNoRowReverse = 1u << 5,  // no 180-degree path in the one pass
};

// The token a FIFO carries; its width in bits follows from the design (token_bits()).
enum TokenKind : int {
  kTokenPixel = 0,  // one 8-bit grey pixel
  kTokenMapEntry,   // one remap-table entry: two 32-bit fixed-point coordinates
  kTokenCost,       // PU matching costs
  kTokenSum,        // PU aggregated costs
  kTokenCode,       // one disparity code
};

// How a stage's pipeline depth (cycles from a firing's reads to its writes: a read, the lane
// arithmetic as balanced trees, a register) follows from the design; stage_latency_cycles().
enum LatencyRule : int {
  kLatencyFixed = 0,   // the stage's `latency` column, whatever the design
  kLatencyCostTree,    // 2 + the depth of the window's tree: census popcount of w*h - 1 bits, SAD sum of w*h
  kLatencyPathSum,     // 4 + the depth of the sum over the design's paths
  kLatencyLaneMin,     // 2 + the depth of the minimum over the PU lanes
  kLatencyMedianSort,  // 2 + the depth of the k x k selection network (k >= 3); 1 without a median
};

struct PipelineStage {
  const char* name;  // the cycle model's stage (reports, timing overrides, ii_<name> fields)
  unsigned when;
  const char* role;  // one line: what the stage does
  bool flips_order;  // its output runs in the opposite pixel order to its input (a reversal)
  unsigned paths;    // SGM stages: the path directions it aggregates (of the design's); else 0
  unsigned reads;    // which parameter reader it is (ParamReader bits, params.hpp): the fields and
                     // run-time registers it is given are those for_each_param marks with it
  LatencyRule latency_rule;
  int latency;  // kLatencyFixed: its depth in cycles
};

struct PipelineFifo {
  const char* name;  // also the exported stream's name and the fifo_depth_<name> field's suffix
  const char* producer;
  const char* consumer;
  TokenKind token;
  unsigned when;
  int pass;  // 1, or 2 for the streams of the second pass of a two-pass design
};

constexpr PipelineStage kPipelineStages[] = {
    {"source", kWhenAlways, "the left and right pixels, from memory or a camera", false, 0, 0, kLatencyFixed, 1},
    {"map_left", kWhenRectify, "the left camera's remap table, from memory", false, 0, 0, kLatencyFixed, 1},
    {"map_right", kWhenRectify, "the right camera's remap table, from memory", false, 0, 0, kLatencyFixed, 1},
    {"rectify_left", kWhenRectify, "remap of the left image through a line buffer (rectify.hpp)", false, 0, 0,
     kLatencyFixed, 5},
    {"rectify_right", kWhenRectify, "remap of the right image through a line buffer (rectify.hpp)", false, 0, 0,
     kLatencyFixed, 5},
    {"cost", kWhenAlways, "Census or SAD matching costs, PU per firing (census.hpp, sad.hpp)", false, 0, kReadByCost,
     kLatencyCostTree, 0},
    {"aggregate", kWhenAlways, "SGM over the forward paths (sgm.hpp)", false, kForwardPaths, kReadByAggregate,
     kLatencyPathSum, 0},
    {"ddr_write", kWhenTwoPass, "costs and forward sums into the DDR frame buffer", false, 0, 0, kLatencyFixed, 1},
    {"ddr_read", kWhenTwoPass, "the same, read back in reverse order", true, 0, 0, kLatencyFixed, 1},
    {"aggregate_back", kWhenTwoPass, "SGM over the backward paths on the reversed stream (sgm.hpp)", false,
     kBackwardPaths, kReadByAggregate, kLatencyPathSum, 0},
    {"row_reverse", kWhenRowReverse, "each row's costs and forward sums, pixels reversed (row_reverse.hpp)", true, 0, 0,
     kLatencyFixed, 2},
    {"aggregate_row", kWhenRowReverse, "SGM's 180-degree path on the reversed rows (sgm.hpp)", false, kPath180,
     kReadByAggregate, kLatencyFixed, 5},
    {"wta_lr", kWhenAlways, "winner-takes-all and left-right check (wta_lr.hpp)", false, 0, kReadBySelect,
     kLatencyLaneMin, 0},
    {"median", kWhenAlways, "k x k median of the codes (median.hpp)", false, 0, kReadByMedian, kLatencyMedianSort, 0},
    {"row_unreverse", kWhenRowReverse, "the codes of each row back in raster order (row_reverse.hpp)", true, 0, 0,
     kLatencyFixed, 2},
    {"sink", kWhenAlways, "the disparity codes out", false, 0, 0, kLatencyFixed, 0},
};

constexpr PipelineFifo kPipelineFifos[] = {
    {"raw_left_px", "source", "rectify_left", kTokenPixel, kWhenRectify, 1},
    {"raw_right_px", "source", "rectify_right", kTokenPixel, kWhenRectify, 1},
    {"map_left", "map_left", "rectify_left", kTokenMapEntry, kWhenRectify, 1},
    {"map_right", "map_right", "rectify_right", kTokenMapEntry, kWhenRectify, 1},
    {"left_px", "source", "cost", kTokenPixel, kWhenNoRectify, 1},
    {"right_px", "source", "cost", kTokenPixel, kWhenNoRectify, 1},
    {"left_px", "rectify_left", "cost", kTokenPixel, kWhenRectify, 1},
    {"right_px", "rectify_right", "cost", kTokenPixel, kWhenRectify, 1},
    {"cost", "cost", "aggregate", kTokenCost, kWhenAlways, 1},
    {"cost_to_ddr", "aggregate", "ddr_write", kTokenCost, kWhenTwoPass, 1},
    {"fwd_to_ddr", "aggregate", "ddr_write", kTokenSum, kWhenTwoPass, 1},
    {"cost_from_ddr", "ddr_read", "aggregate_back", kTokenCost, kWhenTwoPass, 2},
    {"fwd_from_ddr", "ddr_read", "aggregate_back", kTokenSum, kWhenTwoPass, 2},
    {"cost_to_row", "aggregate", "row_reverse", kTokenCost, kWhenRowReverse, 1},
    {"fwd_to_row", "aggregate", "row_reverse", kTokenSum, kWhenRowReverse, 1},
    {"cost_row", "row_reverse", "aggregate_row", kTokenCost, kWhenRowReverse, 1},
    {"fwd_row", "row_reverse", "aggregate_row", kTokenSum, kWhenRowReverse, 1},
    {"sum", "aggregate", "wta_lr", kTokenSum, kWhenOnePass | kWhenNoRowReverse, 1},
    {"sum", "aggregate_row", "wta_lr", kTokenSum, kWhenRowReverse, 1},
    {"sum", "aggregate_back", "wta_lr", kTokenSum, kWhenTwoPass, 2},
    {"disp_lr", "wta_lr", "median", kTokenCode, kWhenOnePass, 1},
    {"disp_lr", "wta_lr", "median", kTokenCode, kWhenTwoPass, 2},
    {"disp_out", "median", "sink", kTokenCode, kWhenOnePass | kWhenNoRowReverse, 1},
    {"disp_out", "median", "row_unreverse", kTokenCode, kWhenRowReverse, 1},
    {"disp_row", "row_unreverse", "sink", kTokenCode, kWhenRowReverse, 1},
    {"disp_out", "median", "sink", kTokenCode, kWhenTwoPass, 2},
};

constexpr int kPipelineStageCount = int(sizeof(kPipelineStages) / sizeof(kPipelineStages[0]));
constexpr int kPipelineFifoCount = int(sizeof(kPipelineFifos) / sizeof(kPipelineFifos[0]));

constexpr bool pipeline_same_name(const char* a, const char* b) {
  while (*a != 0 && *a == *b) ++a, ++b;
  return *a == *b;
}

// The conditions a design meets.
constexpr unsigned pipeline_conditions(unsigned path_mask, bool rectify) {
  return (two_pass_paths(path_mask) ? kWhenTwoPass : kWhenOnePass) | (rectify ? kWhenRectify : kWhenNoRectify) |
         (row_reverse_paths(path_mask) ? kWhenRowReverse : kWhenNoRowReverse);
}
inline unsigned pipeline_conditions(const StereoParams& p, bool rectify) {
  return pipeline_conditions(p.path_mask, rectify);
}
constexpr bool pipeline_has(unsigned when, unsigned conditions) {
  return (when & ~conditions) == 0;
}

// The stage's pipeline depth in cycles for the design (its latency rule). The 180-degree stage on
// reversed rows aggregates one path kind and adds the forward sum: a fixed 5; a remap's bilinear
// taps, two multiply levels and the rounding shift: 5.
inline int stage_latency_cycles(const PipelineStage& st, const StereoParams& p) {
  const int taps = p.window_w * p.window_h;
  switch (st.latency_rule) {
    case kLatencyCostTree:
      return 2 + bits_for(uint64_t(p.cost == kCostCensus ? taps - 1 : taps));
    case kLatencyPathSum:
      return 4 + bits_for(uint64_t(path_count(p) > 1 ? path_count(p) : 1));
    case kLatencyLaneMin:
      return 2 + bits_for(uint64_t(p.parallel_units));
    case kLatencyMedianSort:
      return p.median >= 3 ? 2 + bits_for(uint64_t(p.median) * uint64_t(p.median)) : 1;
    default:
      return st.latency;
  }
}

// Width in bits of one token of this kind for the design.
inline int token_bits(TokenKind t, const StereoParams& p) {
  return t == kTokenPixel      ? 8
         : t == kTokenMapEntry ? 64
         : t == kTokenCost     ? p.parallel_units * cost_bits(p)
         : t == kTokenSum      ? p.parallel_units * aggregate_bits(p)
                               : disparity_bits(p);
}

// The FIFO of this name in the design's variant, or null.
inline const PipelineFifo* pipeline_fifo(const char* name, unsigned conditions) {
  for (int i = 0; i < kPipelineFifoCount; ++i) {
    const PipelineFifo& f = kPipelineFifos[i];
    if (pipeline_same_name(f.name, name) && pipeline_has(f.when, conditions)) return &f;
  }
  return nullptr;
}

// --- how each stage's kernel is configured (issue 43) ---------------------------------------

// The configure() arguments of a stage's kernel beyond the design's parameters, derived from the
// tables above for the design's variant, so that no consumer writes them: SgmAggregate::
// configure(p, sgm_kinds, add_forward, tee_cost) and WtaLr::configure(p, reverse).
struct StageSetup {
  unsigned sgm_kinds;  // SGM stages: StreamPathKind bits of the paths it aggregates (stream_kinds())
  bool add_forward;    // SGM stages: a second input of forward sums F to add (a sum FIFO in)
  bool tee_cost;       // SGM stages: the costs copied to a second output (a cost FIFO out)
  bool reverse;        // other stages: the input runs right to left (pipeline_output_reversed of a
                       // producer); an SGM stage's direction is in its kinds
};
constexpr bool operator==(const StageSetup& a, const StageSetup& b) {
  return a.sgm_kinds == b.sgm_kinds && a.add_forward == b.add_forward && a.tee_cost == b.tee_cost &&
         a.reverse == b.reverse;
}
constexpr bool operator!=(const StageSetup& a, const StageSetup& b) {
  return !(a == b);
}

constexpr const PipelineStage* pipeline_stage(const char* name) {
  for (int i = 0; i < kPipelineStageCount; ++i)
    if (pipeline_same_name(kPipelineStages[i].name, name)) return &kPipelineStages[i];
  return nullptr;
}

// Whether the tokens `stage` emits run right to left in the variant `cond`: a stage without input
// FIFOs emits raster order (or, flipping, the reverse: ddr_read); any other keeps its inputs'
// order unless it flips it.
constexpr bool pipeline_output_reversed(const PipelineStage& st, unsigned cond, int depth = 0) {
  bool in_reversed = false;
  for (int i = 0; i < kPipelineFifoCount && depth < kPipelineStageCount; ++i) {
    const PipelineFifo& f = kPipelineFifos[i];
    if (!pipeline_has(f.when, cond) || !pipeline_same_name(f.consumer, st.name)) continue;
    const PipelineStage* from = pipeline_stage(f.producer);
    if (from != nullptr && pipeline_output_reversed(*from, cond, depth + 1)) in_reversed = true;
  }
  return in_reversed != st.flips_order;
}

// The setup of `stage` in the variant of path_mask (`rectify` does not change any setup). A
// stage not in the variant gets the all-zero setup. constexpr: the export folds it at compile time.
constexpr StageSetup stage_setup(const char* stage, unsigned path_mask, bool rectify = false) {
  StageSetup s = {0u, false, false, false};
  const PipelineStage* st = pipeline_stage(stage);
  const unsigned cond = pipeline_conditions(path_mask, rectify);
  if (st == nullptr || !pipeline_has(st->when, cond)) return s;
  for (int i = 0; i < kPipelineFifoCount; ++i) {
    const PipelineFifo& f = kPipelineFifos[i];
    if (!pipeline_has(f.when, cond)) continue;
    if (pipeline_same_name(f.producer, stage) && f.token == kTokenCost && st->paths != 0) s.tee_cost = true;
    if (!pipeline_same_name(f.consumer, stage)) continue;
    if (f.token == kTokenSum && st->paths != 0) s.add_forward = true;
    const PipelineStage* from = pipeline_stage(f.producer);
    if (st->paths == 0 && from != nullptr && pipeline_output_reversed(*from, cond)) s.reverse = true;
  }
  if (st->paths != 0) s.sgm_kinds = stream_kinds(path_mask & st->paths, (st->paths & kBackwardPaths) != 0);
  return s;
}

// Calls v(stage, setup) for every stage of the design's variant, in pipeline order.
template <class V>
void for_each_stage(unsigned path_mask, bool rectify, V& v) {
  const unsigned cond = pipeline_conditions(path_mask, rectify);
  for (int i = 0; i < kPipelineStageCount; ++i) {
    const PipelineStage& st = kPipelineStages[i];
    if (pipeline_has(st.when, cond)) v(st, stage_setup(st.name, path_mask, rectify));
  }
}

}  // namespace kern
}  // namespace parallax
