// Calibrating the resource model (fit.hpp): DSP thresholds by search, LUT/FF with Ceres.
#include "parallax/resources/fit.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>

#include <ceres/ceres.h>
#include <yaml-cpp/yaml.h>

#include "parallax/config/config.hpp"

namespace parallax::res {

const char* resource_name(int r) {
  static const char* const n[kResourceCount] = {"bram18k", "dsp", "ff", "lut"};
  return r >= 0 && r < kResourceCount ? n[r] : "unknown";
}
int64_t pick(const Usage& u, int r) {
  return r == kResBram ? u.bram18k : r == kResDsp ? u.dsp : r == kResFf ? u.ff : u.lut;
}
int64_t pick(const PublishedUsage& u, int r) {
  return r == kResBram ? u.bram18k : r == kResDsp ? u.dsp : r == kResFf ? u.ff : u.lut;
}

std::vector<FitRow> describe_rows(const std::vector<CsvPoint>& points, const std::vector<FunctionDescription>& fns,
                                  const std::string& file) {
  std::vector<FitRow> out;
  for (const auto& p : points) {
    FitRow row;
    row.kernel = p.kernel;
    row.design = p.design;
    row.source = file + ":" + std::to_string(p.line);
    row.published = p.published;
    const FunctionDescription* fn = find_function(fns, p.kernel);
    if (!fn) {
      row.not_described = "no function description matches kernel '" + p.kernel + "'";
    } else {
      row.function = fn->function;
      row.family = fn->family;
      row.group = fn->group;
      try {
        row.inventory = instantiate(*fn, p.vars);
        row.described = true;
      } catch (const NotDescribable& e) {
        row.not_described = e.what();
      }
    }
    out.push_back(std::move(row));
  }
  return out;
}

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

namespace data {
extern const char* const excluded_points_yaml;
}

std::vector<Exclusion> parse_exclusions(const std::string& text, const std::string& file) {
  YAML::Node doc;
  try {
    doc = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw config::ConfigError(file + ": not valid YAML: " + e.what());
  }
  if (!doc["rows"] || !doc["rows"].IsSequence()) throw config::ConfigError(file + ": missing list 'rows'");
  std::vector<Exclusion> out;
  int i = 0;
  for (const auto& n : doc["rows"]) {
    const std::string where = file + ": rows[" + std::to_string(i++) + "]";
    Exclusion e;
    for (const char* key : {"kernel", "design", "evidence"})
      if (!n[key] || !n[key].IsScalar()) throw config::ConfigError(where + ": missing field '" + key + "'");
    e.kernel = n["kernel"].Scalar();
    e.design = n["design"].Scalar();
    e.evidence = n["evidence"].Scalar();
    if (!n["resources"] || !n["resources"].IsSequence() || n["resources"].size() == 0)
      throw config::ConfigError(where + ": missing list 'resources'");
    for (const auto& r : n["resources"]) {
      int k = 0;
      while (k < kResourceCount && r.Scalar() != resource_name(k)) ++k;
      if (k == kResourceCount)
        throw config::ConfigError(where + ": resources: '" + r.Scalar() + "' is not bram18k, dsp, ff or lut");
      e.resources |= 1u << k;
    }
    out.push_back(std::move(e));
  }
  return out;
}

const std::vector<Exclusion>& default_exclusions() {
  static const std::vector<Exclusion> e =
      parse_exclusions(data::excluded_points_yaml, "models/data/excluded_points.yaml");
  return e;
}

int apply_exclusions(std::vector<FitRow>& rows, const std::vector<Exclusion>& exclusions) {
  int marked = 0;
  for (auto& row : rows)
    for (const auto& e : exclusions)
      if (row.kernel == e.kernel && row.design == e.design) {
        marked += row.excluded == 0;
        row.excluded |= e.resources;
        row.excluded_why += (row.excluded_why.empty() ? "" : "\n") + e.evidence;
      }
  return marked;
}

std::vector<FitRow> load_design_points(const std::string& path, const std::string& root) {
  YAML::Node doc;
  try {
    doc = YAML::Load(config::read_text_file(path, "points file"));
  } catch (const YAML::Exception& e) {
    throw config::ConfigError(path + ": not valid YAML: " + e.what());
  }
  if (!doc["points"] || !doc["points"].IsSequence()) throw config::ConfigError(path + ": missing list 'points'");
  std::vector<FitRow> out;
  for (const auto& n : doc["points"]) {
    FitRow row;
    row.kernel = n["name"] ? n["name"].as<std::string>() : "";
    if (row.kernel.empty()) throw config::ConfigError(path + ": a point without 'name'");
    const std::string where = path + ": point '" + row.kernel + "'";
    row.design = n["source"] ? n["source"].as<std::string>() : "";
    row.function = row.family = row.kernel;
    row.group = "design";
    row.source = path;
    row.validation_only = true;
    const YAML::Node d = n["design"];
    if (!d || !d["config"]) throw config::ConfigError(where + ": missing 'design.config'");
    const int w = int(need_int(d, "width_px", where + ".design"));
    const int h = int(need_int(d, "height_px", where + ".design"));
    const std::string cfg_path = (std::filesystem::path(root) / d["config"].as<std::string>()).string();
    row.inventory = design_inventory(config::load_config(cfg_path), w, h);
    row.described = true;
    const YAML::Node p = n["published"];
    if (!p) throw config::ConfigError(where + ": missing 'published'");
    row.published.bram18k = need_int(p, "bram18k", where + ".published");
    row.published.dsp = need_int(p, "dsp", where + ".published");
    row.published.ff = need_int(p, "ff", where + ".published");
    row.published.lut = need_int(p, "lut", where + ".published");
    out.push_back(std::move(row));
  }
  return out;
}

namespace {

// --- DSP binding: the thresholds that make the most rows exact ---------------------------------

constexpr int kNever = 99;  // a threshold no operand reaches: never on DSP

int64_t row_dsp(const Inventory& inv, const Coefficients& c) {
  int64_t n = 0;
  for (const auto& o : inv.ops) n += dsp_for(o, c, inv.dsp_b_bits);
  return n;
}

// Exact rows, then total |error| (smaller is better), of a candidate rule.
struct DspScore {
  int exact = -1;
  int64_t error = 0;
  bool better_than(const DspScore& o) const { return exact > o.exact || (exact == o.exact && error < o.error); }
};

DspScore score_dsp(const std::vector<FitRow>& rows, const std::vector<bool>& use, const Coefficients& c) {
  DspScore s{0, 0};
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!use[i] || rows[i].published.dsp < 0 || (rows[i].excluded >> kResDsp & 1u)) continue;
    const int64_t d = row_dsp(rows[i].inventory, c) - rows[i].published.dsp;
    s.exact += d == 0;
    s.error += d < 0 ? -d : d;
  }
  return s;
}

