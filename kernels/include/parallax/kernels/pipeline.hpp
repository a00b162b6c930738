// The pipeline, described once (issue 14): every stage and every FIFO of each variant (one pass,
// two passes through a DDR frame buffer, with or without rectification), with the FIFOs'
// producer, consumer and token. The cycle model's graph (sim/src/engine.hpp), the configuration's
// stage names (models/config), the resource model's FIFOs (models/resources) and the HLS export's
// streams (hls/) all read these tables; none keeps a list of its own. C++14, no STL.
#pragma once

#include "parallax/kernels/params.hpp"

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

struct PipelineStage {
  const char* name;  // the cycle model's stage (reports, timing overrides, ii_<name> fields)
  unsigned when;
  const char* role;  // one line: what the stage does
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
    {"source", kWhenAlways, "the left and right pixels, from memory or a camera"},
    {"map_left", kWhenRectify, "the left camera's remap table, from memory"},
    {"map_right", kWhenRectify, "the right camera's remap table, from memory"},
    {"rectify_left", kWhenRectify, "remap of the left image through a line buffer (rectify.hpp)"},
    {"rectify_right", kWhenRectify, "remap of the right image through a line buffer (rectify.hpp)"},
    {"cost", kWhenAlways, "Census or SAD matching costs, PU per firing (census.hpp, sad.hpp)"},
    {"aggregate", kWhenAlways, "SGM over the forward paths (sgm.hpp)"},
    {"ddr_write", kWhenTwoPass, "costs and forward sums into the DDR frame buffer"},
    {"ddr_read", kWhenTwoPass, "the same, read back in reverse order"},
    {"aggregate_back", kWhenTwoPass, "SGM over the backward paths on the reversed stream (sgm.hpp)"},
    {"row_reverse", kWhenRowReverse, "each row's costs and forward sums, pixels reversed (row_reverse.hpp)"},
    {"aggregate_row", kWhenRowReverse, "SGM's 180-degree path on the reversed rows (sgm.hpp)"},
    {"wta_lr", kWhenAlways, "winner-takes-all and left-right check (wta_lr.hpp)"},
    {"median", kWhenAlways, "k x k median of the codes (median.hpp)"},
    {"row_unreverse", kWhenRowReverse, "the codes of each row back in raster order (row_reverse.hpp)"},
    {"sink", kWhenAlways, "the disparity codes out"},
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

// The conditions a design meets.
inline unsigned pipeline_conditions(const StereoParams& p, bool rectify) {
  return (two_pass_paths(p.path_mask) ? kWhenTwoPass : kWhenOnePass) | (rectify ? kWhenRectify : kWhenNoRectify) |
         (row_reverse_paths(p.path_mask) ? kWhenRowReverse : kWhenNoRowReverse);
}
inline bool pipeline_has(unsigned when, unsigned conditions) {
  return (when & ~conditions) == 0;
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
    const char* a = f.name;
    const char* b = name;
    while (*a != 0 && *a == *b) ++a, ++b;
    if (*a == *b && pipeline_has(f.when, conditions)) return &f;
  }
  return nullptr;
}

}  // namespace kern
}  // namespace parallax
