// One JSON form per result type (nlohmann::json's to_json, found by argument-dependent lookup:
// `json j = figures;`): what the commands print with --json and the reports write, built here
// once instead of field by field in each command.
#pragma once

#include <nlohmann/json.hpp>

#include "parallax/design/result.hpp"

namespace parallax {
namespace res {
// {bram18k, uram, lut, ff, dsp}.
void to_json(nlohmann::json& j, const Usage& u);
}  // namespace res

namespace design {
// device, estimate (csynth | routed), the totals, fits_device, utilisation_pct, resource_stages
// (with LUTRAM and SRL LUTs), power_estimate_w and energy_estimate_mj_per_frame.
void to_json(nlohmann::json& j, const ResourceFigures& r);
}  // namespace design

// In the namespace of its type (eval: simulate.hpp) so that lookup finds it; here, beside the
// design's other figures.
namespace eval {
// The cycle model's figures at the design's clock: cycles, latencies, host copies, frame
// interval and fps with what limits them, DDR traffic of two-pass designs, the stages (II,
// latency, firings, stalls) and the FIFOs (depth, tokens, high water, stall-free depth if sized).
void to_json(nlohmann::json& j, const SimulationResult& t);
}  // namespace eval
}  // namespace parallax
