// parallax fit-resources: calibrate the resource model on published rows (a CSV in the columns of
// models/data/vitis_vision_points.csv): per row the prediction, the published value and the
// error, fitted, leave-one-out and leave-one-family-out; rows the function library cannot
// describe are listed with the reason. Optionally writes the coefficients file.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "parallax/design/json.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/reports/resource_page.hpp"
#include "parallax/resources/fit.hpp"
#include "parallax/resources/functions.hpp"
#include "parallax/resources/model.hpp"
#include "parallax/resources/points_csv.hpp"

namespace parallax::cli {

namespace {

using nlohmann::json;
using namespace parallax::eval;
using namespace parallax::design;
using namespace parallax::search;
using namespace parallax::reports;

struct FitOptions {
  std::string points = "models/data/vitis_vision_points.csv", designs = "models/data/published_points.yaml";
  std::string functions, root = ".", write, html, estimate = "csynth", explain;
  bool json = false;
};

// Targets of issue 42 (docs/resources.md, section 6), leave-one-family-out over the kept rows.
constexpr double kBramExactTarget = 0.90, kDspExactTarget = 0.70;
constexpr double kLofoMedianTargetPct = 20.0, kLofoP90TargetPct = 45.0;

json usage_json(const res::Usage& u) {
  return u;  // parallax/design/json.hpp
}
json stats_json(const res::ErrorStats& s) {
  return {{"rows", s.rows},
          {"exact", s.exact},
          {"exact_share", s.exact_share()},
          {"median_abs_pct", s.median_pct},
          {"p90_abs_pct", s.p90_pct},
          {"mean_abs_pct", s.mean_pct}};
}
json published_value(int64_t v) {
  return v < 0 ? json(nullptr) : json(v);
}

json fit_json(const res::FitResult& fr, res::Flavour flavour) {
  json j;
  j["estimate"] = res::flavour_name(flavour);
  j["fitted_rows"] = fr.fitted_rows;
  j["excluded_rows"] = fr.excluded_rows;
  json coef;
  for (int k = 0; k < res::kFeatureCount; ++k)
    coef[res::feature_name(k)] = {{"lut", fr.coefficients.lut[k]}, {"ff", fr.coefficients.ff[k]}};
  j["coefficients"] = coef;
  j["dsp_binding"] = {{"min_bits_by_variable", fr.coefficients.dsp_min_bits_var},
                      {"min_bits_by_constant", fr.coefficients.dsp_min_bits_const},
                      {"slice_bits", {fr.coefficients.dsp_a_bits, fr.coefficients.dsp_b_bits}}};
  for (int r = 0; r < res::kResourceCount; ++r) {
    const res::ResourceStats& s = fr.stats[r];
    j["summary"][res::resource_name(r)] = {{"fitted", stats_json(s.fitted)},
                                           {"leave_one_out", stats_json(s.loo)},
                                           {"leave_one_family_out", stats_json(s.lofo)},
                                           {"leave_one_group_out", stats_json(s.logo)}};
  }
  j["rows"] = json::array();
  for (const auto& row : fr.rows) {
    json o = {{"kernel", row.kernel},       {"design", row.design},
              {"source", row.source},       {"function", row.function},
              {"family", row.family},       {"group", row.group},
              {"described", row.described}, {"validation_only", row.validation_only}};
    if (!row.described) o["not_described"] = row.not_described;
    if (row.excluded != 0) {
      json left_out = json::array();
      for (int r = 0; r < res::kResourceCount; ++r)
        if (row.excluded >> r & 1u) left_out.push_back(res::resource_name(r));
      o["excluded"] = {{"resources", left_out}, {"evidence", row.excluded_why}};
    }
    for (int r = 0; r < res::kResourceCount; ++r) {
      const char* n = res::resource_name(r);
      o[std::string("published_") + n] = published_value(res::pick(row.published, r));
      o[n] = row.described ? json(res::pick(row.fitted, r)) : json(nullptr);
    }
    o["published_uram"] = published_value(row.published.uram);
    if (row.described) {
      const res::Features f = res::features(row.inventory, fr.coefficients);
      json feats;
      for (int k = 0; k < res::kFeatureCount; ++k)
        feats[res::feature_name(k)] = {{"lut", f.lut_f[k]}, {"ff", f.ff_f[k]}};
      o["features"] = feats;
      o["memory_luts"] = f.lut_base;
      o["uram"] = row.fitted.uram;
      o["leave_one_out"] = usage_json(row.loo);
      o["leave_one_family_out"] = usage_json(row.lofo);
    }
    j["rows"].push_back(o);
  }
  return j;
}

std::string err_pct(int64_t pred, int64_t pub) {
  if (pub <= 0) return pub == pred ? "exact" : "";
  char b[32];
  std::snprintf(b, sizeof b, "%+.0f%%", 100.0 * double(pred - pub) / double(pub));
  return b;
}

void print_rows(const res::FitResult& fr) {
  std::printf("%-34s %-16s | %5s %5s | %4s %4s | %6s %6s %6s %6s | %6s %6s %6s %6s\n", "kernel (design row)",
              "function", "BRAM", "pred", "DSP", "pred", "LUT", "fit", "lofo", "err", "FF", "fit", "lofo", "err");
  for (const auto& row : fr.rows) {
    std::string name = row.kernel.substr(0, 34);
    if (!row.described) {
      std::printf("%-34s not described: %s (%s)\n", name.c_str(), row.not_described.c_str(), row.source.c_str());
      continue;
    }
    const auto& p = row.published;
    std::printf("%-34s %-16s | %5lld %5lld | %4lld %4lld | %6lld %6lld %6lld %6s | %6lld %6lld %6lld %6s%s\n",
                name.c_str(), row.function.substr(0, 16).c_str(), (long long)p.bram18k, (long long)row.fitted.bram18k,
                (long long)p.dsp, (long long)row.fitted.dsp, (long long)p.lut, (long long)row.fitted.lut,
                (long long)row.lofo.lut, err_pct(row.lofo.lut, p.lut).c_str(), (long long)p.ff,
                (long long)row.fitted.ff, (long long)row.lofo.ff, err_pct(row.lofo.ff, p.ff).c_str(),
                row.validation_only ? "  (validation: not fitted on)" : "");
  }
  bool header = false;
  for (const auto& row : fr.rows) {
    if (row.excluded == 0) continue;
    if (!header) std::printf("\nleft out (the published figure contradicts its own source):\n");
    header = true;
    std::string which;
    for (int r = 0; r < res::kResourceCount; ++r)
      if (row.excluded >> r & 1u) which += std::string(which.empty() ? "" : ",") + res::resource_name(r);
    std::printf("  %s [%s] (%s): %s\n", row.kernel.c_str(), which.c_str(), row.source.c_str(),
                row.excluded_why.c_str());
  }
}

void print_summary(const res::FitResult& fr) {
  std::printf("\n%-8s %-22s %6s %8s %9s %9s %9s\n", "resource", "predicted", "rows", "exact", "median", "p90", "mean");
  for (int r = 0; r < res::kResourceCount; ++r) {
    const res::ResourceStats& s = fr.stats[r];
    const std::pair<const char*, const res::ErrorStats*> kinds[] = {{"fitted on all", &s.fitted},
                                                                    {"leave-one-out", &s.loo},
                                                                    {"leave-one-family-out", &s.lofo},
                                                                    {"leave-one-group-out", &s.logo}};
    for (const auto& [label, st] : kinds)
      std::printf("%-8s %-22s %6d %7.1f%% %8.1f%% %8.1f%% %8.1f%%\n", res::resource_name(r), label, st->rows,
                  100.0 * st->exact_share(), st->median_pct, st->p90_pct, st->mean_pct);
  }
  const res::ResourceStats* s = fr.stats;
  auto verdict = [](bool ok) { return ok ? "met" : "NOT met"; };
  std::printf(
      "\ntargets (leave-one-family-out): BRAM_18K exact >= 90%%: %.1f%% %s; DSP exact >= 70%%: %.1f%% %s\n",
      100.0 * s[res::kResBram].lofo.exact_share(), verdict(s[res::kResBram].lofo.exact_share() >= kBramExactTarget),
      100.0 * s[res::kResDsp].lofo.exact_share(), verdict(s[res::kResDsp].lofo.exact_share() >= kDspExactTarget));
  for (int r : {int(res::kResLut), int(res::kResFf)})
    std::printf("         %s median <= 20%%: %.1f%% %s; p90 <= 45%%: %.1f%% %s\n", res::resource_name(r),
                s[r].lofo.median_pct, verdict(s[r].lofo.median_pct <= kLofoMedianTargetPct), s[r].lofo.p90_pct,
                verdict(s[r].lofo.p90_pct <= kLofoP90TargetPct));
}

void print_fit_text(const res::FitResult& fr, const std::string& points_path, res::Flavour flavour) {
  const res::Coefficients& k = fr.coefficients;
  std::printf("estimate: %s (the published rows are HLS C-synthesis estimates)\n", res::flavour_name(flavour));
  std::printf("fitted on %d of %zu rows (%s); %d left out for contradicting their source\n", fr.fitted_rows,
              fr.rows.size(), points_path.c_str(), fr.excluded_rows);
  std::printf(
      "DSP binding learned: multiplier by a variable on DSP48 when its narrower operand >= %d bits, by a "
      "constant when >= %d bits (%s)\n",
      k.dsp_min_bits_var, k.dsp_min_bits_const, k.dsp_min_bits_const >= 99 ? "never" : "learned");
  std::printf("%-10s", "per unit");
  for (int f = 0; f < res::kFeatureCount; ++f) std::printf(" %9s", res::feature_name(f));
  std::printf("\n%-10s", "LUT");
  for (int f = 0; f < res::kFeatureCount; ++f) std::printf(" %9.3f", k.lut[f]);
  std::printf("\n%-10s", "FF");
  for (int f = 0; f < res::kFeatureCount; ++f) std::printf(" %9.3f", k.ff[f]);
  std::printf("\n\n");
  print_rows(fr);
  print_summary(fr);
}

// Per stage, where LUT and FF come from (csynth): operators, muxes, memories in LUTs, declared
// registers and the fitted Vitis overheads.
void print_breakdown(const res::Estimate& e) {
  std::printf("\n  %-16s %s | %s\n", "stage", "LUT: operators    muxes memories overhead    total",
              "FF: registers overhead    total");
  res::Breakdown lut, ff;
  auto line = [](const std::string& name, const res::Breakdown& l, const res::Breakdown& f) {
    std::printf("  %-16s %15.0f %8.0f %8.0f %8.0f %8.0f | %13.0f %8.0f %8.0f\n", name.substr(0, 16).c_str(),
                l.operators, l.muxes, l.memories, l.overhead, l.total(), f.registers + f.memories + f.operators,
                f.overhead, f.total());
  };
  for (const auto& s : e.stages) {
    line(s.stage, s.lut, s.ff);
    lut += s.lut;
    ff += s.ff;
  }
  line("total", lut, ff);
}

// The priced items of the rows whose kernel or design contains `text` (csynth, the fitted
// coefficients), by stage, largest LUT first within a stage.
int print_explain(const res::FitResult& fr, const std::string& text) {
  int shown = 0;
  for (const auto& row : fr.rows) {
    if (!row.described || (row.kernel.find(text) == std::string::npos && row.design.find(text) == std::string::npos))
      continue;
    ++shown;
    std::vector<res::PricedItem> items = res::priced_items(row.inventory, fr.coefficients);
    // By stage in pipeline order (a strict weak order: the stage's index, then LUT descending).
    const std::vector<std::string>& stages = row.inventory.stages;
    auto stage_index = [&](const std::string& s) {
      return std::find(stages.begin(), stages.end(), s) - stages.begin();
    };
    std::stable_sort(items.begin(), items.end(), [&](const res::PricedItem& a, const res::PricedItem& b) {
      const auto sa = stage_index(a.stage), sb = stage_index(b.stage);
      return sa != sb ? sa < sb : a.lut > b.lut;
    });
    std::printf("\n%s (%s): published LUT %lld FF %lld DSP %lld BRAM_18K %lld; predicted %lld %lld %lld %lld\n",
                row.kernel.c_str(), row.design.c_str(), (long long)row.published.lut, (long long)row.published.ff,
                (long long)row.published.dsp, (long long)row.published.bram18k, (long long)row.fitted.lut,
                (long long)row.fitted.ff, (long long)row.fitted.dsp, (long long)row.fitted.bram18k);
    std::printf("  %-16s %-30s %-32s %8s %8s %4s %5s\n", "stage", "item", "what", "LUT", "FF", "DSP", "BRAM");
    for (const auto& it : items)
      std::printf("  %-16s %-30s %-32s %8.0f %8.0f %4lld %5lld\n", it.stage.substr(0, 16).c_str(),
                  it.name.substr(0, 30).c_str(), it.what.substr(0, 32).c_str(), it.lut, it.ff, (long long)it.dsp,
                  (long long)it.bram18k);
    print_breakdown(res::estimate(row.inventory, fr.coefficients, res::Flavour::csynth));
  }
  return shown;
}

// Published CSV rows plus this project's designs (validation only).
std::vector<res::FitRow> load_rows(const FitOptions& o) {
  std::vector<res::FitRow> rows;
  try {
    const std::vector<res::FunctionDescription> custom =
        o.functions.empty() ? std::vector<res::FunctionDescription>() : res::load_functions(o.functions);
    const auto& fns = o.functions.empty() ? res::default_functions() : custom;
    rows = res::describe_rows(res::load_points_csv(o.points), fns, o.points);
    res::apply_exclusions(rows, res::default_exclusions());
    if (!o.designs.empty())
      for (auto& r : res::load_design_points(o.designs, o.root)) rows.push_back(std::move(r));
  } catch (const config::ConfigError& e) {
    throw InputError(e.what());
  }
  return rows;
}

int run_fit_resources(const FitOptions& o, const Invocation&) {
  res::Flavour flavour = res::Flavour::csynth;
  try {
    flavour = res::parse_flavour(o.estimate);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("--estimate: ") + e.what());
  }
  std::vector<res::FitRow> rows = load_rows(o);
  std::fprintf(stderr, "parallax: fitting %zu rows (leave-one-out and leave-one-family-out refits)...\n", rows.size());
  res::FitResult fr = res::fit(std::move(rows), res::default_coefficients());
  if (flavour == res::Flavour::routed)
    for (auto& row : fr.rows)
      if (row.described) {
        row.fitted = res::estimate(row.inventory, fr.coefficients, flavour).total;
      }
  if (!o.explain.empty()) {
    if (print_explain(fr, o.explain) == 0)
      throw InputError("--explain: no described row's kernel or design contains '" + o.explain + "'");
    return 0;
  }
  if (o.json)
    std::cout << fit_json(fr, flavour).dump(2) << "\n";
  else
    print_fit_text(fr, o.points, flavour);
  if (!o.html.empty()) {
    std::ofstream page(o.html);
    if (!(page << resource_model_page(fr, flavour, o.points))) throw InputError(o.html + ": cannot write");
    std::fprintf(stderr, "parallax: wrote %s\n", o.html.c_str());
  }
  if (!o.write.empty()) {
    std::ofstream out(o.write);
    if (!out) throw InputError(o.write + ": cannot write");
    out << res::coefficients_yaml(fr.coefficients);
    std::fprintf(stderr, "parallax: wrote %s (rebuild to use it)\n", o.write.c_str());
  }
  return 0;
}

}  // namespace

