// parallax: the command-line front end. Every command has --help; user errors (bad files, bad
// configurations) print one clear message naming the file or field and exit with status 2.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>

#ifdef PARALLAX_HAVE_MPI
#include <mpi.h>
#endif

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "parallax/config/config.hpp"
#include "parallax/uav/avoid.hpp"
#include "parallax/eval/bench.hpp"
#include "parallax/reports/report.hpp"
#include "parallax/uav/fly.hpp"
#include "parallax/hls_flow/hls_export.hpp"
#include "parallax/hls_flow/hls_report.hpp"
#include "parallax/uav/scene.hpp"
#include "parallax/search/sweep.hpp"
#include "parallax/resources/fit.hpp"
#include "parallax/resources/model.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/disparity_io.hpp"
#include "parallax/eval/evaluate.hpp"
#include "parallax/eval/metrics.hpp"
#include "parallax/eval/simulate.hpp"
#include "parallax/sim/func.hpp"
#include "parallax/sim/schedule.hpp"

#include "cli_common.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace parallax;
using namespace parallax::explore;
using namespace parallax::cli;

namespace {

constexpr long long kMaxImagePixels = 8192LL * 8192LL;  // 64 Mpx: KITTI is 0.5, Middlebury 2014 full size 6

// MAVLink output: a file (binary frames back to back) or udp:HOST:PORT; nothing when empty.
class MavlinkSink {
 public:
  explicit MavlinkSink(const std::string& where) {
    if (where.empty()) return;
    if (where.rfind("udp:", 0) == 0) {
      const auto colon = where.rfind(':');
      const std::string host = where.substr(4, colon - 4);
      const int port = std::atoi(where.substr(colon + 1).c_str());
      fd_ = socket(AF_INET, SOCK_DGRAM, 0);
      addr_.sin_family = AF_INET;
      addr_.sin_port = htons(uint16_t(port));
      if (fd_ < 0 || port <= 0 || inet_pton(AF_INET, host.c_str(), &addr_.sin_addr) != 1)
        throw InputError("--mavlink-out '" + where + "': expected udp:IPv4:PORT");
      return;
    }
    file_.open(where, std::ios::binary);
    if (!file_) throw InputError("--mavlink-out '" + where + "': cannot write");
  }
  ~MavlinkSink() {
    if (fd_ >= 0) close(fd_);
  }
  void send(const std::vector<uint8_t>& frame) {
    if (file_.is_open()) file_.write(reinterpret_cast<const char*>(frame.data()), std::streamsize(frame.size()));
    if (fd_ >= 0)
      (void)sendto(fd_, frame.data(), frame.size(), 0, reinterpret_cast<const sockaddr*>(&addr_), sizeof addr_);
  }

 private:
  std::ofstream file_;
  int fd_ = -1;
  sockaddr_in addr_{};
};

// Resources, utilisation and power of a design at its processed size (models/resources).
struct ResourceReport {
  res::Estimate estimate;
  res::Utilisation util;
  res::Power power;
};
ResourceReport resource_report(const config::PipelineConfig& cfg, int width_px, int height_px, const res::Device& dev,
                               int clock_mhz, double frame_interval_ms) {
  ResourceReport r;
  r.estimate = res::estimate(res::design_inventory(cfg, width_px, height_px));
  r.util = res::utilisation(r.estimate.total, dev);
  r.power = res::power(r.estimate.total, clock_mhz, frame_interval_ms);
  return r;
}
void add_resources_json(json& j, const ResourceReport& r) {
  const res::Usage& u = r.estimate.total;
  j["device"] = r.util.device->name;
  j["bram18k"] = u.bram18k;
  j["uram"] = u.uram;
  j["lut"] = u.lut;
  j["ff"] = u.ff;
  j["dsp"] = u.dsp;
  j["fits_device"] = r.util.fits;
  j["utilisation_pct"] = {{"bram18k", r.util.bram18k_pct}, {"uram", r.util.uram_pct}, {"lut", r.util.lut_pct},
                          {"ff", r.util.ff_pct}, {"dsp", r.util.dsp_pct}};
  j["resource_stages"] = json::array();
  for (const auto& s : r.estimate.stages)
    j["resource_stages"].push_back({{"stage", s.stage}, {"bram18k", s.usage.bram18k}, {"lut", s.usage.lut},
                                    {"ff", s.usage.ff}, {"dsp", s.usage.dsp}, {"lutram_luts", s.usage.lutram_luts},
                                    {"srl_luts", s.usage.srl_luts}});
  j["power_estimate_w"] = {{"static", r.power.static_w}, {"dynamic", r.power.dynamic_w}, {"total", r.power.total_w}};
  j["energy_estimate_mj_per_frame"] = r.power.energy_mj_per_frame;
}
void print_resources(const ResourceReport& r) {
  const res::Usage& u = r.estimate.total;
  const res::Device& d = *r.util.device;
  std::printf("\nresources (estimate)  %-8s %8s %8s %8s %8s\n", "BRAM_18K", "LUT", "FF", "DSP", "URAM");
  for (const auto& s : r.estimate.stages)
    std::printf("  %-19s %8lld %8lld %8lld %8lld %8d\n", s.stage.c_str(), (long long)s.usage.bram18k,
                (long long)s.usage.lut, (long long)s.usage.ff, (long long)s.usage.dsp, 0);
  std::printf("  %-19s %8lld %8lld %8lld %8lld %8lld\n", "total", (long long)u.bram18k, (long long)u.lut, (long long)u.ff,
              (long long)u.dsp, (long long)u.uram);
  std::printf("  %-19s %8lld %8lld %8lld %8lld %8lld\n", d.name.c_str(), (long long)d.bram18k, (long long)d.lut,
              (long long)d.ff, (long long)d.dsp, (long long)d.uram);
  std::printf("  %-19s %7.1f%% %7.1f%% %7.1f%% %7.1f%% %7.1f%%\n", "utilisation", r.util.bram18k_pct, r.util.lut_pct,
              r.util.ff_pct, r.util.dsp_pct, r.util.uram_pct);
  std::printf("fits %s: %s\n", d.name.c_str(), r.util.fits ? "yes" : "no");
  std::printf("power (estimate)     %.2f W static + %.2f W dynamic = %.2f W; %.1f mJ per frame\n", r.power.static_w,
              r.power.dynamic_w, r.power.total_w, r.power.energy_mj_per_frame);
}

// What sets each kernel stage's II (sim/schedule.hpp), at the design's own (synthesis) clock.
std::map<std::string, std::string> ii_reasons(const config::PipelineConfig& cfg, int w, int h) {
  std::map<std::string, std::string> out;
  const kern::RectifyParams rect = cfg.rectify_params(w, h);
  for (const auto& s : sim::stage_schedules(cfg.stereo_params(w, h), rect, double(cfg.clock_mhz) * 1e6))
    out[s.stage] = "II " + std::to_string(s.ii) + ": " + s.limit;
  return out;
}

}  // namespace

