// The independent whole-frame golden model of docs/algorithm.md. Section numbers (§) refer to
// that document. Clarity first: whole frames, obvious loops, explicit border rules.
#include "parallax/reference/stereo.hpp"

#include <algorithm>
#include <bitset>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace parallax::ref {
namespace {

// Internal invariants are checked in every build type (not only with assertions enabled): they
// are part of the contract with the kernels (e.g. the derived bit widths).
#define PARALLAX_REF_CHECK(cond)                                                                         \
  do {                                                                                                   \
    if (!(cond)) {                                                                                       \
      std::fprintf(stderr, "parallax::ref invariant violated: %s (%s:%d)\n", #cond, __FILE__, __LINE__); \
      std::abort();                                                                                      \
    }                                                                                                    \
  } while (0)

[[noreturn]] void fail(const std::string& message) {
  throw std::invalid_argument("parallax::ref: " + message);
}

std::size_t pixel_count(int width_px, int height_px) {
  return static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px);
}

int clamp_int(int v, int lo, int hi) {
  return std::min(std::max(v, lo), hi);
}

// Largest value that fits in `bits` bits (bits in [1, 63]).
uint64_t max_for_bits(int bits) {
  return (uint64_t(1) << bits) - 1u;
}

void check_image(const Image8& img, const char* name) {
  if (img.width_px < 1 || img.height_px < 1) fail(std::string(name) + ": image size must be >= 1x1");
  if (img.px.size() != pixel_count(img.width_px, img.height_px))
    fail(std::string(name) + ": px.size() != width_px * height_px");
}

void check_image_matches(const Image8& img, const kern::StereoParams& p, const char* name) {
  check_image(img, name);
  if (img.width_px != p.width_px || img.height_px != p.height_px)
    fail(std::string(name) + ": image size differs from StereoParams width_px x height_px");
}

void check_window(int window_w, int window_h) {
  if (window_w < 1 || window_h < 1) fail("window sides must be >= 1");
  if (window_w % 2 == 0 || window_h % 2 == 0)
    fail("window sides must be odd (got " + std::to_string(window_w) + "x" + std::to_string(window_h) + ")");
}

void check_volume(const std::vector<uint32_t>& volume, const kern::StereoParams& p, const char* name) {
  const std::size_t expected = pixel_count(p.width_px, p.height_px) * static_cast<std::size_t>(p.disparities);
  if (volume.size() != expected)
    fail(std::string(name) + ": volume size must be width_px * height_px * disparities (" + std::to_string(expected) +
         "), got " + std::to_string(volume.size()));
}

// One SGM path direction: the predecessor of p = (x, y) is q = (x + dx, y + dy) (docs §3).
struct PathDirection {
  unsigned bit;
  int dx;
  int dy;
  bool forward;  // forward: raster order; backward: reverse raster order
  int dx2;       // MGM's second predecessor (docs §3): p + (dx2, dy2), across the path
  int dy2;
};

constexpr PathDirection kPathDirections[8] = {
    {kern::kPath0, -1, 0, true, 0, -1},    {kern::kPath45, -1, -1, true, +1, -1},
    {kern::kPath90, 0, -1, true, -1, 0},   {kern::kPath135, +1, -1, true, -1, -1},
    {kern::kPath180, +1, 0, false, 0, +1}, {kern::kPath225, +1, +1, false, -1, +1},
    {kern::kPath270, 0, +1, false, +1, 0}, {kern::kPath315, -1, +1, false, +1, +1},
};

const PathDirection& direction_for(unsigned path_bit) {
  for (const PathDirection& dir : kPathDirections)
    if (dir.bit == path_bit) return dir;
  fail("path_bit must be exactly one kern::PathBit, got " + std::to_string(path_bit));
}

}  // namespace

Image8 make_image(int width_px, int height_px, uint8_t fill_value) {
  if (width_px < 0 || height_px < 0) fail("make_image: negative size");
  Image8 img;
  img.width_px = width_px;
  img.height_px = height_px;
  img.px.assign(pixel_count(width_px, height_px), fill_value);
  return img;
}

