// One design point, evaluated once: its accuracy over the frames of a dataset, its timing (the
// cycle model's schedule at the processed size plus the system figures), its resources, and
// optionally its avoidance scores and flights. Sweeps, the CLI, the HLS export and the reports all
// obtain a design's figures from evaluate_point(); the results store turns a DesignResult into
// its columns in one place (metric_columns()).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "parallax/config/config.hpp"
#include "parallax/design/views.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/metrics.hpp"
#include "parallax/eval/simulate.hpp"
#include "parallax/resources/model.hpp"

namespace parallax::design {

// The names this file takes from the other rooms (one namespace per room).
using eval::Dataset;
using eval::FrameRow;
using eval::GtKind;
using eval::SimulationResult;

// Accuracy over frames (docs/evaluation.md): every frame's counts and their pooled measures.
struct AccuracyFigures {
  std::vector<FrameRow> frames;  // dataset order
  FrameRow pooled;
};

// Resources of the design at its processed size on one device (models/resources).
struct ResourceFigures {
  res::Estimate estimate;        // per stage and total, BRAM_18K / LUT / FF / DSP / URAM
  res::Utilisation utilisation;  // on the device; utilisation.device names it (null: no device)
  res::Power power;              // at the design's clock and frame interval
};

// The avoidance stage run on the design's maps and on the ground truth's, scored against each
// other (docs/avoidance.md): named scores as AvoidAccumulator::metrics() gives them.
struct AvoidanceFigures {
  std::vector<std::pair<std::string, double>> scores;
};

// Flights through one scenario with seeds 1..seeds (docs/flight.md).
struct FlightFigures {
  int seeds = 0;
  int reached_goal = 0;
  int collisions = 0;
  double min_clearance_m = 0.0;      // over all flights
  double mean_time_to_goal_s = 0.0;  // over the flights that reached the goal; 0 when none did
  double success_rate_pct() const { return seeds > 0 ? 100.0 * reached_goal / seeds : 0.0; }
};

struct DesignResult {
  config::PipelineConfig config;
  int width_px = 0, height_px = 0;  // processed size (design_size)
  std::string status = "ok";        // ok | error (the cycle model deadlocked: reason says where)
  std::string reason;
  std::optional<AccuracyFigures> accuracy;
  std::optional<SimulationResult> timing;  // latency_ms, frame_interval_ms, fps, the cycle report
  std::optional<ResourceFigures> resources;
  std::optional<AvoidanceFigures> avoidance;
  std::optional<FlightFigures> flight;
  // The views a report draws (views.hpp), when the request asks for them.
  std::optional<FrameView> frame_view;
  std::optional<FlightView> flight_view;
};

// What to evaluate. Accuracy (and avoidance) need a dataset; timing and resources need only the
// configuration; flights need a scenario.
struct PointRequest {
  const Dataset* dataset = nullptr;  // accuracy over its frames when set
  GtKind gt_kind = GtKind::noc;
  std::string frames;      // frame filter ("" = all with ground truth)
  bool avoidance = false;  // also score the avoidance stage (needs dataset)
  bool timing = true;
  bool resources = true;
  std::string device = "XCZU3EG";  // resources: utilisation and fit on this device ("" = none)
  std::string flight_scenario;     // "" = no flights
  int flight_seeds = 3;
  double flight_speed_mps = 5.0;
  int flight_size_px = 160;
  // Views for a report (reports/ draws them): the design's maps and avoidance stage on one frame
  // of view_dataset ("" = none; view_frame "" = the first with ground truth), and one flight
  // (seed 1) through view_scenario ("" = none) at flight_speed_mps and flight_size_px.
  std::string view_dataset, view_frame, view_scenario;
};

// Evaluates what `request` asks for and `result` does not hold yet, in the order accuracy,
// avoidance, flights, timing, resources (a part measured elsewhere, e.g. the accuracy of designs
// sharing their matching costs in a sweep, is kept as given). A deadlock of the cycle model sets
// status "error" with the reason and leaves timing and resources empty. Throws InputError for
// unusable input (dataset, scenario, device).
void complete_point(DesignResult& result, const PointRequest& request);
DesignResult evaluate_point(const config::PipelineConfig& cfg, const PointRequest& request);

// The views alone (what complete_point adds for view_dataset and view_scenario): the avoidance
// stage on a disparity map of a region at (x0, y0) of a KITTI-sized image, the design on one frame
// of a dataset, one flight. Throw InputError for unusable input.
AvoidanceView view_avoidance(const cv::Mat& disparity_px, const cv::Mat& valid_mask, int max_disparity, int roi_x0_px,
                             int roi_y0_px);
FrameView view_frame(const config::PipelineConfig& cfg, const std::string& dataset, const std::string& frame);
FlightView view_flight(const config::PipelineConfig& cfg, const std::string& scenario_path, double speed_mps,
                       int size_px);

// Resources, utilisation and power at a size, clock and frame interval: the resource part of
// evaluate_point, for the commands that time a design their own way (sim, export).
// device may be null (no utilisation; fits false). The power is at clock_mhz (a command may
// time the design at another clock than its configured one).
ResourceFigures resource_figures(const config::PipelineConfig& cfg, int width_px, int height_px,
                                 const res::Device* device, int clock_mhz, double frame_interval_ms);

// The store's columns of a result: every figure under its metric key (accuracy as named_metrics
// gives it plus "frames", avoidance scores, flight_*, latency_ms, frame_interval_ms, fps,
// cycles_per_frame, bram18k, lut, ff, dsp, fits_device, power_w, energy_mj_per_frame), and the
// per-frame accuracy. The one place where typed figures become columns.
std::map<std::string, double> metric_columns(const DesignResult& r);
std::vector<std::pair<std::string, std::map<std::string, double>>> frame_columns(const DesignResult& r);

}  // namespace parallax::design
