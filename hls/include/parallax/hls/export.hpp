// Export of one design into a Vitis HLS project (docs/hls.md): the design's kernels instantiated
// with its exact sizes under a DATAFLOW top with AXI4-Stream and AXI4-Lite interfaces, a C
// testbench that checks the top bit for bit against golden output of the simulator, the Vitis
// scripts (run_hls.tcl, hls_config.cfg), a Makefile whose `csim` target needs only g++, and a
// README with the models' predictions.
//
// generate_project() is a pure function of its request (no clock, no paths of this machine), so
// the generated sources can be compared with golden files; write_project() puts them on disk.
#pragma once

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "parallax/config/config.hpp"
#include "parallax/kernels/access.hpp"
#include "parallax/kernels/common.hpp"

namespace parallax::hlsx {

// A request that cannot be exported, or a project that cannot be written; the message names the
// field or the path.
class ExportError : public UserError {
 public:
  using UserError::UserError;
};

// One FIFO between two stages of the top, with the depth chosen from the simulator's sizing.
struct ExportFifo {
  std::string name;         // cycle-model name (export_fifo_names)
  int64_t depth = 2;        // STREAM depth in the exported top
  int64_t stall_free = -1;  // the simulator's stall-free depth (-1: not sized)
  std::string why;          // how the depth was chosen, one line
};

// What the cycle model and the resource model predict for the exported design.
struct ExportPrediction {
  std::string device;  // resource model's device (e.g. XCZU3EG)
  double clock_mhz = 0;
  int64_t first_pixel_cycle = 0;  // first output pixel after the first input pixel
  int64_t last_pixel_cycle = 0;   // last output pixel after the first input pixel
  int64_t unbounded_last_pixel_cycle = -1;
  int64_t cycles_per_frame = 0;
  std::string bottleneck;
  double fpga_latency_ms = 0;  // last pixel, at clock_mhz
  double fps = 0;              // one call per frame: clock / max(busiest stage, one call)
  int64_t bram18k = 0, lut = 0, ff = 0, dsp = 0, uram = 0;
  double bram18k_pct = 0, lut_pct = 0, ff_pct = 0, dsp_pct = 0;
  bool fits = false;
  struct Stage {
    std::string name;
    int64_t bram18k = 0, lut = 0, ff = 0, dsp = 0;
  };
  std::vector<Stage> stages;
};

struct ExportRequest {
  config::PipelineConfig config;  // valid (config::validate); every valid design exports
  std::string origin;             // where the design came from (a file, or a store and hash)
  std::string part = "xczu3eg-sbva484-1-e";
  double clock_mhz = 200;         // synthesis clock (run_hls.tcl, hls_config.cfg)
  std::vector<ExportFifo> fifos;  // one per FIFO of the top, cycle-model names
  ExportPrediction prediction;
  // The testbench's stereo pair at the design's size (row-major grey) and the simulator's codes
  // for it (code D = invalid).
  int width_px = 0, height_px = 0;
  std::vector<uint8_t> left, right;
  std::vector<uint16_t> golden;
  std::string pair_source;    // e.g. "data/kitti2015-640x360/.../000000_10.png"
  std::string golden_source;  // e.g. "parallax cycle model (sim::run_cycle)"
  // Rectifying designs: the remap tables of the pair's size in the kernels' fixed point (the
  // pair is then the raw, unrectified images).
  std::vector<kern::MapEntry> map_left, map_right;
  // The cycle model's firings per frame of each stage (sim::StageReport::fires by the cycle
  // model's stage name): the trip counts of the top's `while (!stage.done())` loops, which fire
  // their kernel once per iteration (LOOP_TRIPCOUNT, so that csynth reports a latency).
  std::map<std::string, int64_t> stage_fires;
  // The cycle model's II and pipeline depth of each stage at the export's clock (the II of the
  // kernel stages derived from their schedule declarations): the PIPELINE pragmas are written
  // from it, and stages.json lists it.
  struct StageTiming {
    std::string name;
    int ii_cycles = 1;
    int depth_cycles = 1;
  };
  std::vector<StageTiming> stage_timing;
  // The kernel stages' declared II and recurrences at the export's clock (sim::access_stages):
  // the testbench's table, to which `make csim` adds its own counts (csim_accesses.json).
  std::vector<kern::AccessStage> access_stages;
  // The reduced frame of C/RTL co-simulation (PARALLAX_REDUCED_FRAME): the first
  // reduced_height_px rows of the pair (reduced_frame_rows), the simulator's codes for them and
  // its firings per stage.
  int reduced_height_px = 0;
  std::vector<uint16_t> reduced_golden;
  std::map<std::string, int64_t> reduced_stage_fires;
};

struct GeneratedFile {
  std::string path;     // relative to the project folder
  std::string content;  // text, or the bytes of a binary file
  bool binary = false;
};

// The rows of the reduced frame that C/RTL co-simulation runs by default: the design's first
// min(height_px, 16) rows at its full width (the line buffers are sized by the width).
int reduced_frame_rows(int height_px);

// The names of the FIFOs of an exported top, in pipeline order (the cycle model's names).
std::vector<std::string> export_fifo_names(const config::PipelineConfig& c);

// The whole project. Throws ExportError when the request is inconsistent (sizes, FIFOs).
std::vector<GeneratedFile> generate_project(const ExportRequest& r);

// Throws ExportError when `dir` is a file, or a folder that is not empty and was not written by an
// earlier export (marker file .parallax-export); a new, empty or earlier export's folder passes.
void check_project_dir(const std::string& dir);

// Writes the files under `dir`, creating folders. Refuses (ExportError) a folder that exists, is
// not empty and was not written by an earlier export (marker file .parallax-export).
void write_project(const std::vector<GeneratedFile>& files, const std::string& dir);

// The synthesis clock period in ns as the Vitis scripts write it (e.g. 5.000 for 200 MHz).
std::string clock_period_ns(double clock_mhz);

}  // namespace parallax::hlsx