RemapTable identity_map(int width_px, int height_px, int frac_bits) {
  if (width_px < 0 || height_px < 0) fail("identity_map: negative size");
  if (frac_bits < 0 || frac_bits > 16) fail("identity_map: frac_bits must be in [0, 16]");
  RemapTable map;
  map.width_px = width_px;
  map.height_px = height_px;
  map.frac_bits = frac_bits;
  map.map_x.resize(pixel_count(width_px, height_px));
  map.map_y.resize(pixel_count(width_px, height_px));
  const int32_t one = 1 << frac_bits;
  for (int y = 0; y < height_px; ++y) {
    for (int x = 0; x < width_px; ++x) {
      const std::size_t i =
          static_cast<std::size_t>(y) * static_cast<std::size_t>(width_px) + static_cast<std::size_t>(x);
      map.map_x[i] = x * one;
      map.map_y[i] = y * one;
    }
  }
  return map;
}

// ---------------------------------------------------------------------------------------------
// §1 Rectification
// ---------------------------------------------------------------------------------------------

namespace {

// Reads taps for one output row through the line buffer (docs §1): rows [first_row, last_row]
// are available; a tap outside the image is 0; a tap inside the image but outside the
// available rows is 0 and counted as a window miss.
struct LineBufferReader {
  const Image8& in;
  int first_row;
  int last_row;
  int64_t& misses;

  int tap(int64_t ix, int64_t iy) const {
    if (ix < 0 || ix >= in.width_px || iy < 0 || iy >= in.height_px) return 0;
    if (iy < first_row || iy > last_row) {
      ++misses;
      return 0;
    }
    return in.at(static_cast<int>(ix), static_cast<int>(iy));
  }
};

// floor(v / 2^frac_bits), i.e. the arithmetic shift of docs §1, written without shifting a
// negative value (implementation-defined before C++20).
int64_t floor_div_pow2(int64_t v, int frac_bits) {
  const int64_t scale = int64_t(1) << frac_bits;
  int64_t q = v / scale;  // truncates towards zero
  if (v % scale != 0 && v < 0) q -= 1;
  return q;
}

}  // namespace

RectifyResult rectify(const Image8& in, const RemapTable& map, const kern::RectifyParams& p) {
  check_image(in, "rectify input");
  if (in.width_px != p.width_px || in.height_px != p.height_px)
    fail("rectify: input size differs from RectifyParams width_px x height_px");

  RectifyResult result;
  if (p.mode == kern::kRectifyNone) {
    result.image = in;
    return result;
  }
  if (p.mode != kern::kRectifyNearest && p.mode != kern::kRectifyBilinear)
    fail("rectify: unknown mode " + std::to_string(p.mode));
  if (map.width_px != in.width_px || map.height_px != in.height_px)
    fail("rectify: remap table size differs from the image size");
  const std::size_t n = pixel_count(in.width_px, in.height_px);
  if (map.map_x.size() != n || map.map_y.size() != n)
    fail("rectify: map_x / map_y must have width_px * height_px entries");
  if (map.frac_bits != p.frac_bits) fail("rectify: RemapTable frac_bits differs from RectifyParams frac_bits");
  if (p.mode == kern::kRectifyNearest && p.frac_bits != 0)
    fail("rectify: nearest mode requires frac_bits == 0 (integer maps)");
  if (p.mode == kern::kRectifyBilinear && (p.frac_bits < 1 || p.frac_bits > 16))
    fail("rectify: bilinear mode requires 1 <= frac_bits <= 16");
  if (p.buffer_rows < 1) fail("rectify: buffer_rows must be >= 1");

  const int width = in.width_px;
  const int height = in.height_px;
  const int rows = p.buffer_rows;                 // R
  const int ahead = rows / 2;                     // A = R / 2
  const int frac_bits = p.frac_bits;              // F
  const int64_t scale = int64_t(1) << frac_bits;  // S = 2^F

  result.image = make_image(width, height, 0);
  for (int y = 0; y < height; ++y) {
    // Rows available while producing output row y: [y + A - R + 1, y + A].
    const LineBufferReader reader{in, y + ahead - rows + 1, y + ahead, result.window_misses};
    for (int x = 0; x < width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
      const int64_t mx = map.map_x[i];
      const int64_t my = map.map_y[i];
      int value = 0;
      if (p.mode == kern::kRectifyNearest) {
        value = reader.tap(mx, my);
      } else {
        const int64_t ix = floor_div_pow2(mx, frac_bits);
        const int64_t iy = floor_div_pow2(my, frac_bits);
        const int64_t fx = mx - ix * scale;  // == mx & (S - 1)
        const int64_t fy = my - iy * scale;
        assert(fx >= 0 && fx < scale && fy >= 0 && fy < scale);
        const int64_t t00 = reader.tap(ix, iy);
        const int64_t t10 = reader.tap(ix + 1, iy);
        const int64_t t01 = reader.tap(ix, iy + 1);
        const int64_t t11 = reader.tap(ix + 1, iy + 1);
        const int64_t sum =
            t00 * (scale - fx) * (scale - fy) + t10 * fx * (scale - fy) + t01 * (scale - fx) * fy + t11 * fx * fy;
        const int64_t half = int64_t(1) << (2 * frac_bits - 1);  // 2^(2F-1)
        value = static_cast<int>((sum + half) >> (2 * frac_bits));
      }
      PARALLAX_REF_CHECK(value >= 0 && value <= 255);
      result.image.px[i] = static_cast<uint8_t>(value);
    }
  }
  return result;
}

