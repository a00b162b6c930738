// The tabular outputs of a result store (docs/reports.md): the designs and frames CSV, the JSON,
// and the reading of a stored row (rows.hpp).
#include <algorithm>
#include <cmath>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "html_text.hpp"
#include "parallax/reports/report.hpp"
#include "rows.hpp"

namespace parallax::reports {

// The names this file takes from the other rooms (one namespace per room).
using search::ResultStore;

namespace rows {

std::vector<std::pair<std::string, std::string>> config_fields(const std::string& yaml) {
  std::vector<std::pair<std::string, std::string>> out;
  try {
    const YAML::Node n = YAML::Load(yaml);
    for (const auto& kv : n) {
      if (kv.second.IsScalar()) {
        out.emplace_back(kv.first.as<std::string>(), kv.second.as<std::string>());
      } else if (kv.second.IsSequence()) {
        std::string v;
        for (const auto& item : kv.second) v += (v.empty() ? "" : ",") + item.as<std::string>();
        out.emplace_back(kv.first.as<std::string>(), "[" + v + "]");
      }
    }
  } catch (const YAML::Exception&) {
  }
  return out;
}

std::string path_count(const std::string& paths) {
  if (paths.empty() || paths[0] != '[') return paths;
  return std::to_string(1 + std::count(paths.begin(), paths.end(), ','));
}

double metric(const ResultStore::Row& r, const std::string& k) {
  const auto it = r.metrics.find(k);
  return it == r.metrics.end() ? std::nan("") : it->second;
}

std::string field(const ResultStore::Row& r, const std::string& k) {
  for (const auto& kv : config_fields(r.config_yaml))
    if (kv.first == k) return kv.second;
  return "";
}

}  // namespace rows

namespace {

using json = nlohmann::json;
using rows::config_fields;
using rows::metric;

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string o = "\"";
  for (char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
  return o + "\"";
}

std::vector<std::string> config_columns(const std::vector<ResultStore::Row>& rows) {
  std::vector<std::string> cols;
  std::set<std::string> seen;
  for (const auto& r : rows)
    for (const auto& kv : config_fields(r.config_yaml))
      if (seen.insert(kv.first).second) cols.push_back(kv.first);
  return cols;
}

std::vector<std::string> all_metric_columns(const std::vector<ResultStore::Row>& rows) {
  std::vector<std::string> cols = metric_columns();
  std::set<std::string> known(cols.begin(), cols.end()), extra;
  for (const auto& r : rows)
    for (const auto& kv : r.metrics)
      if (!known.count(kv.first)) extra.insert(kv.first);
  cols.insert(cols.end(), extra.begin(), extra.end());
  return cols;
}

}  // namespace

std::vector<std::string> metric_columns() {
  return {"density_pct",
          "density_gt_pct",
          "correct_3px_pct",
          "d1_all_pct",
          "d1_all_filled_pct",
          "mean_abs_error_px",
          "frames",
          "latency_ms",
          "frame_interval_ms",
          "fps",
          "cycles_per_frame",
          "bram18k",
          "lut",
          "ff",
          "dsp",
          "fits_device",
          "power_w",
          "energy_mj_per_frame",
          "obstacle_precision",
          "obstacle_recall",
          "range_error_m",
          "decision_agreement_pct",
          "mean_ms_per_frame",
          "flight_success_rate",
          "flight_collisions",
          "flight_min_clearance_m",
          "flight_time_to_goal_s"};
}

void write_designs_csv(const std::vector<ResultStore::Row>& rows, std::ostream& out) {
  const auto cfg_cols = config_columns(rows);
  const auto met_cols = all_metric_columns(rows);
  out << "hash,sweep,status,reason";
  for (const auto& c : cfg_cols) out << "," << csv_field(c);
  for (const auto& c : met_cols) out << "," << csv_field(c);
  out << "\n";
  for (const auto& r : rows) {
    out << r.hash << "," << csv_field(r.sweep) << "," << r.status << "," << csv_field(r.reason);
    const auto fields = config_fields(r.config_yaml);
    for (const auto& c : cfg_cols) {
      std::string v;
      for (const auto& kv : fields)
        if (kv.first == c) v = kv.second;
      out << "," << csv_field(v);
    }
    for (const auto& c : met_cols) out << "," << number(metric(r, c));
    out << "\n";
  }
}

void write_frames_csv(const std::vector<ResultStore::Row>& rows, std::ostream& out) {
  std::vector<std::string> cols;
  std::set<std::string> seen;
  for (const auto& r : rows)
    for (const auto& f : r.frames)
      for (const auto& kv : f.second)
        if (seen.insert(kv.first).second) cols.push_back(kv.first);
  out << "hash,frame";
  for (const auto& c : cols) out << "," << c;
  out << "\n";
  for (const auto& r : rows)
    for (const auto& f : r.frames) {
      out << r.hash << "," << csv_field(f.first);
      for (const auto& c : cols) {
        const auto it = f.second.find(c);
        out << "," << (it == f.second.end() ? "" : number(it->second));
      }
      out << "\n";
    }
}

std::string report_json(const std::vector<ResultStore::Row>& rows) {
  json j = json::array();
  for (const auto& r : rows) {
    json c = json::object();
    for (const auto& kv : config_fields(r.config_yaml)) c[kv.first] = kv.second;
    json frames = json::array();
    for (const auto& f : r.frames) frames.push_back({{"frame", f.first}, {"metrics", f.second}});
    json measurement = r.measurement.empty() ? json() : json::parse(r.measurement, nullptr, false);
    if (measurement.is_discarded()) measurement = r.measurement;
    j.push_back({{"hash", r.hash},
                 {"sweep", r.sweep},
                 {"status", r.status},
                 {"reason", r.reason},
                 {"configuration", c},
                 {"metrics", r.metrics},
                 {"frames", frames},
                 {"model_version", r.model_version},
                 {"started_at", r.started_at},
                 {"finished_at", r.finished_at},
                 {"measurement", measurement}});
  }
  return j.dump(2) + "\n";
}

}  // namespace parallax::reports
