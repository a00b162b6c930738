// `parallax sim`: one frame through the cycle model, and the system around it (input, host
// copies, calibration) turned into latency, frame interval and frame rate.
#pragma once

#include <map>
#include <string>

#include <opencv2/core.hpp>

#include "parallax/config/config.hpp"
#include "parallax/sim/cycle.hpp"

namespace parallax::eval {

// The cycle model's options for a design at a clock (MHz), from its configuration.
sim::CycleOptions cycle_options(const config::PipelineConfig& cfg, int clock_mhz);

struct SimulationResult {
  sim::CycleReport cycle;
  std::map<std::string, int64_t> stall_free_depths;  // empty unless sized
  int64_t unbounded_last_pixel_cycle = -1;           // last pixel with unbounded FIFOs (sized runs)
  int clock_mhz = 0;
  double fpga_first_pixel_ms = 0.0;  // first output pixel after the first input pixel
  double fpga_last_pixel_ms = 0.0;   // last output pixel after the first input pixel
  double copy_in_ms = 0.0;           // host copies (store and forward), see config host_copy_gbps
  double copy_out_ms = 0.0;
  double latency_ms = 0.0;         // copy in + FPGA (last pixel) + copy out + host_latency_ms
  double frame_interval_ms = 0.0;  // max(FPGA cycles per frame, host copies, host_frame_ms)
  double fps = 0.0;
  std::string interval_limit;  // what sets the frame interval
};

struct SimulateOptions {
  int clock_mhz = 200;
  bool size_fifos = false;   // also run with unbounded FIFOs to find the smallest stall-free depths
  bool coupled = false;      // fire the kernels' datapath inside the schedule (sim::CycleOptions::coupled)
  bool fast_forward = true;  // apply rows that repeat exactly at once (sim::CycleOptions::fast_forward)
  int threads = 0;           // sim::CycleOptions::threads (0: 2 where there are two hardware threads)
  std::string vcd_path;      // VCD of cycles [vcd_from, vcd_to) when not empty
  int64_t vcd_from = 0, vcd_to = 0;
};

// Runs the cycle model on a grey pair of the ROI size.
SimulationResult simulate(const config::PipelineConfig& cfg, const cv::Mat& left_grey, const cv::Mat& right_grey,
                          const SimulateOptions& so);

// The design's timing at a processed size without the codes: the cycle model's schedule
// (sim::run_timing; it does not depend on the images) and the system figures. What sweeps,
// flights and reports need once per design.
SimulationResult simulate_timing(const config::PipelineConfig& cfg, int width_px, int height_px);
// The processed size of a design: its ROI, or 640 x 360 when it processes whole images.
void design_size(const config::PipelineConfig& cfg, int& width_px, int& height_px);

// Fills the system figures of `res` (latencies, host copies, frame interval, fps) from its cycle
// report and the configuration's host model; cheap, so calibration recomputes them in place.
void system_figures(const config::PipelineConfig& cfg, SimulationResult& res);

// Sets host_latency_ms (and host_frame_ms, when the measured frame interval exceeds the model's)
// so that the simulated result reproduces a measured latency and frame rate at this clock.
// Returns a one-line account of what was set.
std::string calibrate(config::PipelineConfig& cfg, const SimulationResult& at_clock, double measured_latency_ms,
                      double measured_fps);

// A seeded synthetic stereo pair (textured planes at several disparities, an occluding box), used
// when no pair is given.
void test_pattern(int width_px, int height_px, int disparities, uint32_t seed, cv::Mat& left, cv::Mat& right);

}  // namespace parallax::eval