int run_cli(int argc, char** argv) {
  CLI::App app{"parallax: bit-accurate simulator and design-space explorer of an FPGA stereo (SGM) pipeline"};
  app.require_subcommand(1);
  // Command-line mistakes read like every other error: one "parallax: error:" line.
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return std::string("parallax: error: ") + e.what() + "\nRun `parallax COMMAND --help` for the options.\n";
  });
  app.set_version_flag("--version", "parallax 0.1.0");

  // run
  ConfigArgs run_cfg;
  std::string run_left, run_right, run_out, run_gt, run_colour;
  bool run_json = false;
  auto* run = app.add_subcommand("run", "Compute the disparity of one stereo pair with a design (func run)");
  add_config_options(run, run_cfg, true);
  run->add_option("--left", run_left, "Left image (8-bit grey or colour)")->required();
  run->add_option("--right", run_right, "Right image, same size")->required();
  run->add_option("--out", run_out, "Disparity as KITTI 16-bit PNG (value = 256 d, 0 = invalid)")->required()->check(OutputFile(".png"));
  run->add_option("--colour", run_colour, "Colour-coded picture (default: OUT with _colour.png)")->check(OutputFile(".png"));
  run->add_option("--gt", run_gt, "Ground truth (KITTI 16-bit PNG, full image or ROI size) to score against");
  run->add_flag("--json", run_json, "Print a JSON object (metrics when --gt is given)");
  std::string run_html;
  run->add_option("--html", run_html, "Write a self-contained HTML page of this design on this pair (images, timing, resources)")
      ->check(OutputFile());

  // eval
  ConfigArgs eval_cfg;
  std::string eval_dataset, eval_frames, eval_gt = "noc", eval_save, eval_roi;
  bool eval_json = false, eval_quiet = false;
  int eval_threads = default_threads();
  auto* eval = app.add_subcommand("eval", "Score a design on a dataset (KITTI 2015/2012 or Middlebury)");
  add_config_options(eval, eval_cfg, true);
  eval->add_option("--dataset", eval_dataset, "Dataset folder (KITTI root or training/, or a Middlebury pairs.tsv folder)")->required();
  eval->add_option("--frames", eval_frames, "Frames, e.g. 1-5,7 or 000046, or @FILE with one per line (default: all with GT)")
      ->transform(FrameList());
  eval->add_option("--gt", eval_gt, "Ground truth kind: noc or occ")->check(CLI::IsMember({"noc", "occ"}));
  eval->add_option("--roi", eval_roi, "Override the config's ROI: WxH or full");
  std::string eval_context = "roi";
  eval->add_option("--context", eval_context, "roi: match the cropped pair (paper); full: match the whole image, then crop")
      ->check(CLI::IsMember({"roi", "full"}))->capture_default_str();
  eval->add_option("--save", eval_save, "Write each frame's disparity (KITTI PNG) and colour picture here")->check(OutputFolder());
  eval->add_option("--threads", eval_threads, "Frames in parallel (default: all cores)")->check(InRange(1, 256));
  eval->add_flag("--json", eval_json, "Print JSON: pooled metrics, counts and per-frame rows");
  eval->add_flag("--quiet", eval_quiet, "No progress lines");

  // score
  std::string score_pred, score_dataset, score_frames, score_gt = "noc", score_roi;
  bool score_json = false;
  auto* score = app.add_subcommand("score", "Score existing KITTI-format disparity PNGs (any method) with the same protocol");
  score->add_option("--pred", score_pred, "Folder of predictions, one KITTI 16-bit PNG per frame named <frame id>_10.png (as eval --save writes them)")->required();
  score->add_option("--dataset", score_dataset, "Dataset folder with the ground truth")->required();
  score->add_option("--frames", score_frames, "Frames to score, e.g. 1-5,7, or @FILE (default: all with GT)")->transform(FrameList());
  score->add_option("--gt", score_gt, "Ground truth kind: noc or occ")->check(CLI::IsMember({"noc", "occ"}));
  score->add_option("--roi", score_roi, "ROI WxH or full (default: the dataset's, 640x360 for KITTI)");
  score->add_flag("--json", score_json, "Print JSON");

  // baseline
  std::string base_name, base_dataset, base_frames, base_gt = "noc", base_save, base_roi;
  BaselineParams base_params;
  bool base_json = false, base_quiet = false;
  int base_threads = default_threads();
  auto* baseline = app.add_subcommand("baseline", "Score OpenCV StereoSGBM (opencv-hh4 | opencv-sgbm) on the same crops");
  baseline->add_option("method", base_name, "opencv-hh4 or opencv-sgbm")->required()->check(CLI::IsMember({"opencv-hh4", "opencv-sgbm"}));
  baseline->add_option("--dataset", base_dataset, "Dataset folder")->required();
  baseline->add_option("--frames", base_frames, "Frames, e.g. 1-5,7, or @FILE (default: all with GT)")->transform(FrameList());
  baseline->add_option("--gt", base_gt, "noc or occ")->check(CLI::IsMember({"noc", "occ"}));
  baseline->add_option("--roi", base_roi, "ROI WxH or full (default: the dataset's, 640x360 for KITTI)");
  baseline->add_option("--disparities", base_params.disparities, "Disparity count (rounded up to a multiple of 16)")
      ->capture_default_str()->check(InRange(1, 1024));
  baseline->add_option("--block-size", base_params.block_size, "Matching block size (odd)")
      ->capture_default_str()->check(InRange(1, 255))->check(CLI::Validator(
          [](std::string& v) { return std::atoi(v.c_str()) % 2 == 1 ? std::string() : "block size " + v + " is even; OpenCV needs it odd"; },
          "odd"));
  baseline->add_option("--p1", base_params.p1, "P1 (0 <= P1 < P2)")->capture_default_str()->check(InRange(0, 1 << 24));
  baseline->add_option("--p2", base_params.p2, "P2 (> P1)")->capture_default_str()->check(InRange(1, 1 << 24));
  baseline->add_option("--save", base_save, "Write each frame's disparity and colour picture here")->check(OutputFolder());
  baseline->add_option("--threads", base_threads, "Frames in parallel")->check(InRange(1, 256));
  baseline->add_flag("--json", base_json, "Print JSON");
  baseline->add_flag("--quiet", base_quiet, "No progress lines");

  // config
  ConfigArgs show_cfg;
  auto* show = app.add_subcommand("config", "Validate a configuration and print it in canonical form with derived bit widths");
  add_config_options(show, show_cfg, true);

  // crop-dataset
  std::string crop_src, crop_out, crop_frames, crop_roi = "640x360";
  auto* crop = app.add_subcommand("crop-dataset", "Write the centred ROI crop of a KITTI 2015 dataset (images and GT) as a new dataset");
  crop->add_option("--dataset", crop_src, "Source dataset")->required();
  crop->add_option("--frames", crop_frames, "Frames, e.g. 1-5,7, or @FILE (default: all)")->transform(FrameList());
  crop->add_option("--roi", crop_roi, "ROI WxH")->capture_default_str();
  crop->add_option("--out", crop_out, "Output folder")->required()->check(OutputFolder());

  // bench
  ConfigArgs bench_cfg;
  std::string bench_left, bench_right;
  int bench_iterations = 7;
  bool bench_json = false;
  auto* bench = app.add_subcommand("bench", "Time the func run against OpenCV StereoSGBM (HH4, SGBM) on one pair, one thread each, with peak memory");
  add_config_options(bench, bench_cfg, true);
  bench->add_option("--left", bench_left, "Left image")->required();
  bench->add_option("--right", bench_right, "Right image")->required();
  bench->add_option("--iterations", bench_iterations, "Runs per method (the median is reported)")->capture_default_str()->check(InRange(1, 1000));
  bench->add_flag("--json", bench_json, "Print JSON");

  // sim
  ConfigArgs sim_cfg;
  std::string sim_left, sim_right, sim_out, sim_vcd, sim_vcd_cycles, sim_write_config;
  int sim_clock_mhz = 0;
  bool sim_json = false, sim_no_sizing = false, sim_coupled = false, sim_every_firing = false;
  std::string sim_device = "XCZU3EG";
  double sim_cal_latency = 0, sim_cal_fps = 0;
  auto* simc = app.add_subcommand("sim", "Cycle-level simulation of one frame: latency, frame rate, stalls, FIFO depths");
  add_config_options(simc, sim_cfg, true);
  simc->add_option("--left", sim_left, "Left image (default: a generated test pattern of the ROI size)");
  simc->add_option("--right", sim_right, "Right image");
  simc->add_option("--out", sim_out, "Write the disparity (KITTI 16-bit PNG) of the cycle run")->check(OutputFile(".png"));
  simc->add_option("--clock-mhz", sim_clock_mhz, "Processing clock in MHz (default: the config's clock_mhz)")->check(InRange(1, 2000));
  simc->add_flag("--json", sim_json, "Print JSON");
  simc->add_flag("--no-sizing", sim_no_sizing, "Skip the second run that finds stall-free FIFO depths");
  simc->add_flag("--coupled", sim_coupled,
                 "Fire the kernels' datapath inside the schedule at the design's PU (slower; same report and "
                 "output, which by default come from the control-path schedule and the func run)");
  std::string sim_html;
  simc->add_option("--html", sim_html, "Write a self-contained HTML page of this design (timing, FIFOs, resources, images)")
      ->check(OutputFile());
  simc->add_option("--device", sim_device, "Device for utilisation and fit (" + res::device_names() + ")")
      ->capture_default_str();
  simc->add_flag("--every-firing", sim_every_firing,
                 "Simulate every firing instead of applying rows that repeat exactly at once (same report, slower)");
  simc->add_option("--vcd", sim_vcd, "Write FIFO occupancies and stage valid/stall signals as VCD (GTKWave)")->check(OutputFile());
  simc->add_option("--vcd-cycles", sim_vcd_cycles, "Cycle window A:B of the VCD (default 0:20000)");
  simc->add_option("--calibrate-latency-ms", sim_cal_latency, "Measured latency at this clock: set host_latency_ms to match")
      ->check(InRange(0.001, 1e6));
  simc->add_option("--calibrate-fps", sim_cal_fps, "Measured frame rate at this clock: set host_frame_ms to match")
      ->check(InRange(0.001, 1e6));
  simc->add_option("--write-config", sim_write_config, "Write the (calibrated) configuration here")->check(OutputFile());

  // sweep
  std::string sw_spec, sw_base, sw_dataset, sw_frames, sw_gt, sw_db, sw_strategy, sw_name;
  std::vector<std::string> sw_grid;
  int sw_jobs = 0, sw_samples = 0;
  uint32_t sw_seed = 0;
  auto* sweepc = app.add_subcommand("sweep", "Evaluate many designs (accuracy, timing, resources) into a SQLite store; reruns skip finished designs");
  sweepc->add_option("spec", sw_spec, "Sweep file (YAML, docs/explorer.md); optional when --base and --grid say it all");
  sweepc->add_option("--base", sw_base, "Base configuration the axes modify (overrides the file's)");
  sweepc->add_option("--grid", sw_grid, "Axis KEY=V1,V2,... over any configuration field (repeatable)");
  sweepc->add_option("--dataset", sw_dataset, "Dataset folder (KITTI 2015/2012, Middlebury)")->required();
  sweepc->add_option("--frames", sw_frames, "Frame filter, e.g. 0-9,15, or @FILE (default: the file's, else all)")
      ->transform(FrameList());
  sweepc->add_option("--gt", sw_gt, "Ground truth: noc or occ (default: the file's, else noc)");
  sweepc->add_option("--db", sw_db, "Results store (SQLite); created if absent")->required();
  sweepc->add_option("--jobs", sw_jobs, "Designs in parallel (default: all cores)")->check(InRange(0, 256));
  sweepc->add_option("--strategy", sw_strategy, "grid, random, lhs or nsga2 (default: the file's, else grid)");
  sweepc->add_option("--samples", sw_samples, "Designs drawn by random / lhs; population of nsga2")->check(InRange(1, 1000000));
  int sw_generations = 0;
  sweepc->add_option("--generations", sw_generations, "Generations of nsga2 after the first population")->check(InRange(1, 10000));
  sweepc->add_option("--seed", sw_seed, "Seed of random / lhs");
  sweepc->add_option("--name", sw_name, "Sweep name in the store (default: the file's, else 'sweep')");
  bool sw_avoidance = false;
  std::string sw_flight;
  sweepc->add_option("--flight", sw_flight, "Also fly every design through this scenario (configs/scenarios/*.yaml), 3 seeds at 5 m/s");
  sweepc->add_flag("--avoidance", sw_avoidance, "Also score the avoidance stage on every design (obstacle_precision, ...)");
  bool sw_yes = false;
  sweepc->add_flag("--yes", sw_yes, "Run a sweep of more than 10,000 designs (otherwise refused: sample with lhs or nsga2)");
  std::string sw_shard;
  bool sw_mpi = false, sw_no_sharing = false;
  sweepc->add_flag("--no-sharing", sw_no_sharing,
                   "Evaluate every design on its own (by default designs sharing the cost stage share each frame's costs)");
  sweepc->add_option("--shard", sw_shard, "K/N: evaluate only shard K of N (merge the stores with `parallax merge`)");
#ifdef PARALLAX_HAVE_MPI
  sweepc->add_flag("--mpi", sw_mpi, "Under mpirun: rank r evaluates shard r+1 of the ranks into DB.rank<r>; rank 0 merges them into DB");
