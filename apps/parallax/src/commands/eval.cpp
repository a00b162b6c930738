// parallax eval: score a design on a dataset (KITTI 2015/2012 or Middlebury).
#include <memory>
#include <string>

#include "commands.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/evaluate.hpp"

namespace parallax::cli {

namespace {

using namespace parallax::eval;
using namespace parallax::search;

struct EvalCommandOptions {
  ConfigArgs cfg;
  std::string dataset, frames, gt = "noc", save, roi, context = "roi";
  bool json = false, quiet = false;
  int threads = default_threads();
};

int run_eval(const EvalCommandOptions& o, const Invocation&) {
  const config::PipelineConfig cfg = load_config_args(o.cfg);
  const Dataset ds = open_dataset(o.dataset);
  EvalOptions opt = eval_options(o.gt, o.frames, o.threads, o.save, cfg.disparity_end_px(), o.quiet || o.json);
  opt.match_full_image = o.context == "full";
  if (!o.roi.empty()) {
    opt.roi_from_config = false;
    opt.roi = parse_roi_size(o.roi);
  }
  const EvalResult r = evaluate_design(cfg, ds, opt);
  print_notes(r.notes);
  print_evaluation(r, o.json, {{"config", cfg.name}, {"dataset", o.dataset}, {"gt", o.gt}},
                   cfg.name + " on " + o.dataset + " (" + o.gt + ")");
  return 0;
}

}  // namespace

Command add_eval(CLI::App& app) {
  auto o = std::make_shared<EvalCommandOptions>();
  auto* eval = app.add_subcommand("eval", "Score a design on a dataset (KITTI 2015/2012 or Middlebury)");
  add_config_options(eval, o->cfg, true);
  add_engine_option(eval);
  eval->add_option("--dataset", o->dataset,
                   "Dataset folder (KITTI root or training/, or a Middlebury pairs.tsv folder)")
      ->required();
  eval->add_option("--frames", o->frames,
                   "Frames, e.g. 1-5,7 or 000046, or @FILE with one per line (default: all with GT)")
      ->transform(FrameList());
  eval->add_option("--gt", o->gt, "Ground truth kind: noc or occ")->check(CLI::IsMember({"noc", "occ"}));
  eval->add_option("--roi", o->roi, "Override the config's ROI: WxH or full");
  eval->add_option("--context", o->context,
                   "roi: match the cropped pair (paper); full: match the whole image, then crop")
      ->check(CLI::IsMember({"roi", "full"}))
      ->capture_default_str();
  eval->add_option("--save", o->save, "Write each frame's disparity (KITTI PNG) and colour picture here")
      ->check(OutputFolder());
  eval->add_option("--threads", o->threads, "Frames in parallel (default: all cores)")->check(InRange(1, 256));
  eval->add_flag("--json", o->json, "Print JSON: pooled metrics, counts and per-frame rows");
  eval->add_flag("--quiet", o->quiet, "No progress lines");
  return bind_command(eval, o, run_eval);
}

}  // namespace parallax::cli
