// unit: the avoidance stage scored against the scene's obstacles: which obstacles a camera sees,
// the 3D tolerance from the stereo depth error, matching, first detection, blocked within the
// stopping distance, the obstacle list's file and the calibration `scene` writes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "parallax/eval/calibration.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/uav/truth.hpp"

namespace parallax::test {
namespace {

using namespace parallax::eval;
using namespace parallax::uav;

Rig uav_rig() {
  return rig_of(RigSpec{}, 640, 360);
}  // f 554.3 px, B 0.30 m

double metric(const TruthAccumulator& a, const std::string& name) {
  for (const auto& kv : a.metrics())
    if (kv.first == name) return kv.second;
  ADD_FAILURE() << "no metric " << name;
  return -2;
}

Obstacle detection(double lateral_m, double range_m, double width_m = 0.5) {
  Obstacle o;
  o.lateral_m = lateral_m;
  o.range_m = range_m;
  o.width_m = width_m;
  return o;
}

TEST(Truth, ObstaclesInTheFieldOfView) {
  Scene s;
  s.cylinders.push_back({0.0, 10.0, 0.3, 8.0});       // ahead
  s.cylinders.push_back({20.0, 5.0, 0.3, 8.0});       // 76 degrees right: outside the 60 degree view
  s.cylinders.push_back({0.0, -3.0, 0.3, 8.0});       // behind
  s.cylinders.push_back({5.9, 10.0, 0.3, 8.0});       // its edge just inside the right border
  s.boxes.push_back({-50.0, 50.0, 20.0, 20.5, 6.0});  // a wall across
  const auto v = obstacles_in_view(s, uav_rig(), 640, Eigen::Vector3d(0, -1.6, 0), 40.0);
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(v[0].id, 0);
  EXPECT_NEAR(v[0].range_m, 9.7, 1e-9);
  EXPECT_NEAR(v[0].lateral_m, 0.0, 1e-9);
  EXPECT_EQ(v[1].id, 3);
  EXPECT_EQ(v[2].id, 4);
  EXPECT_EQ(v[2].kind, "box");
  EXPECT_NEAR(v[2].range_m, 20.0, 1e-9);
  EXPECT_NEAR(v[2].lateral_m, 0.0, 1e-9);
  // From 8 m further on, the first cylinder is 1.7 m ahead and the wall 12 m.
  const auto w = obstacles_in_view(s, uav_rig(), 640, Eigen::Vector3d(0, -1.6, 8), 40.0);
  ASSERT_FALSE(w.empty());
  EXPECT_NEAR(w[0].range_m, 1.7, 1e-9);
}

TEST(Truth, ToleranceGrowsWithTheSquareOfDepth) {
  const Rig rig = uav_rig();
  TruthScoreParams p;
  // sigma_Z = Z^2 sigma_d / (f B) = 100 x 0.5 / 166.28 = 0.3007 m at 10 m; 3 sigma.
  EXPECT_NEAR(truth_tolerance_m(10.0, rig, p), 3 * 100 * 0.5 / (rig.focal_px * 0.30), 1e-9);
  EXPECT_NEAR(truth_tolerance_m(20.0, rig, p), 4 * truth_tolerance_m(10.0, rig, p), 1e-9);
  EXPECT_EQ(truth_tolerance_m(2.0, rig, p), 0.5);  // the floor
}

TEST(Truth, MatchingFirstDetectionAndBlocking) {
  const Rig rig = uav_rig();
  TruthScoreParams p;
  p.stopping_m = 5.0;
  TruthAccumulator a(p);
  TruthObstacle pole;
  pole.id = 7;
  pole.kind = "cylinder";
  pole.x_m = 0.2;
  pole.z_m = 12.3;
  pole.radius_m = 0.3;
  pole.range_m = 12.0;
  // Frame 1 at 12 m: a detection 2 m to the side is a false positive and the pole a miss.
  a.add({detection(2.2, 12.0)}, {pole}, rig);
  // Frame 2 at 8 m: a detection at the pole's face, 0.4 m deep into the tolerance (0.5 m floor
  // at 8 m: 3 x 64 x 0.5 / 166 = 0.58 m).
  pole.z_m = 8.3;
  pole.range_m = 8.0;
  a.add({detection(0.2, 7.6)}, {pole}, rig);
  // Frame 3 at 4 m, on the path within the stopping distance: not detected, a missed block.
  pole.z_m = 4.3;
  pole.range_m = 4.0;
  a.add({}, {pole}, rig);
  // Frame 4: nothing there, a detection on the path: a false block and a false positive.
  a.add({detection(0.0, 3.0)}, {}, rig);
  EXPECT_EQ(metric(a, "frames"), 4);
  EXPECT_EQ(metric(a, "detection_pct_10_20m"), 0.0);
  EXPECT_EQ(metric(a, "detection_pct_5_10m"), 100.0);
  EXPECT_EQ(metric(a, "detection_pct_0_5m"), 0.0);
  EXPECT_EQ(metric(a, "detection_pct_20_40m"), -1.0);  // nothing there to detect
  EXPECT_NEAR(metric(a, "first_detection_range_m"), 8.0, 1e-9);
  EXPECT_EQ(metric(a, "never_detected"), 0.0);
  EXPECT_NEAR(metric(a, "false_positives_per_frame"), 2.0 / 4.0, 1e-9);
  EXPECT_NEAR(metric(a, "range_error_m"), 0.4, 1e-9);
  EXPECT_EQ(metric(a, "missed_blocks"), 1.0);
  EXPECT_EQ(metric(a, "false_blocks"), 1.0);
  EXPECT_NEAR(metric(a, "blocked_agreement_pct"), 50.0, 1e-9);
  // A detection 1.5 m behind the pole's face at 8 m is outside the tolerance.
  TruthAccumulator b(p);
  pole.z_m = 8.3;
  pole.range_m = 8.0;
  b.add({detection(0.2, 9.5)}, {pole}, rig);
  EXPECT_EQ(metric(b, "detection_pct_5_10m"), 0.0);
  EXPECT_EQ(metric(b, "never_detected"), 1.0);
  // A wall seen as three blobs: one match, and the other two are not false positives; a blob 3 m
  // in front of it is.
  TruthAccumulator c(p);
  TruthObstacle wall;
  wall.id = 1;
  wall.kind = "box";
  wall.x0_m = -10;
  wall.x1_m = 10;
  wall.z0_m = 15;
  wall.z1_m = 15.5;
  wall.range_m = 15;
  c.add({detection(-4, 15.2), detection(0, 15.1), detection(5, 14.9), detection(1, 12)}, {wall}, rig);
  EXPECT_EQ(metric(c, "detection_pct_10_20m"), 100.0);
  EXPECT_EQ(metric(c, "false_positives_per_frame"), 1.0);
}

TEST(Truth, ObstacleFileAndCalibrationRoundTrip) {
  const auto dir = std::filesystem::temp_directory_path() / "parallax_truth_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  Scene s;
  s.cylinders.push_back({0.5, 10.0, 0.3, 8.0});
  s.boxes.push_back({-3.0, 3.0, 15.0, 15.5, 6.0});
  const Rig rig = uav_rig();
  const std::vector<std::vector<TruthObstacle>> frames = {
      obstacles_in_view(s, rig, 640, Eigen::Vector3d(0, -1.6, 0), 40.0),
      obstacles_in_view(s, rig, 640, Eigen::Vector3d(0, -1.6, 2), 40.0)};
  const std::string path = (dir / "obstacles.json").string();
  write_truth(path, frames);
  const auto back = read_truth(path);
  ASSERT_EQ(back.size(), 2u);
  ASSERT_EQ(back.at("000001").size(), 2u);
  EXPECT_NEAR(back.at("000001")[0].z_m, 8.0, 1e-9);
  EXPECT_NEAR(back.at("000001")[1].x1_m, 3.0, 1e-9);
  std::ofstream(dir / "bad.json") << R"({"frames": [{"frame": "000000", "obstacles": [{"id": 1, "kind": "cone"}]}]})";
  try {
    read_truth((dir / "bad.json").string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos);
  }
  // The calibration `scene` writes is KITTI's, and reads back as the rig.
  write_kitti_calibration(rig, 2, dir.string());
  const StereoCalibration c =
      read_kitti_calib(dir / "training" / "calib_cam_to_cam" / "000001.txt", "P_rect_02", "P_rect_03");
  EXPECT_NEAR(c.focal_px, rig.focal_px, 1e-5);
  EXPECT_NEAR(c.baseline_m, rig.baseline_m, 1e-6);
  EXPECT_NEAR(c.cx_px, rig.cx_px, 1e-5);
  EXPECT_NEAR(c.cy_px, rig.cy_px, 1e-5);
}

}  // namespace
}  // namespace parallax::test
