// equiv: the func run's stages against the golden model, per engine (issue 43, item 5): the cost
// volume the kernels' cost stage streams (CensusCostStage / SadCostStage, at the func run's lanes)
// and the fast engine's, reported at the first differing (x, y, d); then, replayed from those
// costs, the selection without the median and the median, over a table of designs; and the
// kernels' path costs of every direction alone and aggregate (the sums their WTA stage reads) in
// each variant of the pipeline (one pass, row reverse, two passes, MGM).
// The later stages of the fast engine are compared stage by stage in tests/models/fast/stage_test.cpp;
// the kernels' whole-frame codes in tests/kernels/equiv_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "parallax/reference/stereo.hpp"
#include "parallax/sim/func.hpp"

namespace parallax::sim {
namespace {

struct Design {
  const char* what;
  int width_px, height_px, disparities, min_disparity, cost, census, window_w, window_h;
};

const Design kDesigns[] = {
    {"census 5x5, D 32", 48, 14, 32, 0, kern::kCostCensus, kern::kCensusFull, 5, 5},
    {"sparse census 9x7, D 40 from m 3", 53, 11, 40, 3, kern::kCostCensus, kern::kCensusSparse, 9, 7},
    {"symmetric census 7x5, D 24 from m 2", 41, 13, 24, 2, kern::kCostCensus, kern::kCensusSymmetric, 7, 5},
    {"SAD 7x7, D 48", 37, 12, 48, 0, kern::kCostSad, kern::kCensusFull, 7, 7},
    {"SAD 3x5, D 96 (two tokens of 48 lanes)", 29, 9, 96, 1, kern::kCostSad, kern::kCensusFull, 3, 5},
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
  p.path_mask = kern::kForwardPaths;
  p.p1 = 8;
  p.p2 = 32;
  p.lr_check = true;
  p.lr_tolerance = 1;
  p.median = 3;
  return p;
}

GreyImage noise(int w, int h, uint32_t seed) {
  std::mt19937 rng(seed);
  GreyImage g{w, h, std::vector<uint8_t>(std::size_t(w) * std::size_t(h))};
  for (auto& v : g.px) v = uint8_t(rng());
  return g;
}

std::string first_difference(const std::vector<uint32_t>& got, const std::vector<uint32_t>& golden,
                             const kern::StereoParams& p) {
  if (got.size() != golden.size()) return "sizes differ";
  for (std::size_t i = 0; i < got.size(); ++i)
    if (got[i] != golden[i]) {
      const std::size_t px = i / std::size_t(p.disparities);
      std::ostringstream s;
      s << "first difference at x " << px % std::size_t(p.width_px) << ", y " << px / std::size_t(p.width_px) << ", d "
        << i % std::size_t(p.disparities) << ": got " << got[i] << ", golden " << golden[i];
      return s.str();
    }
  return "";
}

TEST(FuncStages, CostVolumeOfEachEngineEqualsTheGoldenModel) {
  for (const Design& d : kDesigns) {
    SCOPED_TRACE(d.what);
    const kern::StereoParams p = params(d);
    const GreyImage l = noise(p.width_px, p.height_px, 11), r = noise(p.width_px, p.height_px, 12);
    ref::Image8 rl = ref::make_image(p.width_px, p.height_px), rr = ref::make_image(p.width_px, p.height_px);
    rl.px = l.px;
    rr.px = r.px;
    const std::vector<uint32_t> golden = ref::cost_volume(rl, rr, p);
    for (FuncEngine engine : {FuncEngine::kernels, FuncEngine::fast}) {
      SCOPED_TRACE(to_string(engine));
      FuncPipeline pipe;
      CostRecording rec;
      FuncOptions o;
      o.engine = engine;
      pipe.record_costs(l, r, p, rec, o);
      EXPECT_EQ(first_difference(recorded_cost_volume(rec, p), golden, p), "") << "cost volume";
      // The selection (WTA, LR check) without the median, then the median on the golden selection.
      kern::StereoParams no_median = p;
      no_median.median = 0;
      const std::vector<uint16_t> selected = ref::select_disparity(ref::aggregate(golden, p, &rl), no_median);
      EXPECT_EQ(pipe.run_from_costs(rec, no_median).code, selected) << "selection";
      EXPECT_EQ(pipe.run_from_costs(rec, p).code, ref::median_filter(selected, p.width_px, p.height_px, p.median))
          << "median";
    }
  }
}

// The kernels engine's SGM stages against the golden model: each direction alone (an aggregate of
// one path is its Lr; the backward ones run the two-pass variant, 180 alone the row reversal),
// then the design's paths in every variant of the pipeline, with adaptive P2 and MGM.
TEST(FuncStages, KernelsPathCostsAndAggregateEqualTheGoldenModel) {
  struct Variant {
    const char* what;
    unsigned paths;
    int aggregation, p2_adaptive;
  };
  const Variant kVariants[] = {
      {"one pass", kern::kForwardPaths, kern::kAggregationSgm, 0},
      {"one pass, adaptive P2", kern::kPath0 | kern::kPath90, kern::kAggregationSgm, 16},
      {"row reverse", kern::kForwardPaths | kern::kPath180, kern::kAggregationSgm, 0},
      {"two passes", kern::kAllPaths, kern::kAggregationSgm, 0},
      {"mgm", kern::kForwardPaths, kern::kAggregationMgm, 0},
  };
  for (const Design& d : {kDesigns[0], kDesigns[1], kDesigns[4]}) {
    kern::StereoParams base = params(d);
    const GreyImage l = noise(base.width_px, base.height_px, 21), r = noise(base.width_px, base.height_px, 22);
    ref::Image8 rl = ref::make_image(base.width_px, base.height_px),
                rr = ref::make_image(base.width_px, base.height_px);
    rl.px = l.px;
    rr.px = r.px;
    const std::vector<uint32_t> cost = ref::cost_volume(rl, rr, base);
    FuncPipeline pipe;
    for (unsigned bit = 1; bit <= kern::kPath315; bit <<= 1) {
      SCOPED_TRACE(std::string(d.what) + ", direction bit " + std::to_string(bit));
      kern::StereoParams one = base;
      one.path_mask = bit;
      EXPECT_EQ(first_difference(pipe.kernels_aggregate_volume(l, r, one), ref::path_costs(cost, one, bit), one), "")
          << "path costs";
    }
    for (const Variant& v : kVariants) {
      SCOPED_TRACE(std::string(d.what) + ", " + v.what);
      kern::StereoParams p = base;
      p.path_mask = v.paths;
      p.aggregation = v.aggregation;
      p.p2_adaptive = v.p2_adaptive;
      EXPECT_EQ(first_difference(pipe.kernels_aggregate_volume(l, r, p), ref::aggregate(cost, p, &rl), p), "")
          << "aggregate";
    }
  }
}

}  // namespace
}  // namespace parallax::sim
