// The JSON forms of the UAV room's result types (json.hpp).
#include "parallax/uav/json.hpp"

namespace parallax::uav {

void to_json(nlohmann::json& j, const AvoidAccumulator& acc) {
  const AvoidTimings& t = acc.timing_sum();
  const double n = double(acc.frames());
  j = nlohmann::json::object();
  j["frames"] = acc.frames();
  for (const auto& kv : acc.metrics()) j[kv.first] = kv.second;
  j["ms_split"] = {{"uv_maps", t.uv_maps_ms / n},
                   {"filtering", t.filtering_ms / n},
                   {"contours", t.contours_ms / n},
                   {"planning", t.planning_ms / n}};
}

void to_json(nlohmann::json& j, const TruthAccumulator& acc) {
  j = nlohmann::json::object();
  for (const auto& kv : acc.metrics()) j[kv.first] = kv.second;
}

void to_json(nlohmann::json& j, const TruthObstacle& t) {
  j = {{"id", t.id}, {"kind", t.kind}, {"range_m", t.range_m}, {"lateral_m", t.lateral_m}};
  if (t.kind == "cylinder") {
    j["x_m"] = t.x_m;
    j["z_m"] = t.z_m;
    j["radius_m"] = t.radius_m;
  } else {
    j["x0_m"] = t.x0_m;
    j["x1_m"] = t.x1_m;
    j["z0_m"] = t.z0_m;
    j["z1_m"] = t.z1_m;
  }
}

void to_json(nlohmann::json& j, const FlightSetup& s) {
  j = {{"image_px", {s.width_px, s.height_px}},
       {"focal_px", s.rig.focal_px},
       {"baseline_m", s.rig.baseline_m},
       {"frame_interval_ms", s.frame_interval_ms},
       {"latency_ms", s.latency_ms},
       {"avoid_ms", s.cfg.avoid_ms},
       {"frame_ms", s.frame_s * 1000.0}};
}

void to_json(nlohmann::json& j, const FlightResult& r) {
  j = {{"outcome", to_string(r.outcome)},      {"hit", r.hit},
       {"min_clearance_m", r.min_clearance_m}, {"time_s", r.time_s},
       {"path_length_m", r.path_length_m},     {"flips", r.flips},
       {"recoveries", r.recoveries},           {"frames", r.frames}};
}

}  // namespace parallax::uav
