// parallax fit-resources: fit the resource model's LUT/FF coefficients to published designs
// (Ceres), with leave-one-out errors; optionally write the coefficients file.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/resources/fit.hpp"
#include "parallax/resources/model.hpp"

namespace parallax::cli {

namespace {

using nlohmann::json;
using namespace parallax::explore;

struct FitOptions {
  std::string points = "models/data/published_points.yaml", root = ".", write;
  bool json = false;
};

// The fitted coefficients, leave-one-out errors and per-point figures as one JSON object.
json fit_json(const res::FitResult& fr) {
  const res::Coefficients& k = fr.coefficients;
  json j;
  j["coefficients"] = {{"lut_scale", k.lut_scale},
                       {"lut_per_stage", k.lut_per_stage},
                       {"lut_per_memory", k.lut_per_memory},
                       {"ff_per_op_bit", k.ff_per_op_bit},
                       {"ff_per_stage", k.ff_per_stage}};
  j["lut_loo_mean_pct"] = fr.lut_loo_mean_pct;
  j["lut_loo_max_pct"] = fr.lut_loo_max_pct;
  j["ff_loo_mean_pct"] = fr.ff_loo_mean_pct;
  j["ff_loo_max_pct"] = fr.ff_loo_max_pct;
  j["points"] = json::array();
  for (const auto& row : fr.rows)
    j["points"].push_back(
        {{"name", row.name},
         {"published",
          {{"bram18k", row.published.bram18k},
           {"lut", row.published.lut},
           {"ff", row.published.ff},
           {"dsp", row.published.dsp}}},
         {"fitted",
          {{"bram18k", row.fitted.bram18k}, {"lut", row.fitted.lut}, {"ff", row.fitted.ff}, {"dsp", row.fitted.dsp}}},
         {"leave_one_out", {{"lut", row.loo.lut}, {"ff", row.loo.ff}}}});
  return j;
}

// The same as text on stdout: the fitted formulas, one row per point, the leave-one-out errors.
void print_fit_text(const res::FitResult& fr, std::size_t point_count, const std::string& points_path) {
  const res::Coefficients& k = fr.coefficients;
  std::printf("fitted on %zu published points (%s)\n", point_count, points_path.c_str());
  std::printf("  lut = %.4f x operator LUTs + memory LUTs + %.1f x stages + %.2f x memories\n", k.lut_scale,
              k.lut_per_stage, k.lut_per_memory);
  std::printf("  ff  = register bits + %.4f x operator bits + %.1f x stages\n\n", k.ff_per_op_bit, k.ff_per_stage);
  std::printf("%-26s %8s %8s %8s | %7s %7s %7s %7s | %7s %7s %7s %7s\n", "point", "BRAM pub", "model", "", "LUT pub",
              "fit", "loo", "loo %", "FF pub", "fit", "loo", "loo %");
  for (const auto& row : fr.rows) {
    auto pct = [](int64_t m, int64_t p) { return p > 0 ? 100.0 * double(m - p) / double(p) : 0.0; };
    std::printf("%-26s %8lld %8lld %8s | %7lld %7lld %7lld %+6.1f%% | %7lld %7lld %7lld %+6.1f%%\n", row.name.c_str(),
                (long long)row.published.bram18k, (long long)row.fitted.bram18k,
                row.published.bram18k == row.fitted.bram18k ? "exact" : "", (long long)row.published.lut,
                (long long)row.fitted.lut, (long long)row.loo.lut, pct(row.loo.lut, row.published.lut),
                (long long)row.published.ff, (long long)row.fitted.ff, (long long)row.loo.ff,
                pct(row.loo.ff, row.published.ff));
  }
  std::printf("\nleave-one-out |error|: LUT mean %.1f%% max %.1f%%; FF mean %.1f%% max %.1f%%\n", fr.lut_loo_mean_pct,
              fr.lut_loo_max_pct, fr.ff_loo_mean_pct, fr.ff_loo_max_pct);
}

int run_fit_resources(const FitOptions& o, const Invocation&) {
  std::vector<res::PublishedPoint> points;
  try {
    points = res::load_points(o.points, o.root);
  } catch (const config::ConfigError& e) {
    throw InputError(e.what());
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());
  }
  const res::FitResult fr = res::fit(points, res::default_coefficients());
  if (o.json)
    std::cout << fit_json(fr).dump(2) << "\n";
  else
    print_fit_text(fr, points.size(), o.points);
  if (!o.write.empty()) {
    std::ofstream out(o.write);
    if (!out) throw InputError(o.write + ": cannot write");
    out << "# Coefficients of the resource and power model (models/resources, docs/resources.md).\n"
           "# Written by `parallax fit-resources --write`; compiled into parallax (rebuild after editing).\n"
        << res::coefficients_yaml(fr.coefficients);
    std::fprintf(stderr, "parallax: wrote %s (rebuild to use it)\n", o.write.c_str());
  }
  return 0;
}

}  // namespace

Command add_fit_resources(CLI::App& app) {
  auto o = std::make_shared<FitOptions>();
  auto* fitc = app.add_subcommand(
      "fit-resources",
      "Fit the resource model's LUT/FF coefficients to published designs (Ceres), with leave-one-out errors");
  fitc->add_option("--points", o->points, "Published points (YAML)")->capture_default_str();
  fitc->add_option("--root", o->root, "Repository root the points' config paths are relative to")
      ->capture_default_str();
  fitc->add_option("--write", o->write,
                   "Write the coefficients with the fitted section here (e.g. models/data/resource_model.yaml)")
      ->check(OutputFile());
  fitc->add_flag("--json", o->json, "Print JSON");
  return bind_command(fitc, o, run_fit_resources);
}

}  // namespace parallax::cli
