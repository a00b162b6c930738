// parallax import-hls: read a Vitis HLS csynth.xml back (latency, II per loop, resources); with
// --config, compare it with the model, calibrate the configuration, and write a page.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/eval/simulate.hpp"
#include "parallax/hls_flow/hls_export.hpp"
#include "parallax/hls_flow/hls_report.hpp"
#include "parallax/hls_flow/json.hpp"
#include "parallax/reports/report.hpp"
#include "parallax/resources/model.hpp"

namespace parallax::cli {

namespace {

using nlohmann::json;
using namespace parallax::eval;
using namespace parallax::design;
using namespace parallax::search;
using namespace parallax::hls_flow;
using namespace parallax::reports;

struct ImportHlsOptions {
  std::string report, config, write, html;
  bool json = false;
};

// The report (its own form, parallax/hls_flow/json.hpp) with what calibration set and the model
// beside the synthesis, as one JSON object.
json import_json(const HlsReport& rep, const std::vector<std::string>& set,
                 const std::vector<ModelVsSynthesis>& comparison) {
  json j = rep;
  j["calibrated"] = set;
  j["comparison"] = comparison;
  return j;
}

// The same as text on stdout: the headline, the loops, the resources, what calibration set, and
// the model beside the synthesis with their ratio.
void print_import_text(const HlsReport& rep, const std::vector<std::string>& set,
                       const std::vector<ModelVsSynthesis>& comparison) {
  std::printf(
      "%s on %s (Vitis HLS %s): clock %.2f ns target, %.3f ns estimated; latency %lld-%lld cycles, interval %lld\n",
      rep.top.c_str(), rep.part.c_str(), rep.version.c_str(), rep.target_clock_ns, rep.estimated_clock_ns,
      (long long)rep.best_latency_cycles, (long long)rep.worst_latency_cycles, (long long)rep.interval_max_cycles);
  for (const auto& l : rep.loops)
    std::printf("  loop %-20s trip %lld  II %d  depth %d  latency %lld\n", l.name.c_str(), (long long)l.trip_count,
                l.pipeline_ii, l.pipeline_depth, (long long)l.latency_cycles);
  for (const auto& kv : rep.resources)
    std::printf("  %-9s %lld of %lld\n", kv.first.c_str(), (long long)kv.second,
                (long long)(rep.available.count(kv.first) ? rep.available.at(kv.first) : 0));
  for (const auto& s : set) std::printf("  calibrated %s\n", s.c_str());
  if (!comparison.empty()) {
    std::printf("\n%-28s %14s %14s %10s\n", "model vs synthesis", "model", "synthesis", "syn/model");
    for (const auto& c : comparison) {
      std::printf("%-28s %14.0f %14.0f", c.figure.c_str(), c.model, c.synthesis);
      if (c.model > 0 && c.synthesis >= 0)
        std::printf(" %10.2f", c.synthesis / c.model);
      else
        std::printf(" %10s", "-");
      std::printf("  %s\n", c.note.c_str());
    }
  }
}

int run_import_hls(const ImportHlsOptions& o, const Invocation&) {
  const HlsReport rep = read_csynth_xml(o.report);
  std::vector<std::string> set;
  std::vector<ModelVsSynthesis> comparison;
  sim::CycleReport model_cycle;  // the cycle model at the report's clock, for --html
  int w = 0, h = 0;
  config::PipelineConfig cfg;
  if (!o.config.empty()) {
    cfg = config::load_config(o.config);
    design_size(cfg, w, h);
    comparison = compare_with_model(cfg, rep, w, h, &model_cycle);
    set = calibrate_from_hls(cfg, rep);
  } else if (!o.write.empty()) {
    throw InputError("--write-config needs --config");
  }
  if (!o.html.empty() && o.config.empty()) throw InputError("--html needs --config");
  if (o.json)
    std::cout << import_json(rep, set, comparison).dump(2) << "\n";
  else
    print_import_text(rep, set, comparison);
  if (!o.html.empty()) {
    DesignSection s;
    s.title = cfg.name + ": model and synthesis (" + o.report + ")";
    s.config_yaml = config::to_yaml(cfg);
    s.config_file = cfg.name + "-calibrated.yaml";
    s.command = "parallax import-hls --report " + o.report + " --config " + o.config + " --html " + o.html;
    s.cycle = model_cycle;
    s.resources = res::estimate(res::design_inventory(cfg, w, h));
    s.device = res::find_device(device_for_part(rep.part));
    s.synthesis = comparison;
    write_text_file(o.html, standalone_page(s.title, design_section_html(s)));
  }
  if (!o.write.empty()) write_text_file(o.write, config::to_yaml(cfg));
  return 0;
}

}  // namespace

Command add_import_hls(CLI::App& app) {
  auto o = std::make_shared<ImportHlsOptions>();
  auto* importc = app.add_subcommand(
      "import-hls", "Read a Vitis HLS csynth.xml back: latency, II per loop, resources; calibrate a configuration");
  importc->add_option("--report", o->report, "csynth.xml of a synthesis run")->required();
  importc->add_option("--config", o->config, "Configuration to calibrate (ii_<stage>, latency_<stage> from the loops)");
  importc->add_option("--write-config", o->write, "Write the calibrated configuration here")->check(OutputFile());
  importc->add_flag("--json", o->json, "Print JSON");
  importc
      ->add_option("--html", o->html,
                   "With --config: write a page with the model's and the synthesis figures side by side")
      ->check(OutputFile());
  return bind_command(importc, o, run_import_hls);
}

}  // namespace parallax::cli
