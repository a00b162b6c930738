// unit: the pipeline table (kernels/pipeline.hpp) is the graph the cycle model builds, for each
// variant (one pass, one pass with the 180-degree path on reversed rows, two passes, rectifying): the same stages, and
// the same FIFOs with the same producer and consumer; token widths follow the design. Every
// consumer of the description (the cycle engine, the schedule, the resource inventory) configures
// the SGM and WTA kernels with the setup the description derives (issue 43).
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "parallax/config/config.hpp"
#include "parallax/kernels/pipeline.hpp"
#include "parallax/resources/model.hpp"
#include "parallax/sim/cycle.hpp"
#include "parallax/sim/schedule.hpp"

namespace parallax::sim {
namespace {

using Edge = std::tuple<std::string, std::string, std::string>;  // name, producer, consumer

kern::StereoParams design(unsigned paths) {
  kern::StereoParams p{32, 8, kern::kCostCensus, 5, 5, 16, 4, paths, 8, 32, true, 1, 3, 0, 0};
  return p;
}

void expect_graph_is_the_table(const CycleReport& r, const kern::StereoParams& p, bool rectify) {
  ASSERT_FALSE(r.deadlock) << r.deadlock_message;
  const unsigned conditions = kern::pipeline_conditions(p, rectify);
  std::set<std::string> table_stages, graph_stages;
  for (const kern::PipelineStage& s : kern::kPipelineStages)
    if (kern::pipeline_has(s.when, conditions)) table_stages.insert(s.name);
  for (const StageReport& s : r.stages) graph_stages.insert(s.name);
  EXPECT_EQ(graph_stages, table_stages);
  std::set<Edge> table_fifos, graph_fifos;
  for (const kern::PipelineFifo& f : kern::kPipelineFifos)
    if (kern::pipeline_has(f.when, conditions)) table_fifos.insert({f.name, f.producer, f.consumer});
  for (const FifoReport& f : r.fifos) graph_fifos.insert({f.name, f.producer, f.consumer});
  EXPECT_EQ(graph_fifos, table_fifos);
}

GreyImage blank(int w, int h) {
  return GreyImage{w, h, std::vector<uint8_t>(std::size_t(w) * h, 77)};
}

TEST(PipelineTable, OnePassAndTwoPassGraphs) {
  for (unsigned paths :
       {unsigned(kern::kForwardPaths), unsigned(kern::kAllPaths), unsigned(kern::kForwardPaths | kern::kPath180)}) {
    const kern::StereoParams p = design(paths);
    const CycleReport r = run_timing(blank(p.width_px, p.height_px), blank(p.width_px, p.height_px), p, CycleOptions{});
    expect_graph_is_the_table(r, p, false);
  }
}

TEST(PipelineTable, RectifyingGraph) {
  const kern::StereoParams p = design(kern::kForwardPaths);
  std::vector<kern::MapEntry> identity;
  for (int y = 0; y < p.height_px; ++y)
    for (int x = 0; x < p.width_px; ++x) identity.push_back({x, y});
  CycleOptions o;
  o.rectify = kern::RectifyParams{p.width_px, p.height_px, kern::kRectifyNearest, 0, 4};
  o.rectify_map_left = &identity;
  o.rectify_map_right = &identity;
  const CycleReport r = run_cycle(blank(p.width_px, p.height_px), blank(p.width_px, p.height_px), p, o);
  expect_graph_is_the_table(r, p, true);
}

TEST(PipelineTable, EveryFifoJoinsTwoStagesOfItsVariantAndTokensHaveTheDesignsWidths) {
  for (unsigned rectify : {unsigned(kern::kWhenNoRectify), unsigned(kern::kWhenRectify)})
    for (unsigned passes : {kern::kWhenOnePass | kern::kWhenNoRowReverse, kern::kWhenTwoPass | kern::kWhenNoRowReverse,
                            kern::kWhenOnePass | kern::kWhenRowReverse}) {
      const unsigned conditions = rectify | passes;
      std::set<std::string> stages, names;
      for (const kern::PipelineStage& s : kern::kPipelineStages)
        if (kern::pipeline_has(s.when, conditions)) stages.insert(s.name);
      for (const kern::PipelineFifo& f : kern::kPipelineFifos) {
        if (!kern::pipeline_has(f.when, conditions)) continue;
        EXPECT_TRUE(stages.count(f.producer)) << f.name << " from " << f.producer;
        EXPECT_TRUE(stages.count(f.consumer)) << f.name << " to " << f.consumer;
        EXPECT_TRUE(names.insert(f.name).second) << f.name << " twice in one variant";
      }
    }
  const kern::StereoParams p = design(kern::kForwardPaths);  // census 5x5: 5-bit costs, PU 4
  EXPECT_EQ(kern::token_bits(kern::kTokenCost, p), 4 * 5);
  EXPECT_EQ(kern::token_bits(kern::kTokenCode, p), 5);  // codes 0..16
  EXPECT_EQ(kern::token_bits(kern::kTokenPixel, p), 8);
}

// The setups the description derives, written out by hand from the FIFO table for each variant.
TEST(PipelineSetup, DerivedFromTheWiring) {
  using kern::stage_setup;
  using kern::StageSetup;
  const unsigned fwd = kern::kForwardPaths, all = kern::kAllPaths, rr = fwd | kern::kPath180;
  // One pass: no tee, no forward input, raster order.
  EXPECT_EQ(stage_setup("aggregate", fwd), (StageSetup{0xFu, false, false, false}));
  EXPECT_EQ(stage_setup("wta_lr", fwd), (StageSetup{0u, false, false, false}));
  EXPECT_EQ(stage_setup("aggregate_back", fwd), (StageSetup{0u, false, false, false}));  // not in the variant
  // Two passes: the forward pass tees its costs to DDR; the backward one adds F on the reversed stream.
  EXPECT_EQ(stage_setup("aggregate", all), (StageSetup{0xFu, false, true, false}));
  EXPECT_EQ(stage_setup("aggregate_back", all), (StageSetup{0xFu, true, false, false}));
  EXPECT_EQ(stage_setup("wta_lr", all), (StageSetup{0u, false, false, true}));
  // The 180-degree path on reversed rows: the row stage aggregates one kind (the pixel's).
  EXPECT_EQ(stage_setup("aggregate", rr), (StageSetup{0xFu, false, true, false}));
  EXPECT_EQ(stage_setup("aggregate_row", rr), (StageSetup{1u << kern::kKindPixel, true, false, false}));
  EXPECT_EQ(stage_setup("wta_lr", rr), (StageSetup{0u, false, false, true}));
  // Only some forward paths: the kinds follow the mask.
  EXPECT_EQ(stage_setup("aggregate", kern::kPath0 | kern::kPath90).sgm_kinds,
            (1u << kern::kKindPixel) | (1u << kern::kKindRowUp));
  // Folded at compile time, as the export uses it.
  constexpr StageSetup folded = stage_setup("aggregate_back", kern::kAllPaths);
  static_assert(folded.add_forward && folded.sgm_kinds == 0xFu && !folded.tee_cost, "aggregate_back's setup");
  static_assert(stage_setup("wta_lr", kern::kAllPaths).reverse, "two passes: WTA on the reversed stream");
}

// Each consumer records what it configured the SGM and WTA kernels with; all equal the description,
// for one pass, row reverse, two passes and MGM.
TEST(PipelineSetup, EveryConsumerConfiguresTheKernelsAsDescribed) {
  struct Variant {
    const char* what;
    unsigned paths;
    int aggregation;
  };
  for (const Variant v : {Variant{"one pass", kern::kForwardPaths, kern::kAggregationSgm},
                          Variant{"row reverse", kern::kForwardPaths | kern::kPath180, kern::kAggregationSgm},
                          Variant{"two passes", kern::kAllPaths, kern::kAggregationSgm},
                          Variant{"mgm", kern::kForwardPaths, kern::kAggregationMgm}}) {
    SCOPED_TRACE(v.what);
    kern::StereoParams p = design(v.paths);
    p.aggregation = v.aggregation;
    std::map<std::string, kern::StageSetup> described;
    auto visit = [&](const kern::PipelineStage& st, const kern::StageSetup& s) {
      const std::string name = st.name;
      if (name == "wta_lr" || name.rfind("aggregate", 0) == 0) described[name] = s;
    };
    kern::for_each_stage(p.path_mask, false, visit);
    auto as_map = [](const std::vector<std::pair<std::string, kern::StageSetup>>& recorded) {
      std::map<std::string, kern::StageSetup> m;
      for (const auto& [name, s] : recorded) m[name] = s;
      return m;
    };
    // The cycle engine.
    const CycleReport r = run_timing(blank(p.width_px, p.height_px), blank(p.width_px, p.height_px), p, CycleOptions{});
    ASSERT_FALSE(r.deadlock) << r.deadlock_message;
    EXPECT_EQ(as_map(r.stage_setups), described) << "cycle engine";
    // The schedule.
    std::map<std::string, kern::StageSetup> scheduled;
    for (const StageSchedule& s : stage_schedules(p, kern::RectifyParams{}, 200e6))
      if (s.stage == "wta_lr" || s.stage.rfind("aggregate", 0) == 0) scheduled[s.stage] = s.setup;
    EXPECT_EQ(scheduled, described) << "schedule";
    // The resource inventory.
    config::PipelineConfig cfg;
    cfg.path_mask = p.path_mask;
    cfg.aggregation = v.aggregation == kern::kAggregationMgm ? "mgm" : "sgm";
    cfg.disparities = p.disparities;
    cfg.parallel_units = p.parallel_units;
    EXPECT_EQ(as_map(res::design_inventory(cfg, p.width_px, p.height_px).setups), described) << "resource inventory";
  }
}

}  // namespace
}  // namespace parallax::sim
