// Closed-loop flights (docs/flight.md): a multicopter (vehicle.hpp) flies through a synthetic
// scene; every frame interval of the design (cycle model at its clock, plus the configuration's
// system figures) its rig is rendered at the vehicle's pose, the design's kernels (or, for the
// oracle, the exact disparity) give the disparity, which after the design's latency and the
// avoidance stage's modelled time enters the planner's map (planner.hpp); the planner's velocity
// and yaw setpoints then drive the vehicle.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "parallax/config/config.hpp"
#include "parallax/uav/avoid.hpp"
#include "parallax/uav/planner.hpp"
#include "parallax/uav/mavlink.hpp"
#include "parallax/uav/scene.hpp"
#include "parallax/uav/vehicle.hpp"

namespace parallax::uav {

struct FlightParams {
  double speed_mps = 5.0;  // cruise speed the planner commands when free
  VehicleParams vehicle;
  double time_limit_s = 60.0;
  double dt_s = 0.005;  // integration step
  // 0: the design's own region of interest on the scenario's sensor (the default: the design's
  // timing and range). > 0: the rig scaled to this width (a quick look; the design runs and is
  // timed at that size).
  int width_px = 0;
  double camera_fps = 30.0;  // the cameras' rate: frames come no faster than this nor the design
  bool oracle = false;       // exact disparity instead of the design's: the planner's own limits
  // Not empty: every 10th frame, the planner's map (white free, black occupied, grey unseen) and
  // the pixels it took as obstacle points (white; grey: other trusted points) and the left image
  // go here as PNGs.
  std::string debug_dir;
};

// What a flight is flown with: the design at its window, the rig, the timing.
struct FlightSetup {
  config::PipelineConfig cfg;  // with the processed window as its ROI
  int width_px = 0, height_px = 0;
  Rig rig;
  double frame_interval_ms = 0, latency_ms = 0;  // the design's, from the cycle model
  double frame_s = 0;                            // max(design interval, camera frame)
  double reaction_s = 0;                         // latency + avoid_ms: capture to setpoint
};
FlightSetup flight_setup(const config::PipelineConfig& cfg, const Scenario& sc, const FlightParams& fp);

enum class Outcome { goal, collision, out_of_bounds, time_out };
const char* to_string(Outcome o);

// One setpoint the loop sent: when (flight time), the world-frame velocity and yaw.
struct SentSetpoint {
  double time_s;
  Eigen::Vector3d velocity_mps;
  double yaw_rad;
  // The vehicle then, and why: the planner's free distance along its heading, braking.
  Eigen::Vector3d position_m, vehicle_velocity_mps;
  double vehicle_yaw_rad, free_m;
  bool braking;
};

struct FlightResult {
  Outcome outcome = Outcome::time_out;
  std::string hit;  // the obstacle of a collision (nearest_obstacle)
  bool reached_goal = false, collided = false;
  double min_clearance_m = 1e9, path_length_m = 0, time_s = 0;
  int frames = 0, flips = 0;
  int recoveries = 0;                       // stops long enough to start the planner's recovery (Planner::recoveries)
  std::vector<Eigen::Vector3d> trajectory;  // sampled every frame
  std::vector<CameraPose> poses;            // the left camera's at every frame
  std::vector<SentSetpoint> setpoints;
  double render_wall_s = 0, perception_wall_s = 0;  // this machine's time spent rendering, in the design
};

FlightResult fly(const config::PipelineConfig& cfg, const Scenario& scenario, const Scene& scene,
                 const FlightParams& fp, uint32_t seed = 1);

// The MAVLink stream the loop sent (mavlink.hpp), as a companion computer booted entry_s before
// the flight would send it: hover setpoints from boot every min(period_s, 0.1 s), the loop's
// setpoints at their flight time + entry_s (each repeated every 0.1 s while the next is not due,
// so the rate never drops under PX4's 2 Hz), a heartbeat every second, and DO_SET_MODE OFFBOARD
// and ARM after the first setpoint more than entry_s after the first. World (x right, y down, z
// forward) maps to NED as north = z, east = x, down = y (the flight axis taken as north: a real
// vehicle's local frame needs its heading at boot); body_frd gives the velocity in the vehicle's
// axes when sent and the yaw rate its controller would command (MC_YAW_P, MPC_YAWRAUTO_MAX).
std::vector<std::vector<uint8_t>> flight_mavlink(const FlightResult& r, SetpointFrame frame, double period_s,
                                                 const VehicleParams& vehicle, double entry_s = 1.0);

// The design's frame interval and latency (ms) at its clock, from the cycle model, for images of
// the given size.
void design_timing(const config::PipelineConfig& cfg, int width_px, int height_px, double& frame_interval_ms,
                   double& latency_ms);

// v_max = a (sqrt(tau^2 + 2 d / a) - tau): the speed from which a vehicle reacting after tau and
// braking at a stops within the sensing range d (../shared/docs/published-numbers.md).
double stopping_distance_speed_bound(double accel_mps2, double reaction_s, double range_m);
// Wilson score interval of a rate, in percent: `hits` of `trials` at the normal quantile z (1.96:
// 95 %); {0, 100} when there are no trials.
std::pair<double, double> wilson_interval_pct(int hits, int trials, double z = 1.96);

}  // namespace parallax::uav
