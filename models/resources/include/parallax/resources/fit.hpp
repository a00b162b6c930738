// Fitting the resource model's coefficients to published designs (Ceres, robust loss), with
// leave-one-out validation: `parallax fit-resources`.
#pragma once

#include <string>
#include <vector>

#include "parallax/resources/model.hpp"

namespace parallax::res {

struct PublishedPoint {
  std::string name, source;
  Inventory inventory;  // what our kernels declare for the published configuration
  Usage published;
};

// Reads models/data/published_points.yaml; design configs are resolved against `root` (the
// repository). Throws std::runtime_error naming the file and the field.
std::vector<PublishedPoint> load_points(const std::string& path, const std::string& root);

struct FitRow {
  std::string name;
  Usage published;
  Usage fitted;  // with the coefficients fitted on every point
  Usage loo;     // with the coefficients fitted on every other point
};
struct FitResult {
  Coefficients coefficients;  // start with the fitted section replaced
  std::vector<FitRow> rows;
  // |loo - published| / published, in percent, over the points.
  double lut_loo_mean_pct = 0, lut_loo_max_pct = 0, ff_loo_mean_pct = 0, ff_loo_max_pct = 0;
};

// LUT = lut_scale x operator LUTs + memory LUTs + lut_per_stage x stages + lut_per_memory x
// memories; FF = register bits + ff_per_op_bit x operator bits + ff_per_stage x stages. The
// fitted coefficients are non-negative; residuals are relative, under a Huber loss (0.1).
FitResult fit(const std::vector<PublishedPoint>& points, const Coefficients& start);

}  // namespace parallax::res
