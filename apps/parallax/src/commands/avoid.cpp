// parallax avoid: obstacle detection and avoidance on a design's disparity maps, scored against
// the same stage on the ground truth; optionally MAVLink setpoints to a file or UDP.

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/evaluate.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/sim/func.hpp"
#include "parallax/uav/avoid.hpp"
#include "parallax/uav/fly.hpp"
#include "parallax/uav/json.hpp"
#include "parallax/uav/mavlink.hpp"
#include "parallax/uav/truth.hpp"

namespace parallax::cli {

namespace {

using nlohmann::json;
using namespace parallax::eval;
using namespace parallax::uav;
using namespace parallax::search;

struct AvoidOptions {
  ConfigArgs cfg;
  std::string dataset, frames, gt = "noc", calib, mavlink, truth;
  double sigma_d_px = 0.5, speed_mps = 5.0;
  bool json = false;
};

// The rig of a frame cropped to `roi`: --calib when given, else the frame's own calibration file
// (KITTI calib, Middlebury calib.txt), else KITTI 2015's.
Rig frame_rig(const std::string& calib, const Frame& f, const Roi& roi) {
  Rig rig = kitti_default_rig(roi.x0, roi.y0);
  if (!calib.empty()) {
    rig = load_rig(calib, roi.x0, roi.y0);
  } else if (f.calibration.known) {
    rig.focal_px = f.calibration.focal_px;
    rig.baseline_m = f.calibration.baseline_m;
    rig.cx_px = f.calibration.cx_px - roi.x0;
    rig.cy_px = f.calibration.cy_px - roi.y0;
  }
  return rig;
}

// The accumulated scores as text on stdout.
void print_avoid_text(const config::PipelineConfig& cfg, const AvoidAccumulator& acc,
                      std::map<std::string, double>& m) {
  const AvoidTimings& t = acc.timing_sum();
  const double n = double(acc.frames());
  std::printf(
      "%s on %d frames: obstacle_precision %.1f%%  obstacle_recall %.1f%%  range_error %.2f m  "
      "decision_agreement %.1f%%\n",
      cfg.name.c_str(), acc.frames(), m["obstacle_precision"], m["obstacle_recall"], m["range_error_m"],
      m["decision_agreement_pct"]);
  std::printf(
      "avoidance stage: %.2f ms per frame (U/V maps %.2f, ground + filtering %.2f, contours %.2f, planning %.3f)\n",
      m["mean_ms_per_frame"], t.uv_maps_ms / n, t.filtering_ms / n, t.contours_ms / n, t.planning_ms / n);
}

// One line of the scores against the scene's obstacles.
void print_truth_line(const char* label, const json& t, const json& head) {
  std::printf("  %-22s detected", label);
  for (const char* bin : {"0_5m", "5_10m", "10_20m", "20_40m"}) {
    const double v = t[std::string("detection_pct_") + bin].get<double>();
    if (v >= 0) std::printf("  %s %.0f%%", bin, v);
  }
  std::printf(
      "; first at %.1f m (median; %d never); false positives %.2f/frame; range error %.2f m; blocked within %.1f m "
      "right in %.0f%% of frames (%d missed, %d false)\n",
      t["first_detection_range_m"].get<double>(), int(t["never_detected"].get<double>()),
      t["false_positives_per_frame"].get<double>(), t["range_error_m"].get<double>(), head["stopping_m"].get<double>(),
      t["blocked_agreement_pct"].get<double>(), int(t["missed_blocks"].get<double>()),
      int(t["false_blocks"].get<double>()));
}

// The scores against the scene's obstacles as text on stdout.
void print_truth_text(const json& t) {
  std::printf("against the scene's obstacles (3D, tolerance %s, sigma_d %.2f px; stopping distance at %.0f m/s):\n",
              t["tolerance"].get<std::string>().c_str(), t["sigma_disparity_px"].get<double>(),
              t["speed_mps"].get<double>());
  print_truth_line("design", t, t);
  print_truth_line("exact disparity", t["on_ground_truth_disparity"], t);
}

// One frame of the command: the stage on the design's map and on the ground truth's, and the
// setpoint sent for it.
struct AvoidFrameRow {
  std::string frame;
  AvoidScore score;  // the design's obstacles matched against the ground truth's
  Manoeuvre decision = Manoeuvre::fly_on, reference_decision = Manoeuvre::fly_on;
  double nearest_range_m = 0;             // of the design's nearest obstacle; 0 when it found none
  Eigen::Vector3d velocity_mps{0, 0, 0};  // the setpoint: forward, right, down
  uint32_t time_boot_ms = 0;              // the setpoint's time stamp
};

// A frame row's JSON form: frame, obstacles, reference_obstacles, matched, decision,
// reference_decision, nearest_range_m, velocity_mps [forward, right, down] and time_boot_ms.
void to_json(json& j, const AvoidFrameRow& r) {
  j = {{"frame", r.frame},
       {"obstacles", r.score.predicted},
       {"reference_obstacles", r.score.reference},
       {"matched", r.score.matched},
       {"decision", to_string(r.decision)},
       {"reference_decision", to_string(r.reference_decision)},
       {"nearest_range_m", r.nearest_range_m},
       {"velocity_mps", {r.velocity_mps.x(), r.velocity_mps.y(), r.velocity_mps.z()}},
       {"time_boot_ms", r.time_boot_ms}};
}

int run_avoid(const AvoidOptions& o, const Invocation&) {
  const config::PipelineConfig cfg = load_config_args(o.cfg);
  if (o.gt != "noc" && o.gt != "occ") throw InputError("--gt '" + o.gt + "': expected noc or occ");
  const Dataset ds = open_dataset(o.dataset);
  const auto refs = list_frames(ds, o.gt == "occ" ? GtKind::occ : GtKind::noc, o.frames);
  if (refs.empty()) throw InputError(o.dataset + ": no frame with ground truth matches '" + o.frames + "'");
  MavlinkSink mav(o.mavlink, "--mavlink-out");
  // The companion's clock: time stamps are this machine's monotonic time since the command began
  // (the frames of a dataset are not a flight; what a setpoint says is when it was sent).
  MavlinkStream stream;
  const auto boot = std::chrono::steady_clock::now();
  sim::FuncPipeline pipe;
  AvoidAccumulator acc;
  // The scene's own obstacles (a rendered dataset's obstacles.json), when there are any.
  std::string truth_path = o.truth;
  if (truth_path.empty() && std::filesystem::exists(std::filesystem::path(o.dataset) / "obstacles.json"))
    truth_path = (std::filesystem::path(o.dataset) / "obstacles.json").string();
  const auto truth = truth_path.empty() ? std::map<std::string, std::vector<TruthObstacle>>() : read_truth(truth_path);
  TruthScoreParams tp;
  tp.sigma_disparity_px = o.sigma_d_px;
  TruthAccumulator truth_acc, truth_ref;  // the stage on the design's disparity, on the exact one
  bool truth_started = false;
  std::vector<AvoidFrameRow> per_frame;
  for (const auto& ref : refs) {
    Frame f = load_frame(ref);
    const Roi roi = resolve_roi(roi_for(cfg), f.left.cols, f.left.rows);
    const Rig rig = frame_rig(o.calib, f, roi);
    const DisparityMap d = run_design(cfg, crop_to_roi(f.left, roi).clone(), crop_to_roi(f.right, roi).clone(), pipe);
    const AvoidScore s = acc.add(d.disparity_px, d.valid_mask, crop_to_roi(f.gt_disparity_px, roi),
                                 crop_to_roi(f.gt_mask, roi), cfg.disparity_end_px(), rig);
    const AvoidResult& mine = acc.last_design();
    if (!truth_path.empty()) {
      const auto it = truth.find(f.id);
      if (it == truth.end()) throw InputError(truth_path + ": no obstacle list for frame " + f.id);
      if (!truth_started) {  // the first frame: the stopping distance at the design's size and timing
        truth_started = true;
        double interval_ms = 0, latency_ms = 0;
        design_timing(cfg, roi.width_px, roi.height_px, interval_ms, latency_ms);
        const double tau_s = (latency_ms + cfg.avoid_ms + interval_ms) * 1e-3, a = VehicleParams{}.max_accel_mps2;
        tp.stopping_m = o.speed_mps * tau_s + o.speed_mps * o.speed_mps / (2 * a);
        truth_acc = TruthAccumulator(tp);
        truth_ref = TruthAccumulator(tp);
      }
      // What the design's window sees of them (the list is for the rendered frame's full width).
      std::vector<TruthObstacle> in_roi;
      for (TruthObstacle t : it->second)
        if (clip_to_view(t, rig, roi.width_px, 40.0)) in_roi.push_back(t);
      truth_acc.add(mine.obstacles, in_roi, rig);
      truth_ref.add(acc.last_reference().obstacles, in_roi, rig);
    }
    VelocitySetpoint sp;
    sp.time_boot_ms = uint32_t(
        std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - boot).count());
    sp.velocity_mps = mine.velocity_mps;  // forward, right, down
    sp.frame = SetpointFrame::body_frd;
    if (mav.active())
      for (const auto& frame : stream.setpoint(sp)) mav.send(frame);
    per_frame.push_back({f.id, s, mine.manoeuvre, acc.last_reference().manoeuvre,
                         mine.obstacles.empty() ? 0.0 : mine.obstacles.front().range_m, mine.velocity_mps,
                         sp.time_boot_ms});
  }
  std::map<std::string, double> m;
  for (const auto& kv : acc.metrics()) m[kv.first] = kv.second;
  json j = acc;  // frames, the scores and the stage's time split (parallax/uav/json.hpp)
  j["config"] = cfg.name;
  j["per_frame"] = per_frame;
  if (!truth_path.empty()) {
    json t = {{"file", truth_path},
              {"sigma_disparity_px", tp.sigma_disparity_px},
              {"tolerance", "max(0.5 m, 3 Z^2 sigma_d / (f B))"},
              {"speed_mps", o.speed_mps},
              {"stopping_m", tp.stopping_m}};
    t.update(json(truth_acc));  // the scores against the scene's obstacles
    t["on_ground_truth_disparity"] = truth_ref;
    j["scene_obstacles"] = t;
  }
  if (o.json) {
    std::cout << j.dump(2) << "\n";
  } else {
    print_avoid_text(cfg, acc, m);
    if (!truth_path.empty()) print_truth_text(j["scene_obstacles"]);
  }
  return 0;
}

}  // namespace

