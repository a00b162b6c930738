// parallax baseline: score OpenCV's StereoSGBM (HH4 or SGBM mode) on the same crops as eval.
#include <cstdlib>
#include <memory>
#include <string>

#include "commands.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/evaluate.hpp"
#include "parallax/eval/input_error.hpp"

namespace parallax::cli {

namespace {

using namespace parallax::eval;
using namespace parallax::search;

struct BaselineOptions {
  std::string name, dataset, frames, gt = "noc", save, roi;
  BaselineParams params;
  bool json = false, quiet = false;
  int threads = default_threads();
};

int run_baseline_command(const BaselineOptions& o, const Invocation&) {
  if (o.params.p1 >= o.params.p2)
    throw InputError("--p1 " + std::to_string(o.params.p1) + " must be below --p2 " + std::to_string(o.params.p2) +
                     " (OpenCV's StereoSGBM requires P1 < P2)");
  const Baseline b = parse_baseline(o.name);
  const Dataset ds = open_dataset(o.dataset);
  const EvalOptions opt = eval_options(o.gt, o.frames, o.threads, o.save, o.params.disparities, o.quiet || o.json);
  const RoiSize roi = o.roi.empty() ? default_roi_size(ds.layout) : parse_roi_size(o.roi);
  const EvalResult r = evaluate(
      ds, roi,
      [&]() -> Matcher {
        return [&](const cv::Mat& l, const cv::Mat& rr) { return run_baseline(b, o.params, l, rr); };
      },
      opt);
  print_notes(r.notes);
  print_evaluation(r, o.json, {{"baseline", o.name}}, o.name + " on " + o.dataset + " (" + o.gt + ")");
  return 0;
}

}  // namespace

Command add_baseline(CLI::App& app) {
  auto o = std::make_shared<BaselineOptions>();
  BaselineParams& p = o->params;
  auto* baseline =
      app.add_subcommand("baseline", "Score OpenCV StereoSGBM (opencv-hh4 | opencv-sgbm) on the same crops");
  baseline->add_option("method", o->name, "opencv-hh4 or opencv-sgbm")
      ->required()
      ->check(CLI::IsMember({"opencv-hh4", "opencv-sgbm"}));
  baseline->add_option("--dataset", o->dataset, "Dataset folder")->required();
  baseline->add_option("--frames", o->frames, "Frames, e.g. 1-5,7, or @FILE (default: all with GT)")
      ->transform(FrameList());
  baseline->add_option("--gt", o->gt, "noc or occ")->check(CLI::IsMember({"noc", "occ"}));
  baseline->add_option("--roi", o->roi, "ROI WxH or full (default: the dataset's, 640x360 for KITTI)");
  baseline->add_option("--disparities", p.disparities, "Disparity count (rounded up to a multiple of 16)")
      ->capture_default_str()
      ->check(InRange(1, 1024));
  baseline->add_option("--block-size", p.block_size, "Matching block size (odd)")
      ->capture_default_str()
      ->check(InRange(1, 255))
      ->check(CLI::Validator(
          [](std::string& v) {
            return std::atoi(v.c_str()) % 2 == 1 ? std::string() : "block size " + v + " is even; OpenCV needs it odd";
          },
          "odd"));
  baseline->add_option("--p1", p.p1, "P1 (0 <= P1 < P2)")->capture_default_str()->check(InRange(0, 1 << 24));
  baseline->add_option("--p2", p.p2, "P2 (> P1)")->capture_default_str()->check(InRange(1, 1 << 24));
  baseline->add_option("--save", o->save, "Write each frame's disparity and colour picture here")
      ->check(OutputFolder());
  baseline->add_option("--threads", o->threads, "Frames in parallel")->check(InRange(1, 256));
  baseline->add_flag("--json", o->json, "Print JSON");
  baseline->add_flag("--quiet", o->quiet, "No progress lines");
  return bind_command(baseline, o, run_baseline_command);
}

}  // namespace parallax::cli