Command add_fit_resources(CLI::App& app) {
  auto o = std::make_shared<FitOptions>();
  auto* fitc = app.add_subcommand("fit-resources",
                                  "Calibrate the resource model on published rows (Ceres): per row predicted against "
                                  "published, leave-one-out and leave-one-family-out errors");
  fitc->add_option("--points", o->points, "Published rows, CSV in the columns of models/data/vitis_vision_points.csv")
      ->capture_default_str();
  fitc->add_option("--designs", o->designs,
                   "This project's published designs (YAML), predicted as validation; empty: none")
      ->capture_default_str();
  fitc->add_option("--functions", o->functions,
                   "A directory of function descriptions (*.yaml) instead of the compiled-in models/data/functions");
  fitc->add_option("--root", o->root, "Repository root the designs' config paths are relative to")
      ->capture_default_str();
  fitc->add_option("--estimate", o->estimate, "csynth (like the published rows) or routed (x documented ratios)")
      ->capture_default_str();
  fitc->add_option("--write", o->write,
                   "Write the fitted coefficients here (e.g. models/data/resource_model.yaml; rebuild to use them)")
      ->check(OutputFile());
  fitc->add_option("--html", o->html, "Write a page of predicted against published (SVG scatter per resource)")
      ->check(OutputFile());
  fitc->add_flag("--json", o->json, "Print JSON: the coefficients, the summary and a list of rows");
  fitc->add_option("--explain", o->explain,
                   "Print the priced items (LUT, FF, DSP, BRAM_18K per operator, mux, memory, register and "
                   "overhead) of the rows whose kernel or design contains this text, instead of the table");
  return bind_command(fitc, o, run_fit_resources);
}

}  // namespace parallax::cli
