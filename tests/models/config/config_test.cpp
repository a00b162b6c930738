// unit + reject: configuration parsing, validation (every field named) and the paper presets.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "parallax/config/config.hpp"

namespace parallax::config {
namespace {

TEST(Config, PaperPresetsReproduceTheSeedDesign) {
  for (const char* name : {"ruf2018-census", "ruf2018-sad"}) {
    const PipelineConfig c = load_config(std::string(PARALLAX_CONFIG_DIR) + "/" + name + ".yaml");
    EXPECT_EQ(c.name, name);
    EXPECT_FALSE(c.roi_full);
    EXPECT_EQ(c.roi_width_px, 640);
    EXPECT_EQ(c.roi_height_px, 360);
    EXPECT_EQ(c.window_w, 5);
    EXPECT_EQ(c.window_h, 5);
    EXPECT_EQ(c.disparities, 60);
    EXPECT_EQ(c.path_mask, kern::kPath0 | kern::kPath45 | kern::kPath90 | kern::kPath135);
    EXPECT_TRUE(c.lr_check);
    EXPECT_EQ(c.lr_tolerance, 1);
    EXPECT_EQ(c.median, 5);
    EXPECT_EQ(c.disparities % c.parallel_units, 0);
    if (c.cost == "census") {
      EXPECT_EQ(c.p1, 8);
      EXPECT_EQ(c.p2, 32);
    } else {
      EXPECT_EQ(c.cost, "sad");
      EXPECT_EQ(c.p1, 200);
      EXPECT_EQ(c.p2, 800);
    }
  }
}

// The frontier design (issue 18) is a single-pass design: 5 paths with 180 on reversed rows.
TEST(Config, FrontierDesignIsOnePass) {
  const PipelineConfig c = load_config(std::string(PARALLAX_CONFIG_DIR) + "/frontier-census.yaml");
  EXPECT_TRUE(validate(c).empty());
  EXPECT_EQ(c.path_mask, unsigned(kern::kForwardPaths | kern::kPath180));
  EXPECT_TRUE(kern::row_reverse_paths(c.path_mask));
  EXPECT_FALSE(kern::two_pass_paths(c.path_mask));
  EXPECT_EQ(c.name, "frontier-census");
}

TEST(Config, PathCountsAndLists) {
  EXPECT_EQ(parse_paths("1"), unsigned(kern::kPath0));
  EXPECT_EQ(parse_paths("2"), unsigned(kern::kPath0 | kern::kPath90));
  EXPECT_EQ(parse_paths("3"), unsigned(kern::kPath0 | kern::kPath45 | kern::kPath90));
  EXPECT_EQ(parse_paths("4"), kern::kForwardPaths);
  EXPECT_EQ(parse_paths("8"), kern::kAllPaths);
  EXPECT_EQ(parse_paths("[0, 180]"), unsigned(kern::kPath0 | kern::kPath180));
  EXPECT_EQ(parse_paths("90,270"), unsigned(kern::kPath90 | kern::kPath270));
  EXPECT_EQ(parse_paths("5"), unsigned(kern::kForwardPaths | kern::kPath180));  // one pass, rows reversed
  EXPECT_EQ(paths_to_string(kern::kForwardPaths | kern::kPath180), "5");
  EXPECT_THROW(parse_paths("6"), ConfigError);
  EXPECT_THROW(parse_paths("0,30"), ConfigError);
  EXPECT_EQ(paths_to_string(kern::kForwardPaths), "4");
  EXPECT_EQ(paths_to_string(kern::kPath0 | kern::kPath180), "[0,180]");
}

TEST(Config, CanonicalTextRoundTrips) {
  PipelineConfig c;
  c.name = "x";
  c.cost = "sad";
  c.window_w = 7;
  c.window_h = 3;
  c.disparities = 96;
  c.parallel_units = 12;
  c.path_mask = kern::kPath0 | kern::kPath225;
  c.p1 = 11;
  c.p2 = 99;
  c.lr_check = false;
  c.median = 0;
  c.roi_full = true;
  const PipelineConfig d = parse_config(to_yaml(c), "roundtrip");
  EXPECT_EQ(to_yaml(c), to_yaml(d));
  EXPECT_EQ(d.path_mask, c.path_mask);
  EXPECT_TRUE(d.roi_full);
  // Every path set survives the round trip, a single angle included ([0] is an angle, 0 no count).
  for (unsigned mask = 1; mask <= kern::kAllPaths; ++mask) {
    c.path_mask = mask;
    EXPECT_EQ(parse_config(to_yaml(c), "roundtrip").path_mask, mask) << to_yaml(c);
  }
}

TEST(Config, WindowAcceptsSquareShorthand) {
  const PipelineConfig c = parse_config("window: 7\ncost: sad\n", "t");
  EXPECT_EQ(c.window_w, 7);
  EXPECT_EQ(c.window_h, 7);
}

// Each invalid value is reported with its field name; all of them at once.
// A sparse or centre-symmetric census has half the code bits: 9x9 fits in 64 bits, and the kernel
// parameters carry the kind and its cost_max.
TEST(Config, CensusVariantsTakeLargerWindows) {
  for (const char* kind : {"sparse", "symmetric"}) {
    const PipelineConfig c = parse_config(std::string("cost: census\nwindow: 9x9\ncensus: ") + kind, "case.yaml");
    const kern::StereoParams p = c.stereo_params(64, 32);
    EXPECT_EQ(p.census, census_kind(kind));
    EXPECT_EQ(kern::cost_max(p), 40u) << kind;
  }
  EXPECT_EQ(census_kind("full"), kern::kCensusFull);
  EXPECT_EQ(census_kind("half"), -1);
  EXPECT_EQ(parse_config("cost: census\nwindow: 5x5", "case.yaml").stereo_params(8, 8).census, kern::kCensusFull);
}

// p2_adaptive is a structure constant: it reaches the kernels' parameters, not the registers,
// and one-pass path sets (5 included) take it.
TEST(Config, AdaptiveP2IsAStructureConstantOfOnePassDesigns) {
  const PipelineConfig c = parse_config("p2_adaptive: 24\npaths: 5\n", "case.yaml");
  EXPECT_EQ(c.stereo_params(64, 32).p2_adaptive, 24);
  kern::StereoParams p = c.stereo_params(64, 32);
  kern::set_registers(p, kern::StereoRegisters{1, 2, 0, 0});
  EXPECT_EQ(p.p2_adaptive, 24);
  EXPECT_EQ(parse_config(to_yaml(c), "round.yaml").p2_adaptive, 24);
}

// aggregation is a structure constant; mgm takes forward paths and eight, not five.
TEST(Config, MgmAggregationReachesTheKernels) {
  EXPECT_EQ(parse_config("paths: 4\n", "case.yaml").stereo_params(64, 32).aggregation, kern::kAggregationSgm);
  for (const char* paths : {"1", "4", "8", "[0, 45]"}) {
    const PipelineConfig c = parse_config(std::string("aggregation: mgm\npaths: ") + paths + "\n", "case.yaml");
    EXPECT_EQ(c.stereo_params(64, 32).aggregation, kern::kAggregationMgm) << paths;
    EXPECT_EQ(parse_config(to_yaml(c), "round.yaml").aggregation, "mgm") << paths;
  }
}

// min_disparity reaches the kernels' parameters and moves the design's disparity range.
TEST(Config, MinDisparityMovesTheRange) {
  const PipelineConfig c = parse_config("disparities: 64\nmin_disparity: 12\n", "case.yaml");
  EXPECT_EQ(c.min_disparity, 12);
  EXPECT_EQ(c.disparity_end_px(), 76);
  EXPECT_EQ(c.stereo_params(64, 32).min_disparity, 12);
  EXPECT_EQ(parse_config("disparities: 64\n", "case.yaml").stereo_params(64, 32).min_disparity, 0);
  const PipelineConfig back = parse_config(to_yaml(c), "round.yaml");
  EXPECT_EQ(back.min_disparity, 12);
}

TEST(Config, EveryViolationNamesItsField) {
  const struct {
    const char* yaml;
    const char* field;
  } cases[] = {
      {"window: 4x5", "'window'"},
      {"window: 11x3", "'window'"},
      {"cost: census\nwindow: 9x9", "'window'"},  // 80 census bits
      {"disparities: 0", "'disparities'"},
      {"disparities: 257", "'disparities'"},
      {"parallel_units: 7", "'parallel_units'"},
      {"p1: 32\np2: 32", "'p2'"},
      {"p1: -1", "'p1'"},
      {"median: 4", "'median'"},
      {"lr_tolerance: -2", "'lr_tolerance'"},
      {"cost: ncc", "'cost'"},
      {"paths: 6", "'paths'"},
      {"lr_check: maybe", "'lr_check'"},
      {"roi: 0x10", "'roi'"},
      {"disparities: sixty", "'disparities'"},
      {"colour: red", "'colour'"},
      {"clock_mhz: 0", "'clock_mhz'"},
      {"census: half", "'census'"},
      {"uniqueness_pct: 101", "'uniqueness_pct'"},
      {"min_disparity: -1", "'min_disparity'"},
      {"min_disparity: 257", "'min_disparity'"},
      {"p2_adaptive: 256", "'p2_adaptive'"},
      {"p2_adaptive: 20\npaths: 8", "'p2_adaptive'"},  // the frame buffer carries no intensities
      {"aggregation: sgmm", "'aggregation'"},
      {"subpixel_bits: 5", "'subpixel_bits'"},
      {"aggregation: mgm\npaths: 5", "'aggregation'"},  // 180 in one pass: no second predecessor yet
      {"row_packing: 3", "'row_packing' was removed"},  // the row memories' layout is fixed (issue 41)
      {"row_banks: 0", "'row_banks' was removed"},
  };
  for (const auto& c : cases) {
    try {
      parse_config(c.yaml, "case.yaml");
      ADD_FAILURE() << "accepted: " << c.yaml;
    } catch (const ConfigError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(c.field), std::string::npos) << c.yaml << " -> " << msg;
      EXPECT_NE(msg.find("case.yaml"), std::string::npos) << msg;
    }
  }
  try {
    parse_config("window: 4x4\ndisparities: 0\nmedian: 2\n", "many.yaml");
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    for (const char* f : {"'window'", "'disparities'", "'median'"}) EXPECT_NE(msg.find(f), std::string::npos) << msg;
  }
}

// The documentation comes from the same table as parsing: each field once, in field_names()'s
// order, with what it means; exactly the runtime registers are marked, and they are the values
// registers() returns.
TEST(Config, DocumentationListsEveryFieldOnce) {
  std::istringstream doc(field_documentation());
  std::vector<std::string> names, registers;
  for (std::string line; std::getline(doc, line) && line != "rules between fields:";) {
    const std::size_t colon = line.find(": ");
    ASSERT_NE(colon, std::string::npos) << line;
    EXPECT_GT(line.size(), colon + 2) << line;
    std::string name = line.substr(0, colon);
    const std::string mark = " (register)";
    if (name.size() > mark.size() && name.compare(name.size() - mark.size(), mark.size(), mark) == 0) {
      name.resize(name.size() - mark.size());
      registers.push_back(name);
    }
    names.push_back(name);
  }
  EXPECT_EQ(names, field_names());
  EXPECT_EQ(registers, (std::vector<std::string>{"p1", "p2", "lr_tolerance", "uniqueness_pct"}));
  PipelineConfig c;
  c.p1 = 3;
  c.p2 = 17;
  c.lr_tolerance = 2;
  const kern::StereoRegisters r = c.registers();
  EXPECT_EQ(r.p1, 3);
  EXPECT_EQ(r.p2, 17);
  EXPECT_EQ(r.lr_tolerance, 2);
  const kern::StereoParams p = c.stereo_params(8, 8);
  EXPECT_EQ(p.p1, 3);
  EXPECT_EQ(p.p2, 17);
  EXPECT_EQ(p.lr_tolerance, 2);
}

TEST(Config, NotYamlOrNotAMappingIsRejected) {
  EXPECT_THROW(parse_config("[1, 2", "broken.yaml"), ConfigError);
  EXPECT_THROW(parse_config("- a\n- b\n", "list.yaml"), ConfigError);
  EXPECT_THROW(load_config("/nonexistent/x.yaml"), ConfigError);
}

TEST(Config, DerivedWidthsCoverTheWorstCase) {
  PipelineConfig c;
  c.cost = "sad";
  c.window_w = c.window_h = 9;
  c.p1 = 100;
  c.p2 = 60000;
  c.path_mask = kern::kAllPaths;
  ASSERT_TRUE(validate(c).empty());
  const kern::StereoParams p = c.stereo_params(64, 64);
  // cost_max 20655 + P2 register max 65535 = 86190 < 2^17; times 8 paths < 2^20.
  EXPECT_EQ(kern::cost_bits(p), 15);
  EXPECT_EQ(kern::path_bits(p), 17);
  EXPECT_EQ(kern::aggregate_bits(p), 20);
  EXPECT_EQ(kern::disparity_bits(p), 7);  // D = 64 plus the invalid code
}

}  // namespace
}  // namespace parallax::config
