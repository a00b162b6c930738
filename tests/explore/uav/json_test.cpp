// unit: the UAV room's JSON forms (parallax/uav/json.hpp), what avoid and fly print with --json
// and scene writes to obstacles.json.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <opencv2/core.hpp>

#include <string>

#include "parallax/uav/json.hpp"

namespace {

namespace px = parallax::uav;
using nlohmann::json;

TEST(UavJson, ObstacleCarriesTheFieldsOfItsKind) {
  px::TruthObstacle c;
  c.id = 3;
  c.kind = "cylinder";
  c.x_m = 1.0;
  c.z_m = 9.0;
  c.radius_m = 0.2;
  c.range_m = 8.8;
  const json jc = c;
  EXPECT_EQ(jc["id"].get<int>(), 3);
  EXPECT_DOUBLE_EQ(jc["radius_m"].get<double>(), 0.2);
  EXPECT_FALSE(jc.contains("x0_m"));
  px::TruthObstacle b;
  b.kind = "box";
  b.x0_m = -1.0;
  b.x1_m = 1.0;
  b.z0_m = 5.0;
  b.z1_m = 5.5;
  const json jb = b;
  EXPECT_DOUBLE_EQ(jb["z1_m"].get<double>(), 5.5);
  EXPECT_FALSE(jb.contains("radius_m"));
  EXPECT_FALSE(jb.contains("x_m"));
}

TEST(UavJson, FlightResultLeavesTheTrajectoryOut) {
  px::FlightResult r;
  r.outcome = px::Outcome::collision;
  r.hit = "pole 2";
  r.frames = 12;
  r.trajectory.assign(12, Eigen::Vector3d::Zero());
  const json j = r;
  EXPECT_EQ(j["outcome"].get<std::string>(), px::to_string(px::Outcome::collision));
  EXPECT_EQ(j["hit"].get<std::string>(), "pole 2");
  EXPECT_EQ(j["frames"].get<int>(), 12);
  EXPECT_EQ(j.size(), 8u);
}

TEST(UavJson, AvoidanceSplitsTheStageTimePerFrame) {
  // A wall at disparity 20 over the lower half on both maps: the stage runs, whatever it finds.
  cv::Mat d(120, 200, CV_32F, cv::Scalar(0.0f)), valid(120, 200, CV_8U, cv::Scalar(0));
  d.rowRange(60, 120).setTo(20.0f);
  valid.rowRange(60, 120).setTo(255);
  px::AvoidAccumulator acc;
  for (int i = 0; i < 2; ++i) acc.add(d, valid, d, valid, 64, px::kitti_default_rig(0, 0));
  const json j = acc;
  EXPECT_EQ(j["frames"].get<int>(), 2);
  EXPECT_DOUBLE_EQ(j["ms_split"]["uv_maps"].get<double>(), acc.timing_sum().uv_maps_ms / 2);
  EXPECT_DOUBLE_EQ(j["ms_split"]["planning"].get<double>(), acc.timing_sum().planning_ms / 2);
  for (const auto& kv : acc.metrics()) EXPECT_TRUE(j.contains(kv.first)) << kv.first;
}

}  // namespace
