// parallax fly: closed-loop flights through synthetic scenes with a design's disparity, latency
// and frame rate; at one speed, or searching the highest speed without a collision.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "commands.hpp"
#include "parallax/uav/fly.hpp"
#include "parallax/uav/scene.hpp"

namespace parallax::cli {

namespace {

using nlohmann::json;
using namespace parallax::explore;

struct FlyOptions {
  ConfigArgs cfg;
  std::string scenario;
  int seeds = 3, size = 320;
  double speed = 5.0, noise = 0.0, limit = 40.0;
  bool json = false, find = false;
};

// The flights of seeds 1..N at one speed, summed.
struct FlightTally {
  int ok = 0, collisions = 0;
  double min_clear = 1e9, ratio = 0, time = 0;
};

// Flies the design through the scenes of seeds 1..`seeds` at `speed`; one progress line per
// flight on stderr, and one row per flight in `per_seed` when not null.
FlightTally fly_seeds(const config::PipelineConfig& cfg, const Scenario& sc, FlightParams fp, int seeds, double speed,
                      json* per_seed) {
  fp.speed_mps = speed;
  FlightTally g;
  for (int s = 1; s <= seeds; ++s) {
    const Scene scene = generate_scene(sc, uint32_t(s));
    const FlightResult r = fly(cfg, scene, fp, uint32_t(s));
    g.ok += r.reached_goal ? 1 : 0;
    g.collisions += r.collided ? 1 : 0;
    g.min_clear = std::min(g.min_clear, r.min_clearance_m);
    if (r.reached_goal) {
      g.ratio += r.path_length_m / scene.goal_z_m;
      g.time += r.time_s;
    }
    if (per_seed)
      per_seed->push_back({{"seed", s},
                           {"reached_goal", r.reached_goal},
                           {"collided", r.collided},
                           {"min_clearance_m", r.min_clearance_m},
                           {"time_s", r.time_s},
                           {"frames", r.frames}});
    std::fprintf(stderr, "parallax: %s seed %d at %.1f m/s: %s (min clearance %.2f m, %d frames)\n", sc.name.c_str(), s,
                 speed,
                 r.collided       ? "collision"
                 : r.reached_goal ? "goal"
                                  : "time out",
                 r.min_clearance_m, r.frames);
  }
  return g;
}

int run_fly(const FlyOptions& o, const Invocation&) {
  const config::PipelineConfig cfg = load_config_args(o.cfg);
  const Scenario sc = load_scenario(o.scenario);
  FlightParams fp;
  fp.width_px = o.size;
  fp.disparity_noise_px = o.noise;
  fp.time_limit_s = o.limit;
  double interval_ms = 0, latency_ms = 0;
  {
    config::PipelineConfig c = cfg;
    c.roi_full = false;
    c.roi_width_px = o.size;
    c.roi_height_px = o.size * 9 / 16;
    design_timing(c, o.size, o.size * 9 / 16, interval_ms, latency_ms);
  }
  json j;
  j["config"] = cfg.name;
  j["scenario"] = sc.name;
  j["seeds"] = o.seeds;
  j["frame_interval_ms"] = interval_ms;
  j["latency_ms"] = latency_ms;
  if (o.find) {
    double lo = 0.0, hi = 16.0;
    for (int it = 0; it < 5; ++it) {
      const double mid = (lo + hi) / 2;
      (fly_seeds(cfg, sc, fp, o.seeds, mid, nullptr).collisions == 0 ? lo : hi) = mid;
    }
    const double frame_ms = std::max(interval_ms, 1000.0 / fp.camera_fps);
    const double bound = stopping_distance_speed_bound(fp.max_accel_mps2, (latency_ms + frame_ms) / 1000.0, 12.0);
    j["max_safe_speed_mps"] = lo;
    j["stopping_distance_bound_mps"] = bound;
    if (!o.json)
      std::printf(
          "%s in %s over %d seeds: highest speed without a collision %.2f m/s (searched to 0.5 m/s); "
          "stopping-distance bound %.2f m/s (a %.1f m/s2, reaction %.1f ms = latency + frame, range 12 m)\n",
          cfg.name.c_str(), sc.name.c_str(), o.seeds, lo, bound, fp.max_accel_mps2, latency_ms + frame_ms);
  } else {
    json per_seed = json::array();
    const FlightTally g = fly_seeds(cfg, sc, fp, o.seeds, o.speed, &per_seed);
    const int timeouts = o.seeds - g.ok - g.collisions;
    const auto ok_ci = wilson_interval_pct(g.ok, o.seeds), hit_ci = wilson_interval_pct(g.collisions, o.seeds);
    j["speed_mps"] = o.speed;
    j["success_rate"] = 100.0 * g.ok / o.seeds;
    j["success_ci95_pct"] = {ok_ci.first, ok_ci.second};
    j["collisions"] = g.collisions;
    j["collision_ci95_pct"] = {hit_ci.first, hit_ci.second};
    j["timeouts"] = timeouts;
    j["min_clearance_m"] = g.min_clear;
    j["path_length_ratio"] = g.ok ? g.ratio / g.ok : 0.0;
    j["time_to_goal_s"] = g.ok ? g.time / g.ok : 0.0;
    j["per_seed"] = per_seed;
    if (!o.json)
      std::printf(
          "%s in %s at %.1f m/s over %d seeds: success_rate %.0f%% [%.0f-%.0f%%]  collisions %d [%.0f-%.0f%%]  "
          "timeouts %d  min_clearance %.2f m  path_length_ratio %.3f  time_to_goal %.1f s  (frame %.1f ms, latency "
          "%.1f ms; [ ]: Wilson 95 %% intervals)\n",
          cfg.name.c_str(), sc.name.c_str(), o.speed, o.seeds, j["success_rate"].get<double>(), ok_ci.first,
          ok_ci.second, g.collisions, hit_ci.first, hit_ci.second, timeouts, g.min_clear,
          j["path_length_ratio"].get<double>(), j["time_to_goal_s"].get<double>(), interval_ms, latency_ms);
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
  flyc->add_option(
          "--scenario", o->scenario,
          "Scenario: a shipped one by name (forest, corridor, wall-gap, single-pole) or a file, e.g. my/scene.yaml")
      ->required();
  flyc->add_option("--seeds", o->seeds, "Scenes (seeds 1..N)")->capture_default_str()->check(InRange(1, 1000));
  flyc->add_option("--speed-mps", o->speed, "Cruise speed")->capture_default_str()->check(InRange(0.1, 50.0));
  flyc->add_option("--size", o->size, "Rendered width (height x 9/16); the design's ROI follows")
      ->capture_default_str()
      ->check(InRange(64, 1280));
  flyc->add_flag("--find-max-speed", o->find, "Search the highest speed without a collision over the seeds");
  flyc->add_option("--noise-grey", o->noise, "Sensor noise: Gaussian sigma added to the grey levels")
      ->capture_default_str()
      ->check(InRange(0.0, 50.0));
  flyc->add_option("--time-limit-s", o->limit, "Flight time limit")->capture_default_str()->check(InRange(1.0, 3600.0));
  flyc->add_flag("--json", o->json, "Print JSON");
  return bind_command(flyc, o, run_fly);
}

}  // namespace parallax::cli
