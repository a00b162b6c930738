// Sweeps and Pareto fronts (sweep.hpp); the results store is in store.cpp.
#include "parallax/search/sweep.hpp"
#include "parallax/eval/text_util.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <map>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <mutex>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "parallax/uav/avoid.hpp"
#include "parallax/design/result.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/evaluate.hpp"
#include "parallax/uav/scene.hpp"
#include "parallax/resources/devices.hpp"

namespace parallax::explore {
using detail::utc_now;

using json = nlohmann::json;

// --- spec -------------------------------------------------------------------------------------

namespace {
SweepSpec parse_sweep_fields(const std::string& text, const std::string& source);
}

SweepSpec parse_sweep(const std::string& text, const std::string& source) {
  try {
    return parse_sweep_fields(text, source);
  } catch (const YAML::Exception& e) {  // a field of the wrong shape (a list or mapping for a value)
    throw InputError(source + ": line " + std::to_string(e.mark.line + 1) + ": a field has the wrong shape (" + e.msg +
                     "): names and values are scalars, axes map a field to a list of values");
  }
}

namespace {
SweepSpec parse_sweep_fields(const std::string& text, const std::string& source) {
  YAML::Node n;
  try {
    n = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(source + ": not YAML: " + e.what());
  }
  if (!n.IsMap()) throw InputError(source + ": expected a mapping of sweep fields");
  SweepSpec s;
  static const std::set<std::string> known = {"name", "base", "strategy", "samples", "seed", "generations", "avoidance", "flight", "axes",
                                              "constraints", "objectives", "frames", "gt"};
  for (const auto& kv : n) {
    const std::string key = kv.first.as<std::string>();
    if (!known.count(key)) throw InputError(source + ": unknown field '" + key + "'");
  }
  auto str = [&](const char* k, std::string& out) {
    if (n[k]) out = n[k].as<std::string>();
  };
  try {
    str("name", s.name);
    str("base", s.base);
    str("strategy", s.strategy);
    str("frames", s.frames);
    str("gt", s.gt);
    if (n["samples"]) s.samples = n["samples"].as<int>();
    if (n["seed"]) s.seed = n["seed"].as<uint32_t>();
    if (n["generations"]) s.generations = n["generations"].as<int>();
    if (n["avoidance"]) s.avoidance = n["avoidance"].as<bool>();
    if (n["flight"]) {
      const YAML::Node f = n["flight"];
      if (!f.IsMap()) throw InputError(source + ": field 'flight' must map scenario, seeds, speed_mps, size_px to values");
      for (const auto& kv : f) {
        const std::string k = kv.first.as<std::string>();
        if (k != "scenario" && k != "seeds" && k != "speed_mps" && k != "size_px")
          throw InputError(source + ": flight: unknown field '" + k + "' (known: scenario, seeds, speed_mps, size_px)");
      }
      if (!f["scenario"]) throw InputError(source + ": field 'flight' needs 'scenario' (a file in configs/scenarios)");
      s.flight_scenario = f["scenario"].as<std::string>();
      if (f["seeds"]) s.flight_seeds = f["seeds"].as<int>();
      if (f["speed_mps"]) s.flight_speed_mps = f["speed_mps"].as<double>();
      if (f["size_px"]) s.flight_size_px = f["size_px"].as<int>();
    }
  } catch (const YAML::Exception&) {
    throw InputError(source + ": a scalar field has the wrong type (samples and seed are integers)");
  }
  if (s.strategy != "grid" && s.strategy != "random" && s.strategy != "lhs" && s.strategy != "nsga2")
    throw InputError(source + ": field 'strategy': '" + s.strategy + "' is not grid, random, lhs or nsga2");
  if (s.generations < 1) throw InputError(source + ": field 'generations' must be at least 1");
  if (s.samples < 1) throw InputError(source + ": field 'samples' must be at least 1");
  if (s.gt != "noc" && s.gt != "occ") throw InputError(source + ": field 'gt' must be noc or occ");
  if (n["axes"]) {
    if (!n["axes"].IsMap()) throw InputError(source + ": field 'axes' must map configuration fields to lists");
    for (const auto& kv : n["axes"]) {
      std::vector<std::string> values;
      if (kv.second.IsSequence())
        for (const auto& v : kv.second) values.push_back(v.as<std::string>());
      else
        values.push_back(kv.second.as<std::string>());
      if (values.empty()) throw InputError(source + ": axis '" + kv.first.as<std::string>() + "' has no values");
      s.axes.emplace_back(kv.first.as<std::string>(), values);
    }
  }
  if (n["constraints"]) {
    const YAML::Node c = n["constraints"];
    if (!c.IsMap()) throw InputError(source + ": field 'constraints' must map constraint names to values");
    for (const auto& kv : c) {
      const std::string k = kv.first.as<std::string>();
      if (k != "device" && k != "fits_device" && k != "min_fps" && k != "max_latency_ms")
        throw InputError(source + ": constraints: unknown constraint '" + k +
                         "' (known: device, fits_device, min_fps, max_latency_ms)");
    }
    try {
      if (c["device"]) s.device = c["device"].as<std::string>();
      if (c["fits_device"]) s.require_fit = c["fits_device"].as<bool>();
      if (c["min_fps"]) s.min_fps = c["min_fps"].as<double>();
      if (c["max_latency_ms"]) s.max_latency_ms = c["max_latency_ms"].as<double>();
    } catch (const YAML::Exception&) {
      throw InputError(source + ": field 'constraints': device is a name, fits_device a bool, min_fps and "
                                "max_latency_ms numbers");
    }
    if (!res::find_device(s.device))
      throw InputError(source + ": constraints.device '" + s.device + "' is unknown; known: " + res::device_names());
  }
  if (n["objectives"]) {
    s.objectives.clear();
    for (const auto& o : n["objectives"]) {
      const std::string t = o.as<std::string>();
      const auto sp = t.find(' ');
      const std::string goal = t.substr(0, sp);
      if (sp == std::string::npos || (goal != "max" && goal != "min"))
        throw InputError(source + ": objective '" + t + "': write 'max KEY' or 'min KEY'");
      s.objectives.push_back({t.substr(sp + 1), goal == "max"});
    }
    if (s.objectives.empty()) throw InputError(source + ": field 'objectives' is empty");
  }
  return s;
}
}  // namespace

SweepSpec load_sweep(const std::string& path) {
  std::string text;
  try {
    text = config::read_text_file(path, "sweep file");
  } catch (const config::ConfigError& e) {
    throw InputError(e.what());
  }
  SweepSpec s = parse_sweep(text, path);
  // A relative base is relative to the working directory (as on the command line).
  return s;
}

std::string sweep_to_yaml(const SweepSpec& s) {
  YAML::Emitter e;
  e << YAML::BeginMap << YAML::Key << "name" << YAML::Value << s.name << YAML::Key << "base" << YAML::Value << s.base
    << YAML::Key << "strategy" << YAML::Value << s.strategy << YAML::Key << "samples" << YAML::Value << s.samples
    << YAML::Key << "seed" << YAML::Value << s.seed << YAML::Key << "generations" << YAML::Value << s.generations
    << YAML::Key << "axes" << YAML::Value << YAML::BeginMap;
  for (const auto& a : s.axes) e << YAML::Key << a.first << YAML::Value << YAML::Flow << a.second;
  e << YAML::EndMap << YAML::Key << "constraints" << YAML::Value << YAML::BeginMap << YAML::Key << "device"
    << YAML::Value << s.device << YAML::Key << "fits_device" << YAML::Value << s.require_fit << YAML::Key << "min_fps"
    << YAML::Value << s.min_fps << YAML::Key << "max_latency_ms" << YAML::Value << s.max_latency_ms << YAML::EndMap;
  e << YAML::Key << "objectives" << YAML::Value << YAML::BeginSeq;
  for (const auto& o : s.objectives) e << (std::string(o.maximise ? "max " : "min ") + o.key);
  e << YAML::EndSeq << YAML::Key << "frames" << YAML::Value << s.frames << YAML::Key << "gt" << YAML::Value << s.gt
    << YAML::Key << "avoidance" << YAML::Value << s.avoidance;
  if (!s.flight_scenario.empty())
    e << YAML::Key << "flight" << YAML::Value << YAML::BeginMap << YAML::Key << "scenario" << YAML::Value << s.flight_scenario
      << YAML::Key << "seeds" << YAML::Value << s.flight_seeds << YAML::Key << "speed_mps" << YAML::Value
      << s.flight_speed_mps << YAML::Key << "size_px" << YAML::Value << s.flight_size_px << YAML::EndMap;
  e << YAML::EndMap;
  return e.c_str();
}

void add_axis(SweepSpec& s, const std::string& kv) {
  const auto eq = kv.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 >= kv.size())
    throw InputError("--grid '" + kv + "': expected KEY=V1,V2,...");
  const std::string key = kv.substr(0, eq);
  std::vector<std::string> values;
  std::stringstream ss(kv.substr(eq + 1));
  std::string v;
  while (std::getline(ss, v, ','))
    if (!v.empty()) values.push_back(v);
  if (values.empty()) throw InputError("--grid '" + kv + "': no values");
  for (auto& a : s.axes)
    if (a.first == key) {
      a.second = values;
      return;
    }
  s.axes.emplace_back(key, values);
}

