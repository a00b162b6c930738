// parallax export-hls: a Vitis HLS project of a design (DATAFLOW top, C testbench with the
// simulator's golden output, run_hls.tcl, hls_config.cfg, Makefile), from a configuration or a
// design of a sweep's store.
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/hls/export.hpp"
#include "parallax/hls_flow/hls_export.hpp"
#include "parallax/hls_flow/json.hpp"
#include "parallax/search/sweep.hpp"

namespace parallax::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace parallax::eval;
using namespace parallax::search;
using namespace parallax::hls_flow;

struct ExportHlsOptions {
  ConfigArgs cfg;
  std::string db, design, out, part = "xczu3eg-sbva484-1-e", left, right;
  double clock = 0;
  bool json = false;
};

// The design --db and --design name: the one stored design whose hash starts with the prefix.
// `origin` is set to where it came from. Throws InputError naming the store otherwise.
config::PipelineConfig stored_design(const std::string& db, const std::string& prefix, std::string& origin) {
  if (!fs::exists(db)) throw InputError(db + ": results store not found");
  if (prefix.size() < 4) throw InputError("--design '" + prefix + "': give at least 4 hex digits of the hash");
  ResultStore store(db, ResultStore::Access::read);
  std::vector<ResultStore::Row> hits;
  for (auto& row : store.designs("", false))  // a design measured on several datasets is one design
    if (row.hash.rfind(prefix, 0) == 0 &&
        std::none_of(hits.begin(), hits.end(), [&](const ResultStore::Row& h) { return h.hash == row.hash; }))
      hits.push_back(std::move(row));
  if (hits.empty()) throw InputError(db + ": no design whose hash starts with '" + prefix + "' (see parallax pareto)");
  if (hits.size() > 1)
    throw InputError(db + ": " + std::to_string(hits.size()) + " designs start with '" + prefix +
                     "'; give more digits");
  if (hits[0].status == "invalid") throw InputError(db + ": design " + hits[0].hash + " is invalid: " + hits[0].reason);
  config::PipelineConfig cfg = config::parse_config(hits[0].config_yaml, db + " design " + hits[0].hash);
  origin = db + " design " + hits[0].hash;
  const auto errs = config::validate(cfg);
  if (!errs.empty()) throw InputError(origin + ": field '" + errs.front().field + "': " + errs.front().message);
  return cfg;
}

// The design to export, from --config (with --set) or from --db and --design; `origin` is set to
// where it came from. Throws InputError unless exactly one of the two sources is given.
config::PipelineConfig export_design(const ExportHlsOptions& o, std::string& origin) {
  if (o.cfg.path.empty() == o.db.empty())
    throw InputError("export-hls: give either --config CFG or --db FILE --design ID");
  if (!o.db.empty() && o.design.empty()) throw InputError("export-hls: --db needs --design ID");
  if (!o.cfg.path.empty() && !o.design.empty()) throw InputError("export-hls: --design belongs to --db");
  if (o.cfg.path.empty()) return stored_design(o.db, o.design, origin);
  config::PipelineConfig cfg = load_config_args(o.cfg);
  origin = o.cfg.path;
  for (const auto& s : o.cfg.sets) origin += " --set " + s;
  return cfg;
}

// What was written, as one JSON object: the export's own form (parallax/hls_flow/json.hpp: design,
// part, clock, FIFO depths, the predicted timing and resources) with the folder and its files.
json export_json(const ExportHlsOptions& o, const hlsx::ExportRequest& req,
                 const std::vector<hlsx::GeneratedFile>& files) {
  json j = req;
  j["out"] = o.out;
  j["files"] = json::array();
  for (const auto& f : files) j["files"].push_back(f.path);
  return j;
}

// What was written, as text on stdout, with the next step (make csim).
void print_export_text(const ExportHlsOptions& o, const config::PipelineConfig& cfg, const hlsx::ExportRequest& req,
                       const std::vector<hlsx::GeneratedFile>& files) {
  const auto& pr = req.prediction;
  std::printf("wrote %zu files to %s: Vitis HLS project of %s for %s at %g MHz\n", files.size(), o.out.c_str(),
              cfg.name.c_str(), req.part.c_str(), req.clock_mhz);
  std::printf("  FIFO depths:");
  for (const auto& f : req.fifos) std::printf(" %s=%lld", f.name.c_str(), (long long)f.depth);
  std::printf(
      "\n  predicted: FPGA latency %.2f ms (%lld cycles), %.1f fps; %lld BRAM_18K, %lld LUT, %lld FF, %lld DSP on %s "
      "(estimate: %s)\n",
      pr.fpga_latency_ms, (long long)pr.last_pixel_cycle, pr.fps, (long long)pr.bram18k, (long long)pr.lut,
      (long long)pr.ff, (long long)pr.dsp, pr.device.c_str(), cfg.estimate.c_str());
  std::printf("  next: cd %s && make csim   (g++ alone; bit-exact check against the simulator)\n", o.out.c_str());
}

int run_export_hls(const ExportHlsOptions& o, const Invocation&) {
  std::string origin;
  const config::PipelineConfig cfg = export_design(o, origin);
  try {
    hlsx::check_project_dir(o.out);  // before the simulation: fail fast
  } catch (const hlsx::ExportError& e) {
    throw InputError(e.what());
  }
  std::vector<std::string> notes;
  cv::Mat l, r;
  std::string pair_what;
  load_pair_or_pattern(cfg, o.left, o.right, notes, l, r, pair_what);
  print_notes(notes);
  ExportOptions eo;
  eo.part = o.part;
  eo.clock_mhz = o.clock;
  if (!o.json)
    std::fprintf(stderr, "parallax: simulating %s (FIFO sizing, timing, golden output)...\n", cfg.name.c_str());
  hlsx::ExportRequest req;
  std::vector<hlsx::GeneratedFile> files;
  try {
    req = prepare_export(cfg, l, r, origin, pair_what, eo);
    files = hlsx::generate_project(req);
    hlsx::write_project(files, o.out);
  } catch (const hlsx::ExportError& e) {
    throw InputError(e.what());
  }
  if (o.json)
    std::cout << export_json(o, req, files).dump(2) << "\n";
  else
    print_export_text(o, cfg, req, files);
  return 0;
}

}  // namespace

Command add_export_hls(CLI::App& app) {
  auto o = std::make_shared<ExportHlsOptions>();
  auto* exportc = app.add_subcommand(
      "export-hls",
      "Write a Vitis HLS project of a design: DATAFLOW top, C testbench with the simulator's golden output, "
      "run_hls.tcl, hls_config.cfg, and a Makefile whose `make csim` needs only g++");
  add_config_options(exportc, o->cfg, false);
  exportc->add_option("--db", o->db, "Results store of a sweep; with --design, export one of its designs");
  exportc->add_option("--design", o->design, "Design hash in --db (or a unique prefix of at least 4 hex digits)");
  exportc->add_option("--out", o->out, "Project folder (new, empty, or written by an earlier export)")->required();
  exportc->add_option("--part", o->part, "FPGA part of the synthesis run")->capture_default_str();
  exportc->add_option("--clock-mhz", o->clock, "Synthesis clock in MHz (default: the design's clock_mhz)")
      ->check(InRange(1.0, 2000.0));
  exportc->add_option("--left", o->left,
                      "Left image of the testbench, cropped to the design's ROI (default: a generated test pattern)");
  exportc->add_option("--right", o->right, "Right image of the testbench");
  exportc->add_flag("--json", o->json, "Print JSON");
  return bind_command(exportc, o, run_export_hls);
}

}  // namespace parallax::cli
