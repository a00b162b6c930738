// docs/algorithm.md §2: census codes, census and SAD costs, cost_max where x - d < 0.
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "test_util.hpp"

namespace parallax::ref {
namespace {

using test::at;
using test::image_from_rows;
using test::make_params;

const Image8 kGrid = image_from_rows({{10, 20, 30}, {40, 50, 60}, {70, 80, 90}});

TEST(CensusCodes, CentrePixelRasterOrderFirstTapInMsb) {
  const std::vector<uint64_t> codes = census_codes(kGrid, 3, 3);
  // Centre 50; taps 10 20 30 40 | 60 70 80 90 -> 1 1 1 1 0 0 0 0.
  EXPECT_EQ(codes[4], 0xF0u);
}

TEST(CensusCodes, CornerPixelUsesClampBorder) {
  const std::vector<uint64_t> codes = census_codes(kGrid, 3, 3);
  // Pixel (2, 2) = 90, clamped taps: 50 60 60 | 80 90 | 80 90 90 -> 1 1 1 1 0 1 0 0.
  EXPECT_EQ(codes[8], 0xF4u);
  // Pixel (0, 0) = 10: no tap is strictly darker (clamped taps equal to the centre give 0).
  EXPECT_EQ(codes[0], 0u);
}

TEST(CensusCodes, NonSquareWindows) {
  // 3x1: taps left, right of (1, 1): 40 < 50 -> 1, 60 -> 0.
  EXPECT_EQ(census_codes(kGrid, 3, 1)[4], 0b10u);
  // 1x3: taps above, below: 20 < 50 -> 1, 80 -> 0.
  EXPECT_EQ(census_codes(kGrid, 1, 3)[4], 0b10u);
  // 1x1: no taps, code 0.
  EXPECT_EQ(census_codes(kGrid, 1, 1)[4], 0u);
}

TEST(CensusCodes, SixtyFourBitWindowPutsFirstTapInBit63) {
  // 5 x 13 window = 64 taps. Only the first tap (top-left) of the centre pixel is darker.
  Image8 img = make_image(5, 13, 100);
  img.px[0] = 0;
  const std::vector<uint64_t> codes = census_codes(img, 5, 13);
  EXPECT_EQ(codes[static_cast<std::size_t>(6 * 5 + 2)], uint64_t(1) << 63);
  // Only the last tap (bottom-right) darker -> bit 0.
  Image8 img2 = make_image(5, 13, 100);
  img2.px[static_cast<std::size_t>(12 * 5 + 4)] = 0;
  EXPECT_EQ(census_codes(img2, 5, 13)[static_cast<std::size_t>(6 * 5 + 2)], 1u);
}

TEST(CensusCodes, ImageSmallerThanWindow) {
  // 2x1 image [5, 9], 5x1 window. Pixel 1 (9): clamped taps 5 5 | 9 9 -> 1 1 0 0.
  const std::vector<uint64_t> codes = census_codes(image_from_rows({{5, 9}}), 5, 1);
  EXPECT_EQ(codes[0], 0u);
  EXPECT_EQ(codes[1], 0b1100u);
  // 1x1 image: every tap is the centre.
  EXPECT_EQ(census_codes(image_from_rows({{7}}), 3, 3)[0], 0u);
}

TEST(CensusCodes, RejectsBadWindows) {
  EXPECT_THROW(census_codes(kGrid, 2, 3), std::invalid_argument);
  EXPECT_THROW(census_codes(kGrid, 9, 9), std::invalid_argument);  // 80 bits
  EXPECT_NO_THROW(census_codes(kGrid, 9, 7));                      // 62 bits
}

TEST(CensusCodes, SparseUsesEverySecondTapInRasterOrder) {
  // 3x3 at the centre 50: taps k = 0 .. 8 are 10 20 30 40 [50] 60 70 80 90; sparse keeps the even
  // k but the centre (k = 4): 10 30 70 90 -> 1 1 0 0.
  EXPECT_EQ(census_codes(kGrid, 3, 3, kern::kCensusSparse)[4], 0b1100u);
  EXPECT_EQ(kern::census_bits(kern::kCensusSparse, 3, 3), 4);
  // 7x5 (35 taps, centre k = 17 odd): the 18 even taps all give bits.
  EXPECT_EQ(kern::census_bits(kern::kCensusSparse, 7, 5), 18);
  EXPECT_EQ(kern::census_bits(kern::kCensusSparse, 5, 5), 12);
  // 9x9: 40 bits, within 64 (the full census of 9x9 needs 80).
  EXPECT_EQ(kern::census_bits(kern::kCensusSparse, 9, 9), 40);
  EXPECT_NO_THROW(census_codes(kGrid, 9, 9, kern::kCensusSparse));
}

TEST(CensusCodes, SymmetricComparesEachTapWithItsMirror) {
  // 3x3 at (1, 1): pairs (k, 8 - k) for k = 0 .. 3: 10<90, 20<80, 30<70, 40<60 -> 1 1 1 1.
  EXPECT_EQ(census_codes(kGrid, 3, 3, kern::kCensusSymmetric)[4], 0b1111u);
  // At (0, 0) (value 10) with the clamp: taps (-1,-1) (0,-1) (1,-1) (-1,0) read 10 10 20 10 and
  // their mirrors (1,1) (0,1) (-1,1) (1,0) read 50 40 40 20 -> 1 1 1 1.
  EXPECT_EQ(census_codes(kGrid, 3, 3, kern::kCensusSymmetric)[0], 0b1111u);
  // A mirror-symmetric patch gives 0 whatever its centre.
  const Image8 sym = image_from_rows({{7, 1, 7}, {3, 200, 3}, {7, 1, 7}});
  EXPECT_EQ(census_codes(sym, 3, 3, kern::kCensusSymmetric)[4], 0u);
  EXPECT_EQ(kern::census_bits(kern::kCensusSymmetric, 5, 5), 12);
  EXPECT_EQ(kern::census_bits(kern::kCensusSymmetric, 9, 9), 40);
  EXPECT_THROW(census_codes(kGrid, 3, 3, 3), std::invalid_argument);  // no such kind
}

TEST(CensusCost, HammingDistanceAndCostMaxLeftOfImage) {
  // Left [5, 9] codes (5x1): 0, 0b1100. Right [9, 5] codes: pixel 0 (9): taps 9 9 | 5 5 ->
  // 0 0 1 1 = 0b0011; pixel 1 (5): 0.
  const Image8 left = image_from_rows({{5, 9}});
  const Image8 right = image_from_rows({{9, 5}});
  kern::StereoParams p = make_params(2, 1, kern::kCostCensus, 1, 3, kern::kPath0, 1, 2);
  p.window_w = 5;
  p.window_h = 1;
  const std::vector<uint32_t> c = cost_volume(left, right, p);
  EXPECT_EQ(kern::cost_max(p), 4u);
  EXPECT_EQ(at(c, 0, 0, 0, p), 2u);  // 0 ^ 0b0011
  EXPECT_EQ(at(c, 0, 0, 1, p), 4u);  // x - d < 0 -> cost_max
  EXPECT_EQ(at(c, 0, 0, 2, p), 4u);
  EXPECT_EQ(at(c, 1, 0, 0, p), 2u);  // 0b1100 ^ 0
  EXPECT_EQ(at(c, 1, 0, 1, p), 4u);  // 0b1100 ^ 0b0011
  EXPECT_EQ(at(c, 1, 0, 2, p), 4u);  // x - d < 0
}

TEST(SadCost, HandComputed) {
  const Image8 left = image_from_rows({{10, 20, 30}});
  const Image8 right = image_from_rows({{12, 25, 5}});
  kern::StereoParams p = make_params(3, 1, kern::kCostSad, 1, 3, kern::kPath0, 1, 2);
  p.window_w = 3;
  p.window_h = 1;
  const std::vector<uint32_t> c = cost_volume(left, right, p);
  EXPECT_EQ(kern::cost_max(p), 765u);
  // x=0 d=0: L 10 10 20, R 12 12 25 -> 2 + 2 + 5.
  EXPECT_EQ(at(c, 0, 0, 0, p), 9u);
  EXPECT_EQ(at(c, 0, 0, 1, p), 765u);
  EXPECT_EQ(at(c, 0, 0, 2, p), 765u);
  // x=1 d=0: L 10 20 30, R 12 25 5 -> 2 + 5 + 25.
  EXPECT_EQ(at(c, 1, 0, 0, p), 32u);
  // x=1 d=1: L 10 20 30, R (clamped x-1..x+1 of x-d=0) 12 12 25 -> 2 + 8 + 5.
  EXPECT_EQ(at(c, 1, 0, 1, p), 15u);
  EXPECT_EQ(at(c, 1, 0, 2, p), 765u);
  // x=2 d=1: L 20 30 30, R 12 25 5 -> 8 + 5 + 25.
  EXPECT_EQ(at(c, 2, 0, 1, p), 38u);
  // x=2 d=2: L 20 30 30, R 12 12 25 -> 8 + 18 + 5.
  EXPECT_EQ(at(c, 2, 0, 2, p), 31u);

  // A 3x3 window on a one-row image: the clamp repeats the row three times.
  p.window_h = 3;
  const std::vector<uint32_t> c3 = cost_volume(left, right, p);
  EXPECT_EQ(at(c3, 1, 0, 1, p), 45u);
  EXPECT_EQ(at(c3, 0, 0, 1, p), 255u * 9u);
}

TEST(SadCost, MaxContrastGivesCostMaxEverywhere) {
  const Image8 left = make_image(6, 4, 255);
  const Image8 right = make_image(6, 4, 0);
  const kern::StereoParams p = make_params(6, 4, kern::kCostSad, 5, 8, kern::kPath0, 1, 2);
  for (const uint32_t c : cost_volume(left, right, p)) EXPECT_EQ(c, 255u * 25u);
}

// min_disparity m: code d matches right column x - m - d, so the volume of (D, m) is the
// volume of (m + D, 0) without its first m disparities, cost_max included, for both costs.
TEST(CostVolume, MinDisparityShiftsTheSearchedRange) {
  std::mt19937 rng(31);
  const Image8 left = test::random_image(23, 6, rng);
  const Image8 right = test::random_image(23, 6, rng);
  for (int cost : {int(kern::kCostCensus), int(kern::kCostSad)})
    for (int m : {1, 5, 22, 30}) {
      kern::StereoParams shifted = make_params(23, 6, cost, 5, 7, kern::kPath0, 1, 2);
      shifted.min_disparity = m;
      kern::StereoParams whole = make_params(23, 6, cost, 5, 7 + m, kern::kPath0, 1, 2);
      const std::vector<uint32_t> a = cost_volume(left, right, shifted);
      const std::vector<uint32_t> b = cost_volume(left, right, whole);
      for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 23; ++x)
          for (int d = 0; d < 7; ++d) {
            ASSERT_EQ(at(a, x, y, d, shifted), at(b, x, y, d + m, whole))
                << "cost " << cost << " m " << m << " at (" << x << ", " << y << ", " << d << ")";
            if (x - m - d < 0) {
              ASSERT_EQ(at(a, x, y, d, shifted), kern::cost_max(shifted));
            }
          }
    }
  kern::StereoParams bad = make_params(23, 6, kern::kCostCensus, 5, 7, kern::kPath0, 1, 2);
  bad.min_disparity = -1;
  EXPECT_THROW(cost_volume(left, right, bad), std::invalid_argument);
  bad.min_disparity = kern::kMaxMinDisparity + 1;
  EXPECT_THROW(cost_volume(left, right, bad), std::invalid_argument);
}

TEST(CostVolume, RejectsMismatchedImages) {
  const kern::StereoParams p = make_params(3, 1, kern::kCostSad, 1, 2, kern::kPath0, 1, 2);
  EXPECT_THROW(cost_volume(kGrid, kGrid, p), std::invalid_argument);
}

}  // namespace
}  // namespace parallax::ref