std::vector<std::string> metric_names(const SweepSpec& s) {
  std::vector<std::string> out;
  for (const auto& kv : named_metrics(DerivedMetrics{})) out.push_back(kv.first);
  for (const char* k : {"frames", "latency_ms", "frame_interval_ms", "fps", "cycles_per_frame", "bram18k", "lut", "ff", "dsp",
                        "fits_device", "power_w", "energy_mj_per_frame"})
    out.emplace_back(k);
  if (s.avoidance)
    for (const auto& kv : AvoidAccumulator{}.metrics()) out.push_back(kv.first);
  if (!s.flight_scenario.empty())
    for (const char* k : {"flight_success_rate", "flight_collisions", "flight_min_clearance_m", "flight_time_to_goal_s"})
      out.emplace_back(k);
  return out;
}

double requested_designs(const SweepSpec& s) {
  if (s.strategy == "random" || s.strategy == "lhs") return double(s.samples);
  if (s.strategy == "nsga2") return double(std::max(4, s.samples)) * double(s.generations + 1);
  double n = 1;
  for (const auto& a : s.axes) n *= double(a.second.size());
  return n;
}

void check_sweep_spec(const SweepSpec& s, const config::PipelineConfig& base, bool allow_large) {
  const auto& fields = config::field_names();
  for (const auto& a : s.axes) {
    if (std::find(fields.begin(), fields.end(), a.first) == fields.end()) {
      std::string known;
      for (const auto& f : fields) known += (known.empty() ? "" : ", ") + f;
      throw InputError("sweep '" + s.name + "': axis '" + a.first + "' is not a configuration field (known: " + known + ")");
    }
    for (const auto& v : a.second) {
      config::PipelineConfig c = base;
      try {
        config::set_field(c, a.first, v);
      } catch (const config::ConfigError& e) {
        throw InputError("sweep '" + s.name + "': axis '" + a.first + "', value '" + v + "': " + e.what());
      }
    }
  }
  const std::vector<std::string> metrics = metric_names(s);
  for (const auto& o : s.objectives)
    if (std::find(metrics.begin(), metrics.end(), o.key) == metrics.end()) {
      std::string known;
      for (const auto& m : metrics) known += (known.empty() ? "" : ", ") + m;
      throw InputError("sweep '" + s.name + "': objective '" + o.key + "' is not a metric of this sweep (known: " + known + ")");
    }
  const double n = requested_designs(s);
  if (n > kLargeSweepDesigns && !allow_large) {
    std::ostringstream m;
    m << "sweep '" << s.name << "': the " << s.strategy << " strategy asks for " << std::fixed << std::setprecision(0) << n
      << " designs (more than " << kLargeSweepDesigns
      << "); confirm with --yes, or draw a sample (--strategy lhs --samples N, or nsga2)";
    throw InputError(m.str());
  }
}

