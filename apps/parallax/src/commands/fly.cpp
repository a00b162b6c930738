// parallax fly: closed-loop flights through synthetic scenes with a design's disparity, latency
// and frame rate, each set of seeds also flown with oracle perception (the exact disparity), so
// that the design's share of the outcome and the planner's are told apart; at one speed, or
// searching the highest speed without a collision.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "commands.hpp"
#include "parallax/uav/fly.hpp"
#include "parallax/uav/json.hpp"
#include "parallax/uav/scene.hpp"

namespace parallax::cli {

namespace {

using nlohmann::json;
using namespace parallax::eval;
using namespace parallax::uav;
using namespace parallax::search;

struct FlyOptions {
  ConfigArgs cfg;
  std::string scenario, trace_csv, debug_maps, mavlink_out, mavlink_frame = "local-ned";
  int seeds = 3, first_seed = 1, size = 0, jobs = 0;
  double speed = 5.0, noise = -1.0, limit = 60.0;
  bool json = false, find = false, no_oracle = false;
};

// The flights of seeds first..first+N-1 at one speed, summed.
struct FlightTally {
  int seeds = 0, goal = 0, collisions = 0, out_of_bounds = 0, timeouts = 0, frames = 0, flips = 0, recoveries = 0;
  double min_clear = 1e9, ratio = 0, time = 0, simulated_s = 0, render_s = 0, perception_s = 0;
  double goal_z_m = 0;            // the goal's distance the goal speed is taken over (seed 1's scene)
  json per_seed = json::array();  // each flight's form (parallax/uav/json.hpp) with its seed

