// parallax bench: the func run timed against OpenCV's StereoSGBM (HH4, SGBM) on one pair, one
// thread each, with peak memory.
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "parallax/eval/bench.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/evaluate.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/eval/json.hpp"

namespace parallax::cli {

namespace {

using nlohmann::json;
using namespace parallax::eval;
using namespace parallax::search;

struct BenchOptions {
  ConfigArgs cfg;
  std::string left, right;
  int iterations = 7;
  bool json = false;
};

// The processor's name as the kernel reports it ("model name" of /proc/cpuinfo), or "unknown":
// speed ratios hold per machine (AMD and Intel rank the peers differently).
std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) != 0) continue;
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) break;
    const std::size_t from = line.find_first_not_of(" \t", colon + 1);
    return from == std::string::npos ? "unknown" : line.substr(from);
  }
  return "unknown";
}

// The rows as a table on stdout under a line naming the pair size, the runs per method and the
// processor. The
// ratios: median to median against MODE_HH4 (the accuracy peer) and MODE_SGBM (the speed peer),
// and min to min against MODE_SGBM (less sensitive to other load on the machine).
void print_bench_text(const std::vector<BenchRow>& rows, const cv::Mat& l, int iterations) {
  std::printf("%dx%d pair, %d runs per method, one thread each unless the row says; cpu: %s\n", l.cols, l.rows,
              iterations, cpu_model().c_str());
  std::printf("%-44s %10s %8s %9s %10s %7s %8s %9s\n", "method", "median_ms", "min_ms", "peak_MiB", "extra_MiB",
              "vs_HH4", "vs_SGBM", "min_vs_SGBM");
  for (const auto& row : rows)
    std::printf("%-44s %10.1f %8.1f %9.1f %10.1f %7.2f %8.2f %9.2f\n", row.method.c_str(), row.median_ms, row.min_ms,
                row.peak_rss_mib, row.peak_extra_rss_mib, row.ratio_to_peer, row.ratio_to_sgbm, row.min_ratio_to_sgbm);
}

int run_bench(const BenchOptions& o, const Invocation&) {
  const config::PipelineConfig cfg = load_config_args(o.cfg);
  std::vector<std::string> notes;
  const cv::Mat left = load_grey_file(o.left, "left", notes);
  const cv::Mat right = load_grey_file(o.right, "right", notes);
  if (left.size() != right.size()) throw InputError(o.right + ": size differs from the left image " + o.left);
  const Roi roi = resolve_roi(roi_for(cfg), left.cols, left.rows);
  const cv::Mat l = crop_to_roi(left, roi).clone(), r = crop_to_roi(right, roi).clone();
  const auto rows = bench_pair(cfg, l, r, o.iterations);
  if (o.json)
    std::cout << json(rows).dump(2) << "\n";  // one object per method (parallax/eval/json.hpp)
  else
    print_bench_text(rows, l, o.iterations);
  return 0;
}

}  // namespace

Command add_bench(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  auto* bench = app.add_subcommand(
      "bench",
      "Time the func run against OpenCV StereoSGBM (HH4, SGBM) on one pair, one thread each, with peak memory");
  add_config_options(bench, o->cfg, true);
  bench->add_option("--left", o->left, "Left image")->required();
  bench->add_option("--right", o->right, "Right image")->required();
  bench->add_option("--iterations", o->iterations, "Runs per method (the median is reported)")
      ->capture_default_str()
      ->check(InRange(1, 1000));
  bench->add_flag("--json", o->json, "Print JSON");
  return bind_command(bench, o, run_bench);
}

}  // namespace parallax::cli
