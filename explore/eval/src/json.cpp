// The JSON forms of the scoring room's result types (json.hpp).
#include "parallax/eval/json.hpp"

namespace parallax::eval {

void to_json(nlohmann::json& j, const DerivedMetrics& m) {
  j = nlohmann::json::object();
  for (const auto& kv : named_metrics(m)) j[kv.first] = kv.second;
}

void to_json(nlohmann::json& j, const FrameCounts& c) {
  j = nlohmann::json::object();
  for (const auto& kv : named_counts(c)) j[kv.first] = kv.second;
}

void to_json(nlohmann::json& j, const FrameRow& r) {
  j = r.metrics;
  j["frame"] = r.frame_id;
}

void to_json(nlohmann::json& j, const EvalResult& r) {
  j = r.pooled.metrics;
  j["frames"] = int(r.frames.size());
  j["counts"] = r.pooled.counts;
  j["per_frame"] = r.frames;
  j["seconds"] = r.seconds;
}

void to_json(nlohmann::json& j, const Roi& r) {
  j = {{"x0", r.x0}, {"y0", r.y0}, {"width_px", r.width_px}, {"height_px", r.height_px}};
}

void to_json(nlohmann::json& j, const BenchRow& r) {
  j = {{"method", r.method},
       {"median_ms", r.median_ms},
       {"min_ms", r.min_ms},
       {"peak_rss_mib", r.peak_rss_mib},
       {"peak_extra_rss_mib", r.peak_extra_rss_mib},
       {"ratio_to_hh4", r.ratio_to_peer},
       {"min_ratio_to_hh4", r.min_ratio_to_peer},
       {"ratio_to_sgbm", r.ratio_to_sgbm},
       {"min_ratio_to_sgbm", r.min_ratio_to_sgbm}};
}

}  // namespace parallax::eval
