// Vitis HLS csynth.xml (hls_report.hpp).
#include "parallax/hls_flow/hls_report.hpp"

#include <algorithm>
#include <cmath>

#include <pugixml.hpp>

#include "parallax/eval/dataset.hpp"
#include "parallax/eval/simulate.hpp"
#include "parallax/resources/model.hpp"

namespace parallax::hls_flow {

// The names this file takes from the other rooms (one namespace per room).
using eval::cycle_options;
using eval::InputError;
using eval::simulate_timing;
using eval::SimulationResult;

namespace {

// The integer of element `child` of n: `fallback` when absent or "undef"/"-" (what csynth writes
// for a figure it does not know, e.g. the II of a loop it did not pipeline); InputError naming the
// file and the element for any other text that is not a whole number at least `min_value`.
int64_t to_int(const pugi::xml_node& n, const char* child, const std::string& path, int64_t min_value = 0,
               int64_t fallback = -1) {
  const pugi::xml_node c = n.child(child);
  if (!c) return fallback;
  const std::string t = c.text().as_string();
  if (t.empty() || t == "undef" || t == "-") return fallback;
  std::size_t used = 0;
  int64_t v = 0;
  try {
    v = std::stoll(t, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != t.size() || v < min_value)
    throw InputError(path + ": <" + std::string(n.name()) + "><" + child + "> is '" + t +
                     "', expected a whole number >= " + std::to_string(min_value));
  return v;
}

// A clock period in ns: a positive finite number, else InputError naming the file and element.
double to_period_ns(const pugi::xml_node& n, const char* child, const std::string& path) {
  const std::string t = n.child(child).text().as_string();
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(t, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (t.empty() || used != t.size() || !(v > 0 && v < 1e6))
    throw InputError(path + ": <" + std::string(n.name()) + "><" + child + "> is '" + t +
                     "', expected a clock period in ns (a positive number)");
  return v;
}

}  // namespace

HlsReport read_csynth_xml(const std::string& path) {
  pugi::xml_document doc;
  std::string text;
  try {
    text = config::read_text_file(path, "csynth report", std::size_t(256) << 20);
  } catch (const config::ConfigError& e) {
    throw InputError(e.what());
  }
  const pugi::xml_parse_result ok = doc.load_buffer(text.data(), text.size());
  if (!ok) throw InputError(path + ": not XML: " + ok.description());
  const pugi::xml_node profile = doc.child("profile");
  if (!profile) throw InputError(path + ": no <profile> element: not a Vitis HLS csynth report");
  HlsReport r;
  r.version = profile.child("ReportVersion").child("Version").text().as_string();
  const pugi::xml_node ua = profile.child("UserAssignments");
  r.part = ua.child("Part").text().as_string();
  r.top = ua.child("TopModelName").text().as_string();
  r.target_clock_ns = to_period_ns(ua, "TargetClockPeriod", path);
  const pugi::xml_node pe = profile.child("PerformanceEstimates");
  if (!pe) throw InputError(path + ": no <PerformanceEstimates> element");
  r.estimated_clock_ns = to_period_ns(pe.child("SummaryOfTimingAnalysis"), "EstimatedClockPeriod", path);
  const pugi::xml_node lat = pe.child("SummaryOfOverallLatency");
  r.best_latency_cycles = to_int(lat, "Best-caseLatency", path);
  r.worst_latency_cycles = to_int(lat, "Worst-caseLatency", path);
  r.interval_min_cycles = to_int(lat, "Interval-min", path);
  r.interval_max_cycles = to_int(lat, "Interval-max", path);
  for (const pugi::xml_node loop : pe.child("SummaryOfLoopLatency").children()) {
    HlsLoop l;
    l.name = loop.name();
    l.trip_count = to_int(loop, "TripCount", path);
    l.latency_cycles = to_int(loop, "Latency", path);
    l.iteration_latency = to_int(loop, "IterationLatency", path);
    l.pipeline_ii = int(to_int(loop, "PipelineII", path, 1));  // an II is at least 1
    l.pipeline_depth = int(to_int(loop, "PipelineDepth", path, 1));
    r.loops.push_back(l);
  }
  const pugi::xml_node area = profile.child("AreaEstimates");
  if (!area.child("Resources")) throw InputError(path + ": no <AreaEstimates><Resources> element");
  for (const pugi::xml_node res : area.child("Resources").children()) {
    std::string key = res.name();
    if (key == "DSP48E" || key == "DSP48E2") key = "DSP";
    r.resources[key] = to_int(area.child("Resources"), res.name(), path, 0, 0);
  }
  for (const pugi::xml_node res : area.child("AvailableResources").children()) {
    std::string key = res.name();
    if (key == "DSP48E" || key == "DSP48E2") key = "DSP";
    r.available[key] = to_int(area.child("AvailableResources"), res.name(), path, 0, 0);
  }
  return r;
}

std::vector<std::string> calibrate_from_hls(config::PipelineConfig& cfg, const HlsReport& r) {
  static const std::vector<std::string> stages = {"cost",     "aggregate_back", "aggregate",     "wta_lr",
                                                  "median",   "rectify_left",   "rectify_right", "ddr_write",
                                                  "ddr_read", "source",         "sink"};
  std::vector<std::string> set;
  for (const auto& l : r.loops) {
    std::string best;
    for (const auto& s : stages)
      if (l.name.rfind(s, 0) == 0 && s.size() > best.size()) best = s;
    if (best.empty()) continue;
    if (l.pipeline_ii > 0) {
      cfg.stage_ii[best] = l.pipeline_ii;
      set.push_back("ii_" + best + "=" + std::to_string(l.pipeline_ii));
    }
    const int64_t depth = l.pipeline_depth > 0 ? l.pipeline_depth : l.iteration_latency;
    if (depth > 0) {
      cfg.stage_latency[best] = int(depth);
      set.push_back("latency_" + best + "=" + std::to_string(depth));
    }
  }
  return set;
}

}  // namespace parallax::hls_flow

namespace parallax::hls_flow {

std::vector<ModelVsSynthesis> compare_with_model(const config::PipelineConfig& cfg_in, const HlsReport& r, int w, int h,
                                                 sim::CycleReport* model_cycle) {
  config::PipelineConfig cfg = cfg_in;
  if (r.target_clock_ns > 0) cfg.clock_mhz = std::max(1, int(std::lround(1000.0 / r.target_clock_ns)));
  const SimulationResult sim = simulate_timing(cfg, w, h);
  if (model_cycle) *model_cycle = sim.cycle;
  const sim::TimingModel timing = [&] {
    sim::TimingModel t = sim::default_timing(cfg.stereo_params(w, h), double(cfg.clock_mhz) * 1e6);
    for (const auto& kv : cycle_options(cfg, cfg.clock_mhz).timing) t[kv.first] = kv.second;
    return t;
  }();
  std::vector<ModelVsSynthesis> rows;
  const double latency = sim.cycle.deadlock ? -1.0 : double(sim.cycle.last_pixel_cycle - sim.cycle.first_input_cycle);
  rows.push_back({"latency (cycles)", latency, double(r.worst_latency_cycles),
                  "model: last output pixel after the first input pixel at " + std::to_string(cfg.clock_mhz) + " MHz"});
  rows.push_back({"interval (cycles)", sim.cycle.deadlock ? -1.0 : double(sim.cycle.cycles_per_frame),
                  double(r.interval_max_cycles), "model: cycles per frame in steady state"});
  for (const auto& l : r.loops) {
    std::string stage;
    for (const auto& kv : timing)
      if (l.name.rfind(kv.first, 0) == 0 && kv.first.size() > stage.size()) stage = kv.first;
    if (stage.empty()) continue;
    const sim::StageTiming& t = timing.at(stage);
    if (l.pipeline_ii > 0)
      rows.push_back({"II " + l.name, double(t.ii_cycles), double(l.pipeline_ii), "stage " + stage});
    const int64_t depth = l.pipeline_depth > 0 ? l.pipeline_depth : l.iteration_latency;
    if (depth > 0) rows.push_back({"depth " + l.name, double(t.latency_cycles), double(depth), "stage " + stage});
  }
  const res::Estimate est = res::estimate(res::design_inventory(cfg, w, h));
  const std::pair<const char*, int64_t> model_res[] = {
      {"BRAM_18K", est.total.bram18k}, {"LUT", est.total.lut}, {"FF", est.total.ff}, {"DSP", est.total.dsp}};
  for (const auto& m : model_res) {
    const auto it = r.resources.find(m.first);
    rows.push_back({m.first, double(m.second), it != r.resources.end() ? double(it->second) : -1.0, "resource model"});
  }
  return rows;
}

}  // namespace parallax::hls_flow
