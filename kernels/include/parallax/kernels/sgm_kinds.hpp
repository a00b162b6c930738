// The stream path kinds of an SGM aggregation stage (sgm.hpp): the four predecessor rules one
// raster pass offers, the kinds of a path set in each pass, and the datapaths MGM computes for
// them (docs/algorithm.md §3). C++14 synthesisable subset.
#pragma once

#include "parallax/kernels/params.hpp"

namespace parallax {
namespace kern {

enum StreamPathKind : int {
  kKindPixel = 0,     // predecessor (x-1, y): previous pixel of the stream
  kKindRowLeft = 1,   // predecessor (x-1, y-1): previous row, one column back
  kKindRowUp = 2,     // predecessor (x, y-1): previous row, same column
  kKindRowRight = 3,  // predecessor (x+1, y-1): previous row, one column ahead
  kKindCount = 4
};

// The stream kinds of one pass for an image-direction path mask. forward: 0/45/90/135 map to
// pixel/row-left/row-up/row-right; backward (reversed stream): 180/225/270/315 likewise.
constexpr unsigned stream_kinds(unsigned path_mask, bool backward) {
  return (backward ? (path_mask >> 4) : path_mask) & 0xFu;
}

// The kinds whose datapaths an MGM stage computes for the stream kinds `kinds`: the pixel kind
// for the pair pixel / row-up, the row-left kind for the pair row-left / row-right.
inline unsigned mgm_kinds(unsigned kinds) {
  return ((kinds & ((1u << kKindPixel) | (1u << kKindRowUp))) != 0 ? (1u << kKindPixel) : 0u) |
         ((kinds & ((1u << kKindRowLeft) | (1u << kKindRowRight))) != 0 ? (1u << kKindRowLeft) : 0u);
}
// The kinds with hardware in an aggregation stage of the given stream kinds and aggregation.
inline unsigned datapath_kinds(unsigned kinds, int aggregation) {
  return aggregation == kAggregationMgm ? mgm_kinds(kinds) : kinds;
}

}  // namespace kern
}  // namespace parallax
