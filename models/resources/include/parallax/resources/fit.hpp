// Calibrating the resource model on published rows (`parallax fit-resources`): the rows are
// described by the function library (functions.hpp), the DSP binding thresholds are learned as
// the ones that make the most rows exact, and the per-feature LUT and FF coefficients are fitted
// with Ceres (Cauchy loss on log residuals, non-negative, pulled weakly towards the structural
// priors). Every row is also predicted leave-one-out (fitted on every other row) and
// leave-one-family-out (fitted on the other functions' rows); designs of this project
// (models/data/published_points.yaml) are predicted as validation, never fitted on.
#pragma once

#include <string>
#include <vector>

#include "parallax/resources/functions.hpp"
#include "parallax/resources/model.hpp"
#include "parallax/resources/points_csv.hpp"

namespace parallax::res {

struct FitRow {
  std::string kernel, design;    // as published
  std::string function, family;  // the description (empty when none matched)
  std::string group;             // stereo | filter | geometric | pixelwise | flow | design
  std::string source;            // "FILE:LINE" of the row
  bool described = false;
  std::string not_described;     // why, when !described
  bool validation_only = false;  // predicted, never fitted on (this project's designs)
  // Resources (bit r = Resource r) whose published figure contradicts the function's own source
  // (models/data/excluded_points.yaml): left out of the fit and the error figures, still printed.
  unsigned excluded = 0;
  std::string excluded_why;  // the evidence, one line per excluded resource
  Inventory inventory;
  PublishedUsage published;
  Usage fitted;  // with the coefficients fitted on every row
  Usage loo;     // fitted on every other row
  Usage lofo;    // fitted on the rows of the other families
  Usage logo;    // fitted on the rows of the other groups
};

// Rows of a CSV described with `fns` (rows without a matching description or with an unstated
// variable are kept, marked not described, with the reason).
std::vector<FitRow> describe_rows(const std::vector<CsvPoint>& points, const std::vector<FunctionDescription>& fns,
                                  const std::string& file);

// Published figures that contradict their own source, with the evidence: `kernel` and `design`
// match a row's columns exactly, `resources` lists what is left out (bram18k, dsp, ff, lut).
struct Exclusion {
  std::string kernel, design, evidence;
  unsigned resources = 0;  // bit r = Resource r
};
// The compiled-in list (models/data/excluded_points.yaml), or one parsed from text. Throws
// ConfigError naming the file and the entry.
const std::vector<Exclusion>& default_exclusions();
std::vector<Exclusion> parse_exclusions(const std::string& yaml_text, const std::string& file);
// Marks the rows an exclusion matches; returns how many rows were marked.
int apply_exclusions(std::vector<FitRow>& rows, const std::vector<Exclusion>& exclusions);

// This project's published designs (models/data/published_points.yaml): the design configs are
// resolved against `root` (the repository). Throws ConfigError naming the file and the field.
std::vector<FitRow> load_design_points(const std::string& path, const std::string& root);

// |error| statistics of one resource over the rows that publish it: median, 90th percentile and
// mean of |predicted - published| / published in percent (rows with published > 0), and the
// count of exact rows (all rows that publish it, zeros included).
struct ErrorStats {
  int rows = 0, exact = 0, rows_pct = 0;
  double median_pct = 0, p90_pct = 0, mean_pct = 0;
  double exact_share() const { return rows ? double(exact) / double(rows) : 0.0; }
};
struct ResourceStats {
  ErrorStats fitted, loo, lofo, logo;
};
enum Resource : int { kResBram = 0, kResDsp, kResFf, kResLut, kResourceCount };
const char* resource_name(int r);  // "bram18k", "dsp", "ff", "lut"
int64_t pick(const Usage& u, int r);
int64_t pick(const PublishedUsage& u, int r);

struct FitResult {
  Coefficients coefficients;  // `start` with the fitted values and DSP thresholds replaced
  std::vector<FitRow> rows;   // in input order, validation rows last
  ResourceStats stats[kResourceCount];
  int described_rows = 0, fitted_rows = 0, excluded_rows = 0;
};

// Fits on the described rows that are not validation_only. Throws std::runtime_error when fewer
// than two rows can be fitted on.
FitResult fit(std::vector<FitRow> rows, const Coefficients& start);

// The fit alone (no validation), for the leave-out loops and tests: `use[i]` selects rows.
Coefficients fit_coefficients(const std::vector<FitRow>& rows, const std::vector<bool>& use, const Coefficients& start);

}  // namespace parallax::res