// ---------------------------------------------------------------------------------------------
// Parameters
// ---------------------------------------------------------------------------------------------

void validate_stereo_params(const kern::StereoParams& p) {
  if (p.width_px < 1 || p.height_px < 1)
    fail("image size must be >= 1x1, got " + std::to_string(p.width_px) + "x" + std::to_string(p.height_px));
  if (p.cost != kern::kCostCensus && p.cost != kern::kCostSad)
    fail("cost must be kCostCensus or kCostSad, got " + std::to_string(p.cost));
  check_window(p.window_w, p.window_h);
  const int64_t window_area = int64_t(p.window_w) * int64_t(p.window_h);
  if (p.cost == kern::kCostCensus && (p.census < kern::kCensusFull || p.census > kern::kCensusSymmetric))
    fail("census kind must be full, sparse or symmetric, got " + std::to_string(p.census));
  if (p.cost == kern::kCostCensus && kern::census_bits(p.census, p.window_w, p.window_h) > kern::kMaxCensusBits)
    fail("census window needs <= 64 code bits, got " +
         std::to_string(kern::census_bits(p.census, p.window_w, p.window_h)));
  if (p.cost == kern::kCostSad && window_area * 255 > int64_t(1) << 30) fail("SAD window too large for 32-bit costs");
  if (p.disparities < 1 || p.disparities > kern::kMaxDisparities)
    fail("disparities must be in [1, 256], got " + std::to_string(p.disparities));
  if (p.min_disparity < 0 || p.min_disparity > kern::kMaxMinDisparity)
    fail("min_disparity must be in [0, " + std::to_string(kern::kMaxMinDisparity) + "], got " +
         std::to_string(p.min_disparity));
  if (p.p2_adaptive < 0 || p.p2_adaptive > kern::kMaxP2Adaptive)
    fail("p2_adaptive must be in [0, " + std::to_string(kern::kMaxP2Adaptive) + "], got " +
         std::to_string(p.p2_adaptive));
  if (p.subpixel_bits < 0 || p.subpixel_bits > kern::kMaxSubpixelBits)
    fail("subpixel_bits must be in [0, " + std::to_string(kern::kMaxSubpixelBits) + "], got " +
         std::to_string(p.subpixel_bits));
  if (p.aggregation != kern::kAggregationSgm && p.aggregation != kern::kAggregationMgm)
    fail("aggregation must be kAggregationSgm or kAggregationMgm, got " + std::to_string(p.aggregation));
  if (p.path_mask == 0) fail("path_mask must select at least one path");
  if ((p.path_mask & ~kern::kAllPaths) != 0) fail("path_mask has bits outside the eight kern::PathBit values");
  if (p.p1 < 0) fail("P1 must be >= 0, got " + std::to_string(p.p1));
  if (!(p.p1 < p.p2)) fail("P1 must be < P2, got P1=" + std::to_string(p.p1) + " P2=" + std::to_string(p.p2));
  if (p.lr_tolerance < 0) fail("lr_tolerance must be >= 0");
  if (p.uniqueness_pct < 0 || p.uniqueness_pct > kern::kMaxUniquenessPct)
    fail("uniqueness_pct must be in [0, " + std::to_string(kern::kMaxUniquenessPct) + "]");
  if (p.median != 0 && p.median != 1 && p.median != 3 && p.median != 5 && p.median != 7)
    fail("median must be 0 or 1 (off), 3, 5 or 7, got " + std::to_string(p.median));
  if (kern::aggregate_bits(p) > 32)
    fail("aggregate_bits = " + std::to_string(kern::aggregate_bits(p)) +
         " > 32: P2 or the window too large for uint32 volumes");
}

