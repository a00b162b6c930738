// Accuracy metrics: per-frame integer counts, pooling, derived percentages, and the KITTI
// devkit's background interpolation for the official D1.
#include "parallax/eval/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace parallax::eval {
namespace {

void require_same_size(const cv::Mat& a, const cv::Mat& b, const char* name_a, const char* name_b) {
  if (a.size() != b.size()) {
    throw std::invalid_argument(std::string("metrics: ") + name_a + " is " + std::to_string(a.cols) + "x" +
                                std::to_string(a.rows) + " but " + name_b + " is " + std::to_string(b.cols) + "x" +
                                std::to_string(b.rows));
  }
}

void require_type(const cv::Mat& m, int type, const char* name, const char* type_name) {
  if (m.empty() || m.type() != type) {
    throw std::invalid_argument(std::string("metrics: ") + name + " must be a non-empty " + type_name + " matrix");
  }
}

double ratio(double numerator, std::int64_t denominator) {
  if (denominator == 0) return std::numeric_limits<double>::quiet_NaN();
  return numerator / static_cast<double>(denominator);
}

double percent(std::int64_t numerator, std::int64_t denominator) {
  return 100.0 * ratio(static_cast<double>(numerator), denominator);
}

// |error| > 3 px and |error| > 5 % of the GT. The relative test is written error * 20 > gt,
// which is exact in double for float inputs (0.05 is not representable, 20 is).
bool is_d1_outlier(double error_px, double gt_px) {
  return (error_px > kD1AbsThresholdPx) & (error_px * 20.0 > gt_px);  // both tested: no branch
}

}  // namespace

FrameCounts& FrameCounts::operator+=(const FrameCounts& other) {
  roi_pixels += other.roi_pixels;
  valid_pixels += other.valid_pixels;
  gt_pixels += other.gt_pixels;
  valid_gt_pixels += other.valid_gt_pixels;
  correct_3px += other.correct_3px;
  d1_outliers += other.d1_outliers;
  d1_outliers_filled += other.d1_outliers_filled;
  abs_error_sum_px += other.abs_error_sum_px;
  return *this;
}

// Contract (KITTI stereo devkit, io_disp.h, DisparityImage::interpolateBackground), applied to
// a copy of the prediction; "valid" means the mask is non-zero or the pixel was set by an
// earlier step:
//  1. For each row, left to right: each run of invalid pixels lying strictly inside the row
//     (first pixel of the run at column > 0 and a valid pixel right after it) gets
//     min(value left of the run, value right of the run). Runs touching column 0 are skipped
//     here; runs touching the last column have no right neighbour and are skipped too.
//  2. In the same row: the pixels before the first valid one get the first valid value; the
//     pixels after the last valid one get the last valid value. A row without any valid pixel
//     is left unchanged.
//  3. For each column, after all rows are done: the pixels above the first valid one get its
//     value; the pixels below the last valid one get its value. (So a row with no valid pixel
//     between rows with valid pixels stays invalid, exactly as in the devkit.)
// A map with no valid pixel at all stays entirely invalid.
DisparityMap interpolate_background(const cv::Mat& disparity_px, const cv::Mat& valid_mask) {
  require_type(disparity_px, CV_32FC1, "disparity", "CV_32FC1");
  require_type(valid_mask, CV_8UC1, "validity mask", "CV_8UC1");
  require_same_size(disparity_px, valid_mask, "disparity", "validity mask");

  const int width_px = disparity_px.cols;
  const int height_px = disparity_px.rows;
  cv::Mat d = disparity_px.clone();
  cv::Mat valid(valid_mask.size(), CV_8UC1);
  for (int y = 0; y < height_px; ++y) {
    const std::uint8_t* in = valid_mask.ptr<std::uint8_t>(y);
    std::uint8_t* out = valid.ptr<std::uint8_t>(y);
    for (int x = 0; x < width_px; ++x) out[x] = in[x] != 0 ? 255 : 0;
  }

  for (int y = 0; y < height_px; ++y) {
    float* row = d.ptr<float>(y);
    std::uint8_t* ok = valid.ptr<std::uint8_t>(y);
    // Step 1: inner runs.
    int run_length = 0;
    for (int x = 0; x < width_px; ++x) {
      if (ok[x] != 0) {
        if (run_length >= 1) {
          const int first = x - run_length;
          const int last = x - 1;
          if (first > 0 && last < width_px - 1) {
            const float fill = std::min(row[first - 1], row[last + 1]);
            for (int u = first; u <= last; ++u) {
              row[u] = fill;
              ok[u] = 255;
            }
          }
        }
        run_length = 0;
      } else {
        ++run_length;
      }
    }
    // Step 2: left and right extrapolation.
    for (int x = 0; x < width_px; ++x) {
      if (ok[x] != 0) {
        for (int u = 0; u < x; ++u) {
          row[u] = row[x];
          ok[u] = 255;
        }
        break;
      }
    }
    for (int x = width_px - 1; x >= 0; --x) {
      if (ok[x] != 0) {
        for (int u = x + 1; u < width_px; ++u) {
          row[u] = row[x];
          ok[u] = 255;
        }
        break;
      }
    }
  }

  // Step 3: top and bottom extrapolation per column, row by row: each column's first and last
  // valid rows after steps 1-2, then the rows above the first take its value and those below the
  // last take the last's (the two fills are disjoint and neither changes its source).
  std::vector<int> first_row(static_cast<std::size_t>(width_px), -1), last_row(first_row);
  for (int y = 0; y < height_px; ++y) {
    const std::uint8_t* ok = valid.ptr<std::uint8_t>(y);
    for (int x = 0; x < width_px; ++x) {
      if (ok[x] == 0) continue;
      if (first_row[std::size_t(x)] < 0) first_row[std::size_t(x)] = y;
      last_row[std::size_t(x)] = y;
    }
  }
  for (int y = 0; y < height_px; ++y) {
    float* row = d.ptr<float>(y);
    std::uint8_t* ok = valid.ptr<std::uint8_t>(y);
    for (int x = 0; x < width_px; ++x) {
      const int top = first_row[std::size_t(x)], bottom = last_row[std::size_t(x)];
      if (top < 0 || (y >= top && y <= bottom)) continue;
      row[x] = d.ptr<float>(y < top ? top : bottom)[x];
      ok[x] = 255;
    }
  }
  return DisparityMap{d, valid};
}

