// Reading Vitis HLS synthesis reports back (`parallax import-hls`, docs/hls.md): csynth.xml's
// clock, overall latency and interval, per-loop II and depth, and resources, turned into the
// calibration fields the cycle model uses (ii_<stage>, latency_<stage>).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "parallax/config/config.hpp"
#include "parallax/sim/cycle.hpp"

namespace parallax::hls_flow {

struct HlsLoop {
  std::string name;
  int64_t trip_count = -1, latency_cycles = -1, iteration_latency = -1;
  int pipeline_ii = -1, pipeline_depth = -1;  // -1: not pipelined / not reported
};

struct HlsReport {
  std::string part, top, version;
  double target_clock_ns = 0, estimated_clock_ns = 0;
  int64_t best_latency_cycles = -1, worst_latency_cycles = -1, interval_min_cycles = -1, interval_max_cycles = -1;
  std::vector<HlsLoop> loops;
  std::map<std::string, int64_t> resources, available;  // BRAM_18K, DSP, FF, LUT, URAM
};

// Throws InputError naming the file and the element when the XML is not a csynth report.
HlsReport read_csynth_xml(const std::string& path);

// Sets ii_<stage> and latency_<stage> for every loop named after a stage of the cycle model
// (`<stage>_loop` or `<stage>` ...: the longest stage name that prefixes the loop's name).
// Returns the fields set, "key=value".
std::vector<std::string> calibrate_from_hls(config::PipelineConfig& cfg, const HlsReport& r);

}  // namespace parallax::hls_flow

namespace parallax::hls_flow {

// One figure predicted by Parallax's models next to what synthesis reported.
struct ModelVsSynthesis {
  std::string figure;  // e.g. "latency (cycles)", "II aggregate_loop", "BRAM_18K"
  double model = -1;   // -1: the model has no figure for it
  double synthesis = -1;
  std::string note;  // e.g. which model stage a loop was matched to
};

// The models' figures for the configuration (cycle model at the report's clock, resource model)
// beside the report's: latency and interval, the II and depth of every loop named after a stage,
// and BRAM_18K / LUT / FF / DSP. width_px x height_px: the processed size. model_cycle, when
// given, receives the cycle model's report the figures came from (for a page of the design).
std::vector<ModelVsSynthesis> compare_with_model(const config::PipelineConfig& cfg, const HlsReport& r, int width_px,
                                                 int height_px, sim::CycleReport* model_cycle = nullptr);

}  // namespace parallax::hls_flow
