// Accuracy metrics of a predicted disparity map against ground truth (docs/evaluation.md).
//
// Per frame we keep integer counts, so that pooling over frames is exact: sum the counts of all
// frames, then derive the percentages once. Thresholds:
//   correct      |error| < 3 px                              (the seed paper's metric)
//   D1 outlier   |error| > 3 px and |error| > 5 % of the GT  (KITTI's metric)
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "parallax/eval/disparity_io.hpp"

namespace parallax::eval {

constexpr double kCorrectThresholdPx = 3.0;  // correct: error < 3 px
constexpr double kD1AbsThresholdPx = 3.0;    // D1 outlier: error > 3 px ...
constexpr double kD1RelThreshold = 0.05;     // ... and error > 5 % of the GT disparity

// Integer counts of one frame (or of pooled frames). "valid" = the prediction is valid,
// "GT" = the pixel has ground truth.
struct FrameCounts {
  std::int64_t roi_pixels = 0;          // pixels evaluated (the ROI)
  std::int64_t valid_pixels = 0;        // valid estimates
  std::int64_t gt_pixels = 0;           // pixels with GT
  std::int64_t valid_gt_pixels = 0;     // valid estimates with GT
  std::int64_t correct_3px = 0;         // among valid & GT: error < 3 px
  std::int64_t d1_outliers = 0;         // among valid & GT: D1 outliers
  std::int64_t d1_outliers_filled = 0;  // among GT, after devkit filling: D1 outliers
  double abs_error_sum_px = 0.0;        // among valid & GT: sum of |error|

  FrameCounts& operator+=(const FrameCounts& other);
};

// Derived values. A value whose denominator is 0 is NaN (e.g. no GT pixel at all).
struct DerivedMetrics {
  double density_pct = 0.0;        // valid_pixels / roi_pixels
  double density_gt_pct = 0.0;     // valid_gt_pixels / gt_pixels
  double correct_3px_pct = 0.0;    // correct_3px / valid_gt_pixels
  double d1_all_pct = 0.0;         // d1_outliers / valid_gt_pixels
  double d1_all_filled_pct = 0.0;  // d1_outliers_filled / gt_pixels (KITTI's official D1-all)
  double mean_abs_error_px = 0.0;  // abs_error_sum_px / valid_gt_pixels
};

// Counts one frame. All four maps have the same size (the ROI): disparity_px and gt_px CV_32FC1,
// valid_mask and gt_mask CV_8UC1, non-zero = valid / GT present. Throws std::invalid_argument on
// other types or sizes.
FrameCounts count_frame(const cv::Mat& disparity_px, const cv::Mat& valid_mask, const cv::Mat& gt_px,
                        const cv::Mat& gt_mask);

// The derived values of some counts.
DerivedMetrics derive_metrics(const FrameCounts& counts);

// Sum of the counts of many frames.
FrameCounts pool_counts(const std::vector<FrameCounts>& frames);

// One row of a per-frame table.
struct FrameRow {
  std::string frame_id;
  FrameCounts counts;
  DerivedMetrics metrics;
};

FrameRow make_frame_row(std::string frame_id, const FrameCounts& counts);
// The pooled row of many rows (counts summed, then derived).
FrameRow pool_rows(const std::vector<FrameRow>& rows, std::string pooled_id = "pooled");

// The derived values under their report keys, in this order: density_pct, density_gt_pct,
// correct_3px_pct, d1_all_pct, d1_all_filled_pct, mean_abs_error_px.
std::vector<std::pair<std::string, double>> named_metrics(const DerivedMetrics& metrics);
// The integer counts under their report keys, in declaration order of FrameCounts
// (roi_pixels, valid_pixels, gt_pixels, valid_gt_pixels, correct_3px, d1_outliers,
// d1_outliers_filled); abs_error_sum_px is a double and is not included.
std::vector<std::pair<std::string, std::int64_t>> named_counts(const FrameCounts& counts);

// KITTI devkit's DisparityImage::interpolateBackground (devkit io_disp.h), used before the
// official D1 so that invalid predictions still get a value. Contract in metrics.cpp. Returns
// the filled map: pixels that got a value are valid (mask 255); pixels the devkit leaves unset
// (all pixels of a frame without any valid pixel, rows without a valid pixel between valid
// rows) stay invalid (mask 0).
DisparityMap interpolate_background(const cv::Mat& disparity_px, const cv::Mat& valid_mask);

}  // namespace parallax::eval
