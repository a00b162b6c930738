// The JSON forms of the HLS flow's result types (json.hpp).
#include "parallax/hls_flow/json.hpp"

namespace parallax::hlsx {

void to_json(nlohmann::json& j, const ExportFifo& f) {
  j = {{"name", f.name}, {"depth", f.depth}, {"stall_free", f.stall_free}, {"why", f.why}};
}

void to_json(nlohmann::json& j, const ExportPrediction& p) {
  j = {{"last_pixel_cycle", p.last_pixel_cycle},
       {"fpga_latency_ms", p.fpga_latency_ms},
       {"cycles_per_frame", p.cycles_per_frame},
       {"fps", p.fps},
       {"device", p.device},
       {"bram18k", p.bram18k},
       {"lut", p.lut},
       {"ff", p.ff},
       {"dsp", p.dsp},
       {"fits", p.fits}};
}

void to_json(nlohmann::json& j, const ExportRequest& r) {
  j = nlohmann::json::object();
  j["design"] = r.config.name;
  j["part"] = r.part;
  j["clock_mhz"] = r.clock_mhz;
  j["fifos"] = r.fifos;
  j["prediction"] = r.prediction;
  j["prediction"]["estimate"] = r.config.estimate;
}

}  // namespace parallax::hlsx

namespace parallax::hls_flow {

void to_json(nlohmann::json& j, const HlsLoop& l) {
  j = {{"name", l.name},
       {"trip_count", l.trip_count},
       {"latency_cycles", l.latency_cycles},
       {"ii", l.pipeline_ii},
       {"depth", l.pipeline_depth}};
}

void to_json(nlohmann::json& j, const HlsReport& r) {
  j = nlohmann::json::object();
  j["part"] = r.part;
  j["top"] = r.top;
  j["target_clock_ns"] = r.target_clock_ns;
  j["estimated_clock_ns"] = r.estimated_clock_ns;
  j["latency_cycles"] = {{"best", r.best_latency_cycles}, {"worst", r.worst_latency_cycles}};
  j["interval_cycles"] = {{"min", r.interval_min_cycles}, {"max", r.interval_max_cycles}};
  j["loops"] = r.loops;
  j["resources"] = r.resources;
  j["available"] = r.available;
}

void to_json(nlohmann::json& j, const ModelVsSynthesis& c) {
  j = {{"figure", c.figure}, {"model", c.model}, {"synthesis", c.synthesis}, {"note", c.note}};
}

}  // namespace parallax::hls_flow
