// Metrics on hand-made maps with hand-computed counts, pooling, and the devkit fill.
#include "parallax/eval/metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <vector>

namespace px = parallax::eval;

namespace {

constexpr float kNo = -1.0f;  // marks "invalid / no GT" in the literal maps below

// A CV_32F map and its CV_8U mask from row-major literals; kNo = invalid.
px::DisparityMap make_map(int rows, int cols, const std::vector<float>& values) {
  px::DisparityMap m{cv::Mat(rows, cols, CV_32FC1, cv::Scalar(0)), cv::Mat(rows, cols, CV_8UC1, cv::Scalar(0))};
  for (int y = 0; y < rows; ++y) {
    for (int x = 0; x < cols; ++x) {
      const float v = values.at(static_cast<std::size_t>(y * cols + x));
      if (v == kNo) continue;
      m.disparity_px.at<float>(y, x) = v;
      m.valid_mask.at<std::uint8_t>(y, x) = 255;
    }
  }
  return m;
}

// The filled map as literals (kNo where the fill left the pixel invalid).
std::vector<float> literal(const px::DisparityMap& m) {
  std::vector<float> out;
  for (int y = 0; y < m.disparity_px.rows; ++y)
    for (int x = 0; x < m.disparity_px.cols; ++x)
      out.push_back(m.valid_mask.at<std::uint8_t>(y, x) != 0 ? m.disparity_px.at<float>(y, x) : kNo);
  return out;
}

std::vector<float> fill(int rows, int cols, const std::vector<float>& values) {
  const px::DisparityMap in = make_map(rows, cols, values);
  return literal(px::interpolate_background(in.disparity_px, in.valid_mask));
}

px::FrameCounts count(const px::DisparityMap& pred, const px::DisparityMap& gt) {
  return px::count_frame(pred.disparity_px, pred.valid_mask, gt.disparity_px, gt.valid_mask);
}

}  // namespace

// 2x4 frame. Pixel by pixel (prediction vs GT):
//   p0 10 vs 10   err 0  correct
//   p1 13 vs 10   err 3  not correct (3 is not < 3), not D1 (3 is not > 3)
//   p2 14 vs 10   err 4  D1 (4 > 3 and 4 > 0.5)
//   p3 104 vs 100 err 4  not D1 (4 <= 5 % of 100)
//   p4 106 vs 100 err 6  D1
//   p5 105 vs 100 err 5  not D1 (5 is not > 5)
//   p6 invalid vs 20     GT without estimate; fill: min(105, 7) = 7, err 13 -> D1 filled
//   p7 7 vs no GT        valid without GT
TEST(Metrics, HandComputedCounts) {
  const px::DisparityMap pred = make_map(2, 4, {10, 13, 14, 104, 106, 105, kNo, 7});
  const px::DisparityMap gt = make_map(2, 4, {10, 10, 10, 100, 100, 100, 20, kNo});
  const px::FrameCounts c = count(pred, gt);
  EXPECT_EQ(c.roi_pixels, 8);
  EXPECT_EQ(c.valid_pixels, 7);
  EXPECT_EQ(c.gt_pixels, 7);
  EXPECT_EQ(c.valid_gt_pixels, 6);
  EXPECT_EQ(c.correct_3px, 1);
  EXPECT_EQ(c.d1_outliers, 2);
  EXPECT_EQ(c.d1_outliers_filled, 3);
  EXPECT_DOUBLE_EQ(c.abs_error_sum_px, 22.0);

  const px::DerivedMetrics m = px::derive_metrics(c);
  EXPECT_DOUBLE_EQ(m.density_pct, 100.0 * 7 / 8);
  EXPECT_DOUBLE_EQ(m.density_gt_pct, 100.0 * 6 / 7);
  EXPECT_DOUBLE_EQ(m.correct_3px_pct, 100.0 * 1 / 6);
  EXPECT_DOUBLE_EQ(m.d1_all_pct, 100.0 * 2 / 6);
  EXPECT_DOUBLE_EQ(m.d1_all_filled_pct, 100.0 * 3 / 7);
  EXPECT_DOUBLE_EQ(m.mean_abs_error_px, 22.0 / 6);
}

TEST(Metrics, ThresholdBoundaries) {
  // err 2.99 correct, err 3 not; relative boundary: gt 80, err 4 is exactly 5 % -> not D1;
  // gt 79.5, err 4 -> D1; gt 0, err 3.5 -> D1; negative error counts by magnitude.
  const px::DisparityMap pred = make_map(1, 6, {12.99f, 13, 84, 83.5f, 3.5f, 6});
  const px::DisparityMap gt = make_map(1, 6, {10, 10, 80, 79.5f, 0, 10});
  const px::FrameCounts c = count(pred, gt);
  EXPECT_EQ(c.valid_gt_pixels, 6);
  EXPECT_EQ(c.correct_3px, 1);
  EXPECT_EQ(c.d1_outliers, 3);  // 83.5 vs 79.5, 3.5 vs 0, 6 vs 10
  EXPECT_EQ(c.d1_outliers_filled, 3);
}

