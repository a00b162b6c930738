// parallax run: the disparity of one stereo pair with a design (the func run), as a KITTI PNG and
// a colour picture; scored when ground truth is given; optionally an HTML page.
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/disparity_io.hpp"
#include "parallax/eval/evaluate.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/eval/json.hpp"
#include "parallax/eval/metrics.hpp"
#include "parallax/eval/simulate.hpp"
#include "parallax/reports/report.hpp"
#include "parallax/resources/model.hpp"
#include "parallax/sim/func.hpp"

namespace parallax::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace parallax::eval;
using namespace parallax::design;
using namespace parallax::search;
using namespace parallax::hls_flow;
using namespace parallax::reports;

struct RunOptions {
  ConfigArgs cfg;
  std::string left, right, out, gt, colour, html;
  bool json = false;
};

// The ground truth at `path` on the ROI: a map of the image's size cropped to it, or one of the
// ROI's size as is. Throws InputError naming the file when it is neither size.
DisparityMap ground_truth_on_roi(const std::string& path, const cv::Size& image, const Roi& roi) {
  DisparityMap gt = read_kitti_disparity(path);
  if (gt.disparity_px.size() == image) {
    gt.disparity_px = crop_to_roi(gt.disparity_px, roi);
    gt.valid_mask = crop_to_roi(gt.valid_mask, roi);
  } else if (gt.disparity_px.cols != roi.width_px || gt.disparity_px.rows != roi.height_px) {
    throw InputError(path + ": ground truth is " + std::to_string(gt.disparity_px.cols) + "x" +
                     std::to_string(gt.disparity_px.rows) + ", neither the image size " + std::to_string(image.width) +
                     "x" + std::to_string(image.height) + " nor the ROI size " + std::to_string(roi.width_px) + "x" +
                     std::to_string(roi.height_px));
  }
  return gt;
}

// Completes `section` (which holds the ground-truth pictures and metrics when --gt was given) with
// the design, the pair `l` and its disparity `d`, timing and resources, and writes the page.
void write_run_page(const RunOptions& o, const Invocation& inv, const config::PipelineConfig& cfg, const cv::Mat& l,
                    const DisparityMap& d, const Roi& roi, double density_pct, DesignSection& section) {
  section.title = cfg.name + " on " + o.left;
  section.config_yaml = config::to_yaml(cfg);
  section.command = command_line(inv);
  section.left_grey = l.clone();
  section.frame_id = fs::path(o.left).filename().string();
  section.disparity_colour = colourize_disparity(d.disparity_px, d.valid_mask, double(cfg.disparity_end_px()));
  add_avoidance_images(section, view_avoidance(d.disparity_px, d.valid_mask, cfg.disparity_end_px(), roi.x0, roi.y0));
  if (!section.metrics.count("density_pct")) section.metrics["density_pct"] = density_pct;
  DesignResult figures;  // timing and resources at the pair's ROI, on the default device
  figures.config = cfg;
  figures.width_px = l.cols;
  figures.height_px = l.rows;
  complete_point(figures, PointRequest{});
  add_figures(section, figures);
  write_text_file(o.html, standalone_page("Parallax: " + section.title, design_section_html(section)));
}

// The text answer: the files written, the density and, with --gt, the scores in `j`.
void print_run_text(const RunOptions& o, const std::string& colour, const Roi& roi, const json& j) {
  std::printf("wrote %s and %s (ROI %dx%d at %d,%d)\n", o.out.c_str(), colour.c_str(), roi.width_px, roi.height_px,
              roi.x0, roi.y0);
  std::printf("density_pct %.2f\n", j["density_pct"].get<double>());
  if (!o.gt.empty())
    for (const char* k : {"density_gt_pct", "correct_3px_pct", "d1_all_pct", "d1_all_filled_pct", "mean_abs_error_px"})
      std::printf("%s %.3f\n", k, j[k].get<double>());
}

int run_run(const RunOptions& o, const Invocation& inv) {
  const config::PipelineConfig cfg = load_config_args(o.cfg);
  std::vector<std::string> notes;
  cv::Mat left = load_grey_file(o.left, "left", notes);
  cv::Mat right = load_grey_file(o.right, "right", notes);
  if (left.size() != right.size())
    throw InputError(o.right + ": right image is " + std::to_string(right.cols) + "x" + std::to_string(right.rows) +
                     " but the left image " + o.left + " is " + std::to_string(left.cols) + "x" +
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
  write_kitti_disparity(o.out, d.disparity_px, d.valid_mask);
  std::string colour = o.colour;
  if (colour.empty()) {
    fs::path p(o.out);
    colour = (p.parent_path() / (p.stem().string() + "_colour.png")).string();
  }
  write_png(colour, colourize_disparity(d.disparity_px, d.valid_mask, cfg.disparity_end_px()));
  print_notes(notes);
  json j;
  j["config"] = cfg.name;
  j["roi"] = roi;  // parallax/eval/json.hpp
  j["out"] = o.out;
  j["colour"] = colour;
  if (cfg.rectify != "none") j["rectify_window_misses"] = window_misses;
  const int valid = cv::countNonZero(d.valid_mask);
  j["density_pct"] = 100.0 * valid / double(roi.width_px * roi.height_px);
  DesignSection section;
  if (!o.gt.empty()) {
    const DisparityMap gt = ground_truth_on_roi(o.gt, left.size(), roi);
    const FrameRow row =
        make_frame_row("pair", count_frame(d.disparity_px, d.valid_mask, gt.disparity_px, gt.valid_mask));
    j.update(json(row.metrics));  // parallax/eval/json.hpp
    if (!o.html.empty()) {
      section.gt_colour = colourize_disparity(gt.disparity_px, gt.valid_mask, double(cfg.disparity_end_px()));
      section.error_map = error_map(d.disparity_px, d.valid_mask, gt.disparity_px, gt.valid_mask);
      for (const auto& kv : named_metrics(row.metrics)) section.metrics[kv.first] = kv.second;
    }
  }
  if (!o.html.empty()) write_run_page(o, inv, cfg, l, d, roi, j["density_pct"].get<double>(), section);
  if (o.json)
    std::cout << j.dump(2) << "\n";
  else
    print_run_text(o, colour, roi, j);
  return 0;
}

}  // namespace

Command add_run(CLI::App& app) {
  auto o = std::make_shared<RunOptions>();
  auto* run = app.add_subcommand("run", "Compute the disparity of one stereo pair with a design (func run)");
  add_config_options(run, o->cfg, true);
  add_engine_option(run);
  run->add_option("--left", o->left, "Left image (8-bit grey or colour)")->required();
  run->add_option("--right", o->right, "Right image, same size")->required();
  run->add_option("--out", o->out, "Disparity as KITTI 16-bit PNG (value = 256 d, 0 = invalid)")
      ->required()
      ->check(OutputFile(".png"));
  run->add_option("--colour", o->colour, "Colour-coded picture (default: OUT with _colour.png)")
      ->check(OutputFile(".png"));
  run->add_option("--gt", o->gt, "Ground truth (KITTI 16-bit PNG, full image or ROI size) to score against");
  run->add_flag("--json", o->json, "Print a JSON object (metrics when --gt is given)");
  run->add_option("--html", o->html,
                  "Write a self-contained HTML page of this design on this pair (images, timing, resources)")
      ->check(OutputFile());
  return bind_command(run, o, run_run);
}

}  // namespace parallax::cli
