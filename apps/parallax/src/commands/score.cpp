// parallax score: score existing KITTI-format disparity PNGs (any method) with eval's protocol.
#include <nlohmann/json.hpp>

#include <memory>
#include <string>

#include "commands.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/evaluate.hpp"

namespace parallax::cli {

namespace {

using namespace parallax::eval;
using namespace parallax::search;

struct ScoreOptions {
  std::string pred, dataset, frames, gt = "noc", roi;
  bool json = false;
};

int run_score(const ScoreOptions& o, const Invocation&) {
  const Dataset ds = open_dataset(o.dataset);
  EvalOptions opt;
  opt.gt_kind = parse_gt_kind(o.gt);
  opt.frames = o.frames;
  const RoiSize roi = o.roi.empty() ? default_roi_size(ds.layout) : parse_roi_size(o.roi);
  const EvalResult r = score_predictions(o.pred, ds, roi, opt);
  print_evaluation(r, o.json, nlohmann::json::object(), o.pred + " on " + o.dataset + " (" + o.gt + ")");
  return 0;
}

}  // namespace

Command add_score(CLI::App& app) {
  auto o = std::make_shared<ScoreOptions>();
  auto* score =
      app.add_subcommand("score", "Score existing KITTI-format disparity PNGs (any method) with the same protocol");
  score
      ->add_option(
          "--pred", o->pred,
          "Folder of predictions, one KITTI 16-bit PNG per frame named <frame id>_10.png (as eval --save writes them)")
      ->required();
  score->add_option("--dataset", o->dataset, "Dataset folder with the ground truth")->required();
  score->add_option("--frames", o->frames, "Frames to score, e.g. 1-5,7, or @FILE (default: all with GT)")
      ->transform(FrameList());
  score->add_option("--gt", o->gt, "Ground truth kind: noc or occ")->check(CLI::IsMember({"noc", "occ"}));
  score->add_option("--roi", o->roi, "ROI WxH or full (default: the dataset's, 640x360 for KITTI)");
  score->add_flag("--json", o->json, "Print JSON");
  return bind_command(score, o, run_score);
}

}  // namespace parallax::cli