// ---------------------------------------------------------------------------------------------
// §2 Matching cost
// ---------------------------------------------------------------------------------------------

std::vector<uint64_t> census_codes(const Image8& img, int window_w, int window_h, int kind) {
  check_image(img, "census_codes");
  check_window(window_w, window_h);
  if (kind < kern::kCensusFull || kind > kern::kCensusSymmetric) fail("census kind must be full, sparse or symmetric");
  if (kern::census_bits(kind, window_w, window_h) > kern::kMaxCensusBits) fail("census window needs <= 64 code bits");

  const int width = img.width_px;
  const int height = img.height_px;
  const int rw = window_w / 2;
  const int rh = window_h / 2;
  std::vector<uint64_t> codes(pixel_count(width, height), 0);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      auto at = [&](int i, int j) { return img.at(clamp_int(x + i, 0, width - 1), clamp_int(y + j, 0, height - 1)); };
      const int centre = img.at(x, y);
      // Shifting left once per used tap leaves the first in the most significant used bit. Taps
      // in raster order, k = 0 .. w*h - 1, the centre at k = w*h / 2: full uses all but the
      // centre, sparse the even k but the centre, symmetric k < w*h / 2 against tap (-i, -j).
      uint64_t code = 0;
      int k = 0;
      for (int j = -rh; j <= rh; ++j) {
        for (int i = -rw; i <= rw; ++i, ++k) {
          const bool centre_tap = i == 0 && j == 0;
          if (kind == kern::kCensusFull && centre_tap) continue;
          if (kind == kern::kCensusSparse && (centre_tap || k % 2 != 0)) continue;
          if (kind == kern::kCensusSymmetric && (j > 0 || (j == 0 && i >= 0))) continue;
          const int other = kind == kern::kCensusSymmetric ? at(-i, -j) : centre;
          code = (code << 1) | (at(i, j) < other ? 1u : 0u);
        }
      }
      codes[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)] = code;
    }
  }
  return codes;
}

std::vector<uint32_t> cost_volume(const Image8& left, const Image8& right, const kern::StereoParams& p) {
  validate_stereo_params(p);
  check_image_matches(left, p, "cost_volume left");
  check_image_matches(right, p, "cost_volume right");

  const int width = p.width_px;
  const int height = p.height_px;
  const int num_disp = p.disparities;
  const uint32_t max_cost = kern::cost_max(p);
  const int rw = p.window_w / 2;
  const int rh = p.window_h / 2;
  const int m = p.min_disparity;  // code d matches right column x - m - d

  std::vector<uint32_t> cost(pixel_count(width, height) * static_cast<std::size_t>(num_disp), 0);
  if (p.cost == kern::kCostCensus) {
    const std::vector<uint64_t> codes_l = census_codes(left, p.window_w, p.window_h, p.census);
    const std::vector<uint64_t> codes_r = census_codes(right, p.window_w, p.window_h, p.census);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(width);
        for (int d = 0; d < num_disp; ++d) {
          uint32_t c = max_cost;  // x - m - d < 0: no right pixel to match
          if (x - m - d >= 0) {
            const uint64_t diff =
                codes_l[row + static_cast<std::size_t>(x)] ^ codes_r[row + static_cast<std::size_t>(x - m - d)];
            c = static_cast<uint32_t>(std::bitset<64>(diff).count());
          }
          PARALLAX_REF_CHECK(c <= max_cost);
          cost[volume_index(x, y, d, width, num_disp)] = c;
        }
      }
    }
  } else {
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        for (int d = 0; d < num_disp; ++d) {
          uint32_t c = max_cost;  // x - m - d < 0: no right pixel to match
          if (x - m - d >= 0) {
            c = 0;
            for (int j = -rh; j <= rh; ++j) {
              const int yy = clamp_int(y + j, 0, height - 1);
              for (int i = -rw; i <= rw; ++i) {
                const int l = left.at(clamp_int(x + i, 0, width - 1), yy);
                const int r = right.at(clamp_int(x - m - d + i, 0, width - 1), yy);
                c += static_cast<uint32_t>(std::abs(l - r));
              }
            }
          }
          PARALLAX_REF_CHECK(c <= max_cost);
          cost[volume_index(x, y, d, width, num_disp)] = c;
        }
      }
    }
  }
  return cost;
}

