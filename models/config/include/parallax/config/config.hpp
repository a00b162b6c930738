// PipelineConfig: the single source of truth for one design. Its fields are rows of one table
// (src/field_table.cpp): each row parses, checks, writes and documents its field, followed by the
// few rules between fields. validate() returns all violations with their field names and allowed
// values; the CLI, the explorer and the HLS export all use it. Nothing is silently adjusted.
#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "parallax/config/user_error.hpp"
#include "parallax/kernels/params.hpp"

namespace parallax::config {

// The structure of a design: everything but its registers. The pipeline's shape and sizes (what
// synthesis fixes) and the system around it, for the cycle model.
struct Structure {
  std::string name = "unnamed";
  // Region of interest processed by the design: centred crop of the input (docs/evaluation.md);
  // roi_full = true processes the whole image.
  bool roi_full = false;
  int roi_width_px = 640;
  int roi_height_px = 360;
  std::string cost = "census";  // census | sad
  std::string census = "full";  // full | sparse | symmetric (cost census only)
  int window_w = 5;
  int window_h = 5;
  int disparities = 64;
  int min_disparity = 0;            // m: the disparities searched are [m, m + disparities)
  int p2_adaptive = 0;              // a: along a path P2 drops by (a |I(p) - I(q)|) >> 4, floor p1 + 1 (0 = off)
  std::string aggregation = "sgm";  // sgm | mgm (two predecessors per path step)
  int subpixel_bits = 0;            // f: fraction bits of the disparity codes (parabola fit; 0 = integers)
  int parallel_units = 1;
  unsigned path_mask = kern::kForwardPaths;
  bool lr_check = true;
  int median = 5;                // 0 = off, 3, 5, 7
  int clock_mhz = 200;           // processing clock (used by the timing model)
  std::string rectify = "none";  // none | nearest | bilinear
  int rectify_rows = 16;         // line-buffer rows of the rectification stage
  int rectify_frac_bits = 5;     // fixed-point fraction bits of bilinear maps
  // Remap tables (OpenCV FileStorage with float nodes map_x, map_y: source position of every
  // rectified pixel, as cv::initUndistortRectifyMap writes them). Relative paths in a file are
  // resolved against the file's folder.
  std::string rectify_maps_left;
  std::string rectify_maps_right;

  // --- the system around the pipeline (cycle model, docs/simulator.md) ---
  std::string input = "memory";  // memory: pairs stream from DDR; camera: pixel clock + blanking
  double input_gbps = 4.0;       // memory input bandwidth, GB/s (left + right bytes)
  double camera_pixel_mhz = 25.0;
  int camera_h_blank_px = 0;
  int camera_v_blank_rows = 0;
  double ddr_gbps = 4.0;  // frame buffer of the 8-path variant
  int ddr_latency_ns = 150;
  int fifo_depth = 2;  // default depth of every FIFO
  // Resource figures: what Vitis HLS C synthesis reports (csynth) or after place and route
  // (routed: csynth x the ratios of models/data/resource_model.yaml), docs/resources.md.
  std::string estimate = "csynth";           // csynth | routed
  std::map<std::string, int> fifo_depths;    // fifo_depth_<name>: per FIFO
  std::map<std::string, int> stage_ii;       // ii_<stage>: II override (calibration)
  std::map<std::string, int> stage_latency;  // latency_<stage>: latency override
  std::map<std::string, int> stage_setup;    // setup_<stage>: cycles of per-frame set-up before its first firing
  // Clock-independent share, modelled explicitly: the processor copies each input pair into and
  // each disparity map out of the PL's buffers at host_copy_gbps (0 = frames stream, no copies),
  // plus a fixed host_latency_ms; host_frame_ms bounds the frame interval from below (the
  // processor's own loop). Calibration sets the last two (parallax sim --calibrate-...).
  double host_copy_gbps = 0.0;
  double host_latency_ms = 0.0;
  double host_frame_ms = 0.0;
  // The avoidance stage's time per frame on the processor (a model, so a flight's timing does not
  // depend on the machine that simulates it): a command takes effect latency + avoid_ms after
  // its frame. 0 = none.
  double avoid_ms = 0.0;

  // One past the largest disparity the design can output, m + D, in pixels.
  int disparity_end_px() const { return min_disparity + disparities; }
};

// The runtime registers of a design: the values a hardware register holds, which may change
// between frames without resynthesis (the exported top's AXI4-Lite ports). p1 and p2 are read by
// the SGM aggregation only, lr_tolerance and uniqueness_pct by the WTA / left-right check only.
// A design with uniqueness_pct 0 has no uniqueness hardware (the exported top then has no such
// port); one built with a margin takes any 0..100 at run time.
struct Registers {
  int p1 = 8;
  int p2 = 32;
  int lr_tolerance = 1;
  int uniqueness_pct = 0;
};

// One design: its structure and its registers. Every field is a member under the name users
// write (c.disparities, c.p1); registers() gives the registers alone.
struct PipelineConfig : Structure, Registers {
  // The register values, as the kernels take them.
  kern::StereoRegisters registers() const;
  // The kernel parameters for an image (or ROI) of the given size: the structure and the registers.
  kern::StereoParams stereo_params(int width_px, int height_px) const;
  // The rectification stage's parameters for frames of the given size: mode from `rectify`
  // (kRectifyNone when "none"), fraction bits only when bilinear, `rectify_rows` line-buffer rows.
  kern::RectifyParams rectify_params(int width_px, int height_px) const;
};

struct FieldError {
  std::string field;
  std::string message;
};

// All violations, empty when the configuration is valid.
std::vector<FieldError> validate(const PipelineConfig& c);

// The kernels' census kind (kern::CensusKind) of a `census` field value, -1 when unknown.
int census_kind(const std::string& census);

// A configuration file or override that cannot be used: the message names the file and every
// offending field.
class ConfigError : public UserError {
 public:
  using UserError::UserError;
};

// The whole text of a user-given file (configuration, sweep, scenario, points, report), refusing
// what is not a regular file (a folder, /dev/zero, a FIFO) and anything over max_bytes, so that no
// input can make a command read forever. Throws ConfigError naming the file and `what` it is.
constexpr std::size_t kMaxTextFileBytes = std::size_t(4) << 20;  // 4 MiB: configs are a few kB
std::string read_text_file(const std::string& path, const std::string& what, std::size_t max_bytes = kMaxTextFileBytes);

// Reads a YAML configuration (flat mapping of the field names above). Unknown fields, bad
// values and violated constraints are all reported together. Throws ConfigError.
PipelineConfig load_config(const std::string& path);
PipelineConfig parse_config(const std::string& yaml_text, const std::string& source_name);

// Sets one field from text, as `--set key=value` and sweeps do. Throws ConfigError naming the
// field. Call validate() afterwards.
void set_field(PipelineConfig& c, const std::string& key, const std::string& value);

// The field names accepted in files, in documentation order (a pattern as "ii_<stage>").
const std::vector<std::string>& field_names();

// The reference of the fields, one line each in documentation order: name, "(register)" for a
// runtime register, what it means and the values it takes; then the rules between fields.
std::string field_documentation();

// Canonical text of the configuration (YAML), stable for hashing and for reports.
std::string to_yaml(const PipelineConfig& c);

// "4" / "8" / "0,45,90" -> path mask; throws ConfigError on bad input.
unsigned parse_paths(const std::string& text);
std::string paths_to_string(unsigned mask);

}  // namespace parallax::config