FrameCounts count_frame(const cv::Mat& disparity_px, const cv::Mat& valid_mask, const cv::Mat& gt_px,
                        const cv::Mat& gt_mask) {
  require_type(disparity_px, CV_32FC1, "disparity", "CV_32FC1");
  require_type(valid_mask, CV_8UC1, "validity mask", "CV_8UC1");
  require_type(gt_px, CV_32FC1, "GT disparity", "CV_32FC1");
  require_type(gt_mask, CV_8UC1, "GT mask", "CV_8UC1");
  require_same_size(disparity_px, valid_mask, "disparity", "validity mask");
  require_same_size(disparity_px, gt_px, "disparity", "GT disparity");
  require_same_size(disparity_px, gt_mask, "disparity", "GT mask");

  const DisparityMap filled = interpolate_background(disparity_px, valid_mask);

  FrameCounts c;
  c.roi_pixels = static_cast<std::int64_t>(disparity_px.rows) * disparity_px.cols;
  for (int y = 0; y < disparity_px.rows; ++y) {
    const float* d = disparity_px.ptr<float>(y);
    const std::uint8_t* ok = valid_mask.ptr<std::uint8_t>(y);
    const float* g = gt_px.ptr<float>(y);
    const std::uint8_t* has_gt = gt_mask.ptr<std::uint8_t>(y);
    const float* f = filled.disparity_px.ptr<float>(y);
    const std::uint8_t* f_ok = filled.valid_mask.ptr<std::uint8_t>(y);
    // Counted without branches on the data (validity and outliers are scattered pixel by pixel;
    // the GT mask comes in long runs): an invalid pixel adds zero to every count and +0.0 to the
    // error sum, which leaves a sum of non-negative terms exactly as it was.
    for (int x = 0; x < disparity_px.cols; ++x) {
      const bool valid = ok[x] != 0;
      c.valid_pixels += valid;
      if (has_gt[x] == 0) continue;
      ++c.gt_pixels;
      const double gt = g[x];
      // Official D1: the filled prediction over all GT pixels; a pixel the fill leaves
      // invalid counts as an outlier.
      c.d1_outliers_filled += (f_ok[x] == 0) | is_d1_outlier(std::abs(static_cast<double>(f[x]) - gt), gt);
      const double error_px = std::abs(static_cast<double>(d[x]) - gt);
      c.valid_gt_pixels += valid;
      c.correct_3px += valid & (error_px < kCorrectThresholdPx);
      c.d1_outliers += valid & is_d1_outlier(error_px, gt);
      c.abs_error_sum_px += valid ? error_px : 0.0;
    }
  }
  return c;
}

DerivedMetrics derive_metrics(const FrameCounts& c) {
  DerivedMetrics m;
  m.density_pct = percent(c.valid_pixels, c.roi_pixels);
  m.density_gt_pct = percent(c.valid_gt_pixels, c.gt_pixels);
  m.correct_3px_pct = percent(c.correct_3px, c.valid_gt_pixels);
  m.d1_all_pct = percent(c.d1_outliers, c.valid_gt_pixels);
  m.d1_all_filled_pct = percent(c.d1_outliers_filled, c.gt_pixels);
  m.mean_abs_error_px = ratio(c.abs_error_sum_px, c.valid_gt_pixels);
  return m;
}

FrameCounts pool_counts(const std::vector<FrameCounts>& frames) {
  FrameCounts total;
  for (const FrameCounts& f : frames) total += f;
  return total;
}

FrameRow make_frame_row(std::string frame_id, const FrameCounts& counts) {
  return FrameRow{std::move(frame_id), counts, derive_metrics(counts)};
}

FrameRow pool_rows(const std::vector<FrameRow>& rows, std::string pooled_id) {
  FrameCounts total;
  for (const FrameRow& r : rows) total += r.counts;
  return make_frame_row(std::move(pooled_id), total);
}

std::vector<std::pair<std::string, double>> named_metrics(const DerivedMetrics& m) {
  return {{"density_pct", m.density_pct},
          {"density_gt_pct", m.density_gt_pct},
          {"correct_3px_pct", m.correct_3px_pct},
          {"d1_all_pct", m.d1_all_pct},
          {"d1_all_filled_pct", m.d1_all_filled_pct},
          {"mean_abs_error_px", m.mean_abs_error_px}};
}

std::vector<std::pair<std::string, std::int64_t>> named_counts(const FrameCounts& c) {
  return {{"roi_pixels", c.roi_pixels},
          {"valid_pixels", c.valid_pixels},
          {"gt_pixels", c.gt_pixels},
          {"valid_gt_pixels", c.valid_gt_pixels},
          {"correct_3px", c.correct_3px},
          {"d1_outliers", c.d1_outliers},
          {"d1_outliers_filled", c.d1_outliers_filled}};
}

}  // namespace parallax::eval