// ---------------------------------------------------------------------------------------------
// §3 SGM aggregation
// ---------------------------------------------------------------------------------------------

std::vector<uint32_t> path_costs(const std::vector<uint32_t>& cost, const kern::StereoParams& p, unsigned path_bit,
                                 const Image8* left) {
  validate_stereo_params(p);
  check_volume(cost, p, "path_costs cost");
  if (p.p2_adaptive > 0) {
    if (left == nullptr) fail("path_costs: p2_adaptive > 0 needs the left image");
    check_image_matches(*left, p, "path_costs left");
  }
  const PathDirection& dir = direction_for(path_bit);

  const int width = p.width_px;
  const int height = p.height_px;
  const int num_disp = p.disparities;
  const uint64_t max_cost = kern::cost_max(p);
  for (const uint32_t c : cost)
    if (c > max_cost) fail("path_costs: a cost exceeds cost_max(p)");

  const uint64_t p1 = static_cast<uint64_t>(p.p1);
  const uint64_t p2 = static_cast<uint64_t>(p.p2);
  const uint64_t path_limit = max_cost + p2;  // docs §3: Lr <= cost_max + P2
  const uint64_t path_bits_limit = max_for_bits(kern::path_bits(p));
  PARALLAX_REF_CHECK(path_limit <= path_bits_limit);

  std::vector<uint32_t> lr(cost.size(), 0);
  // done[y*W + x] marks computed pixels: proves each predecessor is ready before it is used.
  std::vector<uint8_t> done(pixel_count(width, height), 0);

  const bool mgm = p.aggregation == kern::kAggregationMgm;
  auto inside = [&](int qx, int qy) { return qx >= 0 && qx < width && qy >= 0 && qy < height; };
  // The step from predecessor q into p at disparity d (docs §3):
  // min(Lr(q, d), Lr(q, d-1) + P1, Lr(q, d+1) + P1, M + P2') - M, with M = min_k Lr(q, k).
  auto step_into = [&](int x, int y, int qx, int qy, std::vector<uint64_t>& out) {
    PARALLAX_REF_CHECK(
        done[static_cast<std::size_t>(qy) * static_cast<std::size_t>(width) + static_cast<std::size_t>(qx)] != 0);
    // P2 of this step: lowered by the left image's intensity step from q to p (docs §3).
    const uint64_t p2_here =
        p.p2_adaptive > 0 ? uint64_t(kern::adaptive_p2(p.p1, p.p2, p.p2_adaptive, left->at(x, y), left->at(qx, qy)))
                          : p2;
    uint64_t min_q = lr[volume_index(qx, qy, 0, width, num_disp)];
    for (int k = 1; k < num_disp; ++k) min_q = std::min<uint64_t>(min_q, lr[volume_index(qx, qy, k, width, num_disp)]);
    for (int d = 0; d < num_disp; ++d) {
      uint64_t best = lr[volume_index(qx, qy, d, width, num_disp)];
      if (d - 1 >= 0) best = std::min<uint64_t>(best, lr[volume_index(qx, qy, d - 1, width, num_disp)] + p1);
      if (d + 1 < num_disp) best = std::min<uint64_t>(best, lr[volume_index(qx, qy, d + 1, width, num_disp)] + p1);
      best = std::min<uint64_t>(best, min_q + p2_here);
      PARALLAX_REF_CHECK(best >= min_q && best - min_q <= p2_here && p2_here <= p2);
      out[static_cast<std::size_t>(d)] = best - min_q;
    }
  };
  std::vector<uint64_t> step_a(static_cast<std::size_t>(num_disp)), step_b(static_cast<std::size_t>(num_disp));

  for (int step_y = 0; step_y < height; ++step_y) {
    const int y = dir.forward ? step_y : height - 1 - step_y;
    for (int step_x = 0; step_x < width; ++step_x) {
      const int x = dir.forward ? step_x : width - 1 - step_x;
      // SGM: the path's predecessor q alone. MGM: also q2 across the path; the steps from the
      // predecessors inside the image are averaged (floor), a path starts where neither is.
      const bool a_inside = inside(x + dir.dx, y + dir.dy);
      const bool b_inside = mgm && inside(x + dir.dx2, y + dir.dy2);
      if (a_inside) step_into(x, y, x + dir.dx, y + dir.dy, step_a);
      if (b_inside) step_into(x, y, x + dir.dx2, y + dir.dy2, step_b);
      for (int d = 0; d < num_disp; ++d) {
        const std::size_t i = volume_index(x, y, d, width, num_disp);
        const std::size_t k = static_cast<std::size_t>(d);
        const uint64_t step = a_inside && b_inside ? (step_a[k] + step_b[k]) / 2
                              : a_inside           ? step_a[k]
                              : b_inside           ? step_b[k]
                                                   : 0;  // path start: Lr(p, d) = C(p, d)
        const uint64_t value = uint64_t(cost[i]) + step;
        PARALLAX_REF_CHECK(value <= path_limit);
        PARALLAX_REF_CHECK(value <= path_bits_limit);
        lr[i] = static_cast<uint32_t>(value);
      }
      done[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)] = 1;
    }
  }
  return lr;
}