#endif

  // merge
  std::string mg_db;
  std::vector<std::string> mg_inputs;
  auto* mergec = app.add_subcommand("merge", "Merge results stores (shards of a sweep) into one");
  mergec->add_option("--db", mg_db, "Store to merge into (created if absent)")->required();
  mergec->add_option("inputs", mg_inputs, "Stores to merge from")->required();

  // pareto
  std::string pa_db, pa_sweep;
  bool pa_json = false;
  auto* paretoc = app.add_subcommand("pareto", "The non-dominated designs of a sweep that meet its constraints");
  paretoc->add_option("--db", pa_db, "Results store")->required();
  paretoc->add_option("--sweep", pa_sweep, "Sweep name (default: the only one in the store)");
  paretoc->add_flag("--json", pa_json, "Print JSON: a list of designs with configuration and metrics");

  // report
  std::string rp_db, rp_sweep, rp_html, rp_csv, rp_frames_csv, rp_json, rp_dataset, rp_frame;
  int rp_details = 6;
  auto* reportc = app.add_subcommand("report", "CSV, JSON and a self-contained HTML report of a sweep");
  reportc->add_option("--db", rp_db, "Results store")->required();
  reportc->add_option("--sweep", rp_sweep, "Sweep name (default: the only one in the store)");
  reportc->add_option("--html", rp_html, "Write the HTML report (one file, viewable offline)")->check(OutputFile());
  reportc->add_option("--csv", rp_csv, "Write one row per design (parameters and metrics)")->check(OutputFile());
  reportc->add_option("--frames-csv", rp_frames_csv, "Write one row per design and frame")->check(OutputFile());
  reportc->add_option("--json", rp_json, "Write the same content as JSON")->check(OutputFile());
  reportc->add_option("--dataset", rp_dataset, "Dataset to render the front designs' images from (optional)");
  reportc->add_option("--frame", rp_frame, "Frame of those images (default: the first with ground truth)");
  reportc->add_option("--details", rp_details, "Front designs with a full section")->capture_default_str()->check(InRange(0, 1000));

  // avoid
  ConfigArgs av_cfg;
  std::string av_dataset, av_frames, av_gt = "noc", av_calib, av_mavlink;
  bool av_json = false;
  auto* avoidc = app.add_subcommand("avoid", "Obstacle detection and avoidance on the design's disparity maps, scored against the same stage on the ground truth");
  add_config_options(avoidc, av_cfg, true);
  avoidc->add_option("--dataset", av_dataset, "Dataset folder (KITTI 2015/2012)")->required();
  avoidc->add_option("--frames", av_frames, "Frame filter, e.g. 0-9,15, or @FILE (default: all with ground truth)")
      ->transform(FrameList());
  avoidc->add_option("--gt", av_gt, "Ground truth: noc or occ")->capture_default_str();
  avoidc->add_option("--calib", av_calib, "Rig calibration: KITTI calib file (P_rect_02/03 or P2/P3) or OpenCV YAML (default: KITTI 2015's)");
  avoidc->add_option("--mavlink-out", av_mavlink, "Write MAVLink 2 (HEARTBEAT + velocity setpoint per frame) to a file or udp:HOST:PORT")
      ->check(OutputFile());
  avoidc->add_flag("--json", av_json, "Print JSON");

  // scene
  std::string sc_scenario, sc_out;
  uint32_t sc_seed = 1;
  int sc_frames = 10, sc_width = 640, sc_height = 360;
  double sc_step = 2.0;
  auto* scenec = app.add_subcommand("scene", "Render a seeded synthetic scene along the flight axis as a KITTI-layout stereo dataset");
  scenec->add_option("--scenario", sc_scenario, "Scenario file, e.g. configs/scenarios/forest.yaml")->required();
  scenec->add_option("--seed", sc_seed, "Scene seed")->capture_default_str();
  scenec->add_option("--frames", sc_frames, "Frames, one every --step-m along the flight axis")->capture_default_str()->check(InRange(1, 10000));
  scenec->add_option("--step-m", sc_step, "Distance between frames")->capture_default_str()->check(InRange(0.01, 100.0));
  scenec->add_option("--size", sc_width, "Image width (height = width x 9/16)")->capture_default_str()->check(InRange(32, 4096));
  scenec->add_option("--out", sc_out, "Output folder (KITTI layout: training/image_2, image_3, disp_noc_0, disp_occ_0)")->required()
      ->check(OutputFolder());
  double sc_k1 = 0.0;
  scenec->add_option("--distortion-k1", sc_k1, "Radial lens distortion: images distorted, OUT/maps_left.yml and maps_right.yml rectify them")
      ->check(InRange(-0.5, 0.5));

  // fly
  ConfigArgs fl_cfg;
  std::string fl_scenario;
  int fl_seeds = 3, fl_size = 320;
  double fl_speed = 5.0;
  bool fl_json = false, fl_find = false;
  auto* flyc = app.add_subcommand("fly", "Closed-loop flights through synthetic scenes with the design's disparity, latency and frame rate");
  add_config_options(flyc, fl_cfg, true);
  flyc->add_option("--scenario", fl_scenario, "Scenario file, e.g. configs/scenarios/forest.yaml")->required();
  flyc->add_option("--seeds", fl_seeds, "Scenes (seeds 1..N)")->capture_default_str()->check(InRange(1, 1000));
  flyc->add_option("--speed-mps", fl_speed, "Cruise speed")->capture_default_str()->check(InRange(0.1, 50.0));
  flyc->add_option("--size", fl_size, "Rendered width (height x 9/16); the design's ROI follows")->capture_default_str()->check(InRange(64, 1280));
  flyc->add_flag("--find-max-speed", fl_find, "Search the highest speed without a collision over the seeds");
  double fl_noise = 0.0, fl_limit = 40.0;
  flyc->add_option("--noise-grey", fl_noise, "Sensor noise: Gaussian sigma added to the grey levels")->capture_default_str()->check(InRange(0.0, 50.0));
  flyc->add_option("--time-limit-s", fl_limit, "Flight time limit")->capture_default_str()->check(InRange(1.0, 3600.0));
  flyc->add_flag("--json", fl_json, "Print JSON");

  // export-hls
  ConfigArgs ex_cfg;
  std::string ex_db, ex_design, ex_out, ex_part = "xczu3eg-sbva484-1-e", ex_left, ex_right;
  double ex_clock = 0;
  bool ex_json = false;
  auto* exportc = app.add_subcommand(
      "export-hls",
      "Write a Vitis HLS project of a design: DATAFLOW top, C testbench with the simulator's golden output, "
      "run_hls.tcl, hls_config.cfg, and a Makefile whose `make csim` needs only g++");
  add_config_options(exportc, ex_cfg, false);
  exportc->add_option("--db", ex_db, "Results store of a sweep; with --design, export one of its designs");
  exportc->add_option("--design", ex_design, "Design hash in --db (or a unique prefix of at least 4 hex digits)");
  exportc->add_option("--out", ex_out, "Project folder (new, empty, or written by an earlier export)")->required();
  exportc->add_option("--part", ex_part, "FPGA part of the synthesis run")->capture_default_str();
  exportc->add_option("--clock-mhz", ex_clock, "Synthesis clock in MHz (default: the design's clock_mhz)")
      ->check(InRange(1.0, 2000.0));
  exportc->add_option("--left", ex_left, "Left image of the testbench, cropped to the design's ROI (default: a generated test pattern)");
  exportc->add_option("--right", ex_right, "Right image of the testbench");
  exportc->add_flag("--json", ex_json, "Print JSON");

  // import-hls
  std::string ih_report, ih_config, ih_write;
  bool ih_json = false;
  auto* importc = app.add_subcommand("import-hls", "Read a Vitis HLS csynth.xml back: latency, II per loop, resources; calibrate a configuration");
  importc->add_option("--report", ih_report, "csynth.xml of a synthesis run")->required();
  importc->add_option("--config", ih_config, "Configuration to calibrate (ii_<stage>, latency_<stage> from the loops)");
  importc->add_option("--write-config", ih_write, "Write the calibrated configuration here")->check(OutputFile());
  importc->add_flag("--json", ih_json, "Print JSON");
  std::string ih_html;
  importc->add_option("--html", ih_html, "With --config: write a page with the model's and the synthesis figures side by side")
      ->check(OutputFile());

  // fit-resources
  std::string fit_points = "models/data/published_points.yaml", fit_root = ".", fit_write;
  bool fit_json = false;
  auto* fitc = app.add_subcommand(
      "fit-resources", "Fit the resource model's LUT/FF coefficients to published designs (Ceres), with leave-one-out errors");
  fitc->add_option("--points", fit_points, "Published points (YAML)")->capture_default_str();
  fitc->add_option("--root", fit_root, "Repository root the points' config paths are relative to")->capture_default_str();
  fitc->add_option("--write", fit_write, "Write the coefficients with the fitted section here (e.g. models/data/resource_model.yaml)")
      ->check(OutputFile());
  fitc->add_flag("--json", fit_json, "Print JSON");

  const std::vector<CLI::App*> commands = app.get_subcommands([](CLI::App*) { return true; });
  if (argc > 1 && argv[1][0] != '-' &&
      std::none_of(commands.begin(), commands.end(), [&](const CLI::App* sc) { return sc->get_name() == argv[1]; })) {
    std::string names;
    for (const CLI::App* sc : commands) names += (names.empty() ? "" : ", ") + sc->get_name();
    std::fprintf(stderr, "parallax: error: unknown command '%s' (commands: %s)\n", argv[1], names.c_str());
    return kExitUserError;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version print and succeed; a malformed command line is a user error (2), as
    // every other bad input is, not CLI11's own codes.
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitUserError;
  }

  try {
    if (*run) {
      const config::PipelineConfig cfg = load_config_args(run_cfg);
      std::vector<std::string> notes;
      cv::Mat left = load_grey_file(run_left, "left", notes);
      cv::Mat right = load_grey_file(run_right, "right", notes);
      if (left.size() != right.size())
        throw InputError(run_right + ": right image is " + std::to_string(right.cols) + "x" + std::to_string(right.rows) +
                         " but the left image " + run_left + " is " + std::to_string(left.cols) + "x" +
                         std::to_string(left.rows));
      int64_t window_misses = 0;
      if (cfg.rectify != "none") {
        rectify_pair(cfg, load_rectify_maps(cfg), left, right, &window_misses);
        if (window_misses > 0)
          notes.push_back("rectification: " + std::to_string(window_misses) +
                          " map taps fell outside the line buffer's rows (read as 0); raise rectify_rows");
      }
      const Roi roi = resolve_roi(roi_for(cfg), left.cols, left.rows);
      const cv::Mat l = crop_to_roi(left, roi), r = crop_to_roi(right, roi);
      sim::FuncPipeline pipe;
      const DisparityMap d = run_design(cfg, l, r, pipe);
      write_kitti_disparity(run_out, d.disparity_px, d.valid_mask);
      DesignSection run_section;
      std::string colour = run_colour;
      if (colour.empty()) {
        fs::path p(run_out);
        colour = (p.parent_path() / (p.stem().string() + "_colour.png")).string();
      }
      write_png(colour, colourize_disparity(d.disparity_px, d.valid_mask, cfg.disparities));
      print_notes(notes);
      json j;
      j["config"] = cfg.name;
      j["roi"] = {{"x0", roi.x0}, {"y0", roi.y0}, {"width_px", roi.width_px}, {"height_px", roi.height_px}};
      j["out"] = run_out;
      j["colour"] = colour;
      if (cfg.rectify != "none") j["rectify_window_misses"] = window_misses;
      const int valid = cv::countNonZero(d.valid_mask);
      j["density_pct"] = 100.0 * valid / double(roi.width_px * roi.height_px);
      if (!run_gt.empty()) {
        DisparityMap gt = read_kitti_disparity(run_gt);
        if (gt.disparity_px.size() == left.size()) {
          gt.disparity_px = crop_to_roi(gt.disparity_px, roi);
          gt.valid_mask = crop_to_roi(gt.valid_mask, roi);
        } else if (gt.disparity_px.cols != roi.width_px || gt.disparity_px.rows != roi.height_px) {
          throw InputError(run_gt + ": ground truth is " + std::to_string(gt.disparity_px.cols) + "x" +
                           std::to_string(gt.disparity_px.rows) + ", neither the image size " + std::to_string(left.cols) +
                           "x" + std::to_string(left.rows) + " nor the ROI size " + std::to_string(roi.width_px) + "x" +
                           std::to_string(roi.height_px));
        }
        const FrameRow row = make_frame_row("pair", count_frame(d.disparity_px, d.valid_mask, gt.disparity_px, gt.valid_mask));
        j.update(metrics_json(row.metrics));
        if (!run_html.empty()) {
          run_section.gt_colour = colourize_disparity(gt.disparity_px, gt.valid_mask, double(cfg.disparities));
          run_section.error_map = error_map(d.disparity_px, d.valid_mask, gt.disparity_px, gt.valid_mask);
          for (const auto& kv : named_metrics(row.metrics)) run_section.metrics[kv.first] = kv.second;
        }
      }
      if (!run_html.empty()) {
        run_section.title = cfg.name + " on " + run_left;
        run_section.config_yaml = config::to_yaml(cfg);
        run_section.command = command_line({argc, argv});
        run_section.left_grey = l.clone();
        run_section.frame_id = fs::path(run_left).filename().string();
        run_section.disparity_colour = colourize_disparity(d.disparity_px, d.valid_mask, double(cfg.disparities));
        add_avoidance_images(run_section, d.disparity_px, d.valid_mask, cfg.disparities, roi.x0, roi.y0);
        if (!run_section.metrics.count("density_pct")) run_section.metrics["density_pct"] = j["density_pct"].get<double>();
        run_section.cycle = simulate_timing(cfg, l.cols, l.rows).cycle;
        run_section.resources = res::estimate(res::design_inventory(cfg, l.cols, l.rows));
        run_section.device = res::find_device("XCZU3EG");
        write_text_file(run_html, standalone_page("Parallax: " + run_section.title, design_section_html(run_section)));
      }
      if (run_json) {
        std::cout << j.dump(2) << "\n";
      } else {
        std::printf("wrote %s and %s (ROI %dx%d at %d,%d)\n", run_out.c_str(), colour.c_str(), roi.width_px,
                    roi.height_px, roi.x0, roi.y0);
        std::printf("density_pct %.2f\n", j["density_pct"].get<double>());
        if (!run_gt.empty())
          for (const char* k : {"density_gt_pct", "correct_3px_pct", "d1_all_pct", "d1_all_filled_pct", "mean_abs_error_px"})
            std::printf("%s %.3f\n", k, j[k].get<double>());
      }
      return 0;
    }
    if (*eval) {
      const config::PipelineConfig cfg = load_config_args(eval_cfg);
      const Dataset ds = open_dataset(eval_dataset);
      EvalOptions opt = eval_options(eval_gt, eval_frames, eval_threads, eval_save, cfg.disparities,
                                     eval_quiet || eval_json);
      opt.match_full_image = eval_context == "full";
      if (!eval_roi.empty()) {
        opt.roi_from_config = false;
        opt.roi = parse_roi_size(eval_roi);
      }
      const EvalResult r = evaluate_design(cfg, ds, opt);
      print_notes(r.notes);
      if (eval_json) {
        json j = result_json(r);
        j["config"] = cfg.name;
        j["dataset"] = eval_dataset;
        j["gt"] = eval_gt;
        std::cout << j.dump(2) << "\n";
      } else {
        print_result_text(r, cfg.name + " on " + eval_dataset + " (" + eval_gt + ")");
      }
      return 0;
    }
    if (*score) {
      const Dataset ds = open_dataset(score_dataset);
      EvalOptions opt;
      opt.gt_kind = parse_gt_kind(score_gt);
      opt.frames = score_frames;
      const RoiSize roi = score_roi.empty() ? default_roi_size(ds.layout) : parse_roi_size(score_roi);
      const EvalResult r = score_predictions(score_pred, ds, roi, opt);
      if (score_json)
        std::cout << result_json(r).dump(2) << "\n";
      else
        print_result_text(r, score_pred + " on " + score_dataset + " (" + score_gt + ")");
      return 0;
    }
    if (*baseline) {
      if (base_params.p1 >= base_params.p2)
        throw InputError("--p1 " + std::to_string(base_params.p1) + " must be below --p2 " + std::to_string(base_params.p2) +
                         " (OpenCV's StereoSGBM requires P1 < P2)");
      const Baseline b = parse_baseline(base_name);
      const Dataset ds = open_dataset(base_dataset);
      const EvalOptions opt = eval_options(base_gt, base_frames, base_threads, base_save, base_params.disparities,
                                           base_quiet || base_json);
      const RoiSize roi = base_roi.empty() ? default_roi_size(ds.layout) : parse_roi_size(base_roi);
      const EvalResult r = evaluate(
          ds, roi,
          [&]() -> Matcher {
            return [&](const cv::Mat& l, const cv::Mat& rr) { return run_baseline(b, base_params, l, rr); };
          },
          opt);
      print_notes(r.notes);
      if (base_json) {
        json j = result_json(r);
        j["baseline"] = base_name;
        std::cout << j.dump(2) << "\n";
      } else {
        print_result_text(r, base_name + " on " + base_dataset + " (" + base_gt + ")");
      }
      return 0;
    }
    if (*show) {
      const config::PipelineConfig cfg = load_config_args(show_cfg);
      std::cout << config::to_yaml(cfg);
      const kern::StereoParams p = cfg.stereo_params(cfg.roi_width_px, cfg.roi_height_px);
      std::cout << "# derived: cost_bits " << kern::cost_bits(p) << ", penalty_bits " << kern::penalty_bits(p)
                << ", path_bits " << kern::path_bits(p) << ", aggregate_bits " << kern::aggregate_bits(p)
                << ", disparity_bits " << kern::disparity_bits(p) << " (invalid code " << kern::invalid_code(p) << ")\n";
      return 0;
    }
    if (*bench) {
      const config::PipelineConfig cfg = load_config_args(bench_cfg);
      std::vector<std::string> notes;
      const cv::Mat left = load_grey_file(bench_left, "left", notes);
      const cv::Mat right = load_grey_file(bench_right, "right", notes);
      if (left.size() != right.size()) throw InputError(bench_right + ": size differs from the left image " + bench_left);
      const Roi roi = resolve_roi(roi_for(cfg), left.cols, left.rows);
      const cv::Mat l = crop_to_roi(left, roi).clone(), r = crop_to_roi(right, roi).clone();
      const auto rows = bench_pair(cfg, l, r, bench_iterations);
      if (bench_json) {
        json j = json::array();
        for (const auto& row : rows)
          j.push_back({{"method", row.method}, {"median_ms", row.median_ms}, {"min_ms", row.min_ms},
                       {"peak_rss_mib", row.peak_rss_mib}, {"peak_extra_rss_mib", row.peak_extra_rss_mib},
                       {"ratio_to_hh4", row.ratio_to_peer}, {"min_ratio_to_hh4", row.min_ratio_to_peer}});
        std::cout << j.dump(2) << "\n";
      } else {
        std::printf("%dx%d pair, %d runs per method, one thread each\n", l.cols, l.rows, bench_iterations);
        std::printf("%-36s %10s %10s %10s %12s %9s %9s\n", "method", "median_ms", "min_ms", "peak_MiB", "extra_MiB",
                    "vs_HH4", "min_vs");
        for (const auto& row : rows)
          std::printf("%-36s %10.1f %10.1f %10.1f %12.1f %9.2f %9.2f\n", row.method.c_str(), row.median_ms, row.min_ms,
                      row.peak_rss_mib, row.peak_extra_rss_mib, row.ratio_to_peer, row.min_ratio_to_peer);
      }
      return 0;
    }
    if (*simc) {
      config::PipelineConfig cfg = load_config_args(sim_cfg);
      const int clock = sim_clock_mhz > 0 ? sim_clock_mhz : cfg.clock_mhz;
      const res::Device* device = res::find_device(sim_device);
      if (!device) throw InputError("--device '" + sim_device + "': unknown device; known: " + res::device_names());
      cv::Mat l, r;
      std::vector<std::string> notes;
      std::string pair_what;
      load_pair_or_pattern(cfg, sim_left, sim_right, notes, l, r, pair_what);
      int64_t vcd_from = 0, vcd_to = 20000;
      if (!sim_vcd_cycles.empty()) {
        const auto colon = sim_vcd_cycles.find(':');
        try {
          if (colon == std::string::npos) throw std::invalid_argument("no colon");
          vcd_from = std::stoll(sim_vcd_cycles.substr(0, colon));
          vcd_to = std::stoll(sim_vcd_cycles.substr(colon + 1));
        } catch (const std::exception&) {
          throw InputError("--vcd-cycles '" + sim_vcd_cycles + "': expected A:B, two cycle numbers");
        }
        if (vcd_from < 0 || vcd_to <= vcd_from) throw InputError("--vcd-cycles: need 0 <= A < B");
      }
      SimulateOptions so;
      so.clock_mhz = clock;
      so.size_fifos = !sim_no_sizing;
      so.coupled = sim_coupled;
      so.fast_forward = !sim_every_firing;
      so.vcd_path = sim_vcd;
      so.vcd_from = vcd_from;
      so.vcd_to = vcd_to;
      SimulationResult res = simulate(cfg, l, r, so);
      if (res.cycle.deadlock) {
        std::fprintf(stderr, "parallax: error: %s\n", res.cycle.deadlock_message.c_str());
        return 3;
      }
      if (!res.cycle.input_overrun.empty()) notes.push_back(res.cycle.input_overrun);
      if (res.cycle.rectify_window_misses > 0)
        notes.push_back("rectification: " + std::to_string(res.cycle.rectify_window_misses) +
                        " map taps fell outside the line buffer's rows (read as 0); raise rectify_rows");
      std::string calibration;
      if (sim_cal_latency > 0 || sim_cal_fps > 0) {
        if (sim_cal_latency <= 0) throw InputError("--calibrate-fps needs --calibrate-latency-ms too");
        calibration = calibrate(cfg, res, sim_cal_latency, sim_cal_fps);
        system_figures(cfg, res);  // the cycles do not change, only the host model
        notes.push_back("calibrated at " + std::to_string(clock) + " MHz: " + calibration);
      }
      if (!sim_write_config.empty()) {
        cfg.clock_mhz = clock;
        std::ofstream(sim_write_config) << "# written by parallax sim" << (calibration.empty() ? "" : " (calibrated: " + calibration + ")") << "\n"
                                        << config::to_yaml(cfg);
      }
      if (!sim_out.empty()) {
        const DisparityMap d = to_disparity_map(res.cycle.codes);
        write_kitti_disparity(sim_out, d.disparity_px, d.valid_mask);
      }
      print_notes(notes);
      const auto& c = res.cycle;
      const ResourceReport rr = resource_report(cfg, l.cols, l.rows, *device, clock, res.frame_interval_ms);
      if (!sim_html.empty()) {
        DesignSection s;
        s.title = cfg.name + " at " + std::to_string(clock) + " MHz" + (sim_left.empty() ? " (test pattern)" : " on " + sim_left);
        s.config_yaml = config::to_yaml(cfg);
        s.command = command_line({argc, argv});
        s.left_grey = l.clone();
        const DisparityMap d = to_disparity_map(res.cycle.codes);
        s.disparity_colour = colourize_disparity(d.disparity_px, d.valid_mask, double(cfg.disparities));
        s.metrics = {{"latency_ms", res.latency_ms}, {"frame_interval_ms", res.frame_interval_ms}, {"fps", res.fps},
                     {"cycles_per_frame", double(res.cycle.cycles_per_frame)}, {"bram18k", double(rr.estimate.total.bram18k)},
                     {"lut", double(rr.estimate.total.lut)}, {"ff", double(rr.estimate.total.ff)},
                     {"dsp", double(rr.estimate.total.dsp)}, {"fits_device", rr.util.fits ? 1.0 : 0.0},
                     {"power_w", rr.power.total_w}, {"energy_mj_per_frame", rr.power.energy_mj_per_frame}};
        s.cycle = res.cycle;
        s.resources = rr.estimate;
        s.device = device;
        write_text_file(sim_html, standalone_page("Parallax: " + s.title, design_section_html(s)));
      }
      if (sim_json) {
        json j;
        j["config"] = cfg.name;
        j["clock_mhz"] = clock;
        j["width_px"] = l.cols;
        j["height_px"] = l.rows;
        j["cycles_per_frame"] = c.cycles_per_frame;
        j["first_pixel_cycle"] = c.first_pixel_cycle;
        j["last_pixel_cycle"] = c.last_pixel_cycle;
        j["first_pixel_latency_ms"] = res.fpga_first_pixel_ms;
        j["last_pixel_latency_ms"] = res.fpga_last_pixel_ms;
        j["host_copy_in_ms"] = res.copy_in_ms;
        j["host_copy_out_ms"] = res.copy_out_ms;
        j["host_latency_ms"] = cfg.host_latency_ms;
        j["latency_ms"] = res.latency_ms;
        j["frame_interval_ms"] = res.frame_interval_ms;
        j["fps"] = res.fps;
        j["interval_limit"] = res.interval_limit;
        j["bottleneck"] = c.bottleneck;
        j["rows_fast_forwarded"] = c.rows_fast_forwarded;
        j["input_period_cycles"] = c.input_period_cycles;
        if (cfg.rectify != "none") j["rectify_window_misses"] = c.rectify_window_misses;
        if (c.ddr_word_bits > 0)  // two passes: the frame buffer's and the map's traffic per frame
          j["ddr"] = {{"word_bits", c.ddr_word_bits},
                      {"frame_bytes_written", c.ddr_bytes_written},
                      {"frame_bytes_read", c.ddr_bytes_read},
                      {"map_bytes_written", c.map_bytes_written},
                      {"gbytes_per_s_at_fps", double(c.ddr_bytes_written + c.ddr_bytes_read + c.map_bytes_written) * res.fps / 1e9},
                      {"ddr_gbps", cfg.ddr_gbps}};
        if (res.unbounded_last_pixel_cycle >= 0) j["unbounded_fifos_last_pixel_cycle"] = res.unbounded_last_pixel_cycle;
        j["stages"] = json::array();
        const std::map<std::string, std::string> why = ii_reasons(cfg, l.cols, l.rows);
        for (const auto& s : c.stages) {
          json sj = {{"name", s.name}, {"ii_cycles", s.ii_cycles}, {"latency_cycles", s.latency_cycles},
                     {"fires", s.fires}, {"busy_cycles", s.busy_cycles},
                     {"input_stall_cycles", s.input_stall_cycles}, {"output_stall_cycles", s.output_stall_cycles},
                     {"port_conflict_cycles", s.port_conflict_cycles},
                     {"first_fire_cycle", s.first_fire_cycle}, {"last_fire_cycle", s.last_fire_cycle}};
          if (why.count(s.name)) sj["ii_limit"] = why.at(s.name);
          j["stages"].push_back(sj);
        }
        j["fifos"] = json::array();
        for (const auto& f : c.fifos) {
          json fj = {{"name", f.name}, {"producer", f.producer}, {"consumer", f.consumer}, {"depth", f.depth},
                     {"tokens", f.tokens}, {"high_water", f.high_water}};
          if (res.stall_free_depths.count(f.name)) fj["stall_free_depth"] = res.stall_free_depths.at(f.name);
          j["fifos"].push_back(fj);
        }
        add_resources_json(j, rr);
        std::cout << j.dump(2) << "\n";
      } else {
        std::printf("%s at %d MHz, %dx%d, D=%d, PU=%d\n", cfg.name.c_str(), clock, l.cols, l.rows, cfg.disparities,
                    cfg.parallel_units);
        std::printf("cycles per frame   %lld (bottleneck: %s)\n", (long long)c.cycles_per_frame, c.bottleneck.c_str());
        std::printf("first pixel        cycle %lld (%.3f ms)\n", (long long)c.first_pixel_cycle, res.fpga_first_pixel_ms);
        std::printf("last pixel         cycle %lld (%.3f ms)\n", (long long)c.last_pixel_cycle, res.fpga_last_pixel_ms);
        std::printf("latency_ms         %.3f (host copies %.3f + %.3f, host %.3f)\n", res.latency_ms, res.copy_in_ms,
                    res.copy_out_ms, cfg.host_latency_ms);
        std::printf("frame_interval_ms  %.3f (%s)\nfps                %.2f\n", res.frame_interval_ms,
                    res.interval_limit.c_str(), res.fps);
        if (c.ddr_word_bits > 0)
          std::printf("ddr per frame      %lld B written + %lld B read (frame buffer, %d-bit words), map %lld B; "
                      "%.2f GB/s at %.2f fps (ddr_gbps %.2f)\n",
                      (long long)c.ddr_bytes_written, (long long)c.ddr_bytes_read, c.ddr_word_bits,
                      (long long)c.map_bytes_written,
                      double(c.ddr_bytes_written + c.ddr_bytes_read + c.map_bytes_written) * res.fps / 1e9, res.fps,
                      cfg.ddr_gbps);
        std::printf("\n");
        std::printf("%-15s %4s %4s %10s %12s %12s %12s %12s %12s\n", "stage", "II", "lat", "fires", "busy", "in_stall",
                    "out_stall", "first_fire", "last_fire");
        for (const auto& s : c.stages)
          std::printf("%-15s %4d %4d %10lld %12lld %12lld %12lld %12lld %12lld\n", s.name.c_str(), s.ii_cycles,
                      s.latency_cycles, (long long)s.fires, (long long)s.busy_cycles, (long long)s.input_stall_cycles,
                      (long long)s.output_stall_cycles, (long long)s.first_fire_cycle, (long long)s.last_fire_cycle);
        std::printf("\nII derived from the kernels' declarations at the design's %d MHz (docs/hls.md):\n", cfg.clock_mhz);
        for (const auto& kv : ii_reasons(cfg, l.cols, l.rows)) std::printf("  %-13s %s\n", kv.first.c_str(), kv.second.c_str());
        if (c.rows_fast_forwarded > 0)
          std::printf("\n%lld of %d output rows repeated the previous rows' schedule exactly and were applied at once\n",
                      (long long)c.rows_fast_forwarded, l.rows);
        if (res.unbounded_last_pixel_cycle >= 0)
          std::printf("\nwith unbounded FIFOs the last pixel leaves at cycle %lld (%+lld cycles); stall_free = depth at which\n"
                      "no producer ever waits (behind a faster producer: its whole backlog, harmless back-pressure)\n",
                      (long long)res.unbounded_last_pixel_cycle,
                      (long long)(res.unbounded_last_pixel_cycle - c.last_pixel_cycle));
        std::printf("\n%-15s %-15s %-15s %7s %10s %10s %12s\n", "fifo", "producer", "consumer", "depth", "tokens",
                    "high_water", "stall_free");
        for (const auto& f : c.fifos) {
          const auto it = res.stall_free_depths.find(f.name);
          std::printf("%-15s %-15s %-15s %7lld %10lld %10lld %12s\n", f.name.c_str(), f.producer.c_str(),
                      f.consumer.c_str(), (long long)f.depth, (long long)f.tokens, (long long)f.high_water,
                      it == res.stall_free_depths.end() ? "-" : std::to_string(it->second).c_str());
        }
        print_resources(rr);
      }
      return 0;
    }
    if (*sweepc) {
      SweepSpec spec = sw_spec.empty() ? SweepSpec{} : load_sweep(sw_spec);
      if (!sw_base.empty()) spec.base = sw_base;
      for (const auto& g : sw_grid) add_axis(spec, g);
      if (!sw_frames.empty()) spec.frames = sw_frames;
      if (!sw_gt.empty()) {
        if (sw_gt != "noc" && sw_gt != "occ") throw InputError("--gt '" + sw_gt + "': expected noc or occ");
        spec.gt = sw_gt;
      }
      if (!sw_strategy.empty()) {
        if (sw_strategy != "grid" && sw_strategy != "random" && sw_strategy != "lhs" && sw_strategy != "nsga2")
          throw InputError("--strategy '" + sw_strategy + "': expected grid, random, lhs or nsga2");
        spec.strategy = sw_strategy;
      }
      if (sw_samples > 0) spec.samples = sw_samples;
      if (sw_generations > 0) spec.generations = sw_generations;
      if (sw_seed > 0) spec.seed = sw_seed;
      if (!sw_name.empty()) spec.name = sw_name;
      if (sw_avoidance) spec.avoidance = true;
      if (!sw_flight.empty()) spec.flight_scenario = sw_flight;
      SweepRunOptions ro;
      ro.allow_large = sw_yes;
      // The spec is checked before the store is opened: a bad axis, value or objective touches no file.
      if (spec.base.empty()) throw InputError("sweep '" + spec.name + "': no base configuration (field 'base' or --base)");
      check_sweep_spec(spec, config::load_config(spec.base), ro.allow_large);
      // A missing or unknown dataset folder, and a frame filter that selects nothing, too.
      (void)list_frames(open_dataset(sw_dataset), parse_gt_kind(spec.gt), spec.frames);
      ro.dataset = sw_dataset;
      ro.jobs = sw_jobs;
      ro.share_costs = !sw_no_sharing;
      if (!sw_shard.empty()) {
        const auto slash = sw_shard.find('/');
        try {
          if (slash == std::string::npos) throw std::invalid_argument("no slash");
          ro.shard_index = std::stoi(sw_shard.substr(0, slash));
          ro.shard_count = std::stoi(sw_shard.substr(slash + 1));
        } catch (const std::exception&) {
          throw InputError("--shard '" + sw_shard + "': expected K/N, e.g. 2/8");
        }
        if (ro.shard_count < 1 || ro.shard_index < 1 || ro.shard_index > ro.shard_count)
          throw InputError("--shard '" + sw_shard + "': expected 1 <= K <= N");
      }
      std::string db_path = sw_db;
      int mpi_rank = 0, mpi_size = 1;
#ifdef PARALLAX_HAVE_MPI
      if (sw_mpi) {
        MPI_Init(&argc, &argv);
        MPI_Comm_rank(MPI_COMM_WORLD, &mpi_rank);
        MPI_Comm_size(MPI_COMM_WORLD, &mpi_size);
        ro.shard_index = mpi_rank + 1;
        ro.shard_count = mpi_size;
        db_path = sw_db + ".rank" + std::to_string(mpi_rank);
      }
#endif
      ResultStore store(db_path);
      const bool tty = isatty(fileno(stderr)) != 0;
      const auto t0 = std::chrono::steady_clock::now();
      ro.progress = [&](int done, int total, int skipped) {
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const int worked = done - skipped;
        const double eta = worked > 0 ? s / worked * double(total - done) : 0.0;
        if (tty) {
          const int width = 30, filled = total > 0 ? done * width / total : width;
          std::fprintf(stderr, "\r[%s%s] %d/%d designs (%d already stored), ETA %.0f s   ",
                       std::string(std::size_t(filled), '#').c_str(), std::string(std::size_t(width - filled), '.').c_str(),
                       done, total, skipped, eta);
          if (done == total) std::fprintf(stderr, "\n");
        } else {
          std::fprintf(stderr, "parallax: sweep %d/%d designs (%d already stored), ETA %.0f s\n", done, total, skipped, eta);
        }
      };
      const SweepSummary sum = run_sweep(spec, store, ro);
      std::printf("sweep '%s'%s: %d designs: %d evaluated (%d invalid, %d failed), %d already in %s; %.1f s\n",
                  spec.name.c_str(),
                  ro.shard_count > 1 ? (" shard " + std::to_string(ro.shard_index) + "/" + std::to_string(ro.shard_count)).c_str() : "",
                  sum.total, sum.evaluated + sum.invalid, sum.invalid, sum.failed, sum.skipped, db_path.c_str(), sum.seconds);
      for (const auto& p : sum.first_problems) std::fprintf(stderr, "parallax: %s\n", p.c_str());
      const bool all_failed = sum.total > 0 && sum.skipped == 0 && sum.invalid + sum.failed >= sum.evaluated + sum.invalid;
#ifdef PARALLAX_HAVE_MPI
      if (sw_mpi) {
        MPI_Barrier(MPI_COMM_WORLD);
        if (mpi_rank == 0) {
          ResultStore merged(sw_db);
          int64_t added = 0;
          for (int r = 0; r < mpi_size; ++r) added += merged.merge_from(sw_db + ".rank" + std::to_string(r));
          std::printf("merged %d ranks into %s: %lld designs added\n", mpi_size, sw_db.c_str(), (long long)added);
        }
        MPI_Finalize();
      }
#endif
      (void)mpi_size;
      if (all_failed) {
        std::fprintf(stderr, "parallax: error: sweep '%s': no design could be evaluated (the first reasons are above)\n",
                     spec.name.c_str());
        return kExitUserError;
      }
      return 0;
    }
    if (*mergec) {
      ResultStore out(mg_db);
      for (const auto& in : mg_inputs) {
        const int64_t added = out.merge_from(in);
        std::printf("%s: %lld designs added\n", in.c_str(), (long long)added);
      }
      std::printf("%s: %lld designs\n", mg_db.c_str(), (long long)out.count_designs());
      return 0;
    }
    if (*paretoc) {
      ResultStore store(pa_db, ResultStore::Access::read);
      const SweepSpec chosen = choose_sweep(store, pa_db, pa_sweep);
      const SweepSpec* spec = &chosen;
      const auto rows = store.designs(spec->name, false);
      const auto front = pareto_front(*spec, rows);
      if (pa_json) {
        json j = json::array();
        for (const auto& r : front) j.push_back({{"hash", r.hash}, {"configuration", r.config_yaml}, {"metrics", r.metrics}});
        std::cout << j.dump(2) << "\n";
      } else {
        int meets = 0;
        for (const auto& r : rows) meets += meets_constraints(*spec, r) ? 1 : 0;
        std::printf("sweep '%s': %zu designs stored, %d meet the constraints, %zu on the front\n", spec->name.c_str(),
                    rows.size(), meets, front.size());
        std::printf("objectives:");
        for (const auto& o : spec->objectives) std::printf(" %s %s", o.maximise ? "max" : "min", o.key.c_str());
        std::printf("\n\n%-18s %-40s", "hash", "design");
        for (const auto& o : spec->objectives) std::printf(" %16s", o.key.c_str());
        std::printf(" %8s %8s\n", "fps", "bram18k");
        for (const auto& r : front) {
          std::string name;
          const auto pos = r.config_yaml.find("name: ");
          if (pos != std::string::npos) name = r.config_yaml.substr(pos + 6, r.config_yaml.find('\n', pos) - pos - 6);
          std::printf("%-18s %-40s", r.hash.c_str(), name.substr(0, 40).c_str());
          auto cell = [&](const std::string& k, int width, int decimals) {  // a missing metric: "-"
            if (r.metrics.count(k)) std::printf(" %*.*f", width, decimals, r.metrics.at(k));
            else std::printf(" %*s", width, "-");
          };
          for (const auto& o : spec->objectives) cell(o.key, 16, 3);
          cell("fps", 8, 1);
          cell("bram18k", 8, 0);
          std::printf("\n");
        }
      }
      return 0;
    }
    if (*reportc) {
      if (rp_html.empty() && rp_csv.empty() && rp_frames_csv.empty() && rp_json.empty())
        throw InputError("report: nothing to write; give --html, --csv, --frames-csv or --json");
      ResultStore store(rp_db, ResultStore::Access::read);
      const SweepSpec chosen = choose_sweep(store, rp_db, rp_sweep);
      const SweepSpec* spec = &chosen;
      const std::string swept = store.sweep_dataset(spec->name);  // the folder the sweep ran on
      check_report_outputs(rp_db, {rp_dataset, swept},
                           {{"--html", rp_html}, {"--csv", rp_csv}, {"--frames-csv", rp_frames_csv}, {"--json", rp_json}});
      const auto rows = store.designs(spec->name);
      auto write = [](const std::string& path, const std::string& text) {
        std::ofstream out(path, std::ios::binary);
        if (!out) throw InputError(path + ": cannot write");
        out << text;
        if (!out) throw InputError(path + ": write failed");
        std::fprintf(stderr, "parallax: wrote %s\n", path.c_str());
      };
      if (!rp_csv.empty()) {
        std::ostringstream o;
        write_designs_csv(rows, o);
        write(rp_csv, o.str());
      }
      if (!rp_frames_csv.empty()) {
        std::ostringstream o;
        write_frames_csv(rows, o);
        write(rp_frames_csv, o.str());
      }
      if (!rp_json.empty()) write(rp_json, report_json(rows));
      if (!rp_html.empty()) {
        ReportOptions ro;
        ro.dataset = rp_dataset.empty() ? images_dataset(swept) : rp_dataset;
        ro.frame = rp_frame;
        ro.details = rp_details;
        write(rp_html, html_report(*spec, rows, ro));
      }
      return 0;
    }
    if (*avoidc) {
      const config::PipelineConfig cfg = load_config_args(av_cfg);
      if (av_gt != "noc" && av_gt != "occ") throw InputError("--gt '" + av_gt + "': expected noc or occ");
      const Dataset ds = open_dataset(av_dataset);
      const auto refs = list_frames(ds, av_gt == "occ" ? GtKind::occ : GtKind::noc, av_frames);
      if (refs.empty()) throw InputError(av_dataset + ": no frame with ground truth matches '" + av_frames + "'");
      MavlinkSink mav(av_mavlink);
      sim::FuncPipeline pipe;
      AvoidAccumulator acc;
      json per_frame = json::array();
      uint8_t seq = 0;
      for (const auto& ref : refs) {
        Frame f = load_frame(ref);
        const Roi roi = resolve_roi(roi_for(cfg), f.left.cols, f.left.rows);
        // The rig: --calib when given, else the frame's own calibration file (KITTI calib,
        // Middlebury calib.txt), else KITTI 2015's.
        Rig rig = kitti_default_rig(roi.x0, roi.y0);
        if (!av_calib.empty()) {
          rig = load_rig(av_calib, roi.x0, roi.y0);
        } else if (f.calibration.known) {
          rig.focal_px = f.calibration.focal_px;
          rig.baseline_m = f.calibration.baseline_m;
          rig.cx_px = f.calibration.cx_px - roi.x0;
          rig.cy_px = f.calibration.cy_px - roi.y0;
        }
        const DisparityMap d = run_design(cfg, crop_to_roi(f.left, roi).clone(), crop_to_roi(f.right, roi).clone(), pipe);
        const AvoidScore s = acc.add(d.disparity_px, d.valid_mask, crop_to_roi(f.gt_disparity_px, roi),
                                     crop_to_roi(f.gt_mask, roi), cfg.disparities, rig);
        const AvoidResult& mine = acc.last_design();
        mav.send(mavlink_heartbeat(seq++, 1, 191));
        mav.send(mavlink_velocity_setpoint(seq++, 1, 191, uint32_t(acc.frames() * 100), mine.velocity_mps));
        per_frame.push_back({{"frame", f.id}, {"obstacles", s.predicted}, {"reference_obstacles", s.reference},
                             {"matched", s.matched}, {"decision", to_string(mine.manoeuvre)},
                             {"reference_decision", to_string(acc.last_reference().manoeuvre)},
                             {"nearest_range_m", mine.obstacles.empty() ? 0.0 : mine.obstacles.front().range_m},
                             {"velocity_mps", {mine.velocity_mps.x(), mine.velocity_mps.y(), mine.velocity_mps.z()}}});
      }
      std::map<std::string, double> m;
      for (const auto& kv : acc.metrics()) m[kv.first] = kv.second;
      const AvoidTimings& t = acc.timing_sum();
      const double n = double(acc.frames());
      if (av_json) {
        json j;
        j["config"] = cfg.name;
        j["frames"] = acc.frames();
        for (const auto& kv : m) j[kv.first] = kv.second;
        j["ms_split"] = {{"uv_maps", t.uv_maps_ms / n}, {"filtering", t.filtering_ms / n},
                         {"contours", t.contours_ms / n}, {"planning", t.planning_ms / n}};
        j["per_frame"] = per_frame;
        std::cout << j.dump(2) << "\n";
      } else {
        std::printf("%s on %d frames: obstacle_precision %.1f%%  obstacle_recall %.1f%%  range_error %.2f m  "
                    "decision_agreement %.1f%%\n",
                    cfg.name.c_str(), acc.frames(), m["obstacle_precision"], m["obstacle_recall"], m["range_error_m"],
                    m["decision_agreement_pct"]);
        std::printf("avoidance stage: %.2f ms per frame (U/V maps %.2f, ground + filtering %.2f, contours %.2f, planning %.3f)\n",
                    m["mean_ms_per_frame"], t.uv_maps_ms / n, t.filtering_ms / n, t.contours_ms / n, t.planning_ms / n);
      }
      return 0;
    }
    if (*scenec) {
      const Scenario s = load_scenario(sc_scenario);
      const Scene scene = generate_scene(s, sc_seed);
      sc_height = sc_width * 9 / 16;
      const Rig rig = scene_rig(sc_width, sc_height);
      std::vector<StereoFrame> frames;
      for (int i = 0; i < sc_frames; ++i)
        frames.push_back(render(scene, rig, sc_width, sc_height, Eigen::Vector3d(0, -1.6, i * sc_step), sc_k1));
      export_kitti(frames, sc_out);
      if (sc_k1 != 0.0) {
        for (const char* side : {"maps_left.yml", "maps_right.yml"})
          write_rectification_maps(rig, sc_width, sc_height, sc_k1, (fs::path(sc_out) / side).string());
        std::printf("distortion k1 = %g: rectify with --set rectify=bilinear --set rectify_maps_left=%s/maps_left.yml "
                    "--set rectify_maps_right=%s/maps_right.yml\n",
                    sc_k1, sc_out.c_str(), sc_out.c_str());
      }
      std::printf("%s (seed %u): %zu poles/trees, %zu boxes; %d frames of %dx%d written to %s/training "
                  "(f = %.1f px, B = %.4f m, camera 1.6 m above the ground)\n",
                  s.name.c_str(), sc_seed, scene.cylinders.size(), scene.boxes.size(), sc_frames, sc_width, sc_height,
                  sc_out.c_str(), rig.focal_px, rig.baseline_m);
      return 0;
    }
    if (*flyc) {
      const config::PipelineConfig cfg = load_config_args(fl_cfg);
      const Scenario sc = load_scenario(fl_scenario);
      FlightParams fp;
      fp.width_px = fl_size;
      fp.disparity_noise_px = fl_noise;
      fp.time_limit_s = fl_limit;
      auto run_speed = [&](double speed, json* per_seed) {
        fp.speed_mps = speed;
        struct Agg {
          int ok = 0, collisions = 0;
          double min_clear = 1e9, ratio = 0, time = 0;
        } g;
        for (int s = 1; s <= fl_seeds; ++s) {
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
            per_seed->push_back({{"seed", s}, {"reached_goal", r.reached_goal}, {"collided", r.collided},
                                 {"min_clearance_m", r.min_clearance_m}, {"time_s", r.time_s}, {"frames", r.frames}});
          std::fprintf(stderr, "parallax: %s seed %d at %.1f m/s: %s (min clearance %.2f m, %d frames)\n", sc.name.c_str(), s,
                       speed, r.collided ? "collision" : r.reached_goal ? "goal" : "time out", r.min_clearance_m, r.frames);
        }
        return g;
      };
      double interval_ms = 0, latency_ms = 0;
      {
        config::PipelineConfig c = cfg;
        c.roi_full = false;
        c.roi_width_px = fl_size;
        c.roi_height_px = fl_size * 9 / 16;
        design_timing(c, fl_size, fl_size * 9 / 16, interval_ms, latency_ms);
      }
      json j;
      j["config"] = cfg.name;
      j["scenario"] = sc.name;
      j["seeds"] = fl_seeds;
      j["frame_interval_ms"] = interval_ms;
      j["latency_ms"] = latency_ms;
      if (fl_find) {
        double lo = 0.0, hi = 16.0;
        for (int it = 0; it < 5; ++it) {
          const double mid = (lo + hi) / 2;
          (run_speed(mid, nullptr).collisions == 0 ? lo : hi) = mid;
        }
        const double frame_ms = std::max(interval_ms, 1000.0 / fp.camera_fps);
        const double bound = stopping_distance_speed_bound(fp.max_accel_mps2, (latency_ms + frame_ms) / 1000.0, 12.0);
        j["max_safe_speed_mps"] = lo;
        j["stopping_distance_bound_mps"] = bound;
        if (!fl_json)
          std::printf("%s in %s over %d seeds: highest speed without a collision %.2f m/s (searched to 0.5 m/s); "
                      "stopping-distance bound %.2f m/s (a %.1f m/s2, reaction %.1f ms = latency + frame, range 12 m)\n",
                      cfg.name.c_str(), sc.name.c_str(), fl_seeds, lo, bound, fp.max_accel_mps2, latency_ms + frame_ms);
      } else {
        json per_seed = json::array();
        const auto g = run_speed(fl_speed, &per_seed);
        j["speed_mps"] = fl_speed;
        j["success_rate"] = 100.0 * g.ok / fl_seeds;
        j["collisions"] = g.collisions;
        j["min_clearance_m"] = g.min_clear;
        j["path_length_ratio"] = g.ok ? g.ratio / g.ok : 0.0;
        j["time_to_goal_s"] = g.ok ? g.time / g.ok : 0.0;
        j["per_seed"] = per_seed;
        if (!fl_json)
          std::printf("%s in %s at %.1f m/s over %d seeds: success_rate %.0f%%  collisions %d  min_clearance %.2f m  "
                      "path_length_ratio %.3f  time_to_goal %.1f s  (frame %.1f ms, latency %.1f ms)\n",
                      cfg.name.c_str(), sc.name.c_str(), fl_speed, fl_seeds, j["success_rate"].get<double>(), g.collisions,
                      g.min_clear, j["path_length_ratio"].get<double>(), j["time_to_goal_s"].get<double>(), interval_ms,
                      latency_ms);
      }
      if (fl_json) std::cout << j.dump(2) << "\n";
      return 0;
    }
    if (*exportc) {
      if (ex_cfg.path.empty() == ex_db.empty())
        throw InputError("export-hls: give either --config CFG or --db FILE --design ID");
      if (!ex_db.empty() && ex_design.empty()) throw InputError("export-hls: --db needs --design ID");
      if (!ex_cfg.path.empty() && !ex_design.empty()) throw InputError("export-hls: --design belongs to --db");
      config::PipelineConfig cfg;
      std::string origin;
      if (!ex_cfg.path.empty()) {
        cfg = load_config_args(ex_cfg);
        origin = ex_cfg.path;
        for (const auto& s : ex_cfg.sets) origin += " --set " + s;
      } else {
        if (!fs::exists(ex_db)) throw InputError(ex_db + ": results store not found");
        if (ex_design.size() < 4) throw InputError("--design '" + ex_design + "': give at least 4 hex digits of the hash");
        ResultStore store(ex_db, ResultStore::Access::read);
        std::vector<ResultStore::Row> hits;
        for (auto& row : store.designs("", false))  // a design measured on several datasets is one design
          if (row.hash.rfind(ex_design, 0) == 0 &&
              std::none_of(hits.begin(), hits.end(), [&](const ResultStore::Row& h) { return h.hash == row.hash; }))
            hits.push_back(std::move(row));
        if (hits.empty()) throw InputError(ex_db + ": no design whose hash starts with '" + ex_design + "' (see parallax pareto)");
        if (hits.size() > 1)
          throw InputError(ex_db + ": " + std::to_string(hits.size()) + " designs start with '" + ex_design + "'; give more digits");
        if (hits[0].status == "invalid") throw InputError(ex_db + ": design " + hits[0].hash + " is invalid: " + hits[0].reason);
        cfg = config::parse_config(hits[0].config_yaml, ex_db + " design " + hits[0].hash);
        origin = ex_db + " design " + hits[0].hash;
        const auto errs = config::validate(cfg);
        if (!errs.empty()) throw InputError(origin + ": field '" + errs.front().field + "': " + errs.front().message);
      }
      try {
        hlsx::check_project_dir(ex_out);  // before the simulation: fail fast
      } catch (const hlsx::ExportError& e) {
        throw InputError(e.what());
      }
      std::vector<std::string> notes;
      cv::Mat l, r;
      std::string pair_what;
      load_pair_or_pattern(cfg, ex_left, ex_right, notes, l, r, pair_what);
      for (const auto& n : notes) std::fprintf(stderr, "parallax: note: %s\n", n.c_str());
      ExportOptions eo;
      eo.part = ex_part;
      eo.clock_mhz = ex_clock;
      if (!ex_json) std::fprintf(stderr, "parallax: simulating %s (FIFO sizing, timing, golden output)...\n", cfg.name.c_str());
      hlsx::ExportRequest req;
      std::vector<hlsx::GeneratedFile> files;
      try {
        req = prepare_export(cfg, l, r, origin, pair_what, eo);
        files = hlsx::generate_project(req);
        hlsx::write_project(files, ex_out);
      } catch (const hlsx::ExportError& e) {
        throw InputError(e.what());
      }
      const auto& pr = req.prediction;
      if (ex_json) {
        json j;
        j["out"] = ex_out;
        j["design"] = cfg.name;
        j["part"] = req.part;
        j["clock_mhz"] = req.clock_mhz;
        j["files"] = json::array();
        for (const auto& f : files) j["files"].push_back(f.path);
        j["fifos"] = json::array();
        for (const auto& f : req.fifos)
          j["fifos"].push_back({{"name", f.name}, {"depth", f.depth}, {"stall_free", f.stall_free}, {"why", f.why}});
        j["prediction"] = {{"last_pixel_cycle", pr.last_pixel_cycle}, {"fpga_latency_ms", pr.fpga_latency_ms},
                           {"cycles_per_frame", pr.cycles_per_frame}, {"fps", pr.fps}, {"device", pr.device},
                           {"bram18k", pr.bram18k}, {"lut", pr.lut}, {"ff", pr.ff}, {"dsp", pr.dsp}, {"fits", pr.fits}};
        std::cout << j.dump(2) << "\n";
      } else {
        std::printf("wrote %zu files to %s: Vitis HLS project of %s for %s at %g MHz\n", files.size(), ex_out.c_str(),
                    cfg.name.c_str(), req.part.c_str(), req.clock_mhz);
        std::printf("  FIFO depths:");
        for (const auto& f : req.fifos) std::printf(" %s=%lld", f.name.c_str(), (long long)f.depth);
        std::printf("\n  predicted: FPGA latency %.2f ms (%lld cycles), %.1f fps; %lld BRAM_18K, %lld LUT, %lld FF, %lld DSP on %s\n",
                    pr.fpga_latency_ms, (long long)pr.last_pixel_cycle, pr.fps, (long long)pr.bram18k, (long long)pr.lut,
                    (long long)pr.ff, (long long)pr.dsp, pr.device.c_str());
        std::printf("  next: cd %s && make csim   (g++ alone; bit-exact check against the simulator)\n", ex_out.c_str());
      }
      return 0;
    }
    if (*importc) {
      const HlsReport rep = read_csynth_xml(ih_report);
      std::vector<std::string> set;
      std::vector<ModelVsSynthesis> comparison;
      sim::CycleReport model_cycle;  // the cycle model at the report's clock, for --html
      int ih_w = 0, ih_h = 0;
      config::PipelineConfig cfg;
      if (!ih_config.empty()) {
        cfg = config::load_config(ih_config);
        design_size(cfg, ih_w, ih_h);
        comparison = compare_with_model(cfg, rep, ih_w, ih_h, &model_cycle);
        set = calibrate_from_hls(cfg, rep);
      } else if (!ih_write.empty()) {
        throw InputError("--write-config needs --config");
      }
      if (!ih_html.empty() && ih_config.empty()) throw InputError("--html needs --config");
      if (ih_json) {
        json j;
        j["part"] = rep.part;
        j["top"] = rep.top;
        j["target_clock_ns"] = rep.target_clock_ns;
        j["estimated_clock_ns"] = rep.estimated_clock_ns;
        j["latency_cycles"] = {{"best", rep.best_latency_cycles}, {"worst", rep.worst_latency_cycles}};
        j["interval_cycles"] = {{"min", rep.interval_min_cycles}, {"max", rep.interval_max_cycles}};
        j["loops"] = json::array();
        for (const auto& l : rep.loops)
          j["loops"].push_back({{"name", l.name}, {"trip_count", l.trip_count}, {"latency_cycles", l.latency_cycles},
                                {"ii", l.pipeline_ii}, {"depth", l.pipeline_depth}});
        j["resources"] = rep.resources;
        j["available"] = rep.available;
        j["calibrated"] = set;
        j["comparison"] = json::array();
        for (const auto& c : comparison)
          j["comparison"].push_back({{"figure", c.figure}, {"model", c.model}, {"synthesis", c.synthesis}, {"note", c.note}});
        std::cout << j.dump(2) << "\n";
      } else {
        std::printf("%s on %s (Vitis HLS %s): clock %.2f ns target, %.3f ns estimated; latency %lld-%lld cycles, interval %lld\n",
                    rep.top.c_str(), rep.part.c_str(), rep.version.c_str(), rep.target_clock_ns, rep.estimated_clock_ns,
                    (long long)rep.best_latency_cycles, (long long)rep.worst_latency_cycles, (long long)rep.interval_max_cycles);
        for (const auto& l : rep.loops)
          std::printf("  loop %-20s trip %lld  II %d  depth %d  latency %lld\n", l.name.c_str(), (long long)l.trip_count,
                      l.pipeline_ii, l.pipeline_depth, (long long)l.latency_cycles);
        for (const auto& kv : rep.resources)
          std::printf("  %-9s %lld of %lld\n", kv.first.c_str(), (long long)kv.second,
                      (long long)(rep.available.count(kv.first) ? rep.available.at(kv.first) : 0));
        for (const auto& s : set) std::printf("  calibrated %s\n", s.c_str());
        if (!comparison.empty()) {
          std::printf("\n%-28s %14s %14s %10s\n", "model vs synthesis", "model", "synthesis", "syn/model");
          for (const auto& c : comparison) {
            std::printf("%-28s %14.0f %14.0f", c.figure.c_str(), c.model, c.synthesis);
            if (c.model > 0 && c.synthesis >= 0) std::printf(" %10.2f", c.synthesis / c.model); else std::printf(" %10s", "-");
            std::printf("  %s\n", c.note.c_str());
          }
        }
      }
      if (!ih_html.empty()) {
        DesignSection s;
        s.title = cfg.name + ": model and synthesis (" + ih_report + ")";
        s.config_yaml = config::to_yaml(cfg);
        s.config_file = cfg.name + "-calibrated.yaml";
        s.command = "parallax import-hls --report " + ih_report + " --config " + ih_config + " --html " + ih_html;
        s.cycle = model_cycle;
        s.resources = res::estimate(res::design_inventory(cfg, ih_w, ih_h));
        s.device = res::find_device(device_for_part(rep.part));
        s.synthesis = comparison;
        write_text_file(ih_html, standalone_page(s.title, design_section_html(s)));
      }
      if (!ih_write.empty()) write_text_file(ih_write, config::to_yaml(cfg));
      return 0;
    }
    if (*fitc) {
      std::vector<res::PublishedPoint> points;
      try {
        points = res::load_points(fit_points, fit_root);
      } catch (const config::ConfigError& e) {
        throw InputError(e.what());
      } catch (const std::runtime_error& e) {
        throw InputError(e.what());
      }
      const res::FitResult fr = res::fit(points, res::default_coefficients());
      const res::Coefficients& k = fr.coefficients;
      if (fit_json) {
        json j;
        j["coefficients"] = {{"lut_scale", k.lut_scale}, {"lut_per_stage", k.lut_per_stage},
                             {"lut_per_memory", k.lut_per_memory}, {"ff_per_op_bit", k.ff_per_op_bit},
                             {"ff_per_stage", k.ff_per_stage}};
        j["lut_loo_mean_pct"] = fr.lut_loo_mean_pct;
        j["lut_loo_max_pct"] = fr.lut_loo_max_pct;
        j["ff_loo_mean_pct"] = fr.ff_loo_mean_pct;
        j["ff_loo_max_pct"] = fr.ff_loo_max_pct;
        j["points"] = json::array();
        for (const auto& row : fr.rows)
          j["points"].push_back({{"name", row.name},
                                 {"published", {{"bram18k", row.published.bram18k}, {"lut", row.published.lut},
                                                {"ff", row.published.ff}, {"dsp", row.published.dsp}}},
                                 {"fitted", {{"bram18k", row.fitted.bram18k}, {"lut", row.fitted.lut},
                                             {"ff", row.fitted.ff}, {"dsp", row.fitted.dsp}}},
                                 {"leave_one_out", {{"lut", row.loo.lut}, {"ff", row.loo.ff}}}});
        std::cout << j.dump(2) << "\n";
      } else {
        std::printf("fitted on %zu published points (%s)\n", points.size(), fit_points.c_str());
        std::printf("  lut = %.4f x operator LUTs + memory LUTs + %.1f x stages + %.2f x memories\n", k.lut_scale,
                    k.lut_per_stage, k.lut_per_memory);
        std::printf("  ff  = register bits + %.4f x operator bits + %.1f x stages\n\n", k.ff_per_op_bit, k.ff_per_stage);
        std::printf("%-26s %8s %8s %8s | %7s %7s %7s %7s | %7s %7s %7s %7s\n", "point", "BRAM pub", "model", "", "LUT pub",
                    "fit", "loo", "loo %", "FF pub", "fit", "loo", "loo %");
        for (const auto& row : fr.rows) {
          auto pct = [](int64_t m, int64_t p) { return p > 0 ? 100.0 * double(m - p) / double(p) : 0.0; };
          std::printf("%-26s %8lld %8lld %8s | %7lld %7lld %7lld %+6.1f%% | %7lld %7lld %7lld %+6.1f%%\n", row.name.c_str(),
                      (long long)row.published.bram18k, (long long)row.fitted.bram18k,
                      row.published.bram18k == row.fitted.bram18k ? "exact" : "",
                      (long long)row.published.lut, (long long)row.fitted.lut, (long long)row.loo.lut,
                      pct(row.loo.lut, row.published.lut), (long long)row.published.ff, (long long)row.fitted.ff,
                      (long long)row.loo.ff, pct(row.loo.ff, row.published.ff));
        }
        std::printf("\nleave-one-out |error|: LUT mean %.1f%% max %.1f%%; FF mean %.1f%% max %.1f%%\n",
                    fr.lut_loo_mean_pct, fr.lut_loo_max_pct, fr.ff_loo_mean_pct, fr.ff_loo_max_pct);
      }
      if (!fit_write.empty()) {
        std::ofstream out(fit_write);
        if (!out) throw InputError(fit_write + ": cannot write");
        out << "# Coefficients of the resource and power model (models/resources, docs/resources.md).\n"
               "# Written by `parallax fit-resources --write`; compiled into parallax (rebuild after editing).\n"
            << res::coefficients_yaml(k);
        std::fprintf(stderr, "parallax: wrote %s (rebuild to use it)\n", fit_write.c_str());
      }
      return 0;
    }
    if (*crop) {
      int w = 640, h = 360;
      const RoiSize rs = parse_roi_size(crop_roi);
      if (rs.full) throw InputError("--roi: crop-dataset needs a size WxH, not full");
      w = rs.width_px;
      h = rs.height_px;
      const CropSummary s = crop_dataset(crop_src, crop_frames, {GtKind::noc, GtKind::occ}, w, h, crop_out);
      std::printf("wrote %zu frames (%zu files) to %s\n", s.frame_ids.size(), s.files_written.size(), crop_out.c_str());
      return 0;
    }
  } catch (...) {
    return report_exception(std::current_exception());
  }
  return 0;
}

int main(int argc, char** argv) {
  // Images are bounded (a forged header must not allocate gigabytes): OpenCV refuses to decode
  // more pixels than this, and the readers name the file. A user's own setting wins.
  setenv("OPENCV_IO_MAX_IMAGE_PIXELS", std::to_string(kMaxImagePixels).c_str(), 0);
  try {
    return run_cli(argc, argv);
  } catch (...) {
    return report_exception(std::current_exception());
  }
}
