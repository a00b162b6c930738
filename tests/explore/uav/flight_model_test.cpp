// unit: the pieces of a faithful flight: the vehicle's PX4-like velocity loop (its limits hold,
// the body pitches with acceleration and drag), the renderer at a yaw and pitch (exact disparity
// of the tilted ground, a pole brought to the centre by yawing), anti-aliasing and the sensor
// model, the scenario's rig and the design's own window, and the planner's map and choices
// (memory of what left the view, unseen directions, no flips between equal sides).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "parallax/config/config.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/uav/fly.hpp"
#include "parallax/uav/planner.hpp"
#include "parallax/uav/scene.hpp"
#include "parallax/uav/vehicle.hpp"

namespace parallax::test {
namespace {

using namespace parallax::eval;
using namespace parallax::uav;

TEST(Vehicle, VelocityLoopKeepsPx4Limits) {
  const VehicleParams p;
  VehicleState s;
  double prev_a = 0, max_a = 0, max_jerk = 0;
  double t95 = -1;
  const double dt = 0.005;
  for (int k = 0; k < 2000; ++k) {
    step_vehicle(s, Eigen::Vector3d(0, 0, 5.0), 0.0, p, dt);
    const double a = s.accel_mps2.norm();
    max_a = std::max(max_a, a);
    max_jerk = std::max(max_jerk, std::fabs(a - prev_a) / dt);
    prev_a = a;
    if (t95 < 0 && s.velocity_mps.z() >= 0.95 * 5.0) t95 = k * dt;
  }
  EXPECT_LE(max_a, p.max_accel_mps2 + 1e-9);
  EXPECT_LE(max_jerk, p.max_jerk_mps3 + 1e-6);
  EXPECT_NEAR(max_a, p.max_accel_mps2, 1e-6);  // the limit is reached on a 5 m/s step
  // A ramp at 3 m/s^2 after a 3/8 s jerk ramp, then the 1.8/s exponential: 95 % in 2.5-3.5 s.
  EXPECT_GT(t95, 2.0);
  EXPECT_LT(t95, 3.5);
  EXPECT_NEAR(s.velocity_mps.z(), 5.0, 1e-3);
  EXPECT_DOUBLE_EQ(s.position_m.y(), -1.6);  // altitude hold
  // In cruise the body leans into the drag: pitch = -atan(k v / g).
  EXPECT_NEAR(s.pitch_rad, -std::atan(p.drag_per_s * 5.0 / 9.81), 1e-3);
  // Yaw: 90 degrees at no more than 45 degrees per second.
  VehicleState y;
  double prev_yaw = 0, max_rate = 0;
  for (int k = 0; k < 1000; ++k) {
    step_vehicle(y, Eigen::Vector3d::Zero(), M_PI / 2, p, dt);
    max_rate = std::max(max_rate, std::fabs(y.yaw_rad - prev_yaw) / dt);
    prev_yaw = y.yaw_rad;
  }
  EXPECT_LE(max_rate, p.max_yaw_rate_dps * M_PI / 180.0 + 1e-9);
  EXPECT_NEAR(y.yaw_rad, M_PI / 2, 1e-3);
  EXPECT_NEAR(wrap_angle(3 * M_PI / 2), -M_PI / 2, 1e-12);
}

Rig level_rig() {
  RigSpec spec;
  return rig_of(spec, spec.width_px, spec.height_px);
}

TEST(Render, PitchedGroundAndYawedPoleAreExact) {
  const Rig rig = level_rig();
  EXPECT_NEAR(rig.focal_px, 320.0 / std::tan(M_PI / 6), 1e-9);  // 60 degrees over 640 px
  // Nose down by 20 degrees: the centre ray meets the ground h / sin(20 deg) away, at that depth.
  CameraPose pose;
  pose.pitch_rad = -20.0 * M_PI / 180.0;
  const StereoFrame f = render(Scene{}, rig, 640, 360, pose, false);
  const Eigen::Vector3d ray =
      camera_axes(pose) * Eigen::Vector3d((319 - rig.cx_px) / rig.focal_px, (179 - rig.cy_px) / rig.focal_px, 1.0);
  const double depth = 1.6 / ray.y();  // the ray's camera z is 1: its parameter is the depth
  EXPECT_NEAR(depth, 1.6 / std::sin(20.0 * M_PI / 180.0), 0.05);
  EXPECT_NEAR(f.disparity_px.at<float>(179, 319), rig.focal_px * rig.baseline_m / depth, 1e-3);
  // A pole 45 degrees to the right, 10 m away, is at the image centre once the camera yaws 45.
  Scene s;
  s.cylinders.push_back({10.0 * std::sin(M_PI / 4), 10.0 * std::cos(M_PI / 4), 0.3, 6.0});
  CameraPose yawed;
  yawed.yaw_rad = M_PI / 4;
  const StereoFrame g = render(s, rig, 640, 360, yawed, false);
  EXPECT_NEAR(g.disparity_px.at<float>(150, 320), rig.focal_px * rig.baseline_m / 9.7, 0.1);
  const StereoFrame level = render(s, rig, 640, 360, CameraPose{}, false);
  EXPECT_LT(level.disparity_px.at<float>(150, 320), 1.0f);  // not ahead when level: sky
}

TEST(Render, AntialiasingBlendsEdgesAndSensorModelsTheCameras) {
  const Rig rig = level_rig();
  Scene s;
  s.cylinders.push_back({0.0, 8.0, 0.3, 6.0});
  const StereoFrame sharp = render(s, rig, 640, 360, CameraPose{}, false);
  const StereoFrame smooth = render(s, rig, 640, 360, CameraPose{}, true);
  // The pole's left edge against the sky (grey 200): some edge pixel takes a value between the
  // pole's and the sky's only with anti-aliasing; away from edges the images agree.
  int blended = 0, differ_inside = 0;
  for (int v = 40; v < 120; ++v)
    for (int u = 290; u < 350; ++u) {
      const int a = sharp.left.at<uint8_t>(v, u), b = smooth.left.at<uint8_t>(v, u);
      const bool edge = sharp.left.at<uint8_t>(v, u - 1) != a || sharp.left.at<uint8_t>(v, u + 1) != a;
      if (a != b && (a == 200 || sharp.left.at<uint8_t>(v, u - 1) == 200 || sharp.left.at<uint8_t>(v, u + 1) == 200))
        ++blended;
      if (!edge && a != b) ++differ_inside;
    }
  EXPECT_GT(blended, 40);
  EXPECT_LT(differ_inside, blended);
  // The right camera's gain and offset, then read noise of the given sigma.
  Imaging im;
  im.right_gain = 1.1;
  im.right_offset_grey = -10;
  StereoFrame g = sharp;
  g.left = sharp.left.clone();
  g.right = sharp.right.clone();
  std::mt19937 rng(3);
  apply_sensor(g, im, rng);
  EXPECT_EQ(cv::norm(g.left, sharp.left, cv::NORM_INF), 0.0);
  EXPECT_EQ(int(g.right.at<uint8_t>(10, 10)), int(std::lround(1.1 * sharp.right.at<uint8_t>(10, 10) - 10)));
  Imaging noisy;
  noisy.noise_grey = 3.0;
  StereoFrame n = sharp;
  n.left = sharp.left.clone();
  n.right = sharp.right.clone();
  apply_sensor(n, noisy, rng);
  cv::Mat diff;
  cv::subtract(n.left(cv::Rect(0, 0, 640, 30)), sharp.left(cv::Rect(0, 0, 640, 30)), diff, cv::noArray(), CV_32F);
  cv::Scalar mean, sd;
  cv::meanStdDev(diff, mean, sd);
  EXPECT_NEAR(sd[0], 3.0, 0.2);  // the sky: the noise alone
  EXPECT_NEAR(mean[0], 0.0, 0.1);
}

TEST(Flight, TheDesignsOwnWindowRigAndTiming) {
  const config::PipelineConfig cfg =
      config::load_config(std::string(PARALLAX_CONFIG_DIR) + "/ruf2018-census-calibrated.yaml");
  const Scenario sc = load_scenario("forest");
  EXPECT_EQ(sc.rig.width_px, 640);
  EXPECT_EQ(sc.imaging.noise_grey, 2.0);
  EXPECT_EQ(sc.bound_half_width_m, 10.0);
  FlightParams fp;
  const FlightSetup s = flight_setup(cfg, sc, fp);
  EXPECT_EQ(s.width_px, 640);
  EXPECT_EQ(s.height_px, 360);
  EXPECT_NEAR(s.latency_ms, 28.5, 0.01);          // the calibrated preset: the paper's latency
  EXPECT_NEAR(s.frame_interval_ms, 34.48, 0.01);  // and its 29 fps
  EXPECT_NEAR(s.reaction_s, (28.5 + 4.2) / 1000.0, 1e-4);
  EXPECT_NEAR(s.rig.focal_px, 554.26, 0.01);
  fp.width_px = 320;  // the quick look: the rig scaled, the design timed at that size
  const FlightSetup q = flight_setup(cfg, sc, fp);
  EXPECT_EQ(q.height_px, 180);
  EXPECT_NEAR(q.rig.focal_px, 277.13, 0.01);
  EXPECT_LT(q.latency_ms, s.latency_ms);
  // A window larger than the sensor is an error naming both.
  config::PipelineConfig big = cfg;
  big.roi_width_px = 1280;
  fp.width_px = 0;
  EXPECT_THROW(flight_setup(big, sc, fp), InputError);
  // Scenario files: the rig and imaging fields, and an unknown field named.
  const auto dir = std::filesystem::temp_directory_path() / "parallax_flight_model";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "r.yaml") << "kind: forest\nrig: {baseline_m: 0.12, hfov_deg: 90, mount_pitch_deg: 10}\n";
  const Scenario r = load_scenario((dir / "r.yaml").string());
  EXPECT_EQ(r.rig.baseline_m, 0.12);
  EXPECT_NEAR(rig_of(r.rig, 640, 360).focal_px, 320.0, 1e-9);
  std::ofstream(dir / "bad.yaml") << "kind: forest\nrig: {baseline: 0.12}\n";
  try {
    load_scenario((dir / "bad.yaml").string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'baseline'"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

// A map fed with the exact disparity of a pole dead ahead.
LocalMap map_with_pole(const Rig& rig, Scene& scene) {
  scene.cylinders.push_back({0.0, 8.0, 0.3, 6.0});
  LocalMap map;
  map.clear_disk(0, 0, 2.0);
  const StereoFrame f = render(scene, rig, 640, 360, CameraPose{}, false);
  for (int k = 0; k < 3; ++k) map.integrate(f.disparity_px, f.valid_mask, rig, CameraPose{}, f.left);
  return map;
}

TEST(Planner, RemembersUnseenDirectionsAndDoesNotFlip) {
  const Rig rig = level_rig();
  Scene scene;
  const LocalMap map = map_with_pole(rig, scene);
  EXPECT_EQ(map.at(0.0, 7.7), LocalMap::Cell::occupied);  // the pole's front
  EXPECT_EQ(map.at(0.0, 4.0), LocalMap::Cell::free);      // the ground in front of it
  EXPECT_EQ(map.at(0.0, 9.0), LocalMap::Cell::unknown);   // hidden behind it
  EXPECT_EQ(map.at(8.0, 4.0), LocalMap::Cell::unknown);   // outside the field of view
  PlannerParams pp;
  pp.cruise_mps = 3.0;
  pp.goal_xz = Eigen::Vector2d(0, 40);
  Planner planner(pp);
  VehicleState st;
  EXPECT_LT(planner.free_distance(map, st.position_m, 0.0), 7.8);       // blocked by the pole
  EXPECT_LT(planner.free_distance(map, st.position_m, M_PI / 2), 2.0);  // never seen past the take-off disk
  const Plan first = planner.plan(map, st);
  EXPECT_FALSE(first.braking);
  // Around the pole, inside the field of view (+-30 degrees).
  EXPECT_GT(std::fabs(first.heading_rad), 2.0 * M_PI / 180.0);
  EXPECT_LT(std::fabs(first.heading_rad), 30.0 * M_PI / 180.0);
  // The same map again and again: the same side (the pole is symmetric, the choice is not redone).
  for (int k = 0; k < 20; ++k) EXPECT_EQ(planner.plan(map, st).heading_rad, first.heading_rad);
  EXPECT_EQ(planner.flips(), 0);
  // Memory: turned away, the map still holds the pole.
  LocalMap turned = map;
  CameraPose away;
  away.yaw_rad = M_PI / 2;
  const StereoFrame side = render(scene, rig, 640, 360, away, false);
  turned.integrate(side.disparity_px, side.valid_mask, rig, away, side.left);
  EXPECT_EQ(turned.at(0.0, 7.7), LocalMap::Cell::occupied);
}

// A dead end: the vehicle inside a U of walls open behind it, having looked all round. A direction
// search towards the goal (ahead) finds nothing free; the cost to the goal over the map leads out
// the way it came, round the U's side.
TEST(Planner, LeavesADeadEndByThePathToTheGoal) {
  const Rig rig = level_rig();
  Scene scene;
  scene.boxes.push_back({-4.3, 4.3, 6.0, 6.3, 5.0});    // across, ahead
  scene.boxes.push_back({-4.3, -4.0, -1.0, 6.0, 5.0});  // the sides
  scene.boxes.push_back({4.0, 4.3, -1.0, 6.0, 5.0});
  LocalMap map;
  map.clear_disk(0, 0, 2.0);
  for (const double yaw_deg : {0.0, 60.0, 120.0, 180.0, 240.0, 300.0}) {
    CameraPose pose;
    pose.yaw_rad = yaw_deg * M_PI / 180.0;
    const StereoFrame f = render(scene, rig, 640, 360, pose, false);
    for (int k = 0; k < 3; ++k) map.integrate(f.disparity_px, f.valid_mask, rig, pose, f.left);
  }
  EXPECT_EQ(map.at(0.0, 6.0), LocalMap::Cell::occupied);
  EXPECT_EQ(map.at(0.0, -5.0), LocalMap::Cell::free);  // behind: open
  PlannerParams pp;
  pp.cruise_mps = 3.0;
  pp.goal_xz = Eigen::Vector2d(0, 40);
  Planner planner(pp);
  VehicleState st;
  st.position_m = CameraPose{}.position_m;
  const Plan plan = planner.plan(map, st);
  EXPECT_FALSE(plan.braking);
  EXPECT_GT(std::fabs(plan.heading_rad), M_PI / 2) << plan.heading_rad;  // out of the U, backwards
  EXPECT_GT(plan.velocity_mps.norm(), 0.5);
}

// A stop the direction search cannot end: seen free only in a narrow lane behind the vehicle, the
// goal ahead through unseen cells. The vehicle stops, and after stuck_plans plans turns on the spot
// a scan step at a time (a whole turn; the map here learns nothing from it), then flies the lane
// away from the goal, never into an unseen cell.
TEST(Planner, RecoversFromAStopByTurningThenFlyingAway) {
  LocalMap map;
  for (int k = 0; k <= 12; ++k) map.clear_disk(0.0, -double(k), 1.2);
  PlannerParams pp;
  pp.goal_xz = Eigen::Vector2d(0, 40);
  Planner planner(pp);
  VehicleState st;
  st.position_m = Eigen::Vector3d(0, -1.6, 0);
  constexpr double kFrameS = 0.0345;
  std::vector<double> scan_yaws_deg;
  int first_move = -1;
  for (int k = 0; k < 600 && first_move < 0; ++k) {
    const Plan plan = planner.plan(map, st);
    if (k < pp.stuck_plans - 1) {  // the stuck_plans-th stop starts the recovery
      EXPECT_TRUE(plan.braking) << k;
      EXPECT_EQ(planner.recoveries(), 0);
    }
    if (plan.velocity_mps.norm() > 0) {
      first_move = k;
      EXPECT_LT(plan.velocity_mps.z(), -0.5 * plan.velocity_mps.norm());  // down the lane, away from the goal
    } else {
      const double yaw_deg = plan.yaw_rad * 180.0 / M_PI;
      if (scan_yaws_deg.empty() || std::fabs(wrap_angle((yaw_deg - scan_yaws_deg.back()) * M_PI / 180.0)) > 1e-6)
        scan_yaws_deg.push_back(yaw_deg);
    }
    for (int i = 0; i < 7; ++i) step_vehicle(st, plan.velocity_mps, plan.yaw_rad, pp.vehicle, kFrameS / 7);
  }
  ASSERT_GT(first_move, pp.stuck_plans);
  EXPECT_EQ(planner.recoveries(), 1);
  // The look ahead (yaw 0), then a whole turn in 60 degree steps.
  ASSERT_EQ(scan_yaws_deg.size(), 7u);
  for (std::size_t i = 1; i < scan_yaws_deg.size(); ++i)
    EXPECT_NEAR(std::fabs(wrap_angle((scan_yaws_deg[i] - scan_yaws_deg[i - 1]) * M_PI / 180.0)), M_PI / 3, 0.02) << i;
  // Flown on: out down the lane, always in seen cells.
  for (int k = 0; k < 150; ++k) {
    const Plan plan = planner.plan(map, st);
    for (int i = 0; i < 7; ++i) step_vehicle(st, plan.velocity_mps, plan.yaw_rad, pp.vehicle, kFrameS / 7);
    ASSERT_NE(map.at(st.position_m.x(), st.position_m.z()), LocalMap::Cell::unknown) << k;
  }
  EXPECT_LT(st.position_m.z(), -1.0);
}

// A vehicle that braked into the bounds' margin may leave it, not go deeper.
TEST(Planner, LeavesTheBoundsMargin) {
  LocalMap map;
  map.clear_disk(9.3, 0.0, 2.0);
  PlannerParams pp;
  pp.bound_half_width_m = 10.0;  // the margin starts at 10 - safety_m = 9.1 m
  const Planner planner(pp);
  const Eigen::Vector3d at(9.3, -1.6, 0.0);
  EXPECT_GT(planner.free_distance(map, at, -M_PI / 2), 1.0);  // inwards: to the seen disk, less its margin
  EXPECT_EQ(planner.free_distance(map, at, M_PI / 2), 0.0);   // outwards: nothing
}

}  // namespace
}  // namespace parallax::test
