// parallax report: CSV, JSON and a self-contained HTML report of a sweep.
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>

#include "commands.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/reports/report.hpp"
#include "parallax/search/sweep.hpp"

namespace parallax::cli {

namespace {

using namespace parallax::eval;
using namespace parallax::design;
using namespace parallax::search;
using namespace parallax::hls_flow;
using namespace parallax::reports;

struct ReportCommandOptions {
  std::string db, sweep, html, csv, frames_csv, json, dataset, frame;
  int details = 6;
};

int run_report(const ReportCommandOptions& o, const Invocation&) {
  if (o.html.empty() && o.csv.empty() && o.frames_csv.empty() && o.json.empty())
    throw InputError("report: nothing to write; give --html, --csv, --frames-csv or --json");
  ResultStore store(o.db, ResultStore::Access::read);
  const SweepSpec spec = choose_sweep(store, o.db, o.sweep);
  const std::string swept = store.sweep_dataset(spec.name);  // the folder the sweep ran on
  check_report_outputs(o.db, {o.dataset, swept},
                       {{"--html", o.html}, {"--csv", o.csv}, {"--frames-csv", o.frames_csv}, {"--json", o.json}});
  const auto rows = store.designs(spec.name);
  if (!o.csv.empty()) {
    std::ostringstream out;
    write_designs_csv(rows, out);
    write_text_file(o.csv, out.str());
  }
  if (!o.frames_csv.empty()) {
    std::ostringstream out;
    write_frames_csv(rows, out);
    write_text_file(o.frames_csv, out.str());
  }
  if (!o.json.empty()) write_text_file(o.json, report_json(rows));
  if (!o.html.empty()) {
    ReportOptions ro;
    ro.dataset = o.dataset.empty() ? images_dataset(swept) : o.dataset;
    ro.details = o.details;
    ro.peers = store.peers(spec.name);
    ro.seed_hash = seed_hash(spec);
    // The sections' figures and views, computed here: timing and resources on the sweep's device,
    // the design on one frame, one flight through the sweep's scenario.
    PointRequest views;
    views.device = spec.device;
    views.view_dataset = ro.dataset;
    views.view_frame = o.frame;
    views.view_scenario = spec.flight_scenario;
    views.flight_speed_mps = spec.flight_speed_mps;
    views.flight_size_px = spec.flight_size_px;
    const auto sections = report_sections(spec, rows, o.details);
    for (std::size_t i = 0; i < sections.size(); ++i) {
      const auto& row = sections[i];
      std::fprintf(stderr, "[%zu/%zu] %s: figures and views\n", i + 1, sections.size(), row.hash.c_str());
      DesignResult& d = ro.sections[row.hash];
      try {
        d = evaluate_point(config::parse_config(row.config_yaml, "design " + row.hash), views);
      } catch (const std::exception& e) {
        d.status = "error";
        d.reason = e.what();
      }
    }
    write_text_file(o.html, html_report(spec, rows, ro));
  }
  return 0;
}

}  // namespace

Command add_report(CLI::App& app) {
  auto o = std::make_shared<ReportCommandOptions>();
  auto* reportc = app.add_subcommand("report", "CSV, JSON and a self-contained HTML report of a sweep");
  reportc->add_option("--db", o->db, "Results store")->required();
  reportc->add_option("--sweep", o->sweep, "Sweep name (default: the only one in the store)");
  reportc->add_option("--html", o->html, "Write the HTML report (one file, viewable offline)")->check(OutputFile());
  reportc->add_option("--csv", o->csv, "Write one row per design (parameters and metrics)")->check(OutputFile());
  reportc->add_option("--frames-csv", o->frames_csv, "Write one row per design and frame")->check(OutputFile());
  reportc->add_option("--json", o->json, "Write the same content as JSON")->check(OutputFile());
  reportc->add_option("--dataset", o->dataset, "Dataset to render the front designs' images from (optional)");
  reportc->add_option("--frame", o->frame, "Frame of those images (default: the first with ground truth)");
  reportc->add_option("--details", o->details, "Front designs with a full section")
      ->capture_default_str()
      ->check(InRange(0, 1000));
  return bind_command(reportc, o, run_report);
}

}  // namespace parallax::cli
