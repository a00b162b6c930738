// Running a design (or a baseline) over stereo pairs and scoring it against ground truth: the
// engine behind `parallax run`, `eval`, `score` and `baseline`.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "parallax/config/config.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/disparity_io.hpp"
#include "parallax/eval/metrics.hpp"
#include "parallax/sim/func.hpp"

namespace parallax::eval {

// Remap tables of both cameras in the kernel's fixed point (docs/algorithm.md §1).
struct RectifyMaps {
  int width_px = 0;
  int height_px = 0;
  std::vector<kern::MapEntry> left, right;
  // No tables configured: the identity remap of whatever size is processed (the images are already
  // rectified; the stage is still in the pipeline, as on the paper's FPGA, and sized by
  // rectify_rows). maps_of_size() makes the tables for one frame size.
  bool identity = false;
};
// Loads the config's map files; InputError naming the file on any problem. Nearest rounds the
// float maps to integers, bilinear to rectify_frac_bits fraction bits. Neither file configured:
// identity maps; only one: InputError.
RectifyMaps load_rectify_maps(const config::PipelineConfig& cfg);
// The tables for frames of width_px x height_px: `maps` itself, or identity tables of that size.
RectifyMaps maps_of_size(const RectifyMaps& maps, const config::PipelineConfig& cfg, int width_px, int height_px);

// Rectifies a full-size grey pair with the rectify kernel; window misses (map entries outside the
// line buffer's rows) are added to *window_misses. InputError when sizes differ from the maps.
void rectify_pair(const config::PipelineConfig& cfg, const RectifyMaps& maps, cv::Mat& left, cv::Mat& right,
                  int64_t* window_misses);

// A CV_8UC1 image as the kernels' input.
sim::GreyImage to_grey_image(const cv::Mat& grey);
// Disparity codes as a disparity in px with its validity mask (the invalid code D becomes mask 0).
DisparityMap to_disparity_map(const sim::DisparityCodes& codes);

// Runs the design's kernels (func run) on one grey pair of equal size; returns the disparity in
// px with its validity mask (invalid codes become mask 0).
DisparityMap run_design(const config::PipelineConfig& cfg, const cv::Mat& left_grey, const cv::Mat& right_grey,
                        sim::FuncPipeline& pipeline, const sim::FuncOptions& options = {});

// The peers every design is compared with: OpenCV's StereoSGBM in two modes.
enum class Baseline { opencv_hh4, opencv_sgbm };
Baseline parse_baseline(const std::string& name);  // "opencv-hh4" | "opencv-sgbm"; InputError otherwise
std::string to_string(Baseline b);

struct BaselineParams {
  int disparities = 64;  // rounded up to a multiple of 16, as OpenCV requires
  int block_size = 5;
  int p1 = 200;
  int p2 = 800;
  int disp12_max_diff = 1;
};
DisparityMap run_baseline(Baseline b, const BaselineParams& bp, const cv::Mat& left_grey, const cv::Mat& right_grey);

struct EvalOptions {
  GtKind gt_kind = GtKind::noc;
  std::string frames;           // filter, "" = all frames with GT of gt_kind
  bool roi_from_config = true;  // else roi below
  RoiSize roi;                  // used when !roi_from_config
  int threads = 1;              // frames evaluated in parallel
  // false: the matcher sees the cropped pair (the paper's protocol); true: it sees the whole
  // image and its output is cropped to the ROI afterwards (more context at the ROI's borders).
  bool match_full_image = false;
  std::filesystem::path save_dir;         // when set: KITTI PNG + colour picture per frame
  double colour_max_disparity_px = 64.0;  // disparity shown as the reddest colour
  std::function<void(int done, int total, const std::string& frame_id)> progress;
  // Applied to each full-size grey pair before the ROI crop (the design's rectification).
  std::function<void(cv::Mat& left, cv::Mat& right)> preprocess;
  // D and m of the design (it searches m .. m + D - 1); D > 0 adds a warning to the notes when
  // frames' disparities reach beyond m + D (disparity_range_warning). evaluate_design sets them.
  int design_disparities = 0;
  int design_min_disparity = 0;
};

struct EvalResult {
  std::vector<FrameRow> frames;  // dataset order
  FrameRow pooled;
  std::vector<std::string> notes;  // e.g. colour input converted to grey
  double seconds = 0.0;
};

// What produces a disparity for a cropped grey pair; used to share the evaluation loop.
using Matcher = std::function<DisparityMap(const cv::Mat& left, const cv::Mat& right)>;
// One matcher per worker thread (pipelines are not shared between threads).
using MatcherFactory = std::function<Matcher()>;

EvalResult evaluate(const Dataset& dataset, const RoiSize& roi, const MatcherFactory& factory, const EvalOptions& opt);
EvalResult evaluate_design(const config::PipelineConfig& cfg, const Dataset& dataset, const EvalOptions& opt);

// Scores existing KITTI-format disparity PNGs in pred_dir, named <frame id>_10.png as
// `eval --save` writes them (KITTI: the GT file's name), or else like the GT file when that is a PNG. A prediction
// of the full image size is cropped to the ROI; one of the ROI size is taken as the crop.
EvalResult score_predictions(const std::filesystem::path& pred_dir, const Dataset& dataset, const RoiSize& roi,
                             const EvalOptions& opt);

// The ROI size for a dataset: the config's unless overridden ("full" keeps whole images).
RoiSize roi_for(const config::PipelineConfig& cfg);

}  // namespace parallax::eval