std::vector<uint32_t> aggregate(const std::vector<uint32_t>& cost, const kern::StereoParams& p, const Image8* left) {
  validate_stereo_params(p);
  check_volume(cost, p, "aggregate cost");
  const uint64_t aggregate_limit = max_for_bits(kern::aggregate_bits(p));

  std::vector<uint64_t> sum(cost.size(), 0);
  for (const PathDirection& dir : kPathDirections) {
    if ((p.path_mask & dir.bit) == 0) continue;
    const std::vector<uint32_t> lr = path_costs(cost, p, dir.bit, left);
    for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += lr[i];
  }

  std::vector<uint32_t> s(cost.size(), 0);
  for (std::size_t i = 0; i < sum.size(); ++i) {
    PARALLAX_REF_CHECK(sum[i] <= aggregate_limit);
    s[i] = static_cast<uint32_t>(sum[i]);
  }
  return s;
}

// ---------------------------------------------------------------------------------------------
// §4 Winner takes all and left-right check
// ---------------------------------------------------------------------------------------------

std::vector<uint16_t> select_disparity(const std::vector<uint32_t>& aggregate_volume, const kern::StereoParams& p) {
  validate_stereo_params(p);
  check_volume(aggregate_volume, p, "select_disparity aggregate");

  const int width = p.width_px;
  const int height = p.height_px;
  const int num_disp = p.disparities;
  const uint16_t invalid = static_cast<uint16_t>(kern::invalid_code(p));
  const int m = p.min_disparity;  // code d is disparity m + d
  auto s = [&](int x, int y, int d) { return aggregate_volume[volume_index(x, y, d, width, num_disp)]; };
  // Uniqueness: no S at two or more disparities from the best below (100 + u) / 100 of the best.
  auto unique = [&](int x, int y, int best_d) {
    if (p.uniqueness_pct <= 0) return true;
    const uint64_t bound = uint64_t(s(x, y, best_d)) * uint64_t(100 + p.uniqueness_pct);
    for (int d = 0; d < num_disp; ++d)
      if (std::abs(d - best_d) >= 2 && uint64_t(s(x, y, d)) * 100u < bound) return false;
    return true;
  };

  // Sub-pixel code of the winner d (docs §4): d * 2^f plus the parabola's vertex offset
  // (a - b) / (2 (a + b)), a = S(d-1) - S(d), b = S(d+1) - S(d), in f fraction bits rounded half
  // up in magnitude; no offset at d = 0, d = D - 1 or a + b = 0.
  const int f = p.subpixel_bits;
  auto refine = [&](int x, int y, int d) {
    int64_t code = int64_t(d) << f;
    if (f > 0 && d > 0 && d + 1 < num_disp) {
      const int64_t a = int64_t(s(x, y, d - 1)) - int64_t(s(x, y, d));
      const int64_t b = int64_t(s(x, y, d + 1)) - int64_t(s(x, y, d));
      PARALLAX_REF_CHECK(a >= 0 && b >= 0);
      if (a + b > 0) {
        const int64_t half_steps = (std::abs(a - b) << f) / (a + b);  // 2^f |offset| * 2, floored
        const int64_t r = (half_steps + 1) / 2;
        PARALLAX_REF_CHECK(r <= (int64_t(1) << f) / 2);
        code += a > b ? r : -r;
      }
    }
    return static_cast<uint16_t>(code);
  };

  std::vector<uint16_t> codes(pixel_count(width, height), invalid);
  std::vector<int> d_left(static_cast<std::size_t>(width), 0);
  std::vector<int> d_right(static_cast<std::size_t>(width), 0);
  for (int y = 0; y < height; ++y) {
    // dL(x, y): the smallest d minimising S(x, y, d) (strict < keeps the first minimum).
    for (int x = 0; x < width; ++x) {
      int best_d = 0;
      for (int d = 1; d < num_disp; ++d)
        if (s(x, y, d) < s(x, y, best_d)) best_d = d;
      d_left[static_cast<std::size_t>(x)] = unique(x, y, best_d) ? best_d : num_disp;
    }
    // dR(xr, y): the smallest d with xr + m + d < W minimising S(xr + m + d, y, d) (0 when no
    // left pixel matches xr).
    for (int xr = 0; xr < width; ++xr) {
      int best_d = 0;
      for (int d = 1; d < num_disp && xr + m + d < width; ++d)
        if (s(xr + m + d, y, d) < s(xr + m + best_d, y, best_d)) best_d = d;
      d_right[static_cast<std::size_t>(xr)] = best_d;
    }
    for (int x = 0; x < width; ++x) {
      const int dl = d_left[static_cast<std::size_t>(x)];
      bool valid = dl < num_disp && m + dl <= x;  // not unique, or the match lies outside the right image
      if (valid && p.lr_check) {
        const int dr = d_right[static_cast<std::size_t>(x - m - dl)];
        valid = std::abs(dl - dr) <= p.lr_tolerance;
      }
      if (valid)
        codes[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)] =
            refine(x, y, dl);
    }
  }
  return codes;
}