  double mean_goal(double sum) const { return goal ? sum / goal : 0.0; }
};

// A tally's JSON form: seeds, success_rate with success_ci95_pct and collisions with
// collision_ci95_pct (Wilson 95 % intervals), out_of_bounds, timeouts, min_clearance_m, the means
// over the flights that reached the goal (path_length_ratio, time_to_goal_s, goal_speed_mps), flips
// and recoveries per flight, the rendering's cost (render_ms_per_frame, render_vs_real_time) and
// per_seed.
void to_json(json& j, const FlightTally& g) {
  const auto ok = wilson_interval_pct(g.goal, g.seeds), hit = wilson_interval_pct(g.collisions, g.seeds);
  j = {{"seeds", g.seeds},
       {"success_rate", 100.0 * g.goal / std::max(1, g.seeds)},
       {"success_ci95_pct", {ok.first, ok.second}},
       {"collisions", g.collisions},
       {"collision_ci95_pct", {hit.first, hit.second}},
       {"out_of_bounds", g.out_of_bounds},
       {"timeouts", g.timeouts},
       {"min_clearance_m", g.min_clear},
       {"path_length_ratio", g.mean_goal(g.ratio)},
       {"time_to_goal_s", g.mean_goal(g.time)},
       {"goal_speed_mps", g.goal ? g.goal_z_m / g.mean_goal(g.time) : 0.0},
       {"flips_per_flight", double(g.flips) / std::max(1, g.seeds)},
       {"recoveries_per_flight", double(g.recoveries) / std::max(1, g.seeds)},
       {"render_ms_per_frame", g.frames ? 1000.0 * g.render_s / g.frames : 0.0},
       {"render_vs_real_time", g.simulated_s > 0 ? g.render_s / g.simulated_s : 0.0},
       {"per_seed", g.per_seed}};
}

// Where --mavlink-out puts a seed's stream: the path itself for one seed, else with _seed<N>
// before the extension.
std::string mavlink_path(const std::string& path, int seed, int seeds) {
  if (seeds == 1) return path;
  const std::size_t dot = path.find_last_of('.'), slash = path.find_last_of('/');
  const std::size_t cut = dot == std::string::npos || (slash != std::string::npos && dot < slash) ? path.size() : dot;
  return path.substr(0, cut) + "_seed" + std::to_string(seed) + path.substr(cut);
}

// The design flights' MAVLink streams (--mavlink-out), one file per seed.
struct MavlinkOut {
  std::string path;
  SetpointFrame frame = SetpointFrame::local_ned;
  double period_s = 0;
  void write(const FlightResult& r, const VehicleParams& vehicle, int seed, int seeds) const {
    const std::string where = mavlink_path(path, seed, seeds);
    MavlinkSink sink(where, "--mavlink-out");
    for (const auto& f : flight_mavlink(r, frame, period_s, vehicle)) sink.send(f);
  }
};

// The tally of one kind of flight over seeds first.. (results and goal_z in seed order).
FlightTally tally_flights(const std::vector<FlightResult>& results, const std::vector<double>& goal_z, int first,
                          const FlightParams& fp, const MavlinkOut* mavlink) {
  const int seeds = int(results.size());
  FlightTally g;
  g.seeds = seeds;
  for (int s = first; s < first + seeds; ++s) {
    const FlightResult& r = results[std::size_t(s - first)];
    if (mavlink != nullptr) mavlink->write(r, fp.vehicle, s, seeds);  // here: an error reaches the command
    g.goal += r.outcome == Outcome::goal ? 1 : 0;
    g.collisions += r.outcome == Outcome::collision ? 1 : 0;
    g.out_of_bounds += r.outcome == Outcome::out_of_bounds ? 1 : 0;
    g.timeouts += r.outcome == Outcome::time_out ? 1 : 0;
    g.min_clear = std::min(g.min_clear, r.min_clearance_m);
    g.frames += r.frames;
    g.flips += r.flips;
    g.recoveries += r.recoveries;
    g.simulated_s += r.time_s;
    g.render_s += r.render_wall_s;
    g.perception_s += r.perception_wall_s;
    if (r.reached_goal) {
      g.ratio += r.path_length_m / goal_z[std::size_t(s - first)];
      g.time += r.time_s;
    }
    json flight = r;  // parallax/uav/json.hpp
    flight["seed"] = s;
    g.per_seed.push_back(flight);
  }
  return g;
}

void write_trace(std::FILE* trace, const char* label, int seed, const FlightResult& r) {
  for (const SentSetpoint& p : r.setpoints)
    std::fprintf(trace, "%s,%d,%.3f,%.3f,%.3f,%.3f,%.3f,%.1f,%.3f,%.3f,%.1f,%.2f,%d\n", label, seed, p.time_s,
                 p.position_m.x(), p.position_m.z(), p.vehicle_velocity_mps.x(), p.vehicle_velocity_mps.z(),
                 p.vehicle_yaw_rad * 180.0 / M_PI, p.velocity_mps.x(), p.velocity_mps.z(), p.yaw_rad * 180.0 / M_PI,
                 p.free_m, p.braking ? 1 : 0);
}

struct FlightSet {
  FlightTally design, oracle;
  std::vector<double> goal_z;  // per seed
};

// Flies seeds first..first+`seeds`-1 at `speed`: the design's flights and, with `oracle`, the
// oracle's (the exact disparity through the same loop), all in one pool of `jobs` threads so that
// flights of both kinds balance one another. One progress line per flight on stderr (in the order
// they end); the trace rows are written after the pool, design flights first and each kind in seed
// order, so that the trace does not depend on the threads.
FlightSet fly_seeds(const config::PipelineConfig& cfg, const Scenario& sc, FlightParams fp, int first, int seeds,
                    double speed, int jobs, bool oracle, std::FILE* trace, const MavlinkOut* mavlink = nullptr) {
  fp.speed_mps = speed;
  FlightParams ofp = fp;
  ofp.oracle = true;
  const int kinds = oracle ? 2 : 1, tasks = kinds * seeds;
  std::vector<FlightResult> results[2];
  for (auto& r : results) r.resize(std::size_t(seeds));
  FlightSet set;
  set.goal_z.assign(std::size_t(seeds), 0.0);
  std::atomic<int> next{0};
  std::mutex out;
  auto worker = [&] {
    for (int t = next++; t < tasks; t = next++) {
      const int kind = t / seeds, s = first + t % seeds;
      const char* label = kind == 0 ? "design" : "oracle";
      const Scene scene = generate_scene(sc, uint32_t(s));
      FlightResult r = fly(cfg, sc, scene, kind == 0 ? fp : ofp, uint32_t(s));
      const std::lock_guard<std::mutex> lock(out);
      std::fprintf(stderr,
                   "parallax: %s %s seed %d at %.1f m/s: %s%s%s after %.1f s (min clearance %.2f m, %d frames)\n",
                   label, sc.name.c_str(), s, speed, to_string(r.outcome), r.hit.empty() ? "" : " with ", r.hit.c_str(),
                   r.time_s, r.min_clearance_m, r.frames);
      set.goal_z[std::size_t(s - first)] = scene.goal_z_m;
      results[kind][std::size_t(s - first)] = std::move(r);
    }
  };
  std::vector<std::thread> pool;
  for (int j = 0; j < std::max(1, std::min(jobs, tasks)); ++j) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  if (trace != nullptr)
    for (int kind = 0; kind < kinds; ++kind)
      for (int s = first; s < first + seeds; ++s)
        write_trace(trace, kind == 0 ? "design" : "oracle", s, results[kind][std::size_t(s - first)]);
  set.design = tally_flights(results[0], set.goal_z, first, fp, mavlink);
  if (oracle) set.oracle = tally_flights(results[1], set.goal_z, first, ofp, nullptr);
  return set;
}

void print_tally(const char* label, const FlightTally& g) {
  const auto ok = wilson_interval_pct(g.goal, g.seeds), hit = wilson_interval_pct(g.collisions, g.seeds);
  std::printf(
      "  %-8s success %3.0f%% [%.0f-%.0f%%]  collisions %d [%.0f-%.0f%%]  out of bounds %d  timeouts %d  "
      "goal speed %.2f m/s  path ratio %.3f  min clearance %.2f m  flips %.1f  recoveries %.2f per flight\n",
      label, 100.0 * g.goal / std::max(1, g.seeds), ok.first, ok.second, g.collisions, hit.first, hit.second,
      g.out_of_bounds, g.timeouts, g.goal ? g.goal_z_m / g.mean_goal(g.time) : 0.0, g.mean_goal(g.ratio), g.min_clear,
      double(g.flips) / std::max(1, g.seeds), double(g.recoveries) / std::max(1, g.seeds));
}

int run_fly(const FlyOptions& o, const Invocation&) {
  const config::PipelineConfig cfg = load_config_args(o.cfg);
  Scenario sc = load_scenario(o.scenario);
  if (o.noise >= 0) sc.imaging.noise_grey = o.noise;
  FlightParams fp;
  fp.width_px = o.size;
  fp.time_limit_s = o.limit;
  fp.debug_dir = o.debug_maps;
  const FlightSetup setup = flight_setup(cfg, sc, fp);
  if (!o.mavlink_out.empty() && o.find)
    throw InputError("--mavlink-out: not with --find-max-speed (it flies many speeds); give --speed-mps");
  if (o.mavlink_out.rfind("udp:", 0) == 0)
    throw InputError("--mavlink-out '" + o.mavlink_out +
                     "': fly writes files (a simulated flight does not run at the wall clock's pace)");
  if (!o.mavlink_out.empty())  // every destination writable before minutes of flying
    for (int seed = o.first_seed; seed < o.first_seed + o.seeds; ++seed)
      MavlinkSink probe(mavlink_path(o.mavlink_out, seed, o.seeds), "--mavlink-out");
  const int jobs = o.jobs > 0 ? o.jobs : int(std::max(1u, std::thread::hardware_concurrency()));
  const double goal_z = generate_scene(sc, 1).goal_z_m;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> trace(nullptr, std::fclose);
  if (!o.trace_csv.empty()) {
    trace.reset(std::fopen(o.trace_csv.c_str(), "w"));
    if (!trace) throw InputError(o.trace_csv + ": cannot write the trace");
    std::fprintf(trace.get(),
                 "perception,seed,time_s,x_m,z_m,vx_mps,vz_mps,yaw_deg,sp_vx_mps,sp_vz_mps,sp_yaw_deg,"
                 "free_m,braking\n");
  }
  json j = setup;  // the rig and the timing flown with (parallax/uav/json.hpp)
  j["config"] = cfg.name;
  j["scenario"] = sc.name;
  j["seeds"] = o.seeds;
  j["first_seed"] = o.first_seed;
  if (o.find) {
    double lo = 0.0, hi = 16.0;
    for (int it = 0; it < 5; ++it) {
      const double mid = (lo + hi) / 2;
      (fly_seeds(cfg, sc, fp, o.first_seed, o.seeds, mid, jobs, false, nullptr).design.collisions == 0 ? lo : hi) = mid;
    }
    const double reaction_s = setup.reaction_s + setup.frame_s;
    const double bound = stopping_distance_speed_bound(fp.vehicle.max_accel_mps2, reaction_s, 12.0);
    j["max_safe_speed_mps"] = lo;
    j["stopping_distance_bound_mps"] = bound;
    if (!o.json)
      std::printf(
          "%s in %s over %d seeds: highest speed without a collision %.2f m/s (searched to 0.5 m/s); "
          "stopping-distance bound %.2f m/s (a %.1f m/s2, reaction %.1f ms = latency + stage + frame, range 12 m)\n",
          cfg.name.c_str(), sc.name.c_str(), o.seeds, lo, bound, fp.vehicle.max_accel_mps2, 1000.0 * reaction_s);
  } else {
    MavlinkOut mav{o.mavlink_out, o.mavlink_frame == "body-frd" ? SetpointFrame::body_frd : SetpointFrame::local_ned,
                   setup.frame_s};
    FlightSet flights = fly_seeds(cfg, sc, fp, o.first_seed, o.seeds, o.speed, jobs, !o.no_oracle, trace.get(),
                                  o.mavlink_out.empty() ? nullptr : &mav);
    FlightTally& design = flights.design;
    FlightTally& oracle = flights.oracle;
    design.goal_z_m = goal_z;
    j["speed_mps"] = o.speed;
    j["design"] = design;
    if (!o.no_oracle) {
      oracle.goal_z_m = goal_z;
      j["oracle"] = oracle;
    }
    if (!o.json) {
      std::printf(
          "%s in %s at %.1f m/s over %d seeds (%dx%d, f %.0f px, B %.2f m; frame %.1f ms, latency %.1f ms + stage "
          "%.1f ms):\n",
          cfg.name.c_str(), sc.name.c_str(), o.speed, o.seeds, setup.width_px, setup.height_px, setup.rig.focal_px,
          setup.rig.baseline_m, setup.frame_s * 1000.0, setup.latency_ms, cfg.avoid_ms);
      print_tally("design", design);
      if (!o.no_oracle) print_tally("oracle", oracle);
      std::printf("  ([ ]: Wilson 95 %% intervals; oracle: the same flights with the exact disparity)\n");
      std::printf("  rendering: %.1f ms per stereo pair, %.2fx real time on one core\n",
                  design.frames ? 1000.0 * design.render_s / design.frames : 0.0,
                  design.simulated_s > 0 ? design.render_s / design.simulated_s : 0.0);
    }
  }
  if (o.json) std::cout << j.dump(2) << "\n";
  return 0;
}

}  // namespace

Command add_fly(CLI::App& app) {
  auto o = std::make_shared<FlyOptions>();
  auto* flyc = app.add_subcommand(
      "fly", "Closed-loop flights through synthetic scenes with the design's disparity, latency and frame rate");
  add_config_options(flyc, o->cfg, true);
  add_engine_option(flyc);
  flyc->add_option("--scenario", o->scenario, scenario_option_help())->required();
  flyc->add_option("--seeds", o->seeds, "Scenes (seeds first..first+N-1)")
      ->capture_default_str()
      ->check(InRange(1, 10000));
  flyc->add_option("--first-seed", o->first_seed, "The first scene's seed (to fly one failing scene again)")
      ->capture_default_str()
      ->check(InRange(1, 1000000));
  flyc->add_option("--speed-mps", o->speed, "Cruise speed")->capture_default_str()->check(InRange(0.1, 50.0));
  flyc->add_option("--size", o->size,
                   "Scale the rig to this image width (0: the design's own region of interest on the scenario's "
                   "sensor; smaller is faster, with the design's timing and range at that size)")
      ->capture_default_str()
      ->check(CLI::Range(0, 0) | InRange(64, 4096));
  flyc->add_option("--threads,--jobs", o->jobs, "Seeds in parallel (default: all cores; --jobs: the same)")
      ->check(InRange(0, 256));
  flyc->add_flag("--find-max-speed", o->find, "Search the highest speed without a collision over the seeds");
  flyc->add_flag("--no-oracle", o->no_oracle, "Skip the oracle flights (the exact disparity through the same loop)");
  flyc->add_option("--noise-grey", o->noise,
                   "Sensor read noise, Gaussian sigma in grey levels (default: the scenario's imaging.noise_grey)")
      ->check(InRange(0.0, 50.0));
  flyc->add_option("--time-limit-s", o->limit, "Flight time limit")->capture_default_str()->check(InRange(1.0, 3600.0));
  flyc->add_option("--trace-csv", o->trace_csv,
                   "Write every setpoint of every flight (vehicle state, setpoint, free distance) to this CSV");
  flyc->add_option("--debug-maps", o->debug_maps,
                   "Every 10th frame, write the planner's map and the pixels it took as obstacles to this folder")
      ->check(CLI::ExistingDirectory);
  flyc->add_option("--mavlink-out", o->mavlink_out,
                   "Write the MAVLink 2 stream each design flight sent (heartbeat 1 Hz, a second of hover setpoints, "
                   "OFFBOARD mode and arm commands, then the loop's velocity setpoints at flight time + 1 s) to this "
                   "file; with several seeds, FILE_seed<N>")
      ->check(OutputFile());
  flyc->add_option("--mavlink-frame", o->mavlink_frame,
                   "Setpoint frame: local-ned (velocity north-east-down and yaw) or body-frd (velocity forward-"
                   "right-down of the vehicle and yaw rate)")
      ->capture_default_str()
      ->check(CLI::IsMember({"local-ned", "body-frd"}));
  flyc->add_flag("--json", o->json, "Print JSON");
  return bind_command(flyc, o, run_fly);
}

}  // namespace parallax::cli
