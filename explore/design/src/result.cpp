#include "parallax/design/result.hpp"

#include <algorithm>

#include "parallax/eval/evaluate.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/resources/devices.hpp"
#include "parallax/uav/avoid.hpp"
#include "parallax/uav/fly.hpp"
#include "parallax/uav/scene.hpp"

namespace parallax::design {

// The names this file takes from the other rooms (one namespace per room).
using eval::crop_to_roi;
using eval::design_size;
using eval::DisparityMap;
using eval::EvalOptions;
using eval::EvalResult;
using eval::evaluate_design;
using eval::Frame;
using eval::InputError;
using eval::list_frames;
using eval::load_frame;
using eval::named_metrics;
using eval::pool_rows;
using eval::resolve_roi;
using eval::Roi;
using eval::roi_for;
using eval::run_design;
using eval::simulate_timing;
using eval::SimulationResult;
using uav::AvoidAccumulator;
using uav::FlightParams;
using uav::FlightResult;
using uav::fly;
using uav::generate_scene;
using uav::kitti_default_rig;
using uav::load_scenario;
using uav::Scenario;
namespace {

AccuracyFigures measure_accuracy(const config::PipelineConfig& cfg, const PointRequest& req) {
  EvalOptions eo;
  eo.gt_kind = req.gt_kind;
  eo.frames = req.frames;
  eo.threads = 1;
  EvalResult er = evaluate_design(cfg, *req.dataset, eo);
  AccuracyFigures a;
  a.pooled = pool_rows(er.frames);
  a.frames = std::move(er.frames);
  return a;
}

AvoidanceFigures measure_avoidance(const config::PipelineConfig& cfg, const PointRequest& req) {
  AvoidAccumulator acc;
  sim::FuncPipeline pipe;
  for (const auto& ref : list_frames(*req.dataset, req.gt_kind, req.frames)) {
    const Frame f = load_frame(ref);
    const Roi r = resolve_roi(roi_for(cfg), f.left.cols, f.left.rows);
    const DisparityMap d = run_design(cfg, crop_to_roi(f.left, r).clone(), crop_to_roi(f.right, r).clone(), pipe);
    acc.add(d.disparity_px, d.valid_mask, crop_to_roi(f.gt_disparity_px, r), crop_to_roi(f.gt_mask, r),
            cfg.disparity_end_px(), kitti_default_rig(r.x0, r.y0));
  }
  return {acc.metrics()};
}

FlightFigures measure_flights(const config::PipelineConfig& cfg, const PointRequest& req) {
  const Scenario sc = load_scenario(req.flight_scenario);
  FlightParams fp;
  fp.speed_mps = req.flight_speed_mps;
  fp.width_px = req.flight_size_px;
  FlightFigures f;
  f.seeds = req.flight_seeds;
  f.min_clearance_m = 1e9;
  double time_s = 0.0;
  for (int s = 1; s <= req.flight_seeds; ++s) {
    const FlightResult r = fly(cfg, sc, generate_scene(sc, uint32_t(s)), fp, uint32_t(s));
    f.reached_goal += r.reached_goal ? 1 : 0;
    f.collisions += r.collided ? 1 : 0;
    f.min_clearance_m = std::min(f.min_clearance_m, r.min_clearance_m);
    if (r.reached_goal) time_s += r.time_s;
  }
  f.mean_time_to_goal_s = f.reached_goal ? time_s / f.reached_goal : 0.0;
  return f;
}

}  // namespace

ResourceFigures resource_figures(const config::PipelineConfig& cfg, int width_px, int height_px,
                                 const res::Device* device, int clock_mhz, double frame_interval_ms) {
  ResourceFigures r;
  r.estimate = res::estimate(res::design_inventory(cfg, width_px, height_px), res::default_coefficients(),
                             res::parse_flavour(cfg.estimate));
  if (device != nullptr) r.utilisation = res::utilisation(r.estimate.total, *device);
  r.power = res::power(r.estimate.total, clock_mhz, frame_interval_ms);
  return r;
}

void complete_point(DesignResult& r, const PointRequest& req) {
  const config::PipelineConfig& cfg = r.config;
  if (r.width_px <= 0 || r.height_px <= 0) design_size(cfg, r.width_px, r.height_px);
  if (req.dataset != nullptr && !r.accuracy) r.accuracy = measure_accuracy(cfg, req);
  if (req.dataset != nullptr && req.avoidance && !r.avoidance) r.avoidance = measure_avoidance(cfg, req);
  if (!req.flight_scenario.empty() && !r.flight) r.flight = measure_flights(cfg, req);
  if (!req.view_dataset.empty() && !r.frame_view) r.frame_view = view_frame(cfg, req.view_dataset, req.view_frame);
  if (!req.view_scenario.empty() && !r.flight_view)
    r.flight_view = view_flight(cfg, req.view_scenario, req.flight_speed_mps, req.flight_size_px);
  if ((req.timing || req.resources) && !r.timing) {
    SimulationResult sr = simulate_timing(cfg, r.width_px, r.height_px);
    if (sr.cycle.deadlock) {
      r.status = "error";
      r.reason = "cycle model: " + sr.cycle.deadlock_message;
      return;
    }
    r.timing = std::move(sr);
  }
  if (req.resources && !r.resources) {
    const res::Device* dev = req.device.empty() ? nullptr : res::find_device(req.device);
    if (!req.device.empty() && dev == nullptr)
      throw InputError("unknown device '" + req.device + "' (known: " + res::device_names() + ")");
    r.resources = resource_figures(cfg, r.width_px, r.height_px, dev, cfg.clock_mhz, r.timing->frame_interval_ms);
  }
}

DesignResult evaluate_point(const config::PipelineConfig& cfg, const PointRequest& request) {
  DesignResult r;
  r.config = cfg;
  complete_point(r, request);
  return r;
}

std::map<std::string, double> metric_columns(const DesignResult& r) {
  std::map<std::string, double> m;
  if (r.accuracy) {
    for (const auto& kv : named_metrics(r.accuracy->pooled.metrics)) m[kv.first] = kv.second;
    m["frames"] = double(r.accuracy->frames.size());
  }
  if (r.avoidance)
    for (const auto& kv : r.avoidance->scores) m[kv.first] = kv.second;
  if (r.flight) {
    m["flight_success_rate"] = r.flight->success_rate_pct();
    m["flight_collisions"] = double(r.flight->collisions);
    m["flight_min_clearance_m"] = r.flight->min_clearance_m;
    m["flight_time_to_goal_s"] = r.flight->mean_time_to_goal_s;
  }
  if (r.timing) {
    m["latency_ms"] = r.timing->latency_ms;
    m["frame_interval_ms"] = r.timing->frame_interval_ms;
    m["fps"] = r.timing->fps;
    m["cycles_per_frame"] = double(r.timing->cycle.cycles_per_frame);
    // 2: the 8-path variant's second pass through a DDR frame buffer (kernels/pipeline.hpp).
    m["passes"] = kern::two_pass_paths(r.config.path_mask) ? 2.0 : 1.0;
  }
  if (r.resources) {
    const res::Usage& u = r.resources->estimate.total;
    m["bram18k"] = double(u.bram18k);
    m["lut"] = double(u.lut);
    m["ff"] = double(u.ff);
    m["dsp"] = double(u.dsp);
    m["fits_device"] = r.resources->utilisation.fits ? 1.0 : 0.0;
    m["power_w"] = r.resources->power.total_w;
    m["energy_mj_per_frame"] = r.resources->power.energy_mj_per_frame;
  }
  return m;
}

std::vector<std::pair<std::string, std::map<std::string, double>>> frame_columns(const DesignResult& r) {
  std::vector<std::pair<std::string, std::map<std::string, double>>> out;
  if (!r.accuracy) return out;
  for (const auto& f : r.accuracy->frames) {
    std::map<std::string, double> fm;
    for (const auto& kv : named_metrics(f.metrics)) fm[kv.first] = kv.second;
    out.emplace_back(f.frame_id, std::move(fm));
  }
  return out;
}

}  // namespace parallax::design
