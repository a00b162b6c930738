// Which stage reads which knob (kernels/param_table.hpp), and what is derived from it: the
// sharing keys of both engines and the sweep, the configuration's readers and register marks,
// and the one parameter check of validate(), the fast engine and the func run.
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "parallax/config/config.hpp"
#include "parallax/fast/engine.hpp"
#include "parallax/kernels/param_table.hpp"
#include "parallax/sim/func.hpp"

namespace parallax {
namespace {

// 18 ints, the path mask and lr_check (padded to 4 bytes): a field added to StereoParams must be
// added to kern::for_each_param and to the changes below.
static_assert(sizeof(kern::StereoParams) == 4 * kern::kParamFieldCount, "a StereoParams field not in the table");

kern::StereoParams census_design() {
  kern::StereoParams p{64, 32, kern::kCostCensus, 5, 5, 32, 4, kern::kForwardPaths, 8, 96, true, 1, 5, 10, 0};
  return p;
}

// One valid change per field of the table, by its name.
const std::map<std::string, std::function<void(kern::StereoParams&)>>& changes() {
  static const std::map<std::string, std::function<void(kern::StereoParams&)>> c = {
      {"width_px", [](kern::StereoParams& p) { p.width_px = 48; }},
      {"height_px", [](kern::StereoParams& p) { p.height_px = 24; }},
      {"cost", [](kern::StereoParams& p) { p.cost = kern::kCostSad; }},
      {"window_w", [](kern::StereoParams& p) { p.window_w = 7; }},
      {"window_h", [](kern::StereoParams& p) { p.window_h = 3; }},
      {"disparities", [](kern::StereoParams& p) { p.disparities = 48; }},
      {"parallel_units", [](kern::StereoParams& p) { p.parallel_units = 8; }},
      {"path_mask", [](kern::StereoParams& p) { p.path_mask = kern::kPath0 | kern::kPath90; }},
      {"p1", [](kern::StereoParams& p) { p.p1 = 9; }},
      {"p2", [](kern::StereoParams& p) { p.p2 = 90; }},
      {"lr_check", [](kern::StereoParams& p) { p.lr_check = false; }},
      {"lr_tolerance", [](kern::StereoParams& p) { p.lr_tolerance = 2; }},
      {"median", [](kern::StereoParams& p) { p.median = 3; }},
      {"uniqueness_pct", [](kern::StereoParams& p) { p.uniqueness_pct = 15; }},
      {"census", [](kern::StereoParams& p) { p.census = kern::kCensusSparse; }},
      {"min_disparity", [](kern::StereoParams& p) { p.min_disparity = 4; }},
      {"p2_adaptive", [](kern::StereoParams& p) { p.p2_adaptive = 8; }},
      {"aggregation", [](kern::StereoParams& p) { p.aggregation = kern::kAggregationMgm; }},
      {"subpixel_bits", [](kern::StereoParams& p) { p.subpixel_bits = 2; }},
  };
  return c;
}

struct Keys {
  std::string cost, aggregate, selection, kernels_cost, sweep_selection;
};
Keys keys_of(const kern::StereoParams& p) {
  return {fast::cost_key(p), fast::aggregate_key(p), fast::selection_key(p),
          sim::cost_sharing_key(p, sim::FuncEngine::kernels), sim::selection_sharing_key(p, sim::FuncEngine::fast)};
}

TEST(ParamTable, EveryFieldOnceWithLimitsThatHoldForTheSeedDesign) {
  std::set<std::string> names;
  int fields = 0;
  kern::for_each_param(census_design(), [&](const kern::ParamField& f) {
    ++fields;
    EXPECT_TRUE(names.insert(f.name).second) << f.name;
    EXPECT_LE(f.lo, f.hi) << f.name;
    EXPECT_TRUE(f.value >= f.lo && f.value <= f.hi) << f.name;
    EXPECT_NE(f.readers, 0u) << f.name << " is read by no stage of a census design";
  });
  EXPECT_EQ(fields, kern::kParamFieldCount);
  EXPECT_EQ(names.size(), changes().size());
  for (const auto& c : changes()) EXPECT_EQ(names.count(c.first), 1u) << c.first;
}

// Change each field in turn: exactly the keys of the stage that reads it and of every stage after
// it change (the fast engine's three, the kernels' cost key and the sweep's ordering key).
TEST(SharingKeys, EachFieldChangesExactlyTheKeysOfItsReadersAndTheirSuccessors) {
  const kern::StereoParams base = census_design();
  ASSERT_TRUE(fast::param_errors(base).empty());
  const Keys k0 = keys_of(base);
  kern::for_each_param(base, [&](const kern::ParamField& f) {
    kern::StereoParams q = base;
    changes().at(f.name)(q);
    ASSERT_TRUE(fast::param_errors(q).empty()) << f.name << ": " << fast::param_errors(q).front();
    const Keys k = keys_of(q);
    const bool cost = (f.readers & kern::kReadByCost) != 0;
    const bool aggregate = cost || (f.readers & kern::kReadByAggregate) != 0;
    const bool selection = aggregate || (f.readers & kern::kReadBySelect) != 0;
    EXPECT_EQ(k.cost != k0.cost, cost) << f.name;
    EXPECT_EQ(k.kernels_cost != k0.kernels_cost, cost) << f.name;
    EXPECT_EQ(k.aggregate != k0.aggregate, aggregate) << f.name;
    EXPECT_EQ(k.selection != k0.selection, selection) << f.name;
    EXPECT_EQ(k.sweep_selection != k0.sweep_selection, selection) << f.name;
  });
}

// A field no stage of the design reads changes no key: the census kind of a SAD design.
TEST(SharingKeys, AFieldTheDesignDoesNotReadChangesNoKey) {
  kern::StereoParams sad = census_design();
  sad.cost = kern::kCostSad;
  kern::StereoParams other = sad;
  other.census = kern::kCensusSymmetric;
  EXPECT_EQ(fast::selection_key(sad), fast::selection_key(other));
  EXPECT_EQ(sim::cost_sharing_key(sad, sim::FuncEngine::kernels),
            sim::cost_sharing_key(other, sim::FuncEngine::kernels));
}

// The configuration's rows say who reads them, from the same table; registers are its registers.
TEST(ConfigReaders, RowsTakeTheirReadersAndRegisterMarksFromTheKernelsTable) {
  std::map<std::string, std::string> read_by;
  std::istringstream doc(config::field_documentation());
  for (std::string line; std::getline(doc, line) && line != "rules between fields:";) {
    const auto at = line.rfind("; read by ");
    ASSERT_NE(at, std::string::npos) << line;
    read_by[line.substr(0, line.find_first_of(" :"))] = line.substr(at + 10);
  }
  EXPECT_EQ(read_by.at("roi"), "cost, aggregate, select, median");
  EXPECT_EQ(read_by.at("window"), "cost");
  EXPECT_EQ(read_by.at("paths"), "aggregate");
  EXPECT_EQ(read_by.at("p1"), "aggregate");
  EXPECT_EQ(read_by.at("uniqueness_pct"), "select");
  EXPECT_EQ(read_by.at("median"), "median");
  EXPECT_EQ(read_by.at("parallel_units"), "system");
  EXPECT_EQ(read_by.at("clock_mhz"), "system");
}

// One check: a design validate() accepts is one every engine runs, over seeded random designs
// around the shipped defaults; and each of the kernels' rules, broken alone, is refused by all.
TEST(ParamCheck, ValidateAcceptsOnlyWhatTheEnginesRun) {
  std::mt19937 rng(43);
  // Each field from values on both sides of its limits, mostly inside.
  auto pick = [&](std::vector<const char*> v) { return std::string(v[rng() % v.size()]); };
  auto any = [&](std::vector<int> v) { return v[rng() % v.size()]; };
  int accepted = 0;
  for (int i = 0; i < 20000; ++i) {
    config::PipelineConfig c;
    c.roi_width_px = 64;
    c.roi_height_px = 32;
    c.cost = pick({"census", "sad"});
    c.census = pick({"full", "sparse", "symmetric"});
    c.window_w = any({1, 3, 5, 5, 7, 9, 4, 11});
    c.window_h = any({1, 3, 5, 5, 7, 9, 6});
    c.disparities = any({16, 32, 64, 64, 256, 0, 257});
    c.parallel_units = any({1, 2, 4, 8, 0, 7});
    c.path_mask = unsigned(any({1, 5, 15, 15, 31, 255, 0, 256}));
    c.p1 = any({0, 8, 10, 200, -1});
    c.p2 = any({96, 150, 65535, 0, 65536});
    c.p2_adaptive = any({0, 0, 8, 255, 256});
    c.aggregation = pick({"sgm", "sgm", "mgm"});
    c.subpixel_bits = any({0, 0, 2, 4, 5, -1});
    c.uniqueness_pct = any({0, 10, 100, 101, -1});
    c.lr_tolerance = any({0, 1, 255, 256, -1});
    c.median = any({0, 3, 5, 7, 1, 4});
    c.min_disparity = any({0, 0, 8, 256, 257, -1});
    const bool valid = config::validate(c).empty();
    const auto errors = sim::func_param_errors(c.stereo_params(64, 32));
    if (valid) {
      ++accepted;
      EXPECT_TRUE(errors.empty()) << "validate() accepted design " << i
                                  << " that the engines refuse: " << errors.front();
    }
  }
  EXPECT_GT(accepted, 50);  // the property is tested on accepted designs, not vacuously
}

TEST(ParamCheck, EachKernelRuleBrokenAloneIsRefusedEverywhere) {
  const std::map<int, std::function<void(config::PipelineConfig&)>> breaks = {
      {kern::kRuleWindowOdd, [](config::PipelineConfig& c) { c.window_w = 4; }},
      {kern::kRuleCensusBits, [](config::PipelineConfig& c) { c.window_w = c.window_h = 9; }},
      {kern::kRulePathsKnown, [](config::PipelineConfig& c) { c.path_mask = 0; }},
      {kern::kRuleP1BelowP2, [](config::PipelineConfig& c) { c.p1 = c.p2; }},
      {kern::kRuleMedianSize, [](config::PipelineConfig& c) { c.median = 4; }},
      {kern::kRuleUnitsDivide, [](config::PipelineConfig& c) { c.parallel_units = 7; }},
      {kern::kRuleP2AdaptiveOnePass,
       [](config::PipelineConfig& c) {
         c.p2_adaptive = 4;
         c.path_mask = kern::kAllPaths;
       }},
      {kern::kRuleMgmPaths,
       [](config::PipelineConfig& c) {
         c.aggregation = "mgm";
         c.path_mask = kern::kForwardPaths | kern::kPath180;
       }},
  };
  // The aggregate's width cannot be broken by fields in range (8 paths x (SAD 9x9 + P2 65535)
  // fits 20 bits): the rule guards the kernels against parameters built outside the table.
  ASSERT_EQ(int(breaks.size()), int(kern::kParamRuleCount) - 1);
  kern::StereoParams widest{64, 32, kern::kCostSad, 9, 9, 256, 1, kern::kAllPaths, 0, 65535, true, 0, 0, 0, 0};
  EXPECT_TRUE(fast::param_errors(widest).empty());
  widest.p2 = 1 << 30;
  EXPECT_FALSE(kern::rule_holds(widest, kern::kRuleAggregateWidth));
  for (const auto& b : breaks) {
    config::PipelineConfig c;
    c.roi_width_px = 64;
    c.roi_height_px = 32;
    ASSERT_TRUE(config::validate(c).empty());
    b.second(c);
    const kern::StereoParams p = c.stereo_params(64, 32);
    EXPECT_FALSE(kern::rule_holds(p, b.first)) << kern::kParamRules[b.first].name;
    EXPECT_FALSE(config::validate(c).empty()) << kern::kParamRules[b.first].name;
    EXPECT_FALSE(fast::param_errors(p).empty()) << kern::kParamRules[b.first].name;
  }
}

}  // namespace
}  // namespace parallax
