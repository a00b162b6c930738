// Vitis HLS csynth.xml (hls_report.hpp).
#include "parallax/explore/hls_report.hpp"

#include <algorithm>
#include <cmath>

#include <pugixml.hpp>

#include "parallax/explore/dataset.hpp"
#include "parallax/explore/simulate.hpp"
#include "parallax/resources/model.hpp"

namespace parallax::explore {

namespace {

int64_t to_int(const pugi::xml_node& n, const char* child, int64_t fallback = -1) {
  const pugi::xml_node c = n.child(child);
  if (!c) return fallback;
  const std::string t = c.text().as_string();
  if (t.empty() || t == "undef" || t == "-") return fallback;
  try {
    return std::stoll(t);
  } catch (const std::exception&) {
    return fallback;
  }
}

}  // namespace

HlsReport read_csynth_xml(const std::string& path) {
  pugi::xml_document doc;
  const pugi::xml_parse_result ok = doc.load_file(path.c_str());
  if (!ok) throw InputError(path + ": not XML: " + ok.description());
  const pugi::xml_node profile = doc.child("profile");
  if (!profile) throw InputError(path + ": no <profile> element: not a Vitis HLS csynth report");
  HlsReport r;
  r.version = profile.child("ReportVersion").child("Version").text().as_string();
  const pugi::xml_node ua = profile.child("UserAssignments");
  r.part = ua.child("Part").text().as_string();
  r.top = ua.child("TopModelName").text().as_string();
  r.target_clock_ns = ua.child("TargetClockPeriod").text().as_double();
  const pugi::xml_node pe = profile.child("PerformanceEstimates");
  if (!pe) throw InputError(path + ": no <PerformanceEstimates> element");
  r.estimated_clock_ns = pe.child("SummaryOfTimingAnalysis").child("EstimatedClockPeriod").text().as_double();
  const pugi::xml_node lat = pe.child("SummaryOfOverallLatency");
  r.best_latency_cycles = to_int(lat, "Best-caseLatency");
  r.worst_latency_cycles = to_int(lat, "Worst-caseLatency");
  r.interval_min_cycles = to_int(lat, "Interval-min");
  r.interval_max_cycles = to_int(lat, "Interval-max");
  for (const pugi::xml_node loop : pe.child("SummaryOfLoopLatency").children()) {
    HlsLoop l;
    l.name = loop.name();
    l.trip_count = to_int(loop, "TripCount");
    l.latency_cycles = to_int(loop, "Latency");
    l.iteration_latency = to_int(loop, "IterationLatency");
    l.pipeline_ii = int(to_int(loop, "PipelineII"));
    l.pipeline_depth = int(to_int(loop, "PipelineDepth"));
    r.loops.push_back(l);
  }
  const pugi::xml_node area = profile.child("AreaEstimates");
  if (!area.child("Resources")) throw InputError(path + ": no <AreaEstimates><Resources> element");
  for (const pugi::xml_node res : area.child("Resources").children()) {
    std::string key = res.name();
    if (key == "DSP48E" || key == "DSP48E2") key = "DSP";
    r.resources[key] = res.text().as_llong();
  }
  for (const pugi::xml_node res : area.child("AvailableResources").children()) {
    std::string key = res.name();
    if (key == "DSP48E" || key == "DSP48E2") key = "DSP";
    r.available[key] = res.text().as_llong();
  }
  return r;
}

std::vector<std::string> calibrate_from_hls(config::PipelineConfig& cfg, const HlsReport& r) {
  static const std::vector<std::string> stages = {"cost",         "aggregate_back", "aggregate",     "wta_lr",
                                                  "median",       "rectify_left",   "rectify_right", "ddr_write",
                                                  "ddr_read",     "source",         "sink"};
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

}  // namespace parallax::explore

namespace parallax::explore {

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
    if (l.pipeline_ii > 0) rows.push_back({"II " + l.name, double(t.ii_cycles), double(l.pipeline_ii), "stage " + stage});
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

}  // namespace parallax::explore
