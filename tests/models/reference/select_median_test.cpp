// docs/algorithm.md §4 (WTA, dL > x, LR check) and §5 (median with invalid codes).
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "test_util.hpp"

#include "parallax/kernels/wta_lr.hpp"

namespace parallax::ref {
namespace {

using test::make_params;
using test::volume_from;

// W = 4, H = 1, D = 3. dL: x0 [0 5 5] -> 0; x1 [5 5 5] -> 0 (tie: smallest); x2 [9 9 1] -> 2;
// x3 [4 1 7] -> 1.
// dR(xr) = argmin over d with xr + d < 4 of S(xr + d, d):
//   xr0: S(0,0)=0 S(1,1)=5 S(2,2)=1 -> 0;  xr1: S(1,0)=5 S(2,1)=9 S(3,2)=7 -> 0;
//   xr2: S(2,0)=9 S(3,1)=1 -> 1;           xr3: S(3,0)=4 -> 0.
const std::vector<uint32_t> kS = volume_from({{{0, 5, 5}, {5, 5, 5}, {9, 9, 1}, {4, 1, 7}}});

TEST(SelectDisparity, WinnerTakesAllWithSmallestDOnTies) {
  const kern::StereoParams p = make_params(4, 1, kern::kCostSad, 1, 3, kern::kPath0, 1, 2);
  EXPECT_EQ(select_disparity(kS, p), (std::vector<uint16_t>{0, 0, 2, 1}));
}

TEST(SelectDisparity, LeftRightCheckWithTolerance) {
  kern::StereoParams p = make_params(4, 1, kern::kCostSad, 1, 3, kern::kPath0, 1, 2);
  p.lr_check = true;
  p.lr_tolerance = 1;
  // x2: dL = 2, dR(0) = 0, |2 - 0| = 2 > 1 -> invalid (code D = 3). x3: dL 1, dR(2) = 1 -> ok.
  EXPECT_EQ(select_disparity(kS, p), (std::vector<uint16_t>{0, 0, 3, 1}));
  p.lr_tolerance = 2;
  EXPECT_EQ(select_disparity(kS, p), (std::vector<uint16_t>{0, 0, 2, 1}));
  p.lr_tolerance = 0;
  EXPECT_EQ(select_disparity(kS, p), (std::vector<uint16_t>{0, 0, 3, 1}));
}

TEST(SelectDisparity, DisparityBeyondTheLeftEdgeIsInvalid) {
  // x0 [5 0 5] -> dL 1 > 0; x1 [5 5 0] -> dL 2 > 1; x2 [5 5 0] -> dL 2 <= 2 valid.
  const kern::StereoParams p = make_params(3, 1, kern::kCostSad, 1, 3, kern::kPath0, 1, 2);
  const std::vector<uint32_t> s = volume_from({{{5, 0, 5}, {5, 5, 0}, {5, 5, 0}}});
  EXPECT_EQ(select_disparity(s, p), (std::vector<uint16_t>{3, 3, 2}));
}

TEST(SelectDisparity, RightDisparityIgnoresTermsBeyondTheRightEdge) {
  // W = 2, H = 2, D = 2, tolerance 0. dR(1) may only use d = 0: a model that read S(2, y, 1)
  // would wrap into the next row's S(0, y + 1, 1) = 0 and find dR(1) = 1.
  //   row 0: x0 [3 9] dL 0, x1 [1 9] dL 0; dR(0) = 0 (3 vs 9), dR(1) = 0 -> both valid.
  //   row 1: x0 [9 0] dL 1 > 0 invalid, x1 [0 9] dL 0, dR(1) = 0 -> valid.
  kern::StereoParams p = make_params(2, 2, kern::kCostSad, 1, 2, kern::kPath0, 1, 2);
  p.lr_check = true;
  p.lr_tolerance = 0;
  const std::vector<uint32_t> s = volume_from({{{3, 9}, {1, 9}}, {{9, 0}, {0, 9}}});
  EXPECT_EQ(select_disparity(s, p), (std::vector<uint16_t>{0, 0, 2, 0}));
}

TEST(SelectDisparity, UniquenessInvalidatesAmbiguousWinners) {
  // W = 4, H = 1, D = 5; every dL <= x only from x = 4 on, so x = 4 .. 7 carry the cases.
  //   x4 [10 11 30 30 30]: the runner-up d = 1 is a neighbour of dL = 0, the rest are 3x -> unique;
  //   x5 [10 30 30 30 11]: d = 4 costs 11 < 1.15 x 10 -> invalid at u = 15, valid at u = 10
  //                        (100 x 11 = 1100 is not < 110 x 10 = 1100: the strict test);
  //   x6 [30 30 10 30 10]: a tie two steps away -> invalid at any u > 0;
  //   x7 [20 20 20 20 20]: all equal, dL = 0, d = 2 ties -> invalid at u > 0.
  kern::StereoParams p = make_params(8, 1, kern::kCostSad, 1, 5, kern::kPath0, 1, 2);
  std::vector<std::vector<uint32_t>> row(4, std::vector<uint32_t>{0, 50, 50, 50, 50});
  row.push_back({10, 11, 30, 30, 30});
  row.push_back({10, 30, 30, 30, 11});
  row.push_back({30, 30, 10, 30, 10});
  row.push_back({20, 20, 20, 20, 20});
  const std::vector<uint32_t> s = volume_from({row});
  const uint16_t inv = 5;
  p.uniqueness_pct = 0;
  EXPECT_EQ(select_disparity(s, p), (std::vector<uint16_t>{0, 0, 0, 0, 0, 0, 2, 0}));
  p.uniqueness_pct = 10;
  EXPECT_EQ(select_disparity(s, p), (std::vector<uint16_t>{0, 0, 0, 0, 0, 0, inv, inv}));
  p.uniqueness_pct = 15;
  EXPECT_EQ(select_disparity(s, p), (std::vector<uint16_t>{0, 0, 0, 0, 0, inv, inv, inv}));
  p.uniqueness_pct = 101;
  EXPECT_THROW(select_disparity(s, p), std::invalid_argument);
}

// The same volume kS with min_disparity m = 1: code d is disparity 1 + d, so a code is valid when
// 1 + d <= x, and dR(xr) = argmin over d with xr + 1 + d < 4 of S(xr + 1 + d, d):
//   xr0: S(1,0)=5 S(2,1)=9 S(3,2)=7 -> 0;  xr1: S(2,0)=9 S(3,1)=1 -> 1;  xr2: S(3,0)=4 -> 0.
// x0 (dL 0) and x2 (dL 2) point left of the right image; x1 (dL 0) checks dR(0) = 0 and x3 (dL 1)
// checks dR(1) = 1, both exact. (Without the offset in dR, or with x - dL instead of x - 1 - dL,
// x3 would meet dR = 0 and fail at tolerance 0.)
TEST(SelectDisparity, MinDisparityOffsetsValidityAndTheRightPixel) {
  kern::StereoParams p = make_params(4, 1, kern::kCostSad, 1, 3, kern::kPath0, 1, 2);
  p.min_disparity = 1;
  EXPECT_EQ(select_disparity(kS, p), (std::vector<uint16_t>{3, 0, 3, 1}));
  p.lr_check = true;
  p.lr_tolerance = 0;
  EXPECT_EQ(select_disparity(kS, p), (std::vector<uint16_t>{3, 0, 3, 1}));
  p.min_disparity = 4;  // every match lies left of the right image
  EXPECT_EQ(select_disparity(kS, p), (std::vector<uint16_t>{3, 3, 3, 3}));
}

// Sub-pixel codes with f = 2 (quarter pixels), W = 8, H = 1, D = 5, no LR check; a = S(d-1) - S(d),
// b = S(d+1) - S(d), t = floor(|a - b| 4 / (a + b)), r = (t + 1) >> 1:
//   x3 [30 12 10 18 30]: d 2, a 2, b 8: t = floor(24 / 10) = 2, r 1, below -> 8 - 1 = 7 (2 - 0.3);
//   x4 [20  4  6 30 30]: d 1, a 16, b 2: t = floor(56 / 18) = 3, r 2 -> 4 + 2 = 6 (1 + 0.39);
//   x5 [30 30 10 10 30]: d 2 (the first minimum), a 20, b 0: t = 4, r 2 -> 10 (the tie's middle);
//   x6 d 0 and x7 d 4 = D - 1: no neighbour on one side, no fraction; invalid is D * 4 = 20.
TEST(SelectDisparity, SubpixelParabolaByHand) {
  kern::StereoParams p = make_params(8, 1, kern::kCostSad, 1, 5, kern::kPath0, 1, 2);
  std::vector<std::vector<uint32_t>> row(3, std::vector<uint32_t>{0, 50, 50, 50, 50});
  row.push_back({30, 12, 10, 18, 30});
  row.push_back({20, 4, 6, 30, 30});
  row.push_back({30, 30, 10, 10, 30});
  row.push_back({5, 30, 30, 30, 30});
  row.push_back({30, 30, 30, 30, 5});
  const std::vector<uint32_t> s = volume_from({row});
  EXPECT_EQ(select_disparity(s, p), (std::vector<uint16_t>{0, 0, 0, 2, 1, 2, 0, 4}));
  p.subpixel_bits = 2;
  EXPECT_EQ(kern::invalid_code(p), 20);
  EXPECT_EQ(select_disparity(s, p), (std::vector<uint16_t>{0, 0, 0, 7, 6, 10, 0, 16}));
  // The kernels' restoring division gives the same codes.
  EXPECT_EQ(kern::subpixel_code(2, 5, 2, 12, 10, 18), 7u);
  EXPECT_EQ(kern::subpixel_code(1, 5, 2, 20, 4, 6), 6u);
  EXPECT_EQ(kern::subpixel_code(2, 5, 2, 30, 10, 10), 10u);
  EXPECT_EQ(kern::subpixel_code(4, 5, 2, 30, 5, 0), 16u);
  p.subpixel_bits = 5;
  EXPECT_THROW(select_disparity(s, p), std::invalid_argument);
}

std::vector<uint16_t> median3_centre_case(const std::vector<uint16_t>& window) {
  return median_filter(window, 3, 3, 3);
}

TEST(MedianFilter, RankRuleWithInvalidCodes) {
  const uint16_t inv = 10;  // D = 10
  // 5 of 9 invalid -> the rank-4 element is invalid.
  EXPECT_EQ(median3_centre_case({inv, 1, inv, 2, inv, 3, inv, 4, inv})[4], inv);
  // 4 of 9 invalid -> rank 4 is the largest valid code.
  EXPECT_EQ(median3_centre_case({inv, 1, inv, 2, 5, 3, inv, 4, inv})[4], 5);
  // A hole surrounded by valid codes is filled.
  EXPECT_EQ(median3_centre_case({2, 2, 2, 2, inv, 2, 2, 2, 2})[4], 2);
  // Plain median of valid codes.
  EXPECT_EQ(median3_centre_case({9, 8, 7, 6, 5, 4, 3, 2, 1})[4], 5);
}

TEST(MedianFilter, ClampBorderAtTheCorner) {
  const uint16_t inv = 10;
  // Corner (0, 0) of a 3x3 window: (0,0) x4, (1,0) x2, (0,1) x2, (1,1) x1.
  // (0,0) invalid: 4 invalid entries -> valid, the rank-4 element of {1,1,2,2,3,inv x4} = 3.
  std::vector<uint16_t> codes = {inv, 1, 0, 2, 3, 0, 0, 0, 0};
  EXPECT_EQ(median_filter(codes, 3, 3, 3)[0], 3);
  // (0,0) and (1,0) invalid: 6 invalid entries -> invalid.
  codes = {inv, inv, 0, 2, 3, 0, 0, 0, 0};
  EXPECT_EQ(median_filter(codes, 3, 3, 3)[0], inv);
}

TEST(MedianFilter, InvalidExactlyWhenMajorityInvalid5x5And7x7) {
  for (const int k : {5, 7}) {
    const int n = k * k;
    for (const int invalid_count : {(n - 1) / 2, (n + 1) / 2}) {
      std::vector<uint16_t> codes(static_cast<std::size_t>(n), 1);
      for (int i = 0; i < invalid_count; ++i) codes[static_cast<std::size_t>(i)] = 99;
      const uint16_t centre = median_filter(codes, k, k, k)[static_cast<std::size_t>(n / 2)];
      EXPECT_EQ(centre, invalid_count >= (n + 1) / 2 ? 99 : 1) << "k " << k << " invalid " << invalid_count;
    }
  }
}

TEST(MedianFilter, OffAndBadK) {
  const std::vector<uint16_t> codes = {3, 1, 2, 0};
  EXPECT_EQ(median_filter(codes, 2, 2, 0), codes);
  EXPECT_EQ(median_filter(codes, 2, 2, 1), codes);
  EXPECT_THROW(median_filter(codes, 2, 2, 4), std::invalid_argument);
  EXPECT_THROW(median_filter(codes, 2, 2, 9), std::invalid_argument);
  EXPECT_THROW(median_filter(codes, 3, 2, 3), std::invalid_argument);
}

TEST(MedianFilter, WidthOne) {
  // 1 x 5 column, 3x3: each window holds the column's 3 neighbours, each 3 times.
  const std::vector<uint16_t> codes = {5, 1, 9, 2, 7};
  EXPECT_EQ(median_filter(codes, 1, 5, 3), (std::vector<uint16_t>{5, 5, 2, 7, 7}));
}

}  // namespace
}  // namespace parallax::ref
