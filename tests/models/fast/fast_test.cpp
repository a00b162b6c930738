// unit/equiv: the fast engine's interface (levels, errors, replays) and its codes at the sizes
// the equivalence table does not reach (a 256-disparity frame with every late knob on).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "parallax/fast/engine.hpp"
#include "parallax/reference/stereo.hpp"

namespace parallax::test {
namespace {

kern::StereoParams seed_like(int w, int h, int d) {
  kern::StereoParams p{};
  p.width_px = w;
  p.height_px = h;
  p.cost = kern::kCostCensus;
  p.window_w = 5;
  p.window_h = 5;
  p.disparities = d;
  p.parallel_units = 1;
  p.path_mask = kern::kForwardPaths;
  p.p1 = 8;
  p.p2 = 32;
  p.lr_check = true;
  p.lr_tolerance = 1;
  p.median = 5;
  p.uniqueness_pct = 0;
  p.census = kern::kCensusFull;
  return p;
}

// A textured scene whose right image is the left shifted by a slanted disparity (0 .. max_d).
void scene(int w, int h, int max_d, uint32_t seed, ref::Image8& left, ref::Image8& right) {
  std::mt19937 rng(seed);
  left = ref::make_image(w, h);
  right = ref::make_image(w, h);
  std::vector<uint8_t> wide(static_cast<std::size_t>(w + max_d + 1) * static_cast<std::size_t>(h));
  for (auto& v : wide) v = static_cast<uint8_t>(rng());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int d = max_d * x / std::max(1, w - 1);
      left.px[static_cast<std::size_t>(y * w + x)] = wide[static_cast<std::size_t>(y * (w + max_d + 1) + x + max_d)];
      right.px[static_cast<std::size_t>(y * w + x)] =
          wide[static_cast<std::size_t>(y * (w + max_d + 1) + std::min(x + d, w + max_d))];
    }
}

TEST(FastEngine, LevelsIncludeBaselineAndUnknownLevelsAreRefused) {
  const std::vector<std::string> levels = fast::supported_simd_levels();
  ASSERT_FALSE(levels.empty());
  EXPECT_EQ(levels.front(), "baseline");
  const std::string before = fast::simd_level();
  EXPECT_NE(std::find(levels.begin(), levels.end(), before), levels.end());
  EXPECT_THROW(fast::set_simd_level("sse9"), std::invalid_argument);
  EXPECT_EQ(std::string(fast::simd_level()), before);  // unchanged by the refusal
}

TEST(FastEngine, BadParametersAndForeignRecordingsAreErrors) {
  kern::StereoParams p = seed_like(16, 8, 16);
  std::vector<uint8_t> img(16 * 8, 7);
  fast::Engine e;
  kern::StereoParams bad = p;
  bad.p1 = bad.p2;
  EXPECT_FALSE(fast::param_errors(bad).empty());
  EXPECT_THROW(e.run(img.data(), img.data(), bad), std::invalid_argument);
  fast::CostVolume costs;
  e.record_costs(img.data(), img.data(), p, costs);
  kern::StereoParams other = p;
  other.disparities = 32;
  EXPECT_THROW(e.run_from_costs(costs, other), std::invalid_argument);
  fast::AggregateVolume agg;
  e.record_aggregate(costs, p, agg);
  kern::StereoParams penalties = p;
  penalties.p2 = 40;
  EXPECT_EQ(fast::cost_key(penalties), fast::cost_key(p));
  EXPECT_NE(fast::aggregate_key(penalties), fast::aggregate_key(p));
  EXPECT_THROW(e.run_from_aggregate(agg, penalties), std::invalid_argument);
}

// D = 256 over a frame wide enough for every disparity, with sub-pixel codes, uniqueness, the
// LR check and the median, in both passes' layouts; replays from costs and aggregates too.
TEST(FastEngine, TwoHundredFiftySixDisparitiesAgainstTheGoldenModel) {
  ref::Image8 l, r;
  scene(300, 24, 200, 41, l, r);
  for (unsigned paths : {unsigned(kern::kForwardPaths | kern::kPath180), unsigned(kern::kAllPaths)}) {
    kern::StereoParams p = seed_like(300, 24, 256);
    p.path_mask = paths;
    p.subpixel_bits = 2;
    p.uniqueness_pct = 5;
    const std::vector<uint16_t> g = ref::compute_disparity(l, r, p);
    for (const std::string& level : fast::supported_simd_levels()) {
      fast::set_simd_level(level);
      fast::Engine e;
      EXPECT_EQ(e.run(l.px.data(), r.px.data(), p), g) << level << " paths " << paths;
      fast::CostVolume costs;
      e.record_costs(l.px.data(), r.px.data(), p, costs);
      EXPECT_EQ(e.run_from_costs(costs, p), g) << level;
      fast::AggregateVolume agg;
      e.record_aggregate(costs, p, agg);
      EXPECT_EQ(e.run_from_aggregate(agg, p), g) << level;
      kern::StereoParams later = p;  // the stages after the aggregate differ
      later.median = 3;
      later.subpixel_bits = 0;
      later.lr_tolerance = 2;
      EXPECT_EQ(e.run_from_aggregate(agg, later), ref::compute_disparity(l, r, later)) << level;
      kern::StereoParams median_only = later;  // the codes before the median are kept: the median alone
      median_only.median = 7;
      EXPECT_EQ(agg.selected_key, fast::selection_key(later));
      EXPECT_EQ(e.run_from_aggregate(agg, median_only), ref::compute_disparity(l, r, median_only)) << level;
      median_only.median = 0;
      EXPECT_EQ(e.run_from_aggregate(agg, median_only), ref::compute_disparity(l, r, median_only)) << level;
    }
    fast::set_simd_level(fast::supported_simd_levels().back());
  }
}

// 32-bit sums (SAD 9x9 with a large P2 over eight paths) and 16-bit sums without padding lanes
// (a P2 near the limit) against the golden model.
TEST(FastEngine, WideAndUnpaddedSumsAgainstTheGoldenModel) {
  ref::Image8 l, r;
  scene(70, 15, 20, 42, l, r);
  kern::StereoParams sad = seed_like(70, 15, 60);
  sad.cost = kern::kCostSad;
  sad.window_w = 9;
  sad.window_h = 9;
  sad.p1 = 300;
  sad.p2 = 9000;
  sad.path_mask = kern::kAllPaths;
  kern::StereoParams near = seed_like(70, 15, 60);
  near.p1 = 100;
  near.p2 = 16000;
  for (const kern::StereoParams& p : {sad, near}) {
    fast::Engine e;
    EXPECT_EQ(e.run(l.px.data(), r.px.data(), p), ref::compute_disparity(l, r, p)) << "cost " << p.cost;
  }
}

// One engine through designs that change every buffer's size and contents (width, height, D,
// Census and SAD, 16- and 32-bit sums, path sets, penalties, the median), at every level: each
// frame's codes are the golden model's whatever ran before. The engine keeps its buffers from
// frame to frame and may rely on nothing it did not write in the frame at hand.
TEST(FastEngine, OneEngineThroughChangingDesignsAtEveryLevel) {
  struct Step {
    int w, h, d, cost, window;
    unsigned paths;
    int p1, p2, median;
  };
  const Step steps[] = {
      {70, 15, 60, kern::kCostCensus, 5, kern::kForwardPaths, 8, 32, 5},
      {40, 12, 32, kern::kCostCensus, 5, kern::kPath0 | kern::kPath90, 4, 24, 3},
      {70, 15, 60, kern::kCostSad, 9, kern::kAllPaths, 300, 9000, 0},  // 32-bit sums
      {53, 9, 16, kern::kCostCensus, 3, kern::kPath0 | kern::kPath45 | kern::kPath90, 12, 64, 5},
      {70, 15, 48, kern::kCostSad, 7, kern::kForwardPaths | kern::kPath180, 100, 2000, 3},
      {70, 15, 60, kern::kCostCensus, 5, kern::kForwardPaths, 8, 32, 5},  // the first again
  };
  const std::string before = fast::simd_level();
  for (const std::string& level : fast::supported_simd_levels()) {
    fast::set_simd_level(level);
    fast::Engine e;
    int k = 0;
    for (const Step& st : steps) {
      ref::Image8 l, r;
      scene(st.w, st.h, st.d / 2, uint32_t(50 + k), l, r);
      kern::StereoParams p = seed_like(st.w, st.h, st.d);
      p.cost = st.cost;
      p.window_w = p.window_h = st.window;
      p.path_mask = st.paths;
      p.p1 = st.p1;
      p.p2 = st.p2;
      p.median = st.median;
      ASSERT_TRUE(fast::param_errors(p).empty()) << "step " << k;
      EXPECT_EQ(e.run(l.px.data(), r.px.data(), p), ref::compute_disparity(l, r, p)) << level << " step " << k;
      ++k;
    }
  }
  fast::set_simd_level(before);
}

}  // namespace
}  // namespace parallax::test