TEST(Metrics, NoGtGivesNaN) {
  const px::DisparityMap pred = make_map(1, 2, {1, 2});
  const px::DisparityMap gt = make_map(1, 2, {kNo, kNo});
  const px::DerivedMetrics m = px::derive_metrics(count(pred, gt));
  EXPECT_DOUBLE_EQ(m.density_pct, 100.0);
  EXPECT_TRUE(std::isnan(m.density_gt_pct));
  EXPECT_TRUE(std::isnan(m.correct_3px_pct));
  EXPECT_TRUE(std::isnan(m.d1_all_filled_pct));
  EXPECT_TRUE(std::isnan(m.mean_abs_error_px));
}

TEST(Metrics, NoValidPredictionCountsAllGtAsFilledOutliers) {
  const px::DisparityMap pred = make_map(2, 2, {kNo, kNo, kNo, kNo});
  const px::DisparityMap gt = make_map(2, 2, {1, 1, kNo, 50});  // even tiny GT: outlier
  const px::FrameCounts c = count(pred, gt);
  EXPECT_EQ(c.valid_pixels, 0);
  EXPECT_EQ(c.gt_pixels, 3);
  EXPECT_EQ(c.valid_gt_pixels, 0);
  EXPECT_EQ(c.d1_outliers_filled, 3);
  EXPECT_DOUBLE_EQ(px::derive_metrics(c).d1_all_filled_pct, 100.0);
}

TEST(Metrics, KeyNames) {
  const auto named = px::named_metrics(px::DerivedMetrics{});
  const std::vector<std::string> keys = {"density_pct", "density_gt_pct",    "correct_3px_pct",
                                         "d1_all_pct",  "d1_all_filled_pct", "mean_abs_error_px"};
  ASSERT_EQ(named.size(), keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) EXPECT_EQ(named[i].first, keys[i]);
  px::FrameCounts c;
  c.correct_3px = 5;
  const auto counts = px::named_counts(c);
  ASSERT_EQ(counts.size(), 7u);
  EXPECT_EQ(counts[4].first, "correct_3px");
  EXPECT_EQ(counts[4].second, 5);
}

TEST(Metrics, RejectsMismatchedInputs) {
  const px::DisparityMap a = make_map(2, 2, {1, 2, 3, 4});
  const px::DisparityMap b = make_map(2, 3, {1, 2, 3, 4, 5, 6});
  EXPECT_THROW(count(a, b), std::invalid_argument);
  cv::Mat wrong_type(2, 2, CV_16UC1, cv::Scalar(0));
  EXPECT_THROW(px::count_frame(a.disparity_px, wrong_type, a.disparity_px, a.valid_mask), std::invalid_argument);
}

