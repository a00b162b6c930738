// One JSON form per result type of the scoring room (nlohmann::json's to_json, found by
// argument-dependent lookup: `json j = result;`): what eval, score, baseline, run and bench print
// with --json, built here once instead of field by field in each command. Objects are plain
// nlohmann::json (keys in alphabetical order when dumped); a NaN measure (no pixel to divide by)
// dumps as null.
#pragma once

#include <nlohmann/json.hpp>

#include "parallax/eval/bench.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/evaluate.hpp"
#include "parallax/eval/metrics.hpp"

namespace parallax::eval {

// The measures under their report keys (named_metrics): density_pct, density_gt_pct,
// correct_3px_pct, d1_all_pct, d1_all_filled_pct, mean_abs_error_px.
void to_json(nlohmann::json& j, const DerivedMetrics& m);
// The integer counts under their report keys (named_counts: roi_pixels ... d1_outliers_filled;
// abs_error_sum_px is left out).
void to_json(nlohmann::json& j, const FrameCounts& c);
// A frame's row: its measures (DerivedMetrics' form) and frame (its id). The counts are left out:
// an evaluation carries the pooled counts once (EvalResult's form).
void to_json(nlohmann::json& j, const FrameRow& r);
// An evaluation: the pooled measures at the top level, frames (how many), counts (the pooled
// counts), per_frame (FrameRow's form, dataset order) and seconds. The notes are not part of it
// (the commands print them on stderr).
void to_json(nlohmann::json& j, const EvalResult& r);
// A region of interest in its image: x0, y0, width_px, height_px.
void to_json(nlohmann::json& j, const Roi& r);
// One bench row: method, median_ms, min_ms, peak_rss_mib, peak_extra_rss_mib, ratio_to_hh4 and
// min_ratio_to_hh4 (the ratios to the first OpenCV row, MODE_HH4).
void to_json(nlohmann::json& j, const BenchRow& r);

}  // namespace parallax::eval
