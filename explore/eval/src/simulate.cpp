#include "parallax/eval/simulate.hpp"

#include "parallax/eval/evaluate.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include <opencv2/imgproc.hpp>

namespace parallax::eval {

sim::CycleOptions cycle_options(const config::PipelineConfig& cfg, int clock_mhz) {
  sim::CycleOptions o;
  o.clock_hz = double(clock_mhz) * 1e6;
  o.synthesis_clock_hz = double(cfg.clock_mhz) * 1e6;  // the design's clock sets its II
  o.input = cfg.input == "camera" ? sim::InputKind::camera : sim::InputKind::memory;
  o.input_bytes_per_s = cfg.input_gbps * 1e9;
  o.camera_pixel_hz = cfg.camera_pixel_mhz * 1e6;
  o.camera_h_blank_px = cfg.camera_h_blank_px;
  o.camera_v_blank_rows = cfg.camera_v_blank_rows;
  o.ddr_bytes_per_s = cfg.ddr_gbps * 1e9;
  o.ddr_latency_s = cfg.ddr_latency_ns * 1e-9;
  o.fifo_depth = std::size_t(cfg.fifo_depth);
  for (const auto& kv : cfg.fifo_depths) o.fifo_depths[kv.first] = std::size_t(kv.second);
  const kern::StereoParams p = cfg.stereo_params(cfg.roi_width_px, cfg.roi_height_px);
  const sim::TimingModel defaults = sim::default_timing(p, o.synthesis_clock_hz);
  // The stage's timing so far: an earlier override, else the default derived from the kernels.
  auto timing_of = [&](const std::string& stage) -> sim::StageTiming& {
    if (!o.timing.count(stage)) o.timing[stage] = defaults.count(stage) ? defaults.at(stage) : sim::StageTiming{};
    return o.timing[stage];
  };
  for (const auto& kv : cfg.stage_ii) timing_of(kv.first).ii_cycles = kv.second;
  for (const auto& kv : cfg.stage_latency) timing_of(kv.first).latency_cycles = kv.second;
  for (const auto& kv : cfg.stage_setup) timing_of(kv.first).setup_cycles = kv.second;
  return o;
}

void system_figures(const config::PipelineConfig& cfg, SimulationResult& res) {
  const double cycle_ms = 1e3 / (double(res.clock_mhz) * 1e6);
  res.fpga_first_pixel_ms = double(res.cycle.first_pixel_cycle + 1) * cycle_ms;
  res.fpga_last_pixel_ms = double(res.cycle.last_pixel_cycle + 1) * cycle_ms;
  res.copy_in_ms = res.copy_out_ms = 0.0;
  if (cfg.host_copy_gbps > 0) {
    const double pixels = double(res.cycle.codes.width_px) * res.cycle.codes.height_px;
    const kern::StereoParams p = cfg.stereo_params(res.cycle.codes.width_px, res.cycle.codes.height_px);
    const int out_bytes_per_px = (kern::disparity_bits(p) + 7) / 8;  // whole bytes per code
    const double out_bytes = pixels * out_bytes_per_px;
    res.copy_in_ms = 2.0 * pixels / (cfg.host_copy_gbps * 1e9) * 1e3;
    res.copy_out_ms = out_bytes / (cfg.host_copy_gbps * 1e9) * 1e3;
  }
  res.latency_ms = res.copy_in_ms + res.fpga_last_pixel_ms + res.copy_out_ms + cfg.host_latency_ms;
  const double fpga_interval = double(res.cycle.cycles_per_frame) * cycle_ms;
  const double host_copies = res.copy_in_ms + res.copy_out_ms;
  res.frame_interval_ms = fpga_interval;
  res.interval_limit = "fpga stage '" + res.cycle.bottleneck + "'";
  if (host_copies > res.frame_interval_ms) {
    res.frame_interval_ms = host_copies;
    res.interval_limit = "host copies";
  }
  if (cfg.host_frame_ms > res.frame_interval_ms) {
    res.frame_interval_ms = cfg.host_frame_ms;
    res.interval_limit = "host frame loop (host_frame_ms)";
  }
  res.fps = res.frame_interval_ms > 0 ? 1e3 / res.frame_interval_ms : 0.0;
}

SimulationResult simulate(const config::PipelineConfig& cfg, const cv::Mat& left, const cv::Mat& right,
                          const SimulateOptions& so) {
  const int clock_mhz = so.clock_mhz;
  sim::CycleOptions opt = cycle_options(cfg, clock_mhz);
  opt.coupled = so.coupled;
  opt.fast_forward = so.fast_forward;
  opt.threads = so.threads;
  opt.vcd_path = so.vcd_path;
  opt.vcd_from = so.vcd_from;
  opt.vcd_to = so.vcd_to;
  const kern::StereoParams p = cfg.stereo_params(left.cols, left.rows);
  const sim::GreyImage l = to_grey_image(left), r = to_grey_image(right);
  RectifyMaps maps;
  if (cfg.rectify != "none") {
    maps = maps_of_size(load_rectify_maps(cfg), cfg, left.cols, left.rows);
    if (maps.width_px != left.cols || maps.height_px != left.rows)
      throw InputError(cfg.rectify_maps_left +
                       ": the cycle model rectifies the frames it processes, so the remap "
                       "tables must be of the processed size " +
                       std::to_string(left.cols) + "x" + std::to_string(left.rows) + " (they are " +
                       std::to_string(maps.width_px) + "x" + std::to_string(maps.height_px) +
                       "); give roi: full with full-size maps");
    opt.rectify = cfg.rectify_params(left.cols, left.rows);
    opt.rectify_map_left = &maps.left;
    opt.rectify_map_right = &maps.right;
  }
  SimulationResult res;
  res.clock_mhz = clock_mhz;
  res.cycle = sim::run_cycle(l, r, p, opt);
  if (so.size_fifos && !res.cycle.deadlock) {
    const sim::FifoSizing sizing = sim::stall_free_depths(l, r, p, opt);
    res.stall_free_depths = sizing.depths;
    res.unbounded_last_pixel_cycle = sizing.last_pixel_cycle;
  }
  system_figures(cfg, res);
  return res;
}

SimulationResult simulate_timing(const config::PipelineConfig& cfg, int w, int h) {
  const sim::GreyImage blank{w, h, std::vector<uint8_t>(std::size_t(w) * std::size_t(h), 0)};
  SimulationResult sr;
  sr.clock_mhz = cfg.clock_mhz;
  sr.cycle = sim::run_timing(blank, blank, cfg.stereo_params(w, h), cycle_options(cfg, cfg.clock_mhz));
  if (!sr.cycle.deadlock) system_figures(cfg, sr);
  return sr;
}

void design_size(const config::PipelineConfig& cfg, int& w, int& h) {
  w = cfg.roi_full ? 640 : cfg.roi_width_px;
  h = cfg.roi_full ? 360 : cfg.roi_height_px;
}

std::string calibrate(config::PipelineConfig& cfg, const SimulationResult& r, double latency_ms, double fps) {
  std::string what;
  const double model_without_host = r.latency_ms - cfg.host_latency_ms;
  cfg.host_latency_ms = std::max(0.0, latency_ms - model_without_host);
  what = "host_latency_ms = " + std::to_string(cfg.host_latency_ms) + " (measured " + std::to_string(latency_ms) +
         " ms - modelled " + std::to_string(model_without_host) + " ms)";
  if (fps > 0) {
    const double interval = 1e3 / fps;
    double model_interval = double(r.cycle.cycles_per_frame) * 1e3 / (double(r.clock_mhz) * 1e6);
    model_interval = std::max(model_interval, r.copy_in_ms + r.copy_out_ms);
    if (interval > model_interval) {
      cfg.host_frame_ms = interval;
      what += "; host_frame_ms = " + std::to_string(interval) + " (measured " + std::to_string(fps) + " fps)";
    } else {
      cfg.host_frame_ms = 0;
      what += "; host_frame_ms = 0 (the model's interval already exceeds the measured one)";
    }
  }
  return what;
}

void test_pattern(int w, int h, int disparities, uint32_t seed, cv::Mat& left, cv::Mat& right) {
  std::mt19937 rng(seed);
  // A textured background at a small disparity, a nearer slanted ground band and a box in front.
  const int pad = disparities + 8;
  cv::Mat tex(h, w + pad, CV_8UC1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w + pad; ++x) tex.at<uint8_t>(y, x) = uint8_t(40 + rng() % 170);
  cv::GaussianBlur(tex, tex, cv::Size(3, 3), 0.8);
  left.create(h, w, CV_8UC1);
  right.create(h, w, CV_8UC1);
  for (int y = 0; y < h; ++y) {
    const int d_row =
        y > h / 2 ? std::min(disparities - 1, 4 + (y - h / 2) * (disparities / 2) / std::max(1, h / 2)) : 4;
    for (int x = 0; x < w; ++x) {
      const bool box = x > w / 3 && x < w / 2 && y > h / 4 && y < 3 * h / 4;
      const int d = box ? std::min(disparities - 1, disparities * 3 / 4) : d_row;
      // L(x) = R(x - d): the left view sees the texture d pixels further along.
      left.at<uint8_t>(y, x) = tex.at<uint8_t>(y, x + pad - d);
      right.at<uint8_t>(y, x) = tex.at<uint8_t>(y, x + pad);
    }
  }
}

}  // namespace parallax::eval
