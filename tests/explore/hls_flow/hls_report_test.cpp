// unit + reject: reading a Vitis HLS csynth.xml (a sample in the documented schema) and turning
// its loops into the cycle model's calibration.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "parallax/eval/dataset.hpp"
#include "parallax/hls_flow/hls_report.hpp"
#include "parallax/eval/simulate.hpp"
#include "parallax/sim/cycle.hpp"

namespace parallax::test {
namespace {

using namespace parallax::eval;
using namespace parallax::hls_flow;
const std::string kSample = PARALLAX_TEST_DATA "/csynth_sample.xml";

TEST(HlsReport, ReadsTheCsynthSchema) {
  const HlsReport r = read_csynth_xml(kSample);
  EXPECT_EQ(r.part, "xczu3eg-sbva484-1-e");
  EXPECT_EQ(r.top, "parallax_top");
  EXPECT_DOUBLE_EQ(r.target_clock_ns, 5.0);
  EXPECT_DOUBLE_EQ(r.estimated_clock_ns, 3.65);
  EXPECT_EQ(r.worst_latency_cycles, 4631240);
  EXPECT_EQ(r.interval_max_cycles, 4608003);
  ASSERT_EQ(r.loops.size(), 4u);
  EXPECT_EQ(r.loops[1].name, "aggregate_loop");
  EXPECT_EQ(r.loops[1].pipeline_ii, 2);
  EXPECT_EQ(r.loops[3].pipeline_ii, -1);  // not pipelined
  EXPECT_EQ(r.resources.at("BRAM_18K"), 134);
  EXPECT_EQ(r.resources.at("LUT"), 25871);
  EXPECT_EQ(r.available.at("DSP"), 360);
}

TEST(HlsReport, LoopsCalibrateTheCycleModel) {
  config::PipelineConfig cfg = config::load_config(std::string(PARALLAX_CONFIG_DIR) + "/ruf2018-census.yaml");
  const auto set = calibrate_from_hls(cfg, read_csynth_xml(kSample));
  EXPECT_EQ(cfg.stage_ii.at("aggregate"), 2);
  EXPECT_EQ(cfg.stage_latency.at("aggregate"), 9);
  EXPECT_EQ(cfg.stage_latency.at("cost"), 8);
  EXPECT_EQ(cfg.stage_ii.count("init_rows"), 0u);
  EXPECT_EQ(set.size(), 6u);
  // The calibrated configuration round-trips and the cycle model runs with its figures.
  const config::PipelineConfig back = config::parse_config(config::to_yaml(cfg), "calibrated");
  EXPECT_EQ(back.stage_latency.at("aggregate"), 9);
  const sim::CycleOptions o = cycle_options(back, back.clock_mhz);
  EXPECT_EQ(o.timing.at("aggregate").latency_cycles, 9);
}

TEST(HlsReport, NotACsynthReportIsNamed) {
  const auto dir = std::filesystem::temp_directory_path() / "parallax_hls_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "bad.xml") << "<html><body/></html>";
  std::ofstream(dir / "broken.xml") << "<profile><Perf";
  for (const char* f : {"bad.xml", "broken.xml", "missing.xml"}) {
    try {
      read_csynth_xml((dir / f).string());
      FAIL() << f;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace parallax::test

namespace parallax::test {
namespace {

// The models' figures beside the report's: the same design's cycle model and resource model, at
// the report's clock; a loop is matched to its stage by name.
TEST(HlsReport, ComparesModelAndSynthesisSideBySide) {
  const hls_flow::HlsReport r = hls_flow::read_csynth_xml(kSample);
  config::PipelineConfig cfg = config::load_config(PARALLAX_CONFIG_DIR "/ruf2018-census.yaml");
  cfg.clock_mhz = 100;  // the report's 5 ns wins
  sim::CycleReport model_cycle;
  const auto rows = hls_flow::compare_with_model(cfg, r, 640, 360, &model_cycle);
  std::map<std::string, hls_flow::ModelVsSynthesis> by;
  for (const auto& row : rows) by[row.figure] = row;
  ASSERT_TRUE(by.count("latency (cycles)"));
  const eval::SimulationResult sim =
      eval::simulate_timing(config::load_config(PARALLAX_CONFIG_DIR "/ruf2018-census.yaml"), 640, 360);
  EXPECT_EQ(by["latency (cycles)"].model, double(sim.cycle.last_pixel_cycle - sim.cycle.first_input_cycle));
  EXPECT_NE(by["latency (cycles)"].note.find("200 MHz"), std::string::npos);
  EXPECT_EQ(by["latency (cycles)"].synthesis, 4631240.0);
  EXPECT_EQ(by["II aggregate_loop"].synthesis, 2.0);
  EXPECT_EQ(by["II aggregate_loop"].note, "stage aggregate");
  EXPECT_EQ(by.count("II init_rows"), 0u);  // no stage of that name
  EXPECT_EQ(by["BRAM_18K"].synthesis, 134.0);
  EXPECT_EQ(by["BRAM_18K"].model, 78.0);  // one word of PU lanes per chunk in the path-cost rows (issue 41)
  // The report handed back is the one the latency came from.
  EXPECT_EQ(double(model_cycle.last_pixel_cycle - model_cycle.first_input_cycle), by["latency (cycles)"].model);
}

}  // namespace
}  // namespace parallax::test