// --- designs ----------------------------------------------------------------------------------

std::vector<DesignPoint> enumerate_designs(const SweepSpec& s) {
  std::vector<DesignPoint> out;
  if (s.axes.empty()) {
    out.push_back({});
    return out;
  }
  auto point = [&](const std::vector<std::size_t>& idx) {
    DesignPoint d;
    for (std::size_t a = 0; a < s.axes.size(); ++a) d.fields.emplace_back(s.axes[a].first, s.axes[a].second[idx[a]]);
    return d;
  };
  if (s.strategy == "grid") {
    std::vector<std::size_t> idx(s.axes.size(), 0);
    for (;;) {
      out.push_back(point(idx));
      std::size_t a = s.axes.size();
      while (a > 0) {
        --a;
        if (++idx[a] < s.axes[a].second.size()) break;
        idx[a] = 0;
        if (a == 0) return out;
      }
    }
  }
  std::mt19937 rng(s.seed);
  std::set<std::vector<std::size_t>> seen;
  const int n = s.samples;
  if (s.strategy == "random") {
    for (int k = 0; k < n * 20 && int(out.size()) < n; ++k) {
      std::vector<std::size_t> idx;
      for (const auto& a : s.axes) idx.push_back(std::uniform_int_distribution<std::size_t>(0, a.second.size() - 1)(rng));
      if (seen.insert(idx).second) out.push_back(point(idx));
    }
    return out;
  }
  // Latin hypercube over the axes' value indices: per axis, n strata in a random order.
  std::vector<std::vector<std::size_t>> columns;
  for (const auto& a : s.axes) {
    std::vector<std::size_t> col(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      const double u = (double(i) + std::uniform_real_distribution<double>(0.0, 1.0)(rng)) / double(n);
      col[std::size_t(i)] = std::min(a.second.size() - 1, std::size_t(u * double(a.second.size())));
    }
    std::shuffle(col.begin(), col.end(), rng);
    columns.push_back(col);
  }
  for (int i = 0; i < n; ++i) {
    std::vector<std::size_t> idx;
    for (const auto& col : columns) idx.push_back(col[std::size_t(i)]);
    if (seen.insert(idx).second) out.push_back(point(idx));
  }
  return out;
}

namespace {

std::string fnv1a_hex(const std::string& s) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}


}  // namespace

MaterialisedDesign materialise(const config::PipelineConfig& base, const DesignPoint& d) {
  MaterialisedDesign m;
  m.config = base;
  for (const auto& f : d.fields) {
    try {
      config::set_field(m.config, f.first, f.second);
    } catch (const config::ConfigError& e) {
      m.errors.push_back(e.what());
    }
  }
  for (const auto& e : config::validate(m.config)) m.errors.push_back(e.field + ": " + e.message);
  std::string name;
  for (const auto& f : d.fields) name += (name.empty() ? "" : " ") + f.first + "=" + f.second;
  m.config.name = base.name + (name.empty() ? "" : " [" + name + "]");
  config::PipelineConfig anonymous = m.config;
  anonymous.name = "design";
  m.yaml = config::to_yaml(m.config);
  m.hash = fnv1a_hex(config::to_yaml(anonymous));
  return m;
}

