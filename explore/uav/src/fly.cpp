// Closed-loop flights (fly.hpp).
#include "parallax/uav/fly.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <random>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "parallax/eval/evaluate.hpp"
#include "parallax/eval/simulate.hpp"
#include "parallax/sim/cycle.hpp"

namespace parallax::uav {

// The names this file takes from the other rooms (one namespace per room).
using eval::DisparityMap;
using eval::run_design;
using eval::simulate_timing;
using eval::SimulationResult;

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

const char* to_string(Outcome o) {
  switch (o) {
    case Outcome::goal:
      return "goal";
    case Outcome::collision:
      return "collision";
    case Outcome::out_of_bounds:
      return "out of bounds";
    case Outcome::time_out:
    default:
      return "time out";
  }
}

FlightSetup flight_setup(const config::PipelineConfig& cfg, const Scenario& sc, const FlightParams& fp) {
  FlightSetup s;
  s.cfg = cfg;
  const RigSpec spec = scaled_rig(sc.rig, fp.width_px);
  // The whole rig scaled (the design processes the scaled sensor), or a full-frame design: the
  // sensor; else the design's own window on it.
  if (fp.width_px > 0 || cfg.roi_full) {
    s.width_px = spec.width_px;
    s.height_px = spec.height_px;
  } else {
    s.width_px = cfg.roi_width_px;
    s.height_px = cfg.roi_height_px;
  }
  s.cfg.roi_full = false;
  s.cfg.roi_width_px = s.width_px;
  s.cfg.roi_height_px = s.height_px;
  s.rig = rig_of(spec, s.width_px, s.height_px);
  design_timing(s.cfg, s.width_px, s.height_px, s.frame_interval_ms, s.latency_ms);
  s.frame_s = std::max(s.frame_interval_ms / 1000.0, 1.0 / fp.camera_fps);
  s.reaction_s = (s.latency_ms + cfg.avoid_ms) / 1000.0;
  return s;
}

namespace {

// A frame captured and on its way through the design and the avoidance stage.
struct InFlight {
  double ready_s;
  cv::Mat disparity_px, valid_mask, left;
  CameraPose pose;
};

// Every 10th frame of a flight: the planner's map and the pixels it took as obstacles
// (FlightParams::debug_dir).
void write_debug_pictures(const FlightParams& fp, uint32_t seed, int frame, const LocalMap& map, const cv::Mat& hits,
                          const cv::Mat& left) {
  char stem[96];
  std::snprintf(stem, sizeof stem, "/%s_seed%u_frame%04d", fp.oracle ? "oracle" : "design", seed, frame);
  cv::Mat big;
  cv::resize(map.picture(), big, cv::Size(), 2, 2, cv::INTER_NEAREST);
  cv::imwrite(fp.debug_dir + stem + "_map.png", big);
  cv::imwrite(fp.debug_dir + stem + "_obstacle_pixels.png", hits);
  cv::imwrite(fp.debug_dir + stem + "_left.png", left);
}

}  // namespace

FlightResult fly(const config::PipelineConfig& cfg, const Scenario& sc, const Scene& scene, const FlightParams& fp,
                 uint32_t seed) {
  using clock = std::chrono::steady_clock;
  const FlightSetup setup = flight_setup(cfg, sc, fp);
  PlannerParams pp;
  pp.cruise_mps = fp.speed_mps;
  pp.brake_mps2 = 0.8 * fp.vehicle.max_accel_mps2;
  // Capture to setpoint, a frame's age, and the jerk-limited onset of braking (a / 2j).
  pp.reaction_s = setup.reaction_s + setup.frame_s + fp.vehicle.max_accel_mps2 / (2.0 * fp.vehicle.max_jerk_mps3);
  pp.vehicle = fp.vehicle;
  pp.safety_m = fp.vehicle.radius_m + 0.4;
  pp.bound_half_width_m = scene.bound_half_width_m;
  pp.goal_xz = Eigen::Vector2d(0.0, scene.goal_z_m);
  Planner planner(pp);
  // The texture a disparity needs to be trusted rises with the cameras' read noise (a property of
  // the cameras the system knows): the 5x5 mean |horizontal gradient| of noise alone is ~0.7
  // sigma.
  MapParams mp;
  mp.min_texture_grey = std::max(2.0, 1.5 + 0.75 * sc.imaging.noise_grey);
  LocalMap map(mp);
  map.clear_disk(0.0, 0.0, 2.0);  // the take-off area is known to be free
  std::mt19937 rng(seed * 7919u + 17u);
  sim::FuncPipeline pipe;
  FlightResult r;
  VehicleState st;
  st.position_m = Eigen::Vector3d(0, -sc.rig.altitude_m, 0);
  Eigen::Vector3d v_sp = Eigen::Vector3d::Zero();  // hover until the first plan
  double yaw_sp = 0;
  std::deque<InFlight> pipeline;
  double next_frame = 0.0;
  const int steps = int(std::ceil(fp.time_limit_s / fp.dt_s));
  for (int k = 0; k <= steps; ++k) {
    const double t = k * fp.dt_s;
    if (t >= next_frame) {
      next_frame += setup.frame_s;
      CameraPose pose;
      pose.position_m = st.position_m;
      pose.yaw_rad = st.yaw_rad;
      pose.pitch_rad = st.pitch_rad + sc.rig.mount_pitch_deg * M_PI / 180.0;
      const auto t0 = clock::now();
      // The oracle reads the left image (the map's texture test) and the exact disparity only.
      StereoFrame f = render(scene, setup.rig, setup.width_px, setup.height_px, pose, sc.imaging.antialias,
                             fp.oracle ? GreyImages::left_only : GreyImages::both);
      apply_sensor(f, sc.imaging, rng);
      const auto t1 = clock::now();
      InFlight in{t + setup.reaction_s, {}, {}, f.left, pose};
      if (fp.oracle) {
        in.disparity_px = f.disparity_px;
        in.valid_mask = f.valid_mask;
      } else {
        DisparityMap d = run_design(setup.cfg, f.left, f.right, pipe);
        in.disparity_px = d.disparity_px;
        in.valid_mask = d.valid_mask;
      }
      r.render_wall_s += std::chrono::duration<double>(t1 - t0).count();
      r.perception_wall_s += std::chrono::duration<double>(clock::now() - t1).count();
      pipeline.push_back(std::move(in));
      r.trajectory.push_back(st.position_m);
      r.poses.push_back(pose);
      ++r.frames;
    }
    // A disparity map through the stage: into the map, then a plan from the current state.
    while (!pipeline.empty() && pipeline.front().ready_s <= t) {
      const InFlight& in = pipeline.front();
      const bool dump = !fp.debug_dir.empty() && r.frames % 10 == 0;
      cv::Mat hits;
      map.integrate(in.disparity_px, in.valid_mask, setup.rig, in.pose, in.left, dump ? &hits : nullptr);
      if (dump) write_debug_pictures(fp, seed, r.frames, map, hits, in.left);
      const Plan plan = planner.plan(map, st);
      v_sp = plan.velocity_mps;
      yaw_sp = plan.yaw_rad;
      r.setpoints.push_back({t, v_sp, yaw_sp, st.position_m, st.velocity_mps, st.yaw_rad, plan.free_m, plan.braking});
      pipeline.pop_front();
    }
    const Eigen::Vector3d before = st.position_m;
    step_vehicle(st, v_sp, yaw_sp, fp.vehicle, fp.dt_s);
    r.path_length_m += (st.position_m - before).norm();
    const double c = clearance_m(scene, st.position_m) - fp.vehicle.radius_m;
    r.min_clearance_m = std::min(r.min_clearance_m, c);
    r.time_s = t;
    if (c < 0) {
      r.outcome = Outcome::collision;
      r.hit = nearest_obstacle(scene, st.position_m);
      break;
    }
    if (std::fabs(st.position_m.x()) > scene.bound_half_width_m) {
      r.outcome = Outcome::out_of_bounds;
      break;
    }
    if (st.position_m.z() >= scene.goal_z_m) {
      r.outcome = Outcome::goal;
      break;
    }
  }
  r.reached_goal = r.outcome == Outcome::goal;
  r.collided = r.outcome == Outcome::collision;
  r.flips = planner.flips();
  r.recoveries = planner.recoveries();
  return r;
}

std::vector<std::vector<uint8_t>> flight_mavlink(const FlightResult& r, SetpointFrame frame, double period_s,
                                                 const VehicleParams& vehicle, double entry_s) {
  constexpr double kResendS = 0.1;  // a setpoint is repeated at least this often (PX4: > 2 Hz)
  const double step_s = period_s > 0 ? std::min(period_s, kResendS) : kResendS;
  MavlinkStream stream(1, 191, entry_s);
  std::vector<std::vector<uint8_t>> out;
  double last_s = -1;
  VelocitySetpoint last;
  auto send = [&](VelocitySetpoint sp, double t_s) {
    for (double t = last_s + kResendS; last_s >= 0 && t < t_s - 1e-9; t += kResendS) {  // fill a gap
      last.time_boot_ms = uint32_t(std::lround(t * 1000.0));
      for (auto& f : stream.setpoint(last)) out.push_back(std::move(f));
    }
    sp.time_boot_ms = uint32_t(std::lround(t_s * 1000.0));
    for (auto& f : stream.setpoint(sp)) out.push_back(std::move(f));
    last = sp;
    last_s = t_s;
  };
  const double yaw0 = r.setpoints.empty() ? 0.0 : r.setpoints.front().vehicle_yaw_rad;
  for (int i = 0; i * step_s < entry_s - 1e-9; ++i) {  // hover before the switch
    VelocitySetpoint sp;
    sp.frame = frame;
    sp.yaw_rad = yaw0;
    send(sp, i * step_s);
  }
  const double rate_max = vehicle.max_yaw_rate_dps * M_PI / 180.0;
  for (const SentSetpoint& p : r.setpoints) {
    VelocitySetpoint sp;
    sp.frame = frame;
    const Eigen::Vector3d& v = p.velocity_mps;
    if (frame == SetpointFrame::local_ned) {
      sp.velocity_mps = Eigen::Vector3d(v.z(), v.x(), v.y());
      sp.yaw_rad = p.yaw_rad;
    } else {
      const double c = std::cos(p.vehicle_yaw_rad), s = std::sin(p.vehicle_yaw_rad);
      sp.velocity_mps = Eigen::Vector3d(s * v.x() + c * v.z(), c * v.x() - s * v.z(), v.y());
      sp.yaw_rate_rps =
          std::clamp(vehicle.yaw_gain_per_s * wrap_angle(p.yaw_rad - p.vehicle_yaw_rad), -rate_max, rate_max);
    }
    send(sp, p.time_s + entry_s);
  }
  return out;
}

}  // namespace parallax::uav
