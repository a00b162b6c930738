// Sweep files (docs/explorer.md): parsing, the canonical YAML, --grid axes, the metric names
// objectives may use, and the checks made before any design runs.
#include <algorithm>
#include <cmath>
#include <set>
#include <iomanip>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "parallax/config/config.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/eval/metrics.hpp"
#include "parallax/resources/devices.hpp"
#include "parallax/search/sweep.hpp"
#include "parallax/uav/scene.hpp"

namespace parallax::search {

// The names this file takes from the other rooms (one namespace per room).
using eval::DerivedMetrics;
using eval::InputError;
using eval::named_metrics;
using uav::AvoidAccumulator;

namespace {
SweepSpec parse_sweep_fields(const std::string& text, const std::string& source);
}

namespace {

// baselines: [opencv-hh4, opencv-sgbm]: the peers measured beside the sweep.
void parse_baselines(const YAML::Node& n, const std::string& source, SweepSpec& s) {
  if (!n["baselines"]) return;
  if (!n["baselines"].IsSequence())
    throw InputError(source + ": field 'baselines' must be a list such as [opencv-hh4, opencv-sgbm]");
  for (const auto& b : n["baselines"]) {
    const std::string name = b.as<std::string>();
    if (name != "opencv-hh4" && name != "opencv-sgbm")
      throw InputError(source + ": baselines: unknown peer '" + name + "' (known: opencv-hh4, opencv-sgbm)");
    if (std::find(s.baselines.begin(), s.baselines.end(), name) == s.baselines.end()) s.baselines.push_back(name);
  }
}

// designs: [{field: value, ...}, ...] (strategy list): each design's fields over the base. The
// axes become the fields the designs set, with the values they take, in order of appearance
// (checked like any axis; the report's columns).
void parse_designs(const YAML::Node& n, const std::string& source, SweepSpec& s) {
  if (!n["designs"]) return;
  if (!n["designs"].IsSequence()) throw InputError(source + ": field 'designs' must be a list of field maps");
  int i = 0;
  for (const auto& d : n["designs"]) {
    ++i;
    if (!d.IsMap() && !d.IsNull())
      throw InputError(source + ": designs: entry " + std::to_string(i) + " is not a map of fields");
    std::vector<std::pair<std::string, std::string>> fields;
    if (d.IsMap())
      for (const auto& kv : d) {
        const std::string k = kv.first.as<std::string>(), v = kv.second.as<std::string>();
        fields.emplace_back(k, v);
        auto axis = std::find_if(s.axes.begin(), s.axes.end(), [&](const auto& a) { return a.first == k; });
        if (axis == s.axes.end()) {
          s.axes.emplace_back(k, std::vector<std::string>{});
          axis = s.axes.end() - 1;
        }
        if (std::find(axis->second.begin(), axis->second.end(), v) == axis->second.end()) axis->second.push_back(v);
      }
    s.designs.push_back(fields);
  }
}

}  // namespace

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
  static const std::set<std::string> known = {"designs",     "name",        "base",      "strategy", "samples",
                                              "seed",        "generations", "avoidance", "flight",   "axes",
                                              "constraints", "objectives",  "frames",    "gt",       "baselines"};
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
    parse_baselines(n, source, s);
    parse_designs(n, source, s);
    if (n["flight"]) {
      const YAML::Node f = n["flight"];
      if (!f.IsMap())
        throw InputError(source + ": field 'flight' must map scenario, seeds, speed_mps, size_px to values");
      for (const auto& kv : f) {
        const std::string k = kv.first.as<std::string>();
        if (k != "scenario" && k != "seeds" && k != "speed_mps" && k != "size_px")
          throw InputError(source + ": flight: unknown field '" + k + "' (known: scenario, seeds, speed_mps, size_px)");
      }
      if (!f["scenario"])
        throw InputError(source +
                         ": field 'flight' needs 'scenario' (a shipped scenario's name such as forest, or a file)");
      s.flight_scenario = f["scenario"].as<std::string>();
      if (f["seeds"]) s.flight_seeds = f["seeds"].as<int>();
      if (f["speed_mps"]) s.flight_speed_mps = f["speed_mps"].as<double>();
      if (f["size_px"]) s.flight_size_px = f["size_px"].as<int>();
      if (s.flight_seeds < 1 || s.flight_seeds > 10000)
        throw InputError(source + ": flight: 'seeds' must be 1..10000, not " + std::to_string(s.flight_seeds));
      if (!(s.flight_speed_mps >= 0.1 && s.flight_speed_mps <= 50.0))
        throw InputError(source + ": flight: 'speed_mps' must be 0.1..50");
      if (s.flight_size_px != 0 && (s.flight_size_px < 64 || s.flight_size_px > 4096))
        throw InputError(source + ": flight: 'size_px' must be 0 (the design's own) or 64..4096, not " +
                         std::to_string(s.flight_size_px));
    }
  } catch (const YAML::Exception&) {
    throw InputError(source + ": a scalar field has the wrong type (samples and seed are integers)");
  }
  if (s.strategy != "grid" && s.strategy != "random" && s.strategy != "lhs" && s.strategy != "nsga2" &&
      s.strategy != "list")
    throw InputError(source + ": field 'strategy': '" + s.strategy + "' is not grid, random, lhs, nsga2 or list");
  if ((s.strategy == "list") != !s.designs.empty())
    throw InputError(source + (s.designs.empty() ? ": strategy list needs a field 'designs'"
                                                 : ": field 'designs' belongs to strategy list"));
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
      if (k != "device" && k != "fits_device" && k != "min_fps" && k != "max_latency_ms" && k != "one_pass")
        throw InputError(source + ": constraints: unknown constraint '" + k +
                         "' (known: device, fits_device, min_fps, max_latency_ms, one_pass)");
    }
    try {
      if (c["device"]) s.device = c["device"].as<std::string>();
      if (c["fits_device"]) s.require_fit = c["fits_device"].as<bool>();
      if (c["min_fps"]) s.min_fps = c["min_fps"].as<double>();
      if (c["max_latency_ms"]) s.max_latency_ms = c["max_latency_ms"].as<double>();
      if (c["one_pass"]) s.one_pass = c["one_pass"].as<bool>();
    } catch (const YAML::Exception&) {
      throw InputError(source +
                       ": field 'constraints': device is a name, fits_device and one_pass bools, min_fps and "
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
  if (s.strategy != "list")  // a list's axes are its designs' fields (parse_designs)
    for (const auto& a : s.axes) e << YAML::Key << a.first << YAML::Value << YAML::Flow << a.second;
  e << YAML::EndMap << YAML::Key << "constraints" << YAML::Value << YAML::BeginMap << YAML::Key << "device"
    << YAML::Value << s.device << YAML::Key << "fits_device" << YAML::Value << s.require_fit << YAML::Key << "min_fps"
    << YAML::Value << s.min_fps << YAML::Key << "max_latency_ms" << YAML::Value << s.max_latency_ms << YAML::Key
    << "one_pass" << YAML::Value << s.one_pass << YAML::EndMap;
  e << YAML::Key << "objectives" << YAML::Value << YAML::BeginSeq;
  for (const auto& o : s.objectives) e << (std::string(o.maximise ? "max " : "min ") + o.key);
  e << YAML::EndSeq << YAML::Key << "frames" << YAML::Value << s.frames << YAML::Key << "gt" << YAML::Value << s.gt
    << YAML::Key << "avoidance" << YAML::Value << s.avoidance;
  if (!s.baselines.empty()) e << YAML::Key << "baselines" << YAML::Value << YAML::Flow << s.baselines;
  if (!s.designs.empty()) {
    e << YAML::Key << "designs" << YAML::Value << YAML::BeginSeq;
    for (const auto& d : s.designs) {
      e << YAML::Flow << YAML::BeginMap;
      for (const auto& f : d) e << YAML::Key << f.first << YAML::Value << f.second;
      e << YAML::EndMap;
    }
    e << YAML::EndSeq;
  }
  if (!s.flight_scenario.empty())
    e << YAML::Key << "flight" << YAML::Value << YAML::BeginMap << YAML::Key << "scenario" << YAML::Value
      << s.flight_scenario << YAML::Key << "seeds" << YAML::Value << s.flight_seeds << YAML::Key << "speed_mps"
      << YAML::Value << s.flight_speed_mps << YAML::Key << "size_px" << YAML::Value << s.flight_size_px << YAML::EndMap;
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
  for (const char* k : {"frames", "latency_ms", "frame_interval_ms", "fps", "cycles_per_frame", "passes", "bram18k",
                        "lut", "ff", "dsp", "fits_device", "power_w", "energy_mj_per_frame"})
    out.emplace_back(k);
  if (s.avoidance)
    for (const auto& kv : AvoidAccumulator{}.metrics()) out.push_back(kv.first);
  if (!s.flight_scenario.empty())
    for (const char* k :
         {"flight_success_rate", "flight_collisions", "flight_min_clearance_m", "flight_time_to_goal_s"})
      out.emplace_back(k);
  return out;
}

double requested_designs(const SweepSpec& s) {
  if (s.strategy == "random" || s.strategy == "lhs") return double(s.samples);
  if (s.strategy == "nsga2") return double(std::max(4, s.samples)) * double(s.generations + 1);
  if (s.strategy == "list") return double(s.designs.size());
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
      throw InputError("sweep '" + s.name + "': axis '" + a.first + "' is not a configuration field (known: " + known +
                       ")");
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
      throw InputError("sweep '" + s.name + "': objective '" + o.key +
                       "' is not a metric of this sweep (known: " + known + ")");
    }
  const double n = requested_designs(s);
  if (n > kLargeSweepDesigns && !allow_large) {
    std::ostringstream m;
    m << "sweep '" << s.name << "': the " << s.strategy << " strategy asks for " << std::fixed << std::setprecision(0)
      << n << " designs (more than " << kLargeSweepDesigns
      << "); confirm with --yes, or draw a sample (--strategy lhs --samples N, or nsga2)";
    throw InputError(m.str());
  }
}
}  // namespace parallax::search