// --- running ----------------------------------------------------------------------------------

namespace {

constexpr const char* kModelVersion = "parallax-models/2026-11-23 (kernels, cycle schedule, resources)";

std::string absolute_path(const std::string& p) {
  std::error_code ec;
  const std::filesystem::path a = std::filesystem::weakly_canonical(std::filesystem::absolute(p, ec), ec);
  return ec ? p : a.lexically_normal().string();
}

}  // namespace

std::string measurement_of(const SweepSpec& s, const std::string& dataset_dir, const std::vector<std::string>& frame_ids) {
  json j;  // keys sorted: one text per measurement
  j["contract"] = kResultsContract;
  j["models"] = kModelVersion;
  j["dataset"] = absolute_path(dataset_dir);
  j["gt"] = s.gt;
  j["frames"] = frame_ids;
  j["device"] = s.device;
  j["avoidance"] = s.avoidance;
  if (!s.flight_scenario.empty())
    j["flight"] = {{"scenario", absolute_path(s.flight_scenario)}, {"seeds", s.flight_seeds},
                   {"speed_mps", s.flight_speed_mps}, {"size_px", s.flight_size_px}};
  return j.dump();
}

std::string result_key(const std::string& design_hash, const std::string& measurement) {
  return design_hash + "@" + fnv1a_hex(measurement);
}

namespace {

// What the sweep asks of every design (docs/explorer.md): its dataset's frames, avoidance,
// flights and device.
PointRequest point_request(const SweepSpec& spec, const Dataset* dataset) {
  PointRequest req;
  req.dataset = dataset;
  req.gt_kind = spec.gt == "occ" ? GtKind::occ : GtKind::noc;
  req.frames = spec.frames;
  req.avoidance = spec.avoidance;
  req.device = spec.device;
  req.flight_scenario = spec.flight_scenario;
  req.flight_seeds = spec.flight_seeds;
  req.flight_speed_mps = spec.flight_speed_mps;
  req.flight_size_px = spec.flight_size_px;
  return req;
}

// Completes a design's result (what the sweep's shared evaluation has not measured) and writes
// it into its row.
void finish_row(const SweepSpec& spec, DesignResult& result, const Dataset* dataset, ResultStore::Row& row) {
  complete_point(result, point_request(spec, dataset));
  row.metrics = metric_columns(result);
  row.frames = frame_columns(result);
  row.status = result.status;
  row.reason = result.reason;
  row.finished_at = utc_now();
}

ResultStore::Row new_row(const SweepSpec& spec, const MaterialisedDesign& m) {
  ResultStore::Row row;
  row.hash = m.hash;
  row.sweep = spec.name;
  row.config_yaml = m.yaml;
  row.model_version = kModelVersion;
  row.started_at = utc_now();
  return row;
}

ResultStore::Row evaluate_one(const SweepSpec& spec, const MaterialisedDesign& m, const Dataset& dataset) {
  ResultStore::Row row = new_row(spec, m);
  DesignResult result;
  result.config = m.config;
  finish_row(spec, result, &dataset, row);
  return row;
}

// Designs sharing the cost stage, evaluated together: each frame decoded and cropped once, its
// costs recorded once and replayed into every design.
std::vector<ResultStore::Row> evaluate_group(const SweepSpec& spec, const std::vector<const MaterialisedDesign*>& group,
                                             const Dataset& dataset) {
  const GtKind gt = spec.gt == "occ" ? GtKind::occ : GtKind::noc;
  const std::vector<FrameRef> refs = list_frames(dataset, gt, spec.frames);
  if (refs.empty()) throw InputError(dataset.root.string() + ": no frame with ground truth matches '" + spec.frames + "'");
  std::vector<ResultStore::Row> rows;
  for (const auto* m : group) rows.push_back(new_row(spec, *m));
  std::vector<AccuracyFigures> accuracy(group.size());
  std::vector<AvoidAccumulator> avoidance(group.size());
  sim::FuncPipeline pipe;
  sim::CostRecording rec;
  const RoiSize roi = roi_for(group.front()->config);
  for (const auto& ref : refs) {
    const Frame f = load_frame(ref);
    const Roi r = resolve_roi(roi, f.left.cols, f.left.rows);
    const cv::Mat l = crop_to_roi(f.left, r), rr = crop_to_roi(f.right, r);
    const cv::Mat gtd = crop_to_roi(f.gt_disparity_px, r), gtm = crop_to_roi(f.gt_mask, r);
    pipe.record_costs(to_grey_image(l), to_grey_image(rr), group.front()->config.stereo_params(l.cols, l.rows), rec);
    for (std::size_t k = 0; k < group.size(); ++k) {
      const kern::StereoParams p = group[k]->config.stereo_params(l.cols, l.rows);
      const DisparityMap d = to_disparity_map(pipe.run_from_costs(rec, p));
      accuracy[k].frames.push_back(make_frame_row(f.id, count_frame(d.disparity_px, d.valid_mask, gtd, gtm)));
      if (spec.avoidance)
        avoidance[k].add(d.disparity_px, d.valid_mask, gtd, gtm, p.disparities, kitti_default_rig(r.x0, r.y0));
    }
  }
  for (std::size_t k = 0; k < group.size(); ++k) {
    DesignResult result;
    result.config = group[k]->config;
    accuracy[k].pooled = pool_rows(accuracy[k].frames);
    result.accuracy = std::move(accuracy[k]);
    if (spec.avoidance) result.avoidance = AvoidanceFigures{avoidance[k].metrics()};
    finish_row(spec, result, &dataset, rows[k]);
  }
  return rows;
}

}  // namespace

