// Closed-loop flights (fly.hpp).
#include "parallax/uav/fly.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <random>

#include "parallax/eval/evaluate.hpp"
#include "parallax/eval/simulate.hpp"
#include "parallax/sim/cycle.hpp"

namespace parallax::explore {

void design_timing(const config::PipelineConfig& cfg, int w, int h, double& interval_ms, double& latency_ms) {
  const SimulationResult sr = simulate_timing(cfg, w, h);
  interval_ms = sr.frame_interval_ms;
  latency_ms = sr.latency_ms;
}

std::pair<double, double> wilson_interval_pct(int hits, int trials, double z) {
  if (trials <= 0) return {0.0, 100.0};
  const double n = trials, p = hits / n, z2 = z * z;
  const double centre = (p + z2 / (2 * n)) / (1 + z2 / n);
  const double half = z * std::sqrt(p * (1 - p) / n + z2 / (4 * n * n)) / (1 + z2 / n);
  return {100.0 * std::max(0.0, centre - half), 100.0 * std::min(1.0, centre + half)};
}

double stopping_distance_speed_bound(double a, double tau, double d) {
  return a * (std::sqrt(tau * tau + 2.0 * d / a) - tau);
}

FlightResult fly(const config::PipelineConfig& cfg_in, const Scene& scene, const FlightParams& fp,
                 uint32_t noise_seed) {
  config::PipelineConfig cfg = cfg_in;
  const int w = fp.width_px, h = fp.width_px * 9 / 16;
  cfg.roi_full = false;
  cfg.roi_width_px = w;
  cfg.roi_height_px = h;
  double interval_ms = 0, latency_ms = 0;
  design_timing(cfg, w, h, interval_ms, latency_ms);
  const Rig rig = scene_rig(w, h);
  AvoidParams ap;
  ap.cruise_mps = fp.speed_mps;
  ap.sidestep_mps = std::max(1.5, 0.6 * fp.speed_mps);
  ap.vehicle_radius_m = fp.vehicle_radius_m;
  // Look far enough ahead to stop: the critical distance grows with the speed.
  ap.critical_distance_m = std::max(12.0, 2.0 * fp.speed_mps * fp.speed_mps / (2.0 * fp.max_accel_mps2) + fp.speed_mps);
  ap.u_threshold = std::max(6, 18 * w / 640);
  ap.min_area_cells = std::max(4, 12 * w / 640);
  std::mt19937 rng(noise_seed);
  std::normal_distribution<double> noise(0.0, fp.disparity_noise_px);
  sim::FuncPipeline pipe;
  FlightResult r;
  Eigen::Vector3d p(0, -1.6, 0), v(0, 0, fp.speed_mps), cmd(0, 0, fp.speed_mps);
  std::deque<std::pair<double, Eigen::Vector3d>> pending;  // (time it takes effect, world velocity)
  const double frame_s = std::max(interval_ms / 1000.0, 1.0 / fp.camera_fps);
  double next_frame = 0.0;
  for (double t = 0; t < fp.time_limit_s; t += fp.dt_s) {
    if (t >= next_frame) {
      next_frame += frame_s;
      StereoFrame f = render(scene, rig, w, h, p);
      if (fp.disparity_noise_px > 0)
        for (cv::Mat* m : {&f.left, &f.right})
          for (int i = 0; i < int(m->total()); ++i)
            m->data[i] = uint8_t(std::clamp(double(m->data[i]) + noise(rng), 0.0, 255.0));
      const DisparityMap d = run_design(cfg, f.left, f.right, pipe);
      const AvoidResult a = avoid(d.disparity_px, d.valid_mask, cfg.disparity_end_px(), rig, ap);
      // Body (x forward, y right, z down) to world (x right, y down, z forward).
      const Eigen::Vector3d world(a.velocity_mps.y(), a.velocity_mps.z(), a.velocity_mps.x());
      // The avoidance stage's time is the configuration's model, not this machine's clock.
      pending.emplace_back(t + latency_ms / 1000.0 + cfg.avoid_ms / 1000.0, world);
      r.trajectory.push_back(p);
      ++r.frames;
    }
    while (!pending.empty() && pending.front().first <= t) {
      cmd = pending.front().second;
      pending.pop_front();
    }
    // First-order response under an acceleration limit.
    Eigen::Vector3d acc = (cmd - v) / fp.response_s;
    if (acc.norm() > fp.max_accel_mps2) acc *= fp.max_accel_mps2 / acc.norm();
    v += acc * fp.dt_s;
    const Eigen::Vector3d step = v * fp.dt_s;
    p += step;
    p.y() = std::min(p.y(), -0.3);  // the vehicle keeps off the ground
    r.path_length_m += step.norm();
    const double c = clearance_m(scene, p) - fp.vehicle_radius_m;
    r.min_clearance_m = std::min(r.min_clearance_m, c);
    r.time_s = t;
    if (c < 0) {
      r.collided = true;
      break;
    }
    if (p.z() >= scene.goal_z_m) {
      r.reached_goal = true;
      break;
    }
  }
  return r;
}

}  // namespace parallax::explore
