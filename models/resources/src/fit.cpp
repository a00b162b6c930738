// Fitting the resource model (fit.hpp) with Ceres.
#include "parallax/resources/fit.hpp"

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include <ceres/ceres.h>
#include "parallax/config/config.hpp"
#include <yaml-cpp/yaml.h>

namespace parallax::res {

namespace {

int64_t need_int(const YAML::Node& n, const std::string& key, const std::string& where) {
  if (!n[key]) throw config::ConfigError(where + ": missing field '" + key + "'");
  try {
    return n[key].as<int64_t>();
  } catch (const YAML::Exception&) {
    throw config::ConfigError(where + ": field '" + key + "' is not an integer");
  }
}

}  // namespace

std::vector<PublishedPoint> load_points(const std::string& path, const std::string& root) {
  YAML::Node doc;
  try {
    doc = YAML::Load(config::read_text_file(path, "points file"));
  } catch (const YAML::Exception& e) {
    throw config::ConfigError(path + ": not valid YAML: " + e.what());
  }
  if (!doc["points"] || !doc["points"].IsSequence()) throw config::ConfigError(path + ": missing list 'points'");
  std::vector<PublishedPoint> out;
  for (const auto& n : doc["points"]) {
    PublishedPoint pt;
    pt.name = n["name"] ? n["name"].as<std::string>() : "";
    const std::string where = path + ": point '" + pt.name + "'";
    if (pt.name.empty()) throw config::ConfigError(path + ": a point without 'name'");
    pt.source = n["source"] ? n["source"].as<std::string>() : "";
    const YAML::Node d = n["design"];
    if (!d) throw config::ConfigError(where + ": missing 'design'");
    const int w = int(need_int(d, "width_px", where + ".design"));
    const int h = int(need_int(d, "height_px", where + ".design"));
    if (d["config"]) {
      const std::string cfg_path = (std::filesystem::path(root) / d["config"].as<std::string>()).string();
      pt.inventory = design_inventory(config::load_config(cfg_path), w, h);
    } else if (d["stage"] && d["stage"].as<std::string>() == "median") {
      pt.inventory = median_inventory(w, h, int(need_int(d, "k", where + ".design")),
                                      int(need_int(d, "value_bits", where + ".design")));
    } else if (d["stage"] && d["stage"].as<std::string>() == "rectify") {
      const std::string mode = d["mode"] ? d["mode"].as<std::string>() : "";
      if (mode != "bilinear" && mode != "nearest")
        throw config::ConfigError(where + ".design: field 'mode' must be bilinear or nearest");
      pt.inventory = rectify_inventory(w, h, mode == "bilinear" ? kern::kRectifyBilinear : kern::kRectifyNearest,
                                       int(need_int(d, "frac_bits", where + ".design")),
                                       int(need_int(d, "buffer_rows", where + ".design")));
    } else {
      throw config::ConfigError(where + ".design: needs 'config' or 'stage: median|rectify'");
    }
    const YAML::Node p = n["published"];
    if (!p) throw config::ConfigError(where + ": missing 'published'");
    pt.published.bram18k = need_int(p, "bram18k", where + ".published");
    pt.published.dsp = need_int(p, "dsp", where + ".published");
    pt.published.ff = need_int(p, "ff", where + ".published");
    pt.published.lut = need_int(p, "lut", where + ".published");
    out.push_back(std::move(pt));
  }
  return out;
}

namespace {

struct LutResidual {
  double op_luts, memory_luts, stages, memories, published;
  template <class T>
  bool operator()(const T* const x, T* r) const {
    const T pred = x[0] * op_luts + T(memory_luts) + x[1] * stages + x[2] * memories;
    r[0] = (pred - T(published)) / T(published);
    return true;
  }
};
struct FfResidual {
  double register_bits, op_bits, stages, published;
  template <class T>
  bool operator()(const T* const y, T* r) const {
    const T pred = T(register_bits) + y[0] * op_bits + y[1] * stages;
    r[0] = (pred - T(published)) / T(published);
    return true;
  }
};

// Fits on the points whose index != skip (skip < 0: all).
Coefficients fit_on(const std::vector<PublishedPoint>& pts, const Coefficients& start, int skip) {
  double x[3] = {start.lut_scale, start.lut_per_stage, start.lut_per_memory};
  double y[2] = {start.ff_per_op_bit, start.ff_per_stage};
  ceres::Problem lut, ff;
  for (int i = 0; i < int(pts.size()); ++i) {
    if (i == skip) continue;
    const Features f = features(pts[std::size_t(i)].inventory, start);
    lut.AddResidualBlock(
        new ceres::AutoDiffCostFunction<LutResidual, 1, 3>(
            new LutResidual{f.op_luts, f.memory_luts, f.stages, f.memories, double(pts[std::size_t(i)].published.lut)}),
        new ceres::HuberLoss(0.1), x);
    ff.AddResidualBlock(new ceres::AutoDiffCostFunction<FfResidual, 1, 2>(new FfResidual{
                            f.register_bits, f.op_bits, f.stages, double(pts[std::size_t(i)].published.ff)}),
                        new ceres::HuberLoss(0.1), y);
  }
  for (int k = 0; k < 3; ++k) lut.SetParameterLowerBound(x, k, 0.0);
  for (int k = 0; k < 2; ++k) ff.SetParameterLowerBound(y, k, 0.0);
  ceres::Solver::Options opt;
  opt.max_num_iterations = 200;
  opt.logging_type = ceres::SILENT;
  ceres::Solver::Summary sum;
  ceres::Solve(opt, &lut, &sum);
  ceres::Solve(opt, &ff, &sum);
  Coefficients c = start;
  c.lut_scale = x[0];
  c.lut_per_stage = x[1];
  c.lut_per_memory = x[2];
  c.ff_per_op_bit = y[0];
  c.ff_per_stage = y[1];
  return c;
}

double pct(int64_t model, int64_t published) {
  return published > 0 ? 100.0 * std::fabs(double(model - published)) / double(published) : 0.0;
}

}  // namespace

FitResult fit(const std::vector<PublishedPoint>& pts, const Coefficients& start) {
  if (pts.size() < 2) throw std::runtime_error("fit-resources: need at least two published points");
  FitResult r;
  r.coefficients = fit_on(pts, start, -1);
  std::string names;
  for (const auto& p : pts) names += (names.empty() ? "" : ", ") + p.name;
  r.coefficients.fitted_on = "published points " + names + " (models/data/published_points.yaml)";
  for (int i = 0; i < int(pts.size()); ++i) {
    FitRow row;
    row.name = pts[std::size_t(i)].name;
    row.published = pts[std::size_t(i)].published;
    row.fitted = estimate(pts[std::size_t(i)].inventory, r.coefficients).total;
    row.loo = estimate(pts[std::size_t(i)].inventory, fit_on(pts, start, i)).total;
    const double el = pct(row.loo.lut, row.published.lut), ef = pct(row.loo.ff, row.published.ff);
    r.lut_loo_mean_pct += el / double(pts.size());
    r.ff_loo_mean_pct += ef / double(pts.size());
    r.lut_loo_max_pct = std::max(r.lut_loo_max_pct, el);
    r.ff_loo_max_pct = std::max(r.ff_loo_max_pct, ef);
    r.rows.push_back(row);
  }
  return r;
}

}  // namespace parallax::res