namespace {

// Evaluates the designs (skipping stored ones) with `jobs` threads; counts into `sum`. Designs
// sharing the cost stage form groups (opt.share_costs) that a thread evaluates together. Each
// group claims its designs in the store first: designs another live process claimed are left to
// it and waited for at the end (and evaluated here if it dies or fails them).
void evaluate_batch(const SweepSpec& spec, const std::vector<MaterialisedDesign>& designs, ResultStore& store,
                    const Dataset& dataset, const SweepRunOptions& opt, SweepSummary& sum, int total_for_progress,
                    int done_before, const std::string& measurement) {
  std::atomic<int> done{0}, skipped{0}, evaluated{0}, invalid{0}, failed{0};
  std::mutex mu;  // progress, the waiting list, the first failure
  const int skipped_before = sum.skipped;
  auto report = [&] {
    if (!opt.progress) return;
    std::lock_guard<std::mutex> lock(mu);
    opt.progress(done_before + done.load(), total_for_progress, skipped_before + skipped.load());
  };
  std::mutex problems_mu;
  auto note_problem = [&](const ResultStore::Row& r) {  // the first reasons, for the summary
    std::lock_guard<std::mutex> lock(problems_mu);
    if (sum.first_problems.size() < 5) sum.first_problems.push_back("design " + r.hash + " (" + r.status + "): " + r.reason);
  };
  auto key_of = [&](const MaterialisedDesign& m) { return result_key(m.hash, measurement); };
  auto reused = [&](const MaterialisedDesign& m) {
    store.add_member(spec.name, key_of(m));
    ++skipped;
    ++done;
    report();
  };
  // Stored, duplicate and invalid designs are settled now; the rest is evaluated.
  std::vector<const MaterialisedDesign*> todo;
  std::set<std::string> seen;
  for (const auto& m : designs) {
    if (!seen.insert(m.hash).second) {
      ++skipped;
      ++done;
      report();
      continue;
    }
    if (store.has_result(key_of(m))) {
      reused(m);
      continue;
    }
    if (!m.errors.empty()) {
      ResultStore::Row r = new_row(spec, m);
      r.status = "invalid";
      for (const auto& e : m.errors) r.reason += (r.reason.empty() ? "" : "; ") + e;
      r.finished_at = r.started_at;
      r.measurement = measurement;
      r.key = key_of(m);
      if (store.put_design(r)) {
        note_problem(r);
        ++invalid;
      } else {
        ++skipped;
      }
      ++done;
      report();
      continue;
    }
    todo.push_back(&m);
  }
  const int jobs = opt.jobs > 0 ? opt.jobs : std::max(1, int(std::thread::hardware_concurrency()));
  using Unit = std::vector<const MaterialisedDesign*>;
  auto make_units = [&](const std::vector<const MaterialisedDesign*>& ds) {
    std::vector<Unit> units;
    std::map<std::string, std::size_t> unit_of_key;
    for (const auto* m : ds) {
      const RoiSize roi = roi_for(m->config);
      const std::string key = opt.share_costs && m->config.rectify == "none" && !roi.full
                                  ? sim::cost_sharing_key(m->config.stereo_params(roi.width_px, roi.height_px))
                                  : "";
      const auto it = key.empty() ? unit_of_key.end() : unit_of_key.find(key);
      if (it != unit_of_key.end()) {
        units[it->second].push_back(m);
        continue;
      }
      if (!key.empty()) unit_of_key[key] = units.size();
      units.push_back({m});
    }
    // Fewer groups than threads: split the largest so that every thread works.
    while (int(units.size()) < jobs) {
      auto big = std::max_element(units.begin(), units.end(), [](const Unit& a, const Unit& b) { return a.size() < b.size(); });
      if (big == units.end() || big->size() < 2) break;
      Unit half(big->begin() + std::ptrdiff_t(big->size() / 2), big->end());
      big->resize(big->size() / 2);
      units.push_back(half);
    }
    return units;
  };
  auto store_row = [&](ResultStore::Row& r) {
    r.measurement = measurement;
    r.key = result_key(r.hash, measurement);
    if (store.put_design(r)) {
      if (r.status == "error") {
        ++failed;
        note_problem(r);
      }
      ++evaluated;
    } else {
      ++skipped;  // another process stored it meanwhile (it took over a claim it thought stale)
    }
    ++done;
    report();
  };
  auto error_row = [&](const MaterialisedDesign& m, const std::string& what) {
    ResultStore::Row r = new_row(spec, m);
    r.status = "error";
    r.reason = what;
    r.finished_at = utc_now();
    return r;
  };
  std::vector<const MaterialisedDesign*> waiting;  // claimed by another live process
  auto evaluate_unit = [&](const Unit& unit) {
    std::vector<std::string> keys;
    for (const auto* m : unit) keys.push_back(key_of(*m));
    const std::vector<ResultStore::Claim> claims = store.claim(keys);
    Unit mine;
    for (std::size_t k = 0; k < unit.size(); ++k) {
      if (claims[k] == ResultStore::Claim::reusable) {
        reused(*unit[k]);
      } else if (claims[k] == ResultStore::Claim::busy) {
        std::lock_guard<std::mutex> lock(mu);
        waiting.push_back(unit[k]);
      } else {
        mine.push_back(unit[k]);
      }
    }
    if (mine.empty()) return;
    std::vector<ResultStore::Row> rows;
    try {
      if (mine.size() == 1) rows.push_back(evaluate_one(spec, *mine.front(), dataset));
      else rows = evaluate_group(spec, mine, dataset);
    } catch (const std::exception& e) {
      rows.clear();
      for (const auto* m : mine) rows.push_back(error_row(*m, e.what()));
    }
    for (auto& r : rows) store_row(r);
  };
  // The units on `jobs` threads; a failure of the store (not of a design) stops them all and is
  // rethrown here.
  auto run_units = [&](const std::vector<Unit>& units) {
    std::atomic<std::size_t> next{0};
    std::atomic<bool> stop{false};
    std::exception_ptr failure;
    auto worker = [&] {
      try {
        while (!stop) {
          const std::size_t i = next.fetch_add(1);
          if (i >= units.size()) return;
          evaluate_unit(units[i]);
        }
      } catch (...) {
        std::lock_guard<std::mutex> lock(mu);
        if (!failure) failure = std::current_exception();
        stop = true;
      }
    };
    std::vector<std::thread> pool;
    for (int j = 0; j < std::min<int>(jobs, int(units.size())); ++j) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
  };
  run_units(make_units(todo));
  // Designs other processes are evaluating: wait for their results; take over a design whose
  // process died or failed it.
  auto last_note = std::chrono::steady_clock::now() - std::chrono::hours(1);
  while (!waiting.empty()) {
    std::vector<const MaterialisedDesign*> again;
    again.swap(waiting);
    run_units(make_units(again));
    if (waiting.empty()) break;
    if (std::chrono::steady_clock::now() - last_note > std::chrono::seconds(60)) {
      std::fprintf(stderr, "parallax: note: waiting for %zu designs that another sweep on %s is evaluating\n", waiting.size(),
                   store.path().c_str());
      last_note = std::chrono::steady_clock::now();
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  sum.evaluated += evaluated;
  sum.skipped += skipped;
  sum.invalid += invalid;
  sum.failed += failed;
}

// --- NSGA-II over the axes' value indices -----------------------------------------------------

using Genome = std::vector<std::size_t>;

DesignPoint point_of(const SweepSpec& s, const Genome& g) {
  DesignPoint d;
  for (std::size_t a = 0; a < s.axes.size(); ++a) d.fields.emplace_back(s.axes[a].first, s.axes[a].second[g[a]]);
  return d;
}

// Objective vector, larger is better; infeasible designs get -inf everywhere (constrained
// domination: every feasible design dominates them), a missing metric -inf in its place.
std::vector<double> objective_vector(const SweepSpec& s, const ResultStore::Row* r) {
  std::vector<double> v;
  const bool feasible = r && meets_constraints(s, *r);
  for (const auto& o : s.objectives) {
    if (!feasible) {
      v.push_back(-std::numeric_limits<double>::infinity());
      continue;
    }
    v.push_back(objective_value(*r, o));
  }
  return v;
}

bool dominates_vec(const std::vector<double>& a, const std::vector<double>& b) {
  bool strictly = false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (a[k] < b[k]) return false;
    if (a[k] > b[k]) strictly = true;
  }
  return strictly;
}

// Fronts (indices) of non-dominated sorting, then crowding distance per index.
void rank_and_crowd(const std::vector<std::vector<double>>& f, std::vector<int>& rank, std::vector<double>& crowd) {
  const std::size_t n = f.size();
  rank.assign(n, 0);
  crowd.assign(n, 0.0);
  std::vector<std::vector<std::size_t>> dominated(n);
  std::vector<int> count(n, 0);
  std::vector<std::size_t> front;
  for (std::size_t p = 0; p < n; ++p) {
    for (std::size_t q = 0; q < n; ++q) {
      if (dominates_vec(f[p], f[q])) dominated[p].push_back(q);
      else if (dominates_vec(f[q], f[p])) ++count[p];
    }
    if (count[p] == 0) front.push_back(p);
  }
  int r = 0;
  while (!front.empty()) {
    for (std::size_t p : front) rank[p] = r;
    // Crowding distance inside this front.
    for (std::size_t k = 0; k < (f.empty() ? 0 : f[0].size()); ++k) {
      std::vector<std::size_t> order = front;
      std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return f[a][k] < f[b][k]; });
      const double lo = f[order.front()][k], hi = f[order.back()][k];
      crowd[order.front()] = crowd[order.back()] = std::numeric_limits<double>::infinity();
      if (!(hi > lo) || !std::isfinite(hi - lo)) continue;
      for (std::size_t i = 1; i + 1 < order.size(); ++i) crowd[order[i]] += (f[order[i + 1]][k] - f[order[i - 1]][k]) / (hi - lo);
    }
    std::vector<std::size_t> next;
    for (std::size_t p : front)
      for (std::size_t q : dominated[p])
        if (--count[q] == 0) next.push_back(q);
    front = next;
    ++r;
  }
}

}  // namespace