// Coordinate search: the multiplier thresholds over 1..27 bits and never, then the DSP slices per
// floating-point core (multiply 0..4, add 0..3, exp 0..10), twice. Ties keep the earlier (smaller)
// candidate.
void learn_dsp(const std::vector<FitRow>& rows, const std::vector<bool>& use, Coefficients& c) {
  std::vector<int> thresholds;
  for (int t = 1; t <= 27; ++t) thresholds.push_back(t);
  thresholds.push_back(kNever);
  for (int round = 0; round < 2; ++round) {
    DspScore best;
    Coefficients trial = c;
    for (int tv : thresholds)
      for (int tc : thresholds) {
        trial.dsp_min_bits_var = tv;
        trial.dsp_min_bits_const = tc;
        const DspScore s = score_dsp(rows, use, trial);
        if (s.better_than(best)) {
          best = s;
          c.dsp_min_bits_var = tv;
          c.dsp_min_bits_const = tc;
        }
      }
    best = DspScore{};
    trial = c;
    for (int fm = 0; fm <= 4; ++fm)
      for (int fa = 0; fa <= 3; ++fa)
        for (int fe = 0; fe <= 10; ++fe) {
          trial.dsp_per_fmul = fm;
          trial.dsp_per_fadd = fa;
          trial.dsp_per_fexp = fe;
          const DspScore s = score_dsp(rows, use, trial);
          if (s.better_than(best)) {
            best = s;
            c.dsp_per_fmul = fm;
            c.dsp_per_fadd = fa;
            c.dsp_per_fexp = fe;
          }
        }
  }
}

