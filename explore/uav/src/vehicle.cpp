// The multicopter's velocity loop (vehicle.hpp).
#include "parallax/uav/vehicle.hpp"

#include <algorithm>
#include <cmath>

namespace parallax::uav {

double wrap_angle(double a) {
  a = std::fmod(a + M_PI, 2.0 * M_PI);
  if (a <= 0) a += 2.0 * M_PI;
  return a - M_PI;
}

void step_vehicle(VehicleState& s, const Eigen::Vector3d& v_sp, double yaw_sp, const VehicleParams& p, double dt) {
  constexpr double kGravity = 9.81;
  Eigen::Vector3d want = p.vel_gain_per_s * (v_sp - s.velocity_mps);
  want.y() = 0;  // altitude hold
  // The tilt bounds the horizontal acceleration too: tan(tilt) g.
  const double limit = std::min(p.max_accel_mps2, std::tan(p.max_tilt_deg * M_PI / 180.0) * kGravity);
  if (want.norm() > limit) want *= limit / want.norm();
  Eigen::Vector3d change = want - s.accel_mps2;
  const double max_change = p.max_jerk_mps3 * dt;
  if (change.norm() > max_change) change *= max_change / change.norm();
  s.accel_mps2 += change;
  s.velocity_mps += s.accel_mps2 * dt;
  s.position_m += s.velocity_mps * dt;
  const double err = wrap_angle(yaw_sp - s.yaw_rad);
  const double rate_max = p.max_yaw_rate_dps * M_PI / 180.0;
  s.yaw_rad = wrap_angle(s.yaw_rad + std::clamp(p.yaw_gain_per_s * err, -rate_max, rate_max) * dt);
  // Thrust balances gravity, the acceleration and the drag: the body leans into a + k v.
  const Eigen::Vector3d lean = s.accel_mps2 + p.drag_per_s * s.velocity_mps;
  const Eigen::Vector3d ahead(std::sin(s.yaw_rad), 0, std::cos(s.yaw_rad));
  const double tilt_max = p.max_tilt_deg * M_PI / 180.0;
  s.pitch_rad = std::clamp(-std::atan2(lean.dot(ahead), kGravity), -tilt_max, tilt_max);
}

}  // namespace parallax::uav