// ---------------------------------------------------------------------------------------------
// §5 Median
// ---------------------------------------------------------------------------------------------

std::vector<uint16_t> median_filter(const std::vector<uint16_t>& codes, int width_px, int height_px, int k) {
  if (width_px < 1 || height_px < 1) fail("median_filter: size must be >= 1x1");
  if (codes.size() != pixel_count(width_px, height_px)) fail("median_filter: codes.size() != width_px * height_px");
  if (k == 0 || k == 1) return codes;
  if (k != 3 && k != 5 && k != 7) fail("median_filter: k must be 0 or 1 (off), 3, 5 or 7, got " + std::to_string(k));

  const int radius = k / 2;
  const std::size_t rank = static_cast<std::size_t>((k * k - 1) / 2);
  std::vector<uint16_t> out(codes.size(), 0);
  std::vector<uint16_t> window;
  window.reserve(static_cast<std::size_t>(k) * static_cast<std::size_t>(k));
  for (int y = 0; y < height_px; ++y) {
    for (int x = 0; x < width_px; ++x) {
      window.clear();
      for (int j = -radius; j <= radius; ++j) {
        const int yy = clamp_int(y + j, 0, height_px - 1);
        for (int i = -radius; i <= radius; ++i) {
          const int xx = clamp_int(x + i, 0, width_px - 1);
          window.push_back(
              codes[static_cast<std::size_t>(yy) * static_cast<std::size_t>(width_px) + static_cast<std::size_t>(xx)]);
        }
      }
      std::sort(window.begin(), window.end());
      out[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_px) + static_cast<std::size_t>(x)] =
          window[rank];
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Full pipeline
// ---------------------------------------------------------------------------------------------

std::vector<uint16_t> compute_disparity(const Image8& left, const Image8& right, const kern::StereoParams& p) {
  validate_stereo_params(p);
  const std::vector<uint32_t> cost = cost_volume(left, right, p);
  const std::vector<uint32_t> s = aggregate(cost, p, &left);
  const std::vector<uint16_t> codes = select_disparity(s, p);
  return median_filter(codes, p.width_px, p.height_px, p.median);
}

}  // namespace parallax::ref
