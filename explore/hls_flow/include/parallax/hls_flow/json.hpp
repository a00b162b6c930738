// One JSON form per result type of the HLS flow (nlohmann::json's to_json, found by
// argument-dependent lookup: `json j = request;`): what export-hls and import-hls print with
// --json, built here once instead of field by field in the commands. The export's types belong to
// the generator (hls/, namespace hlsx); their forms live here, beside the flow that prepares
// them, so that the generator needs no JSON. Objects are plain nlohmann::json (keys in
// alphabetical order when dumped).
#pragma once

#include <nlohmann/json.hpp>

#include "parallax/hls/export.hpp"
#include "parallax/hls_flow/hls_report.hpp"

namespace parallax::hlsx {

// A FIFO of the exported top: name, depth, stall_free (-1: not sized) and why.
void to_json(nlohmann::json& j, const ExportFifo& f);
// The models' prediction for the exported design: last_pixel_cycle, fpga_latency_ms,
// cycles_per_frame, fps, device, bram18k, lut, ff, dsp and fits.
void to_json(nlohmann::json& j, const ExportPrediction& p);
// An export: design (the configuration's name), part, clock_mhz (the synthesis clock), fifos
// (ExportFifo's form, pipeline order) and prediction (ExportPrediction's form with estimate, the
// configuration's resource estimate flavour). The testbench's pair, golden output and maps are
// not part of it.
void to_json(nlohmann::json& j, const ExportRequest& r);

}  // namespace parallax::hlsx

namespace parallax::hls_flow {

// A loop of a csynth report: name, trip_count, latency_cycles, ii and depth (-1: not reported or
// not pipelined).
void to_json(nlohmann::json& j, const HlsLoop& l);
// A csynth report: part, top, target_clock_ns, estimated_clock_ns, latency_cycles {best, worst},
// interval_cycles {min, max}, loops (HlsLoop's form), resources and available (by resource name).
// The tool's version is not part of it.
void to_json(nlohmann::json& j, const HlsReport& r);
// A figure of the models beside synthesis: figure, model, synthesis (-1: no figure) and note.
void to_json(nlohmann::json& j, const ModelVsSynthesis& c);

}  // namespace parallax::hls_flow