// Pooled counts equal the counts of one frame made by putting the frames side by side. Each
// frame's first and last columns are valid, so the devkit fill never crosses frame borders and
// even the filled D1 count must match.
TEST(Metrics, PoolingEqualsConcatenation) {
  cv::RNG rng(12345);
  const int rows = 9;
  std::vector<px::DisparityMap> preds;
  std::vector<px::DisparityMap> gts;
  std::vector<px::FrameRow> frame_rows;
  for (int f = 0; f < 4; ++f) {
    const int cols = 5 + 3 * f;
    px::DisparityMap pred{cv::Mat(rows, cols, CV_32FC1), cv::Mat(rows, cols, CV_8UC1)};
    px::DisparityMap gt{cv::Mat(rows, cols, CV_32FC1), cv::Mat(rows, cols, CV_8UC1)};
    for (int y = 0; y < rows; ++y) {
      for (int x = 0; x < cols; ++x) {
        const float g = static_cast<float>(rng.uniform(0.0, 80.0));
        gt.disparity_px.at<float>(y, x) = g;
        gt.valid_mask.at<std::uint8_t>(y, x) = rng.uniform(0, 4) == 0 ? 0 : 255;
        pred.disparity_px.at<float>(y, x) = g + static_cast<float>(rng.uniform(-8.0, 8.0));
        const bool border = x == 0 || x == cols - 1;
        pred.valid_mask.at<std::uint8_t>(y, x) = border || rng.uniform(0, 3) != 0 ? 255 : 0;
      }
    }
    frame_rows.push_back(px::make_frame_row("f" + std::to_string(f), count(pred, gt)));
    preds.push_back(pred);
    gts.push_back(gt);
  }
  px::DisparityMap all_pred;
  px::DisparityMap all_gt;
  std::vector<cv::Mat> pd, pm, gd, gm;
  for (std::size_t i = 0; i < preds.size(); ++i) {
    pd.push_back(preds[i].disparity_px);
    pm.push_back(preds[i].valid_mask);
    gd.push_back(gts[i].disparity_px);
    gm.push_back(gts[i].valid_mask);
  }
  cv::hconcat(pd, all_pred.disparity_px);
  cv::hconcat(pm, all_pred.valid_mask);
  cv::hconcat(gd, all_gt.disparity_px);
  cv::hconcat(gm, all_gt.valid_mask);
  const px::FrameCounts whole = count(all_pred, all_gt);

  const px::FrameRow pooled = px::pool_rows(frame_rows);
  EXPECT_EQ(pooled.frame_id, "pooled");
  EXPECT_EQ(px::named_counts(pooled.counts), px::named_counts(whole));
  EXPECT_NEAR(pooled.counts.abs_error_sum_px, whole.abs_error_sum_px, 1e-9);
  EXPECT_GT(whole.d1_outliers_filled, whole.d1_outliers);  // the fill did something

  std::vector<px::FrameCounts> counts;
  for (const px::FrameRow& r : frame_rows) counts.push_back(r.counts);
  const px::FrameCounts summed = px::pool_counts(counts);
  EXPECT_EQ(px::named_counts(summed), px::named_counts(whole));
  const px::DerivedMetrics a = px::derive_metrics(whole);
  EXPECT_DOUBLE_EQ(pooled.metrics.correct_3px_pct, a.correct_3px_pct);
  EXPECT_DOUBLE_EQ(pooled.metrics.d1_all_filled_pct, a.d1_all_filled_pct);
  EXPECT_NEAR(pooled.metrics.mean_abs_error_px, a.mean_abs_error_px, 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Devkit fill (interpolateBackground)

TEST(DevkitFill, InnerRunsTakeTheSmallerNeighbour) {
  EXPECT_EQ(fill(1, 6, {1, kNo, kNo, 4, kNo, 2}), (std::vector<float>{1, 1, 1, 4, 2, 2}));
  EXPECT_EQ(fill(1, 5, {9, kNo, 3, kNo, 8}), (std::vector<float>{9, 3, 3, 3, 8}));
}

TEST(DevkitFill, LeftAndRightExtrapolation) {
  EXPECT_EQ(fill(1, 7, {kNo, kNo, 5, kNo, 3, kNo, kNo}), (std::vector<float>{5, 5, 5, 3, 3, 3, 3}));
  EXPECT_EQ(fill(1, 3, {kNo, 7, kNo}), (std::vector<float>{7, 7, 7}));
  // A run touching column 0 is extrapolated with the first valid value, not min-filled.
  EXPECT_EQ(fill(1, 4, {kNo, kNo, 2, 9}), (std::vector<float>{2, 2, 2, 9}));
  // A valid 0 is a value like any other.
  EXPECT_EQ(fill(1, 4, {0, kNo, 6, kNo}), (std::vector<float>{0, 0, 6, 6}));
}

TEST(DevkitFill, TopAndBottomExtrapolationAndEmptyRows) {
  // Rows: 0 empty, 1 = [1 . 3], 2 empty (between valid rows), 3 = [. . 9], 4 empty.
  const std::vector<float> filled = fill(5, 3, {kNo, kNo, kNo, 1, kNo, 3, kNo, kNo, kNo, kNo, kNo, 9, kNo, kNo, kNo});
  const std::vector<float> expected = {1,   1,   3,    // top: copies row 1 after its fill
                                       1,   1,   3,    // inner run: min(1, 3)
                                       kNo, kNo, kNo,  // between valid rows: the devkit leaves it
                                       9,   9,   9,    // left extrapolation
                                       9,   9,   9};   // bottom: copies row 3
  EXPECT_EQ(filled, expected);
}

TEST(DevkitFill, NoValidPixelStaysInvalid) {
  EXPECT_EQ(fill(2, 2, {kNo, kNo, kNo, kNo}), (std::vector<float>{kNo, kNo, kNo, kNo}));
}

TEST(DevkitFill, EmptyRowBetweenValidRowsCountsAsFilledOutlier) {
  const px::DisparityMap pred = make_map(3, 2, {5, 5, kNo, kNo, 5, 5});
  const px::DisparityMap gt = make_map(3, 2, {5, 5, 5, 1, 5, 5});
  const px::FrameCounts c = count(pred, gt);
  EXPECT_EQ(c.gt_pixels, 6);
  EXPECT_EQ(c.d1_outliers, 0);
  EXPECT_EQ(c.d1_outliers_filled, 2);
}
