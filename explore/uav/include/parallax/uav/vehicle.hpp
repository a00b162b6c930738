// The multicopter of closed-loop flights (docs/flight.md): a point mass under a velocity loop
// shaped like PX4's multicopter position controller in offboard velocity control. Every figure is
// a PX4 default (src/modules/mc_pos_control and mc_att_control parameter files) unless said.
#pragma once

#include <Eigen/Core>

namespace parallax::uav {

struct VehicleParams {
  double vel_gain_per_s = 1.8;     // MPC_XY_VEL_P_ACC: acceleration per m/s of velocity error
  double max_accel_mps2 = 3.0;     // MPC_ACC_HOR: the horizontal acceleration limit
  double max_jerk_mps3 = 8.0;      // MPC_JERK_MAX: how fast the acceleration setpoint may change
  double max_tilt_deg = 45.0;      // MPC_TILTMAX_AIR
  double yaw_gain_per_s = 2.8;     // MC_YAW_P: yaw rate per rad of yaw error
  double max_yaw_rate_dps = 45.0;  // MPC_YAWRAUTO_MAX: yaw rate limit in autonomous modes
  // Linear drag (an assumption, not PX4's): at 5 m/s a 1.5 m/s^2 drag, so the body pitches about
  // 9 degrees nose-down in cruise; the cameras pitch with it.
  double drag_per_s = 0.3;
  double radius_m = 0.5;  // collision radius
};

// World frame as the scenes': x right, y down, z forward; yaw 0 = +z, positive towards +x; pitch
// positive nose-up. The vehicle holds its altitude (y constant).
struct VehicleState {
  Eigen::Vector3d position_m{0, -1.6, 0};
  Eigen::Vector3d velocity_mps{0, 0, 0};
  Eigen::Vector3d accel_mps2{0, 0, 0};
  double yaw_rad = 0, pitch_rad = 0;
};

// One integration step of dt: the acceleration setpoint K (v_sp - v), limited in norm and rate
// (jerk), integrated; the yaw turned towards yaw_sp at the limited rate; the pitch that balances
// acceleration and drag (thrust along the body's up axis), limited to the tilt.
void step_vehicle(VehicleState& s, const Eigen::Vector3d& velocity_setpoint_mps, double yaw_setpoint_rad,
                  const VehicleParams& p, double dt_s);

// An angle wrapped into (-pi, pi].
double wrap_angle(double rad);

}  // namespace parallax::uav