Command add_avoid(CLI::App& app) {
  auto o = std::make_shared<AvoidOptions>();
  auto* avoidc = app.add_subcommand("avoid",
                                    "Obstacle detection and avoidance on the design's disparity maps, scored against "
                                    "the same stage on the ground truth");
  add_config_options(avoidc, o->cfg, true);
  add_engine_option(avoidc);
  avoidc->add_option("--dataset", o->dataset, "Dataset folder (KITTI 2015/2012)")->required();
  avoidc->add_option("--frames", o->frames, "Frame filter, e.g. 0-9,15, or @FILE (default: all with ground truth)")
      ->transform(FrameList());
  avoidc->add_option("--gt", o->gt, "Ground truth: noc or occ")->capture_default_str();
  avoidc->add_option(
      "--calib", o->calib,
      "Rig calibration: KITTI calib file (P_rect_02/03 or P2/P3) or OpenCV YAML (default: KITTI 2015's)");
  avoidc
      ->add_option("--mavlink-out", o->mavlink,
                   "Write MAVLink 2 to a file or udp:IPv4:PORT: a heartbeat each second, a body-frame velocity "
                   "setpoint per frame, OFFBOARD mode and arm commands after the first second")
      ->check(OutputFile());
  avoidc
      ->add_option("--truth", o->truth,
                   "The scene's obstacles per frame (obstacles.json, written by `parallax scene`; default: the "
                   "dataset's own when it has one): detections matched in 3D, scored by range")
      ->check(CLI::ExistingFile);
  avoidc->add_option("--sigma-d-px", o->sigma_d_px, "Disparity error (one sigma) for the 3D match tolerance")
      ->capture_default_str()
      ->check(InRange(0.01, 10.0));
  avoidc->add_option("--speed-mps", o->speed_mps, "Speed whose stopping distance decides 'blocked' (3D scores)")
      ->capture_default_str()
      ->check(InRange(0.1, 50.0));
  avoidc->add_flag("--json", o->json, "Print JSON");
  return bind_command(avoidc, o, run_avoid);
}

}  // namespace parallax::cli
