// One JSON form per result type of the UAV room (nlohmann::json's to_json, found by
// argument-dependent lookup: `json j = result;`): what avoid and fly print with --json and what
// scene writes to obstacles.json, built here once instead of field by field in each command.
// Objects are plain nlohmann::json (keys in alphabetical order when dumped).
#pragma once

#include <nlohmann/json.hpp>

#include "parallax/uav/avoid.hpp"
#include "parallax/uav/fly.hpp"
#include "parallax/uav/truth.hpp"

namespace parallax::uav {

// The scores over the frames so far: frames, the named scores (AvoidAccumulator::metrics():
// obstacle_precision, obstacle_recall, range_error_m, decision_agreement_pct, mean_ms_per_frame)
// and ms_split, the design's stage per frame split into uv_maps, filtering, contours and planning
// (mean ms; NaN, dumped as null, before the first frame).
void to_json(nlohmann::json& j, const AvoidAccumulator& acc);
// The named scores against the scene's obstacles (TruthAccumulator::metrics()); the parameters
// it scores with are not part of it.
void to_json(nlohmann::json& j, const TruthAccumulator& acc);
// An obstacle of obstacles.json: id, kind, range_m, lateral_m, and x_m, z_m, radius_m for a
// cylinder or x0_m, x1_m, z0_m, z1_m for a box (what read_truth reads back).
void to_json(nlohmann::json& j, const TruthObstacle& t);
// What a flight is flown with: image_px [width, height], focal_px and baseline_m of the rig,
// frame_interval_ms and latency_ms (the design's, from the cycle model), avoid_ms (the
// configuration's avoidance stage) and frame_ms (the frame period flown, ms).
void to_json(nlohmann::json& j, const FlightSetup& s);
// One flight's outcome: outcome, hit (the obstacle of a collision, else ""), min_clearance_m,
// time_s, path_length_m, flips, recoveries and frames. The trajectory, poses, setpoints and the
// wall-clock figures are not part of it.
void to_json(nlohmann::json& j, const FlightResult& r);

}  // namespace parallax::uav
