// unit: the avoidance stage on synthetic scenes with known geometry, the planner's choices,
// MAVLink 2 frames against an independent bitwise CRC and decoder, and rig files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "parallax/uav/avoid.hpp"
#include "parallax/eval/dataset.hpp"

namespace parallax::test {
namespace {

using namespace parallax::explore;

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

// --- MAVLink ---------------------------------------------------------------------------------

// Bitwise CRC-16/MCRF4XX (reflected 0x1021 = 0x8408, init 0xFFFF), written independently of the
// table-free byte formula in avoid.cpp.
uint16_t crc_bitwise(const std::vector<uint8_t>& bytes) {
  uint16_t crc = 0xFFFF;
  for (uint8_t b : bytes) {
    crc ^= b;
    for (int i = 0; i < 8; ++i) crc = (crc & 1) ? uint16_t((crc >> 1) ^ 0x8408) : uint16_t(crc >> 1);
  }
  return crc;
}

TEST(Mavlink, CrcTestVectors) {
  const std::string check = "123456789";
  EXPECT_EQ(mavlink_crc(reinterpret_cast<const uint8_t*>(check.data()), check.size()), 0x6F91);  // CRC-16/MCRF4XX check
  EXPECT_EQ(crc_bitwise(std::vector<uint8_t>(check.begin(), check.end())), 0x6F91);
}

// Decodes a MAVLink 2 frame independently: header, zero-extended payload, CRC with CRC_EXTRA.
struct Decoded {
  uint8_t len, seq, sysid, compid;
  uint32_t msgid;
  std::vector<uint8_t> payload;
  bool crc_ok;
};
Decoded decode(const std::vector<uint8_t>& f, uint8_t crc_extra, std::size_t full_len) {
  Decoded d{};
  EXPECT_EQ(f.at(0), 0xFD);
  d.len = f[1];
  EXPECT_EQ(f.size(), std::size_t(d.len) + 12);
  EXPECT_EQ(f[2], 0);  // incompat flags: unsigned
  EXPECT_EQ(f[3], 0);
  d.seq = f[4];
  d.sysid = f[5];
  d.compid = f[6];
  d.msgid = uint32_t(f[7]) | uint32_t(f[8]) << 8 | uint32_t(f[9]) << 16;
  d.payload.assign(f.begin() + 10, f.begin() + 10 + d.len);
  EXPECT_TRUE(d.len == full_len || (d.len >= 1 && d.payload.back() != 0)) << "trailing zeros must be trimmed";
  d.payload.resize(full_len, 0);
  std::vector<uint8_t> covered(f.begin() + 1, f.begin() + 10 + d.len);
  covered.push_back(crc_extra);
  d.crc_ok = crc_bitwise(covered) == uint16_t(f[10 + d.len] | f[11 + d.len] << 8);
  return d;
}

TEST(Mavlink, HeartbeatFrame) {
  const auto f = mavlink_heartbeat(7, 1, 191);
  const Decoded d = decode(f, 50, 9);
  EXPECT_TRUE(d.crc_ok);
  EXPECT_EQ(d.msgid, 0u);
  EXPECT_EQ(d.seq, 7);
  EXPECT_EQ(d.sysid, 1);
  EXPECT_EQ(d.compid, 191);
  EXPECT_EQ(d.payload[4], 18);  // MAV_TYPE_ONBOARD_CONTROLLER
  EXPECT_EQ(d.payload[8], 3);   // mavlink_version
}

TEST(Mavlink, VelocitySetpointFrame) {
  const auto f = mavlink_velocity_setpoint(9, 1, 191, 1234, Eigen::Vector3d(2.5, -1.5, 0.25), 1, 1);
  const Decoded d = decode(f, 143, 53);
  EXPECT_TRUE(d.crc_ok);
  EXPECT_EQ(d.msgid, 84u);
  uint32_t t;
  float v[3];
  uint16_t mask;
  std::memcpy(&t, d.payload.data(), 4);
  std::memcpy(v, d.payload.data() + 16, 12);
  std::memcpy(&mask, d.payload.data() + 48, 2);
  EXPECT_EQ(t, 1234u);
  EXPECT_FLOAT_EQ(v[0], 2.5f);
  EXPECT_FLOAT_EQ(v[1], -1.5f);
  EXPECT_FLOAT_EQ(v[2], 0.25f);
  EXPECT_EQ(mask, 0x0DC7);
  EXPECT_EQ(d.payload[50], 1);  // target system
  EXPECT_EQ(d.payload[51], 1);  // target component
  EXPECT_EQ(d.payload[52], 8);  // MAV_FRAME_BODY_NED
  // A corrupted byte fails the CRC.
  auto bad = f;
  bad[20] ^= 0x01;
  EXPECT_FALSE(decode(bad, 143, 53).crc_ok);
}

#if defined(PARALLAX_NODE) && defined(PARALLAX_MAVLINK_CHECK)
// `parallax avoid --mavlink-out` on the shipped frames, decoded by node-mavlink (npm): every frame
// valid (CRC with CRC_EXTRA), HEARTBEAT and SET_POSITION_TARGET_LOCAL_NED alternating, and the
// velocities those of the planner's decisions.
TEST(Mavlink, NodeMavlinkDecodesTheAvoidOutput) {
  const std::string dir = PARALLAX_MAVLINK_CHECK;
  if (!std::filesystem::exists(dir + "/node_modules/node-mavlink"))
    GTEST_SKIP() << "npm install in " << dir << " first";
  const auto tmp = std::filesystem::temp_directory_path() / "parallax_mavlink_test";
  std::filesystem::create_directories(tmp);
  const std::string bin = (tmp / "out.mav").string(), js = (tmp / "avoid.json").string();
  const std::string cmd = std::string(PARALLAX_CLI) + " avoid --config " + PARALLAX_CONFIG_DIR +
                          "/ruf2018-census.yaml --dataset " + PARALLAX_DATA_DIR +
                          "/kitti2015-640x360 --json --mavlink-out " + bin + " > " + js + " 2>/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const std::string dec = (tmp / "decoded.json").string();
  ASSERT_EQ(std::system((std::string(PARALLAX_NODE) + " " + dir + "/verify.js " + bin + " > " + dec).c_str()), 0);
  std::ifstream a(js), b(dec);
  const auto avoid_json = nlohmann::json::parse(a);
  const auto decoded = nlohmann::json::parse(b);
  EXPECT_EQ(decoded["invalid"].get<int>(), 0);
  const auto& packets = decoded["packets"];
  const auto& frames = avoid_json["per_frame"];
  ASSERT_EQ(packets.size(), 2 * frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const auto& hb = packets[2 * i];
    const auto& sp = packets[2 * i + 1];
    EXPECT_EQ(hb["msgid"].get<int>(), 0);
    EXPECT_EQ(sp["msgid"].get<int>(), 84);
    EXPECT_EQ(sp["seq"].get<int>(), int(2 * i + 1));
    EXPECT_EQ(sp["typeMask"].get<int>(), 0x0DC7);
    EXPECT_EQ(sp["coordinateFrame"].get<int>(), 8);
    const auto& v = frames[i]["velocity_mps"];
    EXPECT_FLOAT_EQ(sp["vx"].get<float>(), v[0].get<float>());
    EXPECT_FLOAT_EQ(sp["vy"].get<float>(), v[1].get<float>());
    EXPECT_FLOAT_EQ(sp["vz"].get<float>(), v[2].get<float>());
  }
}
#endif

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
