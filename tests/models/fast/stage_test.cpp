// equiv: the fast engine stage by stage against the golden model (issue 43, item 5), libSGM-style:
// over a table of designs, the cost volume, the path costs of every direction alone, the aggregate
// of the design's paths, the selection (WTA, uniqueness, LR check, sub-pixel codes) and the median,
// each compared in full and reported at its first differing position (x, y, d). The whole-frame
// codes are compared in tests/kernels/equiv_test.cpp; this says which stage a difference is in.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "parallax/fast/engine.hpp"
#include "parallax/reference/stereo.hpp"

namespace parallax::test {
namespace {

struct Design {
  const char* what;
  int width_px, height_px, disparities, min_disparity;
  int cost, census, window_w, window_h;
  int p1, p2, p2_adaptive, aggregation;
  unsigned paths;
  bool lr_check;
  int uniqueness_pct, subpixel_bits, median;
};

// One row per stage knob the fast engine treats in its own way (widths of the cost, padding of D
// to the SIMD lanes, sparse and symmetric census, SAD, m, adaptive P2, MGM, eight paths,
// uniqueness, sub-pixel codes, odd sizes).
const Design kDesigns[] = {
    {"seed-like census 5x5, D 32", 48, 14, 32, 0, kern::kCostCensus, kern::kCensusFull, 5, 5, 8, 32, 0, 0,
     kern::kForwardPaths, true, 0, 0, 5},
    {"sparse census 9x7, D 40 from m 3", 53, 11, 40, 3, kern::kCostCensus, kern::kCensusSparse, 9, 7, 6, 40, 0, 0,
     kern::kAllPaths, true, 5, 0, 3},
    {"symmetric census 7x5, adaptive P2, sub-pixel", 41, 13, 24, 2, kern::kCostCensus, kern::kCensusSymmetric, 7, 5, 4,
     64, 16, 0, kern::kForwardPaths | kern::kPath180, true, 0, 2, 7},
    {"SAD 7x7, D 48, eight paths, wide sums", 37, 12, 48, 0, kern::kCostSad, kern::kCensusFull, 7, 7, 120, 2400, 0, 0,
     kern::kAllPaths, true, 10, 0, 0},
    {"MGM, no LR check", 45, 10, 32, 0, kern::kCostCensus, kern::kCensusFull, 5, 5, 8, 48, 0, kern::kAggregationMgm,
     kern::kForwardPaths, false, 0, 0, 5},
};

kern::StereoParams params(const Design& d) {
  kern::StereoParams p{};
  p.width_px = d.width_px;
  p.height_px = d.height_px;
  p.cost = d.cost;
  p.census = d.census;
  p.window_w = d.window_w;
  p.window_h = d.window_h;
  p.disparities = d.disparities;
  p.min_disparity = d.min_disparity;
  p.parallel_units = 1;
  p.path_mask = d.paths;
  p.p1 = d.p1;
  p.p2 = d.p2;
  p.p2_adaptive = d.p2_adaptive;
  p.aggregation = d.aggregation;
  p.lr_check = d.lr_check;
  p.lr_tolerance = 1;
  p.uniqueness_pct = d.uniqueness_pct;
  p.subpixel_bits = d.subpixel_bits;
  p.median = d.median;
  return p;
}

// A textured pair whose right image is the left shifted by a slanted disparity, with noise.
void scene(const kern::StereoParams& p, uint32_t seed, ref::Image8& left, ref::Image8& right) {
  std::mt19937 rng(seed);
  const int w = p.width_px, h = p.height_px, max_d = p.min_disparity + p.disparities - 1;
  left = ref::make_image(w, h);
  right = ref::make_image(w, h);
  const int wide_w = w + max_d + 1;
  std::vector<uint8_t> wide(std::size_t(wide_w) * std::size_t(h));
  for (auto& v : wide) v = uint8_t(rng());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int d = p.min_disparity + (p.disparities - 1) * x / std::max(1, w - 1);
      left.px[std::size_t(y * w + x)] = wide[std::size_t(y * wide_w + x + max_d)];
      right.px[std::size_t(y * w + x)] =
          uint8_t(wide[std::size_t(y * wide_w + std::min(x + d, wide_w - 1))] ^ (rng() % 7 == 0 ? 1u : 0u));
    }
}

// "" when equal, else the first differing (x, y, d) with both values. `fast_at(x, y, d)` reads the
// fast engine's volume in its own layout (padded lanes).
template <class FastAt>
std::string first_difference(const std::vector<uint32_t>& golden, const kern::StereoParams& p, FastAt fast_at) {
  for (int y = 0; y < p.height_px; ++y)
    for (int x = 0; x < p.width_px; ++x)
      for (int d = 0; d < p.disparities; ++d) {
        const uint32_t g = golden[ref::volume_index(x, y, d, p.width_px, p.disparities)];
        const uint32_t f = fast_at(x, y, d);
        if (f != g) {
          std::ostringstream s;
          s << "first difference at x " << x << ", y " << y << ", d " << d << ": fast " << f << ", golden " << g;
          return s.str();
        }
      }
  return "";
}

std::string first_code_difference(const std::vector<uint16_t>& fast, const std::vector<uint16_t>& golden, int w) {
  if (fast.size() != golden.size()) return "sizes differ";
  for (std::size_t i = 0; i < fast.size(); ++i)
    if (fast[i] != golden[i]) {
      std::ostringstream s;
      s << "first difference at x " << int(i) % w << ", y " << int(i) / w << ": fast " << fast[i] << ", golden "
        << golden[i];
      return s.str();
    }
  return "";
}

uint32_t aggregate_at(const fast::AggregateVolume& a, int x, int y, int d) {
  const std::size_t n = a.wide ? a.sum32.size() : a.sum16.size();
  const std::size_t lanes = n / (std::size_t(a.width_px) * std::size_t(a.height_px));
  const std::size_t i = (std::size_t(y) * std::size_t(a.width_px) + std::size_t(x)) * lanes + std::size_t(d);
  return a.wide ? a.sum32[i] : a.sum16[i];
}

TEST(FastStages, EachStageEqualsTheGoldenModelOverTheTable) {
  for (const Design& d : kDesigns) {
    SCOPED_TRACE(d.what);
    const kern::StereoParams p = params(d);
    ref::Image8 l, r;
    scene(p, 7u + uint32_t(d.disparities), l, r);
    fast::Engine e;
    // The cost volume.
    fast::CostVolume cv;
    e.record_costs(l.px.data(), r.px.data(), p, cv);
    const std::vector<uint32_t> cost = ref::cost_volume(l, r, p);
    const std::size_t cost_lanes = cv.cost.size() / (std::size_t(p.width_px) * std::size_t(p.height_px));
    EXPECT_EQ(
        first_difference(
            cost, p,
            [&](int x, int y, int k) {
              return uint32_t(
                  cv.cost[(std::size_t(y) * std::size_t(p.width_px) + std::size_t(x)) * cost_lanes + std::size_t(k)]);
            }),
        "")
        << "cost volume";
    // The path costs of each direction alone (an aggregate of one path is its Lr). MGM's paths
    // step from two predecessors together: its aggregate is compared whole, below.
    if (p.aggregation == kern::kAggregationSgm)
      for (unsigned bit = 1; bit <= kern::kPath315; bit <<= 1) {
        kern::StereoParams one = p;
        one.path_mask = bit;
        // A direction of the second pass runs without adaptive P2: no design has both (the
        // frame buffer does not carry the intensities, kern::kRuleP2AdaptiveOnePass).
        if (kern::two_pass_paths(bit)) one.p2_adaptive = 0;
        fast::AggregateVolume a;
        e.record_aggregate(cv, one, a);
        const std::vector<uint32_t> lr = ref::path_costs(cost, one, bit, &l);
        EXPECT_EQ(first_difference(lr, p, [&](int x, int y, int k) { return aggregate_at(a, x, y, k); }), "")
            << "path costs of direction bit " << bit;
      }
    // The aggregate of the design's paths.
    fast::AggregateVolume agg;
    e.record_aggregate(cv, p, agg);
    const std::vector<uint32_t> sum = ref::aggregate(cost, p, &l);
    EXPECT_EQ(first_difference(sum, p, [&](int x, int y, int k) { return aggregate_at(agg, x, y, k); }), "")
        << "aggregate";
    // The selection (no median), then the median on it.
    kern::StereoParams no_median = p;
    no_median.median = 0;
    const std::vector<uint16_t> selected = ref::select_disparity(sum, no_median);
    EXPECT_EQ(first_code_difference(e.run_from_aggregate(agg, no_median), selected, p.width_px), "") << "selection";
    EXPECT_EQ(first_code_difference(e.run_from_aggregate(agg, p),
                                    ref::median_filter(selected, p.width_px, p.height_px, p.median), p.width_px),
              "")
        << "median";
  }
}

// The comparison finds a single changed value and says where it is.
TEST(FastStages, AComparisonNamesTheFirstDifference) {
  kern::StereoParams p = params(kDesigns[0]);
  std::vector<uint32_t> golden(std::size_t(p.width_px) * std::size_t(p.height_px) * std::size_t(p.disparities), 5u);
  const std::string same = first_difference(golden, p, [](int, int, int) { return 5u; });
  EXPECT_EQ(same, "");
  const std::string diff =
      first_difference(golden, p, [](int x, int y, int d) { return x == 3 && y == 2 && d == 7 ? 6u : 5u; });
  EXPECT_EQ(diff, "first difference at x 3, y 2, d 7: fast 6, golden 5");
}

}  // namespace
}  // namespace parallax::test