SweepSummary run_sweep(const SweepSpec& spec, ResultStore& store, const SweepRunOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  if (spec.base.empty()) throw InputError("sweep '" + spec.name + "': no base configuration (field 'base' or --base)");
  const config::PipelineConfig base = config::load_config(spec.base);
  check_sweep_spec(spec, base, opt.allow_large);
  const Dataset dataset = open_dataset(opt.dataset);
  if (!res::find_device(spec.device)) throw InputError("sweep: unknown device '" + spec.device + "'");
  if (opt.shard_count < 1 || opt.shard_index < 1 || opt.shard_index > opt.shard_count)
    throw InputError("shard " + std::to_string(opt.shard_index) + "/" + std::to_string(opt.shard_count) +
                     ": expected K/N with 1 <= K <= N");
  if (spec.strategy == "nsga2" && opt.shard_count > 1)
    throw InputError("nsga2 cannot be sharded: each generation depends on the last");
  if (spec.strategy == "nsga2" && spec.axes.empty()) throw InputError("nsga2 needs at least one axis");
  // What the results are measured on; inputs that would fail every design fail the sweep now,
  // before anything is stored.
  const GtKind gt = spec.gt == "occ" ? GtKind::occ : GtKind::noc;
  std::vector<std::string> frame_ids;
  for (const auto& ref : list_frames(dataset, gt, spec.frames)) frame_ids.push_back(ref.id);
  if (frame_ids.empty())
    throw InputError(opt.dataset + ": no frame with " + spec.gt + " ground truth matches '" + spec.frames + "'");
  if (!spec.flight_scenario.empty()) (void)load_scenario(spec.flight_scenario);
  const std::string dataset_dir = absolute_path(dataset.root.string());
  const std::string measurement = measurement_of(spec, dataset_dir, frame_ids);
  SweepSummary sum;
  if (store.put_sweep(spec, dataset_dir, measurement)) {
    sum.notes.push_back("sweep '" + spec.name + "' in " + store.path() +
                        " was measured on other data (dataset, frames, ground truth or models) before: it now lists "
                        "only the designs measured on " + dataset_dir + " frames '" + spec.frames + "' (" + spec.gt +
                        "); the earlier results stay in the store");
    std::fprintf(stderr, "parallax: note: %s\n", sum.notes.back().c_str());
  }
  if (spec.strategy == "nsga2") {
    std::mt19937 rng(spec.seed);
    const int pop_n = std::max(4, spec.samples);
    auto random_genome = [&] {
      Genome g;
      for (const auto& a : spec.axes) g.push_back(std::uniform_int_distribution<std::size_t>(0, a.second.size() - 1)(rng));
      return g;
    };
    std::map<Genome, std::string> hash_of;  // genome -> design hash
    std::set<std::string> visited;
    auto evaluate = [&](const std::vector<Genome>& genomes, int generation) {
      std::vector<MaterialisedDesign> batch;
      for (const auto& g : genomes) {
        batch.push_back(materialise(base, point_of(spec, g)));
        hash_of[g] = batch.back().hash;
        visited.insert(batch.back().hash);
      }
      const int total = pop_n * (spec.generations + 1);
      evaluate_batch(spec, batch, store, dataset, opt, sum, total, generation * pop_n, measurement);
    };
    auto rows_by_hash = [&] {
      std::map<std::string, ResultStore::Row> m;
      for (auto& r : store.designs(spec.name, false)) m[r.hash] = std::move(r);  // this sweep's, as measured now
      return m;
    };
    std::vector<Genome> pop;
    for (int i = 0; i < pop_n; ++i) pop.push_back(random_genome());
    evaluate(pop, 0);
    for (int gen = 1; gen <= spec.generations; ++gen) {
      const auto rows = rows_by_hash();
      auto fitness = [&](const std::vector<Genome>& gs) {
        std::vector<std::vector<double>> f;
        for (const auto& g : gs) {
          const auto it = rows.find(hash_of[g]);
          f.push_back(objective_vector(spec, it == rows.end() ? nullptr : &it->second));
        }
        return f;
      };
      std::vector<int> rank;
      std::vector<double> crowd;
      rank_and_crowd(fitness(pop), rank, crowd);
      auto tournament = [&]() -> const Genome& {
        const std::size_t a = std::uniform_int_distribution<std::size_t>(0, pop.size() - 1)(rng);
        const std::size_t b = std::uniform_int_distribution<std::size_t>(0, pop.size() - 1)(rng);
        if (rank[a] != rank[b]) return rank[a] < rank[b] ? pop[a] : pop[b];
        return crowd[a] >= crowd[b] ? pop[a] : pop[b];
      };
      std::vector<Genome> children;
      const double p_mut = 1.0 / double(spec.axes.size());
      for (int tries = 0; int(children.size()) < pop_n && tries < pop_n * 50; ++tries) {
        const Genome& x = tournament();
        const Genome& y = tournament();
        Genome c(x.size());
        for (std::size_t k = 0; k < c.size(); ++k) {
          c[k] = std::uniform_int_distribution<int>(0, 1)(rng) ? x[k] : y[k];  // uniform crossover
          if (std::uniform_real_distribution<double>(0.0, 1.0)(rng) < p_mut)
            c[k] = std::uniform_int_distribution<std::size_t>(0, spec.axes[k].second.size() - 1)(rng);
        }
        const std::string h = materialise(base, point_of(spec, c)).hash;
        if (visited.count(h)) continue;  // only new designs cost an evaluation
        children.push_back(c);
        visited.insert(h);
      }
      if (children.empty()) break;  // the space is exhausted
      evaluate(children, gen);
      // Environmental selection: the best pop_n of parents + children by rank, then crowding.
      std::vector<Genome> merged = pop;
      merged.insert(merged.end(), children.begin(), children.end());
      const auto rows2 = rows_by_hash();
      std::vector<std::vector<double>> f;
      for (const auto& g : merged) {
        const auto it = rows2.find(hash_of[g]);
        f.push_back(objective_vector(spec, it == rows2.end() ? nullptr : &it->second));
      }
      rank_and_crowd(f, rank, crowd);
      std::vector<std::size_t> idx(merged.size());
      for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
      std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) {
        return rank[a] != rank[b] ? rank[a] < rank[b] : crowd[a] > crowd[b];
      });
      pop.clear();
      for (std::size_t i = 0; i < idx.size() && int(pop.size()) < pop_n; ++i) pop.push_back(merged[idx[i]]);
    }
    sum.total = int(visited.size());
  } else {
    std::vector<DesignPoint> points;
    const std::vector<DesignPoint> all = enumerate_designs(spec);
    for (std::size_t i = 0; i < all.size(); ++i)
      if (int(i % std::size_t(opt.shard_count)) == opt.shard_index - 1) points.push_back(all[i]);
    sum.total = int(points.size());
    std::vector<MaterialisedDesign> designs;
    for (const auto& p : points) designs.push_back(materialise(base, p));
    evaluate_batch(spec, designs, store, dataset, opt, sum, sum.total, 0, measurement);
  }
  sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return sum;
}

