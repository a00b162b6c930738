// The independent whole-frame golden model of the disparity algorithm (docs/algorithm.md).
//
// Every function works on whole frames held in std::vector, with obvious loops, so that each
// line can be checked against the specification. The streaming kernels are compared with this
// model bit for bit; it shares nothing with them but the parameter header.
//
// Layouts (all row-major):
//   images and disparity codes: index y * W + x;
//   cost, path-cost and aggregate volumes: index (y * W + x) * D + d, see volume_index().
//
// Errors: bad parameters or inconsistent inputs throw std::invalid_argument with a message;
// broken internal invariants (e.g. a value exceeding its derived bit width) abort.
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "parallax/kernels/params.hpp"

namespace parallax::ref {

// An 8-bit grey image, row-major: px[y * width_px + x].
struct Image8 {
  int width_px = 0;
  int height_px = 0;
  std::vector<uint8_t> px;

  // Requires 0 <= x < width_px and 0 <= y < height_px (asserted).
  uint8_t at(int x, int y) const {
    assert(x >= 0 && x < width_px && y >= 0 && y < height_px);
    return px[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_px) + static_cast<std::size_t>(x)];
  }
};

// An image of width_px x height_px pixels, every pixel set to fill_value.
Image8 make_image(int width_px, int height_px, uint8_t fill_value = 0);

// A remap table (docs §1): for output pixel (x, y), the source position is
// (map_x[i], map_y[i]) / 2^frac_bits with i = y * width_px + x (signed fixed point).
struct RemapTable {
  int width_px = 0;
  int height_px = 0;
  int frac_bits = 0;
  std::vector<int32_t> map_x;
  std::vector<int32_t> map_y;
};

// The identity map: output (x, y) reads source (x, y), in fixed point with frac_bits bits.
RemapTable identity_map(int width_px, int height_px, int frac_bits);

struct RectifyResult {
  Image8 image;
  // Taps inside the image but outside the line buffer's available rows (docs §1), counted once
  // per tap (a bilinear output pixel has four taps, even those with weight 0).
  int64_t window_misses = 0;
};

// Rectification (docs §1). in, map and p must all have the same size. p.mode:
//   kRectifyNone: output = input, no misses (map is ignored);
//   kRectifyNearest: requires frac_bits == 0;
//   kRectifyBilinear: requires 1 <= frac_bits <= 16.
// map.frac_bits must equal p.frac_bits; p.buffer_rows >= 1.
RectifyResult rectify(const Image8& in, const RemapTable& map, const kern::RectifyParams& p);

// Throws std::invalid_argument when p violates docs/algorithm.md or cannot be represented by
// this model: size >= 1 x 1, cost kind census/SAD, windows odd and >= 1, census w*h-1 <= 64,
// 1 <= D <= 256, path_mask a non-empty subset of kAllPaths, 0 <= P1 < P2, lr_tolerance >= 0,
// 0 <= uniqueness_pct <= 100,
// median in {0, 1, 3, 5, 7} (0 and 1 mean off), aggregate_bits(p) <= 32 (uint32 volumes).
// parallel_units is a kernel structure field with no effect on the result and is not checked.
void validate_stereo_params(const kern::StereoParams& p);

// Index of (x, y, d) in a cost / path-cost / aggregate volume of width_px x H x disparities.
inline std::size_t volume_index(int x, int y, int d, int width_px, int disparities) {
  return (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_px) + static_cast<std::size_t>(x)) *
             static_cast<std::size_t>(disparities) +
         static_cast<std::size_t>(d);
}

// Census codes of one image (docs §2), row-major. Window window_w x window_h, both odd, with
// window_w * window_h - 1 <= 64; the code uses the low window_w * window_h - 1 bits, the first
// tap (raster order, centre skipped) in the most significant of them; a bit is 1 when the
// (clamped) tap is strictly darker than the centre.
std::vector<uint64_t> census_codes(const Image8& img, int window_w, int window_h, int kind = kern::kCensusFull);

// Cost volume C[(y*W + x)*D + d] (docs §2), census or SAD per p.cost; C = cost_max(p) where
// x - d < 0. left and right must be p.width_px x p.height_px.
std::vector<uint32_t> cost_volume(const Image8& left, const Image8& right, const kern::StereoParams& p);

// Path cost volume Lr for ONE path (docs §3); path_bit is a single kern::PathBit (it need not be
// in p.path_mask). cost must have W*H*D entries, each <= cost_max(p). Every result satisfies
// Lr <= cost_max(p) + p.p2 < 2^path_bits(p) (checked; a violation aborts). With
// p.p2_adaptive > 0 the step's P2 follows the left image's intensities: left is required then
// (std::invalid_argument without it) and ignored otherwise.
std::vector<uint32_t> path_costs(const std::vector<uint32_t>& cost, const kern::StereoParams& p, unsigned path_bit,
                                 const Image8* left = nullptr);

// Aggregate S = sum of Lr over the paths in p.path_mask, same layout. Every result is
// < 2^aggregate_bits(p) (checked; a violation aborts). left as for path_costs.
std::vector<uint32_t> aggregate(const std::vector<uint32_t>& cost, const kern::StereoParams& p,
                                const Image8* left = nullptr);

// Winner takes all and left-right check (docs §4) on an aggregate volume: one code per pixel,
// row-major; code d in [0, D) is a disparity, code D (kern::invalid_code) is invalid. Ties go to
// the smallest d. dL > x is invalid; with p.uniqueness_pct = u > 0, a dL with some d,
// |d - dL| >= 2, where 100 S(d) < (100 + u) S(dL) is invalid; with p.lr_check,
// |dL - dR(x - dL)| > p.lr_tolerance is invalid.
std::vector<uint16_t> select_disparity(const std::vector<uint32_t>& aggregate, const kern::StereoParams& p);

// k x k median of codes (docs §5) with the clamp border: the element of rank (k*k - 1) / 2
// (0-based) of the sorted window. k in {0, 1} returns codes unchanged; k in {3, 5, 7}.
std::vector<uint16_t> median_filter(const std::vector<uint16_t>& codes, int width_px, int height_px, int k);

// Full pipeline: cost -> aggregate -> select (+ LR check) -> median. Codes, row-major.
// Rectification is not included (call rectify() first).
std::vector<uint16_t> compute_disparity(const Image8& left, const Image8& right, const kern::StereoParams& p);

}  // namespace parallax::ref