// --- LUT and FF: Ceres ------------------------------------------------------------------------

constexpr double kPriorWeight = 0.05;  // per feature, against log residuals of order 0.1 .. 1
constexpr double kCauchyScale = 0.15;  // log residual (about 15 %) beyond which a row's pull fades

struct LogResidual {
  double base, published;
  double f[kFeatureCount];
  template <class T>
  bool operator()(const T* const x, T* r) const {
    T pred = T(base);
    for (int k = 0; k < kFeatureCount; ++k) pred += x[k] * f[k];
    if (pred < T(1.0)) pred = T(1.0);
    r[0] = log(pred) - T(std::log(published));
    return true;
  }
};

struct PriorResidual {
  double prior[kFeatureCount];
  template <class T>
  bool operator()(const T* const x, T* r) const {
    for (int k = 0; k < kFeatureCount; ++k) r[k] = T(kPriorWeight) * (x[k] - prior[k]) / T(std::max(prior[k], 1.0));
    return true;
  }
};

void fit_one(const std::vector<FitRow>& rows, const std::vector<bool>& use, const Coefficients& c, bool lut,
             double* x) {
  const double* prior = lut ? c.lut_prior : c.ff_prior;
  for (int k = 0; k < kFeatureCount; ++k) x[k] = prior[k];
  ceres::Problem problem;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const int64_t pub = lut ? rows[i].published.lut : rows[i].published.ff;
    if (!use[i] || pub <= 0 || (rows[i].excluded >> (lut ? kResLut : kResFf) & 1u)) continue;
    const Features f = features(rows[i].inventory, c);
    auto* res = new LogResidual{lut ? f.lut_base : f.ff_base, double(pub), {}};
    for (int k = 0; k < kFeatureCount; ++k) res->f[k] = lut ? f.lut_f[k] : f.ff_f[k];
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<LogResidual, 1, kFeatureCount>(res),
                             new ceres::CauchyLoss(kCauchyScale), x);
  }
  auto* pr = new PriorResidual{};
  std::copy(prior, prior + kFeatureCount, pr->prior);
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PriorResidual, kFeatureCount, kFeatureCount>(pr), nullptr,
                           x);
  for (int k = 0; k < kFeatureCount; ++k) problem.SetParameterLowerBound(x, k, 0.0);
  ceres::Solver::Options opt;
  opt.max_num_iterations = 200;
  opt.logging_type = ceres::SILENT;
  ceres::Solver::Summary sum;
  ceres::Solve(opt, &problem, &sum);
}

}  // namespace

Coefficients fit_coefficients(const std::vector<FitRow>& rows, const std::vector<bool>& use,
                              const Coefficients& start) {
  Coefficients c = start;
  learn_dsp(rows, use, c);
  fit_one(rows, use, c, true, c.lut);
  fit_one(rows, use, c, false, c.ff);
  return c;
}

