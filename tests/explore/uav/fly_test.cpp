// unit: a closed-loop flight past a single pole reaches the goal without a collision; the
// stopping-distance bound; the design's timing feeds the loop.
#include <gtest/gtest.h>

#include "parallax/config/config.hpp"
#include "parallax/uav/fly.hpp"

namespace parallax::test {
namespace {

using namespace parallax::uav;

TEST(Fly, PastASinglePoleToTheGoal) {
  const config::PipelineConfig cfg = config::load_config(std::string(PARALLAX_CONFIG_DIR) + "/ruf2018-census.yaml");
  const Scenario sc = load_scenario(std::string(PARALLAX_CONFIG_DIR) + "/scenarios/single-pole.yaml");
  Scene scene = generate_scene(sc, 1);
  scene.cylinders[0].x_m = 0.0;  // dead ahead
  FlightParams fp;
  fp.width_px = 160;
  fp.speed_mps = 4.0;
  const FlightResult r = fly(cfg, sc, scene, fp);
  EXPECT_TRUE(r.reached_goal);
  EXPECT_FALSE(r.collided);
  EXPECT_GT(r.min_clearance_m, 0.0);
  EXPECT_GT(r.path_length_m / scene.goal_z_m, 1.0);  // it went around
  EXPECT_LT(r.path_length_m / scene.goal_z_m, 1.3);
  EXPECT_GT(r.frames, 100);
  // Straight through, the same pole is hit: the scene and the clearance check can fail a flight.
  double straight_clear = 1e9;
  for (double z = 0; z < scene.goal_z_m; z += 0.05)
    straight_clear = std::min(straight_clear, clearance_m(scene, Eigen::Vector3d(0, -1.6, z)) - fp.vehicle.radius_m);
  EXPECT_LT(straight_clear, 0.0);
}

// A flight is a function of the configuration, the scene and the seed: the avoidance stage's
// time is the configuration's model (avoid_ms), not the host's clock, so two runs agree exactly,
// and a slower stage changes the flight.
TEST(Fly, RepeatableWithTheModelledAvoidanceTime) {
  config::PipelineConfig cfg = config::load_config(std::string(PARALLAX_CONFIG_DIR) + "/ruf2018-census.yaml");
  EXPECT_EQ(cfg.avoid_ms, 4.2);
  const Scenario sc = load_scenario("forest");
  const Scene scene = generate_scene(sc, 2);
  FlightParams fp;
  fp.width_px = 160;
  fp.time_limit_s = 4.0;
  const FlightResult a = fly(cfg, sc, scene, fp, 2), b = fly(cfg, sc, scene, fp, 2);
  ASSERT_EQ(a.trajectory.size(), b.trajectory.size());
  for (std::size_t i = 0; i < a.trajectory.size(); ++i) EXPECT_EQ(a.trajectory[i], b.trajectory[i]) << i;
  EXPECT_EQ(a.path_length_m, b.path_length_m);
  cfg.avoid_ms = 200.0;
  const FlightResult slow = fly(cfg, sc, scene, fp, 2);
  bool differs = slow.trajectory.size() != a.trajectory.size();
  for (std::size_t i = 0; !differs && i < a.trajectory.size(); ++i) differs = slow.trajectory[i] != a.trajectory[i];
  EXPECT_TRUE(differs);
}

// Wilson 95 % intervals against values computed by hand: 20 of 20 gives [83.9, 100], 0 of 20
// [0, 16.1], 95 of 100 [88.8, 97.8]; they contain the rate and shrink with more trials.
TEST(Fly, WilsonIntervals) {
  auto near = [](std::pair<double, double> ci, double lo, double hi) {
    EXPECT_NEAR(ci.first, lo, 0.05);
    EXPECT_NEAR(ci.second, hi, 0.05);
  };
  near(wilson_interval_pct(20, 20), 83.89, 100.0);
  near(wilson_interval_pct(0, 20), 0.0, 16.11);
  near(wilson_interval_pct(95, 100), 88.82, 97.85);
  const auto few = wilson_interval_pct(9, 10), many = wilson_interval_pct(90, 100);
  EXPECT_LT(many.second - many.first, few.second - few.first);
  EXPECT_LE(few.first, 90.0);
  EXPECT_GE(few.second, 90.0);
  near(wilson_interval_pct(0, 0), 0.0, 100.0);
}

TEST(Fly, StoppingDistanceBoundAndDesignTiming) {
  EXPECT_NEAR(stopping_distance_speed_bound(4.0, 0.1, 12.0), 4.0 * (std::sqrt(0.01 + 6.0) - 0.1), 1e-12);
  EXPECT_NEAR(stopping_distance_speed_bound(4.0, 0.0, 12.0), std::sqrt(2.0 * 4.0 * 12.0), 1e-12);  // v^2 = 2 a d
  config::PipelineConfig cfg = config::load_config(std::string(PARALLAX_CONFIG_DIR) + "/ruf2018-census.yaml");
  double interval = 0, latency = 0;
  design_timing(cfg, 640, 360, interval, latency);
  EXPECT_NEAR(latency, 26.61, 0.05);  // the uncalibrated preset at 200 MHz (docs/simulator.md)
  EXPECT_GT(interval, 0.0);
}

}  // namespace
}  // namespace parallax::test