// --- Pareto -----------------------------------------------------------------------------------

bool meets_constraints(const SweepSpec& s, const ResultStore::Row& r) {
  if (r.status != "ok") return false;
  // A missing (or non-finite) metric meets no bound on it.
  auto get = [&](const char* k) {
    const auto it = r.metrics.find(k);
    return it == r.metrics.end() ? std::nan("") : it->second;
  };
  if (s.require_fit && !(get("fits_device") >= 0.5)) return false;
  if (s.min_fps > 0 && !(get("fps") >= s.min_fps)) return false;
  if (s.max_latency_ms > 0 && !(get("latency_ms") <= s.max_latency_ms)) return false;
  return true;
}

double objective_value(const ResultStore::Row& r, const Objective& o) {
  const auto it = r.metrics.find(o.key);
  if (it == r.metrics.end() || !std::isfinite(it->second)) return -std::numeric_limits<double>::infinity();
  return o.maximise ? it->second : -it->second;
}

std::vector<ResultStore::Row> pareto_front(const SweepSpec& s, const std::vector<ResultStore::Row>& rows) {
  std::vector<const ResultStore::Row*> ok;
  for (const auto& r : rows)
    if (meets_constraints(s, r)) ok.push_back(&r);
  auto dominates = [&](const ResultStore::Row& a, const ResultStore::Row& b) {
    bool strictly = false;
    for (const auto& o : s.objectives) {
      const double va = objective_value(a, o), vb = objective_value(b, o);
      if (va < vb) return false;
      if (va > vb) strictly = true;
    }
    return strictly;
  };
  std::vector<ResultStore::Row> front;
  for (const auto* a : ok) {
    bool dominated = false;
    for (const auto* b : ok)
      if (b != a && dominates(*b, *a)) {
        dominated = true;
        break;
      }
    if (!dominated) front.push_back(*a);
  }
  return front;
}

}  // namespace parallax::explore
