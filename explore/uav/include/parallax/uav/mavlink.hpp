// MAVLink 2 as the companion computer speaks it to a PX4 autopilot (docs/flight.md): frames
// encoded by hand (a handful of messages, no generated library), the OFFBOARD entry sequence, a
// 1 Hz heartbeat, velocity setpoints in the local NED frame or the body frame, and sinks (a file
// of frames back to back, or UDP).
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <netinet/in.h>

namespace parallax::uav {

// CRC-16/MCRF4XX (X.25) as MAVLink uses it: init 0xFFFF, reflected polynomial 0x1021.
uint16_t mavlink_crc(const uint8_t* data, std::size_t n, uint16_t crc = 0xFFFF);

// Frames: 0xFD, len, incompat 0, compat 0, seq, sysid, compid, 24-bit msgid, payload with trailing
// zeros trimmed, CRC over everything after the magic plus the message's CRC_EXTRA.
// HEARTBEAT (0) of an onboard controller (MAV_TYPE_ONBOARD_CONTROLLER, MAV_AUTOPILOT_INVALID).
std::vector<uint8_t> mavlink_heartbeat(uint8_t seq, uint8_t sysid, uint8_t compid);

// The frame a velocity setpoint is given in.
enum class SetpointFrame {
  local_ned,  // MAV_FRAME_LOCAL_NED (1): north, east, down; with the yaw to hold
  body_frd,   // forward, right, down of the vehicle when sent; with a yaw rate. Sent as
              // MAV_FRAME_BODY_NED (8), which MAVLink defines as body FRD for velocities and which
              // PX4's offboard mode accepts (its docs list LOCAL_NED and BODY_NED, not BODY_FRD = 12)
};
// type_mask of each: position and acceleration ignored, and the yaw rate (local_ned: 0x09C7) or
// the yaw (body_frd: 0x05C7).
uint16_t setpoint_type_mask(SetpointFrame f);
uint8_t setpoint_coordinate_frame(SetpointFrame f);

struct VelocitySetpoint {
  uint32_t time_boot_ms = 0;
  Eigen::Vector3d velocity_mps{0, 0, 0};  // in the frame's axes
  double yaw_rad = 0;                     // local_ned: heading from north, positive to the east
  double yaw_rate_rps = 0;                // body_frd
  SetpointFrame frame = SetpointFrame::local_ned;
};
// SET_POSITION_TARGET_LOCAL_NED (84).
std::vector<uint8_t> mavlink_velocity_setpoint(uint8_t seq, uint8_t sysid, uint8_t compid, const VelocitySetpoint& sp,
                                               uint8_t target_system = 1, uint8_t target_component = 1);

// COMMAND_LONG (76) with params 1-7.
std::vector<uint8_t> mavlink_command_long(uint8_t seq, uint8_t sysid, uint8_t compid, uint16_t command,
                                          const float (&params)[7], uint8_t target_system = 1,
                                          uint8_t target_component = 1);
constexpr uint16_t kMavCmdDoSetMode = 176;           // param1 base mode, param2 custom main mode
constexpr uint16_t kMavCmdComponentArmDisarm = 400;  // param1 1 = arm
constexpr float kMavModeFlagCustomModeEnabled = 1;
constexpr float kPx4CustomMainModeOffboard = 6;

// The stream a companion computer sends: a heartbeat at start and once a second after (one, never
// a burst, after a pause), velocity setpoints as they come, and, once setpoints have streamed for
// more than entry_s without a gap of kMaxSetpointGapMs (PX4 wants > 2 Hz for more than a second
// before it enters OFFBOARD), DO_SET_MODE OFFBOARD then ARM, once. The vehicle is taken to be
// airborne and holding (PX4's Position mode) when the companion takes over: ARM is then a no-op,
// and the stream does not take off. Sequence numbers wrap at 256.
class MavlinkStream {
 public:
  static constexpr uint32_t kMaxSetpointGapMs = 500;
  explicit MavlinkStream(uint8_t sysid = 1, uint8_t compid = 191, double entry_s = 1.0)
      : sysid_(sysid), compid_(compid), entry_ms_(uint32_t(entry_s * 1000.0)) {}
  // The heartbeat when one is due, the setpoint, then the commands once the setpoints span more
  // than entry_s. Times must not go back.
  std::vector<std::vector<uint8_t>> setpoint(const VelocitySetpoint& sp);
  bool offboard_requested() const { return entered_; }

 private:
  uint8_t sysid_, compid_;
  uint32_t entry_ms_;
  uint8_t seq_ = 0;
  bool started_ = false, entered_ = false;
  uint32_t first_setpoint_ms_ = 0, last_setpoint_ms_ = 0, next_heartbeat_ms_ = 0;
};

// A destination for frames: a file (binary frames back to back) or udp:IPv4:PORT; nothing when
// empty. Throws InputError naming `option` when the destination cannot be used.
class MavlinkSink {
 public:
  MavlinkSink(const std::string& where, const std::string& option);
  ~MavlinkSink();
  MavlinkSink(const MavlinkSink&) = delete;
  MavlinkSink& operator=(const MavlinkSink&) = delete;
  void send(const std::vector<uint8_t>& frame);
  bool active() const { return fd_ >= 0 || file_.is_open(); }

 private:
  std::ofstream file_;
  int fd_ = -1;
  sockaddr_in addr_{};
};

}  // namespace parallax::uav
