// timing: the presets against the published figures (../shared/docs/published-numbers.md), the
// validation set of the cycle model. The figures are expectations here, never inputs of the model.
#include <gtest/gtest.h>

#include <string>

#include "parallax/config/config.hpp"
#include "parallax/eval/simulate.hpp"

namespace parallax::eval {
namespace {

const std::string kConfigs = PARALLAX_CONFIG_DIR;

SimulationResult run(const config::PipelineConfig& cfg, int clock_mhz) {
  cv::Mat l, r;
  test_pattern(cfg.roi_width_px, cfg.roi_height_px, cfg.disparities, 1, l, r);
  SimulateOptions so;
  so.clock_mhz = clock_mhz;
  return simulate(cfg, l, r, so);
}

// Vitis' SemiGlobalBM, 1920x1080, NDISP 64, PU 32, R 4: 42 ms published at 200 MHz.
TEST(PublishedTiming, VitisSgbm1080pAt200MHz) {
  const auto cfg = config::load_config(kConfigs + "/vitis-sgbm-1080p.yaml");
  const SimulationResult r = run(cfg, 200);
  EXPECT_GE(r.latency_ms, 41.5);
  EXPECT_LE(r.latency_ms, 42.5);
  EXPECT_EQ(r.cycle.cycles_per_frame, int64_t(1920) * 1080 * (64 / 32) * 2);  // pixels x D/PU x II
}

// Ruf et al. 2018: 28.5 ms at 200 MHz (uncalibrated model within 10 %); calibrated on that point
// only, 53.2 ms at 100 MHz within 10 %, and about 29 / 20 frames per second.
TEST(PublishedTiming, Ruf2018CensusAt200And100MHz) {
  auto cfg = config::load_config(kConfigs + "/ruf2018-census.yaml");
  const SimulationResult at200 = run(cfg, 200);
  EXPECT_NEAR(at200.latency_ms, 28.5, 2.85);
  calibrate(cfg, at200, 28.5, 29.0);
  const SimulationResult cal200 = run(cfg, 200);
  EXPECT_NEAR(cal200.latency_ms, 28.5, 1e-6);
  EXPECT_NEAR(cal200.fps, 29.0, 1e-6);
  const SimulationResult at100 = run(cfg, 100);
  EXPECT_NEAR(at100.latency_ms, 53.2, 5.32);
  EXPECT_NEAR(at100.fps, 20.0, 2.0);
  // The clock-dependent part doubles exactly when the clock halves.
  EXPECT_NEAR(at100.fpga_last_pixel_ms, 2.0 * cal200.fpga_last_pixel_ms, 1e-9);
}

TEST(PublishedTiming, SadPresetHasTheSameSchedule) {
  const auto census = config::load_config(kConfigs + "/ruf2018-census.yaml");
  const auto sad = config::load_config(kConfigs + "/ruf2018-sad.yaml");
  EXPECT_EQ(run(census, 200).cycle.cycles_per_frame, run(sad, 200).cycle.cycles_per_frame);
}

}  // namespace
}  // namespace parallax::eval
