// MAVLink 2 frames, the companion's stream and its sinks (mavlink.hpp).
#include "parallax/uav/mavlink.hpp"

#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>

#include "parallax/eval/input_error.hpp"

namespace parallax::uav {

// The names this file takes from the other rooms (one namespace per room).
using eval::InputError;

uint16_t mavlink_crc(const uint8_t* data, std::size_t n, uint16_t crc) {
  for (std::size_t i = 0; i < n; ++i) {
    uint8_t tmp = uint8_t(data[i] ^ uint8_t(crc & 0xFF));
    tmp = uint8_t(tmp ^ uint8_t(tmp << 4));
    crc = uint16_t((crc >> 8) ^ (uint16_t(tmp) << 8) ^ (uint16_t(tmp) << 3) ^ (tmp >> 4));
  }
  return crc;
}

namespace {

std::vector<uint8_t> frame(uint8_t seq, uint8_t sysid, uint8_t compid, uint32_t msgid, std::vector<uint8_t> payload,
                           uint8_t crc_extra) {
  while (payload.size() > 1 && payload.back() == 0) payload.pop_back();  // MAVLink 2 truncation
  const std::size_t n = payload.size();
  std::vector<uint8_t> f(10 + n + 2, 0);
  const uint8_t header[10] = {0xFD,
                              uint8_t(n),
                              0,
                              0,
                              seq,
                              sysid,
                              compid,
                              uint8_t(msgid & 0xFF),
                              uint8_t((msgid >> 8) & 0xFF),
                              uint8_t((msgid >> 16) & 0xFF)};
  for (std::size_t i = 0; i < 10; ++i) f[i] = header[i];
  for (std::size_t i = 0; i < n; ++i) f[10 + i] = payload[i];
  uint16_t crc = mavlink_crc(f.data() + 1, 9 + n);
  crc = mavlink_crc(&crc_extra, 1, crc);
  f[10 + n] = uint8_t(crc & 0xFF);
  f[11 + n] = uint8_t(crc >> 8);
  return f;
}

template <class T>
void put(std::vector<uint8_t>& b, T v) {
  uint8_t raw[sizeof(T)];
  std::memcpy(raw, &v, sizeof(T));  // little-endian host (x86, ARM): MAVLink's wire order
  b.insert(b.end(), raw, raw + sizeof(T));
}

}  // namespace

std::vector<uint8_t> mavlink_heartbeat(uint8_t seq, uint8_t sysid, uint8_t compid) {
  std::vector<uint8_t> p;
  put<uint32_t>(p, 0);  // custom_mode
  p.push_back(18);      // type: MAV_TYPE_ONBOARD_CONTROLLER
  p.push_back(8);       // autopilot: MAV_AUTOPILOT_INVALID (not an autopilot)
  p.push_back(0);       // base_mode
  p.push_back(4);       // system_status: MAV_STATE_ACTIVE
  p.push_back(3);       // mavlink_version
  return frame(seq, sysid, compid, 0, p, 50);
}

uint16_t setpoint_type_mask(SetpointFrame f) {
  // Bits: 1|2|4 position, 64|128|256 acceleration, 1024 yaw, 2048 yaw rate (ignored when set).
  return f == SetpointFrame::local_ned ? 0x09C7 : 0x05C7;
}

uint8_t setpoint_coordinate_frame(SetpointFrame f) {
  return f == SetpointFrame::local_ned ? 1 : 8;
}

std::vector<uint8_t> mavlink_velocity_setpoint(uint8_t seq, uint8_t sysid, uint8_t compid, const VelocitySetpoint& sp,
                                               uint8_t target_system, uint8_t target_component) {
  std::vector<uint8_t> p;
  put<uint32_t>(p, sp.time_boot_ms);
  for (int i = 0; i < 3; ++i) put<float>(p, 0);  // x, y, z
  for (int i = 0; i < 3; ++i) put<float>(p, float(sp.velocity_mps[i]));
  for (int i = 0; i < 3; ++i) put<float>(p, 0);  // afx, afy, afz
  const bool ned = sp.frame == SetpointFrame::local_ned;
  put<float>(p, ned ? float(sp.yaw_rad) : 0.0F);
  put<float>(p, ned ? 0.0F : float(sp.yaw_rate_rps));
  put<uint16_t>(p, setpoint_type_mask(sp.frame));
  p.push_back(target_system);
  p.push_back(target_component);
  p.push_back(setpoint_coordinate_frame(sp.frame));
  return frame(seq, sysid, compid, 84, p, 143);
}

std::vector<uint8_t> mavlink_command_long(uint8_t seq, uint8_t sysid, uint8_t compid, uint16_t command,
                                          const float (&params)[7], uint8_t target_system, uint8_t target_component) {
  std::vector<uint8_t> p;
  for (float v : params) put<float>(p, v);
  put<uint16_t>(p, command);
  p.push_back(target_system);
  p.push_back(target_component);
  p.push_back(0);  // confirmation
  return frame(seq, sysid, compid, 76, p, 152);
}

std::vector<std::vector<uint8_t>> MavlinkStream::setpoint(const VelocitySetpoint& sp) {
  std::vector<std::vector<uint8_t>> out;
  const uint32_t t = sp.time_boot_ms;
  if (!started_) {
    started_ = true;
    first_setpoint_ms_ = t;
    next_heartbeat_ms_ = t;
  } else if (t - last_setpoint_ms_ >= kMaxSetpointGapMs && !entered_) {
    first_setpoint_ms_ = t;  // the stream broke: PX4 would not count what came before
  }
  last_setpoint_ms_ = t;
  if (t >= next_heartbeat_ms_) {  // one heartbeat, even after a long gap
    out.push_back(mavlink_heartbeat(seq_++, sysid_, compid_));
    next_heartbeat_ms_ += 1000;
    if (next_heartbeat_ms_ <= t) next_heartbeat_ms_ = t + 1000;
  }
  out.push_back(mavlink_velocity_setpoint(seq_++, sysid_, compid_, sp));
  if (!entered_ && t - first_setpoint_ms_ > entry_ms_) {  // after the setpoint that completes the span
    entered_ = true;
    const float mode[7] = {kMavModeFlagCustomModeEnabled, kPx4CustomMainModeOffboard, 0, 0, 0, 0, 0};
    out.push_back(mavlink_command_long(seq_++, sysid_, compid_, kMavCmdDoSetMode, mode));
    const float arm[7] = {1, 0, 0, 0, 0, 0, 0};
    out.push_back(mavlink_command_long(seq_++, sysid_, compid_, kMavCmdComponentArmDisarm, arm));
  }
  return out;
}

MavlinkSink::MavlinkSink(const std::string& where, const std::string& option) {
  if (where.empty()) return;
  if (where.rfind("udp:", 0) == 0) {
    const auto colon = where.rfind(':');
    const std::string host = where.substr(4, colon - 4);
    const int port = std::atoi(where.substr(colon + 1).c_str());
    addr_.sin_family = AF_INET;
    addr_.sin_port = htons(uint16_t(port));
    if (colon <= 4 || port <= 0 || port > 65535 || inet_pton(AF_INET, host.c_str(), &addr_.sin_addr) != 1)
      throw InputError(option + " '" + where + "': expected udp:IPv4:PORT");
    fd_ = socket(AF_INET, SOCK_DGRAM, 0);
    if (fd_ < 0) throw InputError(option + " '" + where + "': cannot open a UDP socket");
    return;
  }
  file_.open(where, std::ios::binary);
  if (!file_) throw InputError(option + " '" + where + "': cannot write");
}

MavlinkSink::~MavlinkSink() {
  if (fd_ >= 0) close(fd_);
}

void MavlinkSink::send(const std::vector<uint8_t>& f) {
  if (file_.is_open()) file_.write(reinterpret_cast<const char*>(f.data()), std::streamsize(f.size()));
  if (fd_ >= 0) (void)sendto(fd_, f.data(), f.size(), 0, reinterpret_cast<const sockaddr*>(&addr_), sizeof addr_);
}

}  // namespace parallax::uav
