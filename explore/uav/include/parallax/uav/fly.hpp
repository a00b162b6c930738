// Closed-loop flights (issue 8, docs/flight.md): a point-mass UAV flies through a synthetic scene;
// every frame interval of the design (cycle model at its clock) the stereo rig is rendered, the
// design's kernels compute the disparity, the avoidance stage plans, and the command takes effect
// after the design's latency plus the stage's own time.
#pragma once

#include <utility>
#include <string>
#include <vector>

#include "parallax/config/config.hpp"
#include "parallax/uav/avoid.hpp"
#include "parallax/uav/scene.hpp"

namespace parallax::explore {

struct FlightParams {
  double speed_mps = 5.0;       // cruise speed commanded
  double max_accel_mps2 = 4.0;  // |a| limit
  double response_s = 0.3;      // first-order velocity response time constant
  double vehicle_radius_m = 0.5;
  double time_limit_s = 40.0;
  double dt_s = 0.005;              // integration step
  double disparity_noise_px = 0.0;  // sensor noise added to the pixels (grey levels, sigma)
  int width_px = 320;               // rendered size; the design's ROI is set to it
  double camera_fps = 30.0;         // the cameras' rate: frames come no faster than this nor the design
};

struct FlightResult {
  bool reached_goal = false, collided = false;
  double min_clearance_m = 1e9, path_length_m = 0, time_s = 0;
  int frames = 0;
  std::vector<Eigen::Vector3d> trajectory;  // sampled every frame
};

// The design's frame interval and latency (ms) at its clock, from the cycle model, for images of
// the given size.
void design_timing(const config::PipelineConfig& cfg, int width_px, int height_px, double& frame_interval_ms,
                   double& latency_ms);

FlightResult fly(const config::PipelineConfig& cfg, const Scene& scene, const FlightParams& fp,
                 uint32_t noise_seed = 1);

// v_max = a (sqrt(tau^2 + 2 d / a) - tau): the speed from which a vehicle reacting after tau and
// braking at a stops within the sensing range d (../shared/docs/published-numbers.md).
double stopping_distance_speed_bound(double accel_mps2, double reaction_s, double range_m);
// Wilson score interval of a rate, in percent: `hits` of `trials` at the normal quantile z (1.96:
// 95 %); {0, 100} when there are no trials.
std::pair<double, double> wilson_interval_pct(int hits, int trials, double z = 1.96);

}  // namespace parallax::explore
