// unit: the avoidance stage on synthetic scenes with known geometry, the planner's choices, and
// rig files (MAVLink: mavlink_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "parallax/uav/avoid.hpp"
#include "parallax/eval/dataset.hpp"

namespace parallax::test {
namespace {

using namespace parallax::eval;
using namespace parallax::uav;

// A flat ground 1.6 m below the camera and, optionally, a box standing on it.
struct Scene {
  cv::Mat disp, valid;
};
Scene make_scene(const Rig& rig, int w, int h, bool box, double box_z, double box_x0, double box_x1, double box_top_y) {
  Scene s{cv::Mat::zeros(h, w, CV_32F), cv::Mat::zeros(h, w, CV_8U)};
  const double cam_h = 1.6;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double d = 0;
      if (y > rig.cy_px + 2) d = rig.baseline_m * (y - rig.cy_px) / cam_h;  // ground: Z = f h / (y - cy)
      if (box) {
        const double u0 = rig.cx_px + rig.focal_px * box_x0 / box_z, u1 = rig.cx_px + rig.focal_px * box_x1 / box_z;
        const double v0 = rig.cy_px + rig.focal_px * box_top_y / box_z, v1 = rig.cy_px + rig.focal_px * cam_h / box_z;
        if (x >= u0 && x < u1 && y >= v0 && y < v1) d = rig.focal_px * rig.baseline_m / box_z;
      }
      if (d > 0.5 && d < 63) {
        s.disp.at<float>(y, x) = float(d);
        s.valid.at<uint8_t>(y, x) = 255;
      }
    }
  return s;
}

Rig test_rig() {
  Rig r;
  r.focal_px = 700;
  r.baseline_m = 0.5;
  r.cx_px = 320;
  r.cy_px = 150;
  return r;
}

TEST(Avoid, BoxInThePathIsFoundWithItsGeometryAndAvoided) {
  const Rig rig = test_rig();
  // A box 8 m ahead, from 0.3 m left to 2.3 m right of the camera, 2.5 m tall.
  const Scene s = make_scene(rig, 640, 360, true, 8.0, -0.3, 2.3, 1.6 - 2.5);
  const AvoidResult r = avoid(s.disp, s.valid, 64, rig);
  ASSERT_TRUE(r.ground_found);
  EXPECT_NEAR(r.ground_slope, 1.6 / 0.5, 0.2);  // row = cy + d h / B
  ASSERT_GE(r.obstacles.size(), 1u);
  const Obstacle& o = r.obstacles.front();
  EXPECT_NEAR(o.range_m, 8.0, 0.6);
  EXPECT_NEAR(o.lateral_m, 1.0, 0.35);
  EXPECT_NEAR(o.width_m, 2.6, 0.5);
  EXPECT_GT(o.height_m, 1.5);
  // Passing left needs 0.3 + 1.5 m, right 2.3 + 1.5 m, up more: left.
  EXPECT_EQ(r.manoeuvre, Manoeuvre::left);
  EXPECT_LT(r.velocity_mps.y(), 0.0);
  EXPECT_GT(r.velocity_mps.x(), 0.0);
  EXPECT_GT(r.timings.total_ms(), 0.0);
}

// The obstacle's range uses the disparities' fractions (sub-pixel codes): a box at 8 m has
// d = 43.75 px; integer codes give the bin's f B / 44 = 7.95 m, fractional ones the true range.
TEST(Avoid, RangeUsesSubpixelDisparities) {
  const Rig rig = test_rig();
  const Scene s = make_scene(rig, 640, 360, true, 8.0, -0.3, 2.3, 1.6 - 2.5);
  cv::Mat quarter, integer;
  s.disp.convertTo(quarter, CV_32F, 4.0);
  for (int y = 0; y < quarter.rows; ++y)
    for (int x = 0; x < quarter.cols; ++x) quarter.at<float>(y, x) = std::round(quarter.at<float>(y, x)) / 4.0f;
  s.disp.convertTo(integer, CV_32F);
  for (int y = 0; y < integer.rows; ++y)
    for (int x = 0; x < integer.cols; ++x) integer.at<float>(y, x) = std::round(integer.at<float>(y, x));
  const AvoidResult fine = avoid(quarter, s.valid, 64, rig);
  const AvoidResult coarse = avoid(integer, s.valid, 64, rig);
  ASSERT_GE(fine.obstacles.size(), 1u);
  ASSERT_GE(coarse.obstacles.size(), 1u);
  EXPECT_NEAR(fine.obstacles.front().range_m, 8.0, 1e-6);  // 43.75 is exact in quarter pixels
  EXPECT_NEAR(coarse.obstacles.front().range_m, 700 * 0.5 / 44.0, 1e-6);
}

TEST(Avoid, TheMirroredBoxIsPassedOnTheRight) {
  const Rig rig = test_rig();
  const Scene s = make_scene(rig, 640, 360, true, 7.0, -2.3, 0.3, 1.6 - 2.5);
  const AvoidResult r = avoid(s.disp, s.valid, 64, rig);
  EXPECT_EQ(r.manoeuvre, Manoeuvre::right);
  EXPECT_GT(r.velocity_mps.y(), 0.0);
}

TEST(Avoid, ALowWideObstacleIsPassedAbove) {
  const Rig rig = test_rig();
  // 6 m wide, 0.5 m tall (its top 1.1 m below the camera), 6 m ahead: over it is the shortest way.
  const Scene s = make_scene(rig, 640, 360, true, 6.0, -3.0, 3.0, 1.1);
  AvoidParams p;
  p.u_threshold = 8;  // a low obstacle has few rows per column
  const AvoidResult r = avoid(s.disp, s.valid, 64, rig, p);
  ASSERT_GE(r.obstacles.size(), 1u);
  EXPECT_FALSE(r.obstacles.front().reaches_roi_top);
  EXPECT_EQ(r.manoeuvre, Manoeuvre::up);
  EXPECT_LT(r.velocity_mps.z(), 0.0);  // NED: up is negative z
}

TEST(Avoid, NothingNearMeansFlyOn) {
  const Rig rig = test_rig();
  const AvoidResult ground = avoid(make_scene(rig, 640, 360, false, 0, 0, 0, 0).disp,
                                   make_scene(rig, 640, 360, false, 0, 0, 0, 0).valid, 64, rig);
  EXPECT_TRUE(ground.obstacles.empty());
  EXPECT_EQ(ground.manoeuvre, Manoeuvre::fly_on);
  EXPECT_DOUBLE_EQ(ground.velocity_mps.x(), AvoidParams{}.cruise_mps);
  // Beyond the critical distance, and beside the corridor: found, not avoided.
  const Scene far = make_scene(rig, 640, 360, true, 25.0, -1, 1, -1);
  const AvoidResult rf = avoid(far.disp, far.valid, 64, rig);
  EXPECT_EQ(rf.manoeuvre, Manoeuvre::fly_on);
  const Scene side = make_scene(rig, 640, 360, true, 8.0, 3.0, 4.0, -1);
  const AvoidResult rs = avoid(side.disp, side.valid, 64, rig);
  ASSERT_GE(rs.obstacles.size(), 1u);
  EXPECT_EQ(rs.manoeuvre, Manoeuvre::fly_on);
}

TEST(Avoid, ScoringMatchesByUMapOverlap) {
  const Rig rig = test_rig();
  const Scene s = make_scene(rig, 640, 360, true, 8.0, -0.3, 2.3, -0.9);
  const AvoidResult a = avoid(s.disp, s.valid, 64, rig);
  const AvoidScore same = score_avoidance(a, a);
  EXPECT_EQ(same.matched, same.predicted);
  EXPECT_TRUE(same.same_decision);
  EXPECT_DOUBLE_EQ(same.range_error_sum_m, 0.0);
  const AvoidResult none = avoid(make_scene(rig, 640, 360, false, 0, 0, 0, 0).disp,
                                 make_scene(rig, 640, 360, false, 0, 0, 0, 0).valid, 64, rig);
  EXPECT_EQ(score_avoidance(none, a).matched, 0);
  EXPECT_FALSE(score_avoidance(none, a).same_decision);
}

// --- rig files ---------------------------------------------------------------------------------

TEST(Rig, KittiAndOpenCvFiles) {
  const auto dir = std::filesystem::temp_directory_path() / "parallax_rig_test";
  std::filesystem::create_directories(dir);
  {
    std::ofstream k(dir / "calib.txt");
    k << "P_rect_02: 7.215377e+02 0 6.095593e+02 4.485728e+01 0 7.215377e+02 1.72854e+02 2.163791e-01 0 0 1 "
         "2.745884e-03\n"
         "P_rect_03: 7.215377e+02 0 6.095593e+02 -3.395242e+02 0 7.215377e+02 1.72854e+02 2.199936e+00 0 0 1 "
         "2.729905e-03\n";
  }
  const Rig r = load_rig((dir / "calib.txt").string(), 301, 7);
  EXPECT_NEAR(r.focal_px, 721.5377, 1e-6);
  EXPECT_NEAR(r.baseline_m, 0.5327, 1e-3);
  EXPECT_NEAR(r.cx_px, 609.5593 - 301, 1e-6);
  EXPECT_NEAR(r.cy_px, 172.854 - 7, 1e-6);
  {
    std::ofstream y(dir / "rig.yml");
    y << "%YAML:1.0\n---\nfocal_px: 500.0\nbaseline_m: 0.12\ncx_px: 320.0\ncy_px: 240.0\n";
  }
  const Rig o = load_rig((dir / "rig.yml").string(), 0, 0);
  EXPECT_DOUBLE_EQ(o.baseline_m, 0.12);
  {
    std::ofstream y(dir / "bad.yml");
    y << "%YAML:1.0\n---\nfocal_px: 500.0\n";
  }
  try {
    load_rig((dir / "bad.yml").string(), 0, 0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("baseline_m"), std::string::npos);
  }
}

}  // namespace
}  // namespace parallax::test