namespace {

ErrorStats stats_of(const std::vector<FitRow>& rows, int r, Usage FitRow::*which) {
  ErrorStats s;
  std::vector<double> pct;
  for (const auto& row : rows) {
    const int64_t pub = pick(row.published, r);
    if (!row.described || row.validation_only || pub < 0 || (row.excluded >> r & 1u)) continue;
    const int64_t pred = pick(row.*which, r);
    ++s.rows;
    s.exact += pred == pub;
    if (pub > 0) pct.push_back(100.0 * std::fabs(double(pred - pub)) / double(pub));
  }
  s.rows_pct = int(pct.size());
  if (pct.empty()) return s;
  std::sort(pct.begin(), pct.end());
  auto quantile = [&](double q) {  // linear interpolation between order statistics
    const double pos = q * double(pct.size() - 1);
    const std::size_t lo = std::size_t(pos);
    const std::size_t hi = std::min(lo + 1, pct.size() - 1);
    return pct[lo] + (pos - double(lo)) * (pct[hi] - pct[lo]);
  };
  s.median_pct = quantile(0.5);
  s.p90_pct = quantile(0.9);
  double sum = 0;
  for (double v : pct) sum += v;
  s.mean_pct = sum / double(pct.size());
  return s;
}

// Predictions of the rows selected by `target` with coefficients fitted on the trainable rows
// outside it.
void predict_left_out(std::vector<FitRow>& rows, const std::vector<bool>& trainable, const std::vector<bool>& target,
                      const Coefficients& start, Usage FitRow::*into) {
  std::vector<bool> use(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) use[i] = trainable[i] && !target[i];
  const Coefficients c = fit_coefficients(rows, use, start);
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (target[i] && rows[i].described) rows[i].*into = estimate(rows[i].inventory, c).total;
}

}  // namespace

FitResult fit(std::vector<FitRow> rows, const Coefficients& start) {
  std::vector<bool> trainable(rows.size());
  int n = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    trainable[i] = rows[i].described && !rows[i].validation_only;
    n += trainable[i];
  }
  if (n < 2)
    throw std::runtime_error("fit-resources: need at least two described published rows, got " + std::to_string(n));
  FitResult r;
  r.fitted_rows = n;
  r.coefficients = fit_coefficients(rows, trainable, start);
  for (auto& row : rows) {
    r.described_rows += row.described && !row.validation_only;
    r.excluded_rows += row.described && !row.validation_only && row.excluded != 0;
    if (row.described) row.fitted = estimate(row.inventory, r.coefficients).total;
  }
  // Leave one out: each trainable row; validation rows are already out of every fit.
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!rows[i].described) continue;
    if (!trainable[i]) {
      rows[i].loo = rows[i].lofo = rows[i].logo = rows[i].fitted;
      continue;
    }
    std::vector<bool> target(rows.size(), false);
    target[i] = true;
    predict_left_out(rows, trainable, target, start, &FitRow::loo);
  }
  // Leave one family out, and one group out.
  for (const auto unit : {&FitRow::family, &FitRow::group}) {
    std::map<std::string, std::vector<bool>> by;
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (trainable[i]) {
        auto& v = by[rows[i].*unit];
        v.resize(rows.size(), false);
        v[i] = true;
      }
    for (const auto& kv : by)
      predict_left_out(rows, trainable, kv.second, start, unit == &FitRow::family ? &FitRow::lofo : &FitRow::logo);
  }
  for (int k = 0; k < kResourceCount; ++k) {
    r.stats[k].fitted = stats_of(rows, k, &FitRow::fitted);
    r.stats[k].loo = stats_of(rows, k, &FitRow::loo);
    r.stats[k].lofo = stats_of(rows, k, &FitRow::lofo);
    r.stats[k].logo = stats_of(rows, k, &FitRow::logo);
  }
  std::string families;
  std::map<std::string, int> seen;
  for (const auto& row : rows)
    if (row.described && !row.validation_only && seen[row.family]++ == 0)
      families += (families.empty() ? "" : ", ") + row.family;
  r.coefficients.fitted_on = std::to_string(n) + " published rows of " + families;
  r.rows = std::move(rows);
  return r;
}

}  // namespace parallax::res
