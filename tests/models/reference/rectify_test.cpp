// docs/algorithm.md §1: nearest and bilinear remapping through a line buffer of R rows.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <stdexcept>

#include "test_util.hpp"

namespace parallax::ref {
namespace {

using test::image_from_rows;

kern::RectifyParams rectify_params(int width_px, int height_px, int mode, int frac_bits, int rows) {
  kern::RectifyParams p{};
  p.width_px = width_px;
  p.height_px = height_px;
  p.mode = mode;
  p.frac_bits = frac_bits;
  p.buffer_rows = rows;
  return p;
}

void set_map(RemapTable& map, int x, int y, int32_t mx, int32_t my) {
  map.map_x[static_cast<std::size_t>(y * map.width_px + x)] = mx;
  map.map_y[static_cast<std::size_t>(y * map.width_px + x)] = my;
}

TEST(Rectify, BilinearWeightsAndRounding) {
  const Image8 in = image_from_rows({{10, 21, 30}, {40, 50, 61}, {70, 80, 90}});
  RemapTable map = identity_map(3, 3, 2);  // F = 2, S = 4
  // (0,0) <- (0.25, 0.5): weights t00 3*2, t10 1*2, t01 3*2, t11 1*2 (sum 16):
  //   10*6 + 21*2 + 40*6 + 50*2 = 442, (442 + 8) >> 4 = 28 (27.625 rounds up).
  set_map(map, 0, 0, 1, 2);
  // (1,0) <- (-0.25, 0): ix = -1, fx = 3; only t10 = I(0,0) = 10 with weight 3*4:
  //   (120 + 8) >> 4 = 8 (7.5: half rounds up); the taps at x = -1 are outside, read as 0.
  set_map(map, 1, 0, -1, 0);
  // (2,0) <- (1.25, 0.25): t00 = 21 w9, t10 = 30 w3, t01 = 50 w3, t11 = 61 w1:
  //   189 + 90 + 150 + 61 = 490, (490 + 8) >> 4 = 31 (30.625).
  set_map(map, 2, 0, 5, 1);
  // (2,1) <- (1, 0.25): t00 = 21 w12, t01 = 50 w4: 452, (452 + 8) >> 4 = 28 (28.25 rounds down).
  set_map(map, 2, 1, 4, 1);
  // R = 3, A = 1: output row y sees rows [y-1, y+1], so no tap misses.
  const RectifyResult r = rectify(in, map, rectify_params(3, 3, kern::kRectifyBilinear, 2, 3));
  EXPECT_EQ(r.window_misses, 0);
  EXPECT_EQ(r.image.at(0, 0), 28);
  EXPECT_EQ(r.image.at(1, 0), 8);
  EXPECT_EQ(r.image.at(2, 0), 31);
  EXPECT_EQ(r.image.at(2, 1), 28);
  // Untouched identity entries reproduce the input.
  EXPECT_EQ(r.image.at(0, 1), 40);
  EXPECT_EQ(r.image.at(1, 1), 50);
  EXPECT_EQ(r.image.at(2, 2), 90);
}

TEST(Rectify, BilinearAllWhiteStaysWhite) {
  // Weights sum to S^2 and rounding never overflows 255.
  const Image8 in = make_image(4, 4, 255);
  RemapTable map = identity_map(4, 4, 5);
  set_map(map, 1, 1, 32 + 17, 32 + 9);
  const RectifyResult r = rectify(in, map, rectify_params(4, 4, kern::kRectifyBilinear, 5, 3));
  EXPECT_EQ(r.image.at(1, 1), 255);
}

TEST(Rectify, NearestWindowMissesCounting) {
  // 1 x 6 column; R = 2, A = 1: output row y sees rows [y, y+1].
  const Image8 in = image_from_rows({{11}, {22}, {33}, {44}, {55}, {66}});
  RemapTable map = identity_map(1, 6, 0);
  const int32_t source_rows[6] = {0, 3, 1, 4, -1, 6};
  for (int y = 0; y < 6; ++y) set_map(map, 0, y, 0, source_rows[y]);
  // y0 <- row 0 (available); y1 <- row 3 (miss, not in [1,2]); y2 <- row 1 (miss, not in
  // [2,3]); y3 <- row 4 (available); y4 <- row -1 and y5 <- row 6: outside the image, 0, no miss.
  const RectifyResult r = rectify(in, map, rectify_params(1, 6, kern::kRectifyNearest, 0, 2));
  EXPECT_EQ(r.window_misses, 2);
  EXPECT_EQ(r.image.px, (std::vector<uint8_t>{11, 0, 0, 55, 0, 0}));

  // R = 4, A = 2: rows [y-1, y+2]: both former misses are now served.
  const RectifyResult r4 = rectify(in, map, rectify_params(1, 6, kern::kRectifyNearest, 0, 4));
  EXPECT_EQ(r4.window_misses, 0);
  EXPECT_EQ(r4.image.px, (std::vector<uint8_t>{11, 44, 22, 55, 0, 0}));

  // A column outside the image is 0 and not a miss.
  set_map(map, 0, 0, 1, 0);
  EXPECT_EQ(rectify(in, map, rectify_params(1, 6, kern::kRectifyNearest, 0, 4)).image.px[0], 0);
}

TEST(Rectify, IdentityMapReproducesTheImage) {
  const unsigned seed = 99u;
  SCOPED_TRACE(testing::Message() << "seed " << seed);
  std::mt19937 rng(seed);
  const int w = 13, h = 7;
  const Image8 in = test::random_image(w, h, rng);

  const RectifyResult nearest = rectify(in, identity_map(w, h, 0), rectify_params(w, h, kern::kRectifyNearest, 0, 1));
  EXPECT_EQ(nearest.image.px, in.px);
  EXPECT_EQ(nearest.window_misses, 0);

  const RectifyResult bilinear = rectify(in, identity_map(w, h, 5), rectify_params(w, h, kern::kRectifyBilinear, 5, 2));
  EXPECT_EQ(bilinear.image.px, in.px);
  EXPECT_EQ(bilinear.window_misses, 0);

  // With R = 1 the zero-weight taps of row y+1 are still taps: counted as misses (t01 for
  // every x, t11 for x < W-1, on rows y < H-1), without changing the image.
  const RectifyResult one_row = rectify(in, identity_map(w, h, 5), rectify_params(w, h, kern::kRectifyBilinear, 5, 1));
  EXPECT_EQ(one_row.image.px, in.px);
  EXPECT_EQ(one_row.window_misses, int64_t(h - 1) * (2 * w - 1));

  const RectifyResult none = rectify(in, RemapTable{}, rectify_params(w, h, kern::kRectifyNone, 0, 1));
  EXPECT_EQ(none.image.px, in.px);
  EXPECT_EQ(none.window_misses, 0);
}

TEST(Rectify, RejectsBadParameters) {
  const Image8 in = make_image(4, 3, 7);
  EXPECT_THROW(rectify(in, identity_map(4, 3, 1), rectify_params(4, 3, kern::kRectifyNearest, 1, 3)),
               std::invalid_argument);
  EXPECT_THROW(rectify(in, identity_map(4, 3, 0), rectify_params(4, 3, kern::kRectifyBilinear, 0, 3)),
               std::invalid_argument);
  EXPECT_THROW(rectify(in, identity_map(4, 3, 5), rectify_params(4, 3, kern::kRectifyBilinear, 4, 3)),
               std::invalid_argument);
  EXPECT_THROW(rectify(in, identity_map(4, 3, 5), rectify_params(4, 3, kern::kRectifyBilinear, 5, 0)),
               std::invalid_argument);
  EXPECT_THROW(rectify(in, identity_map(3, 3, 5), rectify_params(4, 3, kern::kRectifyBilinear, 5, 3)),
               std::invalid_argument);
  EXPECT_THROW(rectify(in, identity_map(4, 3, 5), rectify_params(4, 4, kern::kRectifyBilinear, 5, 3)),
               std::invalid_argument);
  EXPECT_THROW(rectify(in, identity_map(4, 3, 0), rectify_params(4, 3, 7, 0, 3)), std::invalid_argument);
}

}  // namespace
}  // namespace parallax::ref
