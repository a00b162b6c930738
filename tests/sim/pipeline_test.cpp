// unit: the pipeline table (kernels/pipeline.hpp) is the graph the cycle model builds, for each
// variant (one pass, one pass with the 180-degree path on reversed rows, two passes, rectifying): the same stages, and
// the same FIFOs with the same producer and consumer; token widths follow the design.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "parallax/kernels/pipeline.hpp"
#include "parallax/sim/cycle.hpp"

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

}  // namespace
}  // namespace parallax::sim
