// unit: MAVLink 2 frames against an independent bitwise CRC and decoder, the companion's stream
// (heartbeat each second, OFFBOARD entry after a second of setpoints), the flight's frames (NED
// and body axes), and the streams of `avoid` and `fly` decoded by node-mavlink.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "parallax/uav/fly.hpp"
#include "parallax/uav/mavlink.hpp"

namespace parallax::test {
namespace {

using namespace parallax::uav;

// Bitwise CRC-16/MCRF4XX (reflected 0x1021 = 0x8408, init 0xFFFF), written independently of the
// byte formula in mavlink.cpp.
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

template <class T>
T field(const Decoded& d, std::size_t offset) {
  T v;
  std::memcpy(&v, d.payload.data() + offset, sizeof(T));
  return v;
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

TEST(Mavlink, VelocitySetpointInBothFrames) {
  VelocitySetpoint sp;
  sp.time_boot_ms = 1234;
  sp.velocity_mps = Eigen::Vector3d(2.5, -1.5, 0.25);
  sp.yaw_rad = 0.75;
  sp.yaw_rate_rps = -0.5;
  const auto f = mavlink_velocity_setpoint(9, 1, 191, sp, 1, 1);
  const Decoded d = decode(f, 143, 53);
  EXPECT_TRUE(d.crc_ok);
  EXPECT_EQ(d.msgid, 84u);
  EXPECT_EQ(field<uint32_t>(d, 0), 1234u);
  EXPECT_FLOAT_EQ(field<float>(d, 16), 2.5F);
  EXPECT_FLOAT_EQ(field<float>(d, 20), -1.5F);
  EXPECT_FLOAT_EQ(field<float>(d, 24), 0.25F);
  EXPECT_FLOAT_EQ(field<float>(d, 40), 0.75F);  // yaw
  EXPECT_FLOAT_EQ(field<float>(d, 44), 0.0F);   // yaw rate: not sent
  EXPECT_EQ(field<uint16_t>(d, 48), 0x09C7);    // velocity and yaw
  EXPECT_EQ(d.payload[50], 1);                  // target system
  EXPECT_EQ(d.payload[51], 1);                  // target component
  EXPECT_EQ(d.payload[52], 1);                  // MAV_FRAME_LOCAL_NED
  sp.frame = SetpointFrame::body_frd;
  const Decoded b = decode(mavlink_velocity_setpoint(10, 1, 191, sp), 143, 53);
  EXPECT_TRUE(b.crc_ok);
  EXPECT_FLOAT_EQ(field<float>(b, 40), 0.0F);
  EXPECT_FLOAT_EQ(field<float>(b, 44), -0.5F);
  EXPECT_EQ(field<uint16_t>(b, 48), 0x05C7);  // velocity and yaw rate
  EXPECT_EQ(b.payload[52], 8);                // MAV_FRAME_BODY_NED: body FRD for velocities
  // A corrupted byte fails the CRC.
  auto bad = f;
  bad[20] ^= 0x01;
  EXPECT_FALSE(decode(bad, 143, 53).crc_ok);
}

TEST(Mavlink, CommandLongFrame) {
  const float params[7] = {1, 6, 0, 0, 0, 0, 0};
  const Decoded d = decode(mavlink_command_long(3, 1, 191, kMavCmdDoSetMode, params), 152, 33);
  EXPECT_TRUE(d.crc_ok);
  EXPECT_EQ(d.msgid, 76u);
  EXPECT_FLOAT_EQ(field<float>(d, 0), 1.0F);  // MAV_MODE_FLAG_CUSTOM_MODE_ENABLED
  EXPECT_FLOAT_EQ(field<float>(d, 4), 6.0F);  // PX4 main mode OFFBOARD
  EXPECT_EQ(field<uint16_t>(d, 28), 176);
  EXPECT_EQ(d.payload[30], 1);
  EXPECT_EQ(d.payload[31], 1);
}

// What a stream says, frame by frame.
struct Event {
  uint32_t msgid;
  uint8_t seq;
  uint32_t time_ms;  // setpoints: their time stamp
  uint16_t command;  // COMMAND_LONG
};
std::vector<Event> events(const std::vector<std::vector<uint8_t>>& frames) {
  std::vector<Event> out;
  for (const auto& f : frames) {
    const uint32_t msgid = uint32_t(f.at(7));
    const uint8_t extra = msgid == 0 ? 50 : msgid == 76 ? 152 : 143;
    const Decoded d = decode(f, extra, msgid == 0 ? 9 : msgid == 76 ? 33 : 53);
    EXPECT_TRUE(d.crc_ok);
    out.push_back(
        {msgid, d.seq, msgid == 84 ? field<uint32_t>(d, 0) : 0, msgid == 76 ? field<uint16_t>(d, 28) : uint16_t(0)});
  }
  return out;
}

// PX4 enters OFFBOARD only after more than a second of setpoints at more than 2 Hz: the stream's
// commands come after that, once, mode before arming; heartbeats once a second.
TEST(Mavlink, StreamEntersOffboardAfterASecondOfSetpoints) {
  MavlinkStream stream;
  std::vector<std::vector<uint8_t>> frames;
  for (int i = 0; i < 150; ++i) {  // 5 s at 30 Hz
    VelocitySetpoint sp;
    sp.time_boot_ms = uint32_t(i * 100 / 3);
    for (auto& f : stream.setpoint(sp)) frames.push_back(f);
  }
  const auto ev = events(frames);
  ASSERT_FALSE(ev.empty());
  EXPECT_EQ(ev.front().msgid, 0u);
  int heartbeats = 0, modes = 0, arms = 0, setpoints_before = 0;
  uint32_t last_ms = 0, first_ms = 0;
  for (std::size_t i = 0; i < ev.size(); ++i) {
    EXPECT_EQ(ev[i].seq, uint8_t(i));
    if (ev[i].msgid == 0) ++heartbeats;
    if (ev[i].msgid == 84) {
      if (modes == 0) ++setpoints_before;
      if (setpoints_before == 1) first_ms = ev[i].time_ms;
      last_ms = ev[i].time_ms;
    }
    if (ev[i].msgid == 76 && ev[i].command == kMavCmdDoSetMode) {
      ++modes;
      EXPECT_GE(last_ms - first_ms, 1000u) << "mode requested before a second of setpoints";
      EXPECT_EQ(arms, 0) << "mode before arming";
    }
    if (ev[i].msgid == 76 && ev[i].command == kMavCmdComponentArmDisarm) ++arms;
  }
  EXPECT_EQ(modes, 1);
  EXPECT_EQ(arms, 1);
  EXPECT_GE(setpoints_before, 30);
  EXPECT_EQ(heartbeats, 5);  // at 0, 1, 2, 3 and 4 s
  EXPECT_TRUE(stream.offboard_requested());
}

// A pause in the stream: one heartbeat when it resumes (no burst), and the second of setpoints
// PX4 needs before OFFBOARD counts again from the resumption.
TEST(Mavlink, StreamAfterAPause) {
  MavlinkStream stream;
  std::vector<std::vector<uint8_t>> frames;
  auto at = [&](uint32_t ms) {
    VelocitySetpoint sp;
    sp.time_boot_ms = ms;
    for (auto& f : stream.setpoint(sp)) frames.push_back(f);
  };
  for (uint32_t t = 0; t < 1000; t += 100) at(t);
  for (uint32_t t = 3000; t <= 5000; t += 100) at(t);
  std::vector<uint32_t> heartbeats_after;  // the setpoint time each heartbeat precedes
  uint32_t mode_after_ms = 0;
  const auto ev = events(frames);
  for (std::size_t i = 0; i < ev.size(); ++i) {
    if (ev[i].msgid == 0 && i + 1 < ev.size()) heartbeats_after.push_back(ev[i + 1].time_ms);
    if (ev[i].msgid == 76 && ev[i].command == kMavCmdDoSetMode) mode_after_ms = ev[i - 1].time_ms;
  }
  EXPECT_EQ(heartbeats_after, (std::vector<uint32_t>{0, 3000, 4000, 5000}));
  EXPECT_EQ(mode_after_ms, 4100u);  // more than a second after the resumption at 3.0 s
}

// A flight's setpoints in NED (north = the flight axis z, east = x) and in the body's axes.
TEST(Mavlink, FlightFramesInNedAndBodyAxes) {
  FlightResult r;
  SentSetpoint p{};
  p.position_m = Eigen::Vector3d::Zero();
  p.vehicle_velocity_mps = Eigen::Vector3d::Zero();
  p.time_s = 0.5;
  p.velocity_mps = Eigen::Vector3d(1.0, 0.0, 2.0);  // 1 m/s right (east), 2 m/s forward (north)
  p.yaw_rad = M_PI / 2 + 0.1;
  p.vehicle_yaw_rad = M_PI / 2;  // facing east
  r.setpoints.push_back(p);
  VehicleParams vp;
  for (SetpointFrame frame : {SetpointFrame::local_ned, SetpointFrame::body_frd}) {
    const auto frames = flight_mavlink(r, frame, 0.1, vp);
    // Heartbeats at 0 and 1 s, 10 hover setpoints, the last one repeated every 0.1 s from 1.0 to
    // 1.4 s (PX4 leaves OFFBOARD under 2 Hz), mode and arm after 1.1 s, the flight's setpoint.
    ASSERT_EQ(frames.size(), 2u + 10u + 5u + 2u + 1u);
    const Decoded last = decode(frames.back(), 143, 53);
    ASSERT_EQ(last.msgid, 84u);
    EXPECT_EQ(field<uint32_t>(last, 0), 1500u);  // flight time + the second of entry
    if (frame == SetpointFrame::local_ned) {
      EXPECT_FLOAT_EQ(field<float>(last, 16), 2.0F);  // north
      EXPECT_FLOAT_EQ(field<float>(last, 20), 1.0F);  // east
      EXPECT_NEAR(field<float>(last, 40), M_PI / 2 + 0.1, 1e-6);
    } else {
      EXPECT_NEAR(field<float>(last, 16), 1.0F, 1e-6);   // forward: east
      EXPECT_NEAR(field<float>(last, 20), -2.0F, 1e-6);  // right of east is south
      EXPECT_NEAR(field<float>(last, 44), 0.28, 1e-6);   // MC_YAW_P 2.8 x 0.1 rad
    }
    int hover = 0;
    for (const auto& e : events(frames)) hover += e.msgid == 84 && e.time_ms < 1000 ? 1 : 0;
    EXPECT_EQ(hover, 10);  // a second of hover setpoints every 0.1 s
  }
}

#if defined(PARALLAX_NODE) && defined(PARALLAX_MAVLINK_CHECK)
nlohmann::json run_json(const std::string& cmd) {
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  return nlohmann::json::parse(std::ifstream(cmd.substr(cmd.rfind("> ") + 2, cmd.rfind(" 2>") - cmd.rfind("> ") - 2)));
}

// Decodes a file with node-mavlink (npm, an implementation independent of ours).
nlohmann::json node_decode(const std::string& bin, const std::filesystem::path& tmp) {
  const std::string dec = (tmp / "decoded.json").string();
  return run_json(std::string(PARALLAX_NODE) + " " + PARALLAX_MAVLINK_CHECK + "/verify.js " + bin + " > " + dec +
                  " 2>/dev/null");
}

bool node_ready() {
  return std::filesystem::exists(std::string(PARALLAX_MAVLINK_CHECK) + "/node_modules/node-mavlink");
}

// `parallax avoid --mavlink-out` on the shipped frames: every frame valid, one body-frame velocity
// setpoint per frame with its time stamp and the planner's velocity.
TEST(Mavlink, NodeMavlinkDecodesTheAvoidOutput) {
  if (!node_ready()) GTEST_SKIP() << "npm install in " << PARALLAX_MAVLINK_CHECK << " first";
  const auto tmp = std::filesystem::temp_directory_path() / "parallax_mavlink_avoid_test";
  std::filesystem::create_directories(tmp);
  const std::string bin = (tmp / "out.mav").string();
  const auto avoid_json =
      run_json(std::string(PARALLAX_CLI) + " avoid --config " + PARALLAX_CONFIG_DIR +
               "/ruf2018-census.yaml --dataset " + PARALLAX_DATA_DIR + "/kitti2015-640x360 --json --mavlink-out " +
               bin + " > " + (tmp / "avoid.json").string() + " 2>/dev/null");
  const auto decoded = node_decode(bin, tmp);
  EXPECT_EQ(decoded["invalid"].get<int>(), 0);
  const auto& frames = avoid_json["per_frame"];
  std::vector<nlohmann::json> sps;
  for (const auto& p : decoded["packets"])
    if (p["msgid"].get<int>() == 84) sps.push_back(p);
  ASSERT_EQ(sps.size(), frames.size());
  EXPECT_EQ(decoded["packets"][0]["msgid"].get<int>(), 0);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(sps[i]["typeMask"].get<int>(), 0x05C7);
    EXPECT_EQ(sps[i]["coordinateFrame"].get<int>(), 8);
    EXPECT_EQ(sps[i]["timeBootMs"].get<uint32_t>(), frames[i]["time_boot_ms"].get<uint32_t>());
    const auto& v = frames[i]["velocity_mps"];
    EXPECT_FLOAT_EQ(sps[i]["vx"].get<float>(), v[0].get<float>());
    EXPECT_FLOAT_EQ(sps[i]["vy"].get<float>(), v[1].get<float>());
    EXPECT_FLOAT_EQ(sps[i]["vz"].get<float>(), v[2].get<float>());
  }
}

// `parallax fly --mavlink-out` through a scene: heartbeats a second apart, a second of setpoints
// at more than 2 Hz before OFFBOARD (mode 6) and arming, then the loop's setpoints (the trace's) in
// NED at flight time + 1 s.
TEST(Mavlink, NodeMavlinkDecodesTheFlightStream) {
  if (!node_ready()) GTEST_SKIP() << "npm install in " << PARALLAX_MAVLINK_CHECK << " first";
  const auto tmp = std::filesystem::temp_directory_path() / "parallax_mavlink_fly_test";
  std::filesystem::create_directories(tmp);
  const std::string bin = (tmp / "flight.mav").string(), trace = (tmp / "trace.csv").string();
  const std::string cmd = std::string(PARALLAX_CLI) + " fly --config " + PARALLAX_CONFIG_DIR +
                          "/ruf2018-census.yaml --scenario single-pole --seeds 1 --size 160 --no-oracle "
                          "--time-limit-s 4 --speed-mps 3 --trace-csv " +
                          trace + " --mavlink-out " + bin + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const auto decoded = node_decode(bin, tmp);
  EXPECT_EQ(decoded["invalid"].get<int>(), 0);
  EXPECT_EQ(decoded["unknown"].get<int>(), 0);
  std::ifstream in(trace);
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<double>> rows;  // time_s, sp_vx, sp_vz, sp_yaw_deg
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::vector<std::string> c;
    for (std::string cell; std::getline(ss, cell, ',');) c.push_back(cell);
    rows.push_back({std::stod(c[2]), std::stod(c[8]), std::stod(c[9]), std::stod(c[10])});
  }
  ASSERT_GT(rows.size(), 50u);
  const auto& packets = decoded["packets"];
  ASSERT_EQ(packets[0]["msgid"].get<int>(), 0);
  std::vector<uint32_t> heartbeat_ms;
  uint32_t last_sp_ms = 0, first_sp_ms = 0, mode_ms = 0;
  int sps = 0, modes = 0, arms = 0, before_mode = 0;
  std::size_t flight = 0;
  for (std::size_t i = 0; i < packets.size(); ++i) {
    const auto& p = packets[i];
    EXPECT_EQ(p["seq"].get<int>(), int(i % 256));
    EXPECT_EQ(p["sysid"].get<int>(), 1);
    EXPECT_EQ(p["compid"].get<int>(), 191);
    const int id = p["msgid"].get<int>();
    if (id == 0) heartbeat_ms.push_back(last_sp_ms);
    if (id == 76) {
      if (p["command"].get<int>() == 176) {
        ++modes;
        mode_ms = last_sp_ms;
        EXPECT_FLOAT_EQ(p["_param2"].get<float>(), 6.0F);  // PX4 OFFBOARD
        EXPECT_EQ(arms, 0);
      } else {
        EXPECT_EQ(p["command"].get<int>(), 400);
        EXPECT_FLOAT_EQ(p["_param1"].get<float>(), 1.0F);
        ++arms;
      }
    }
    if (id != 84) continue;
    const uint32_t t = p["timeBootMs"].get<uint32_t>();
    if (sps++ == 0) first_sp_ms = t;
    EXPECT_GE(t, last_sp_ms);
    EXPECT_LT(t - last_sp_ms, 500u) << "setpoints must come at more than 2 Hz";
    last_sp_ms = t;
    EXPECT_EQ(p["coordinateFrame"].get<int>(), 1);
    if (t < 1000) {  // hover before the switch
      EXPECT_EQ(modes, 0);
      EXPECT_EQ(p["vx"].get<double>(), 0.0);
      EXPECT_EQ(p["vy"].get<double>(), 0.0);
      ++before_mode;
      continue;
    }
    ASSERT_LT(flight, rows.size());
    const auto& r = rows[flight++];
    EXPECT_NEAR(t, (r[0] + 1.0) * 1000.0, 1.0);
    EXPECT_NEAR(p["vx"].get<double>(), r[2], 1e-3);  // north = forward (z)
    EXPECT_NEAR(p["vy"].get<double>(), r[1], 1e-3);  // east = right (x)
    EXPECT_NEAR(p["yaw"].get<double>() * 180.0 / M_PI, r[3], 0.06);
  }
  EXPECT_EQ(flight, rows.size());
  EXPECT_EQ(modes, 1);
  EXPECT_EQ(arms, 1);
  EXPECT_GE(mode_ms - first_sp_ms, 1000u);  // after a second of setpoints
  EXPECT_GE(before_mode, 3);
  ASSERT_GE(heartbeat_ms.size(), 4u);
  for (std::size_t i = 1; i < heartbeat_ms.size(); ++i)
    EXPECT_NEAR(double(heartbeat_ms[i] - heartbeat_ms[i - 1]), 1000.0, 60.0) << "heartbeat " << i;
}
#endif

}  // namespace
}  // namespace parallax::test
