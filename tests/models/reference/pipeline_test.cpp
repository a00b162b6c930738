// The full pipeline (cost -> aggregate -> select + LR -> median) on scenes whose answer is
// known, degenerate sizes, and parameter validation.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

#include "test_util.hpp"

namespace parallax::ref {
namespace {

using test::make_params;

struct CostSetup {
  int cost;
  int p1;
  int p2;
  const char* name;
};
const CostSetup kCensus{kern::kCostCensus, 2, 12, "census 5x5"};
const CostSetup kSad{kern::kCostSad, 50, 800, "SAD 5x5"};

// Left = texture, right = texture shifted so that L(x, y) = R(x - shift, y).
void make_shifted_pair(int width_px, int height_px, int shift_px, std::mt19937& rng, Image8& left, Image8& right) {
  const Image8 texture = test::random_image(width_px + shift_px, height_px, rng);
  left = make_image(width_px, height_px);
  right = make_image(width_px, height_px);
  for (int y = 0; y < height_px; ++y)
    for (int x = 0; x < width_px; ++x) {
      left.px[static_cast<std::size_t>(y * width_px + x)] = texture.at(x, y);
      right.px[static_cast<std::size_t>(y * width_px + x)] = texture.at(x + shift_px, y);
    }
}

TEST(ComputeDisparity, ShiftedTextureGivesTheShift) {
  const int w = 64, h = 40, num_disp = 16, shift = 7;
  for (const unsigned seed : {1u, 2u, 3u}) {
    for (const CostSetup& setup : {kCensus, kSad}) {
      for (const unsigned mask : {kern::kForwardPaths, kern::kAllPaths}) {
        SCOPED_TRACE(testing::Message() << "seed " << seed << ", " << setup.name << ", paths mask " << mask);
        std::mt19937 rng(seed);
        Image8 left, right;
        make_shifted_pair(w, h, shift, rng, left, right);
        kern::StereoParams p = make_params(w, h, setup.cost, 5, num_disp, mask, setup.p1, setup.p2);
        p.lr_check = true;
        p.median = 3;
        const std::vector<uint16_t> codes = compute_disparity(left, right, p);
        int interior = 0, correct = 0;
        for (int y = 2; y < h - 2; ++y)
          for (int x = shift + 2; x < w - 2; ++x) {
            ++interior;
            if (codes[static_cast<std::size_t>(y * w + x)] == shift) ++correct;
          }
        EXPECT_GE(correct, interior * 98 / 100) << correct << " of " << interior << " correct";
        // Left of the shift the match lies outside the right image: never the true shift.
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) EXPECT_LE(codes[static_cast<std::size_t>(y * w + x)], num_disp);
      }
    }
  }
}

// A fronto-parallel square (disparity 10) in front of a background (disparity 2). The left
// background columns [32, 40) of the square's rows are hidden in the right image.
struct OcclusionScene {
  static constexpr int kW = 80, kH = 40, kD = 16;
  static constexpr int kBgDisp = 2, kFgDisp = 10;
  static constexpr int kX0 = 40, kX1 = 60, kY0 = 10, kY1 = 30;  // square in the left image
  Image8 left, right;

  explicit OcclusionScene(std::mt19937& rng) {
    const Image8 bg = test::random_image(kW + kD, kH, rng);
    const Image8 fg = test::random_image(kW + kD, kH, rng);
    left = make_image(kW, kH);
    right = make_image(kW, kH);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const bool rows = y >= kY0 && y < kY1;
        const bool fg_left = rows && x >= kX0 && x < kX1;
        const bool fg_right = rows && x + kFgDisp >= kX0 && x + kFgDisp < kX1;
        left.px[static_cast<std::size_t>(y * kW + x)] = fg_left ? fg.at(x, y) : bg.at(x, y);
        right.px[static_cast<std::size_t>(y * kW + x)] = fg_right ? fg.at(x + kFgDisp, y) : bg.at(x + kBgDisp, y);
      }
  }
};

TEST(ComputeDisparity, LeftRightCheckInvalidatesOccludedPixels) {
  for (const unsigned seed : {11u, 12u}) {
    for (const CostSetup& setup : {kCensus, kSad}) {
      SCOPED_TRACE(testing::Message() << "seed " << seed << ", " << setup.name);
      std::mt19937 rng(seed);
      const OcclusionScene scene(rng);
      const int w = OcclusionScene::kW;
      kern::StereoParams p =
          make_params(w, OcclusionScene::kH, setup.cost, 5, OcclusionScene::kD, kern::kAllPaths, setup.p1, setup.p2);
      const std::vector<uint16_t> no_lr = compute_disparity(scene.left, scene.right, p);
      p.lr_check = true;
      const std::vector<uint16_t> with_lr = compute_disparity(scene.left, scene.right, p);
      const uint16_t invalid = OcclusionScene::kD;

      int occluded = 0, occluded_invalid = 0, occluded_invalid_no_lr = 0;
      for (int y = OcclusionScene::kY0 + 2; y < OcclusionScene::kY1 - 2; ++y)
        for (int x = 34; x < 38; ++x) {
          const std::size_t i = static_cast<std::size_t>(y * w + x);
          ++occluded;
          if (with_lr[i] == invalid) ++occluded_invalid;
          if (no_lr[i] == invalid) ++occluded_invalid_no_lr;
        }
      EXPECT_EQ(occluded_invalid_no_lr, 0);
      EXPECT_GE(occluded_invalid, occluded * 9 / 10) << occluded_invalid << " of " << occluded;

      // Visible square and visible background away from the edges keep their disparity.
      int visible = 0, visible_correct = 0;
      for (int y = OcclusionScene::kY0 + 3; y < OcclusionScene::kY1 - 3; ++y) {
        for (int x = OcclusionScene::kX0 + 3; x < OcclusionScene::kX1 - 3; ++x) {
          ++visible;
          if (with_lr[static_cast<std::size_t>(y * w + x)] == OcclusionScene::kFgDisp) ++visible_correct;
        }
        for (int x = 10; x < 28; ++x) {
          ++visible;
          if (with_lr[static_cast<std::size_t>(y * w + x)] == OcclusionScene::kBgDisp) ++visible_correct;
        }
      }
      EXPECT_GE(visible_correct, visible * 95 / 100) << visible_correct << " of " << visible;
    }
  }
}

TEST(ComputeDisparity, WidthOneGivesDisparityZero) {
  // With W = 1 only d = 0 has a right pixel; every other cost is cost_max, so d = 0 wins
  // (ties go to the smallest d) and dR = 0: every pixel is valid with code 0.
  const unsigned seed = 5u;
  SCOPED_TRACE(testing::Message() << "seed " << seed);
  std::mt19937 rng(seed);
  for (const CostSetup& setup : {kCensus, kSad}) {
    const Image8 left = test::random_image(1, 9, rng);
    const Image8 right = test::random_image(1, 9, rng);
    kern::StereoParams p = make_params(1, 9, setup.cost, 3, 4, kern::kAllPaths, setup.p1, setup.p2);
    p.lr_check = true;
    p.median = 3;
    EXPECT_EQ(compute_disparity(left, right, p), std::vector<uint16_t>(9, 0)) << setup.name;
  }
}

TEST(ComputeDisparity, ImagesSmallerThanTheWindow) {
  // 1x1 images, SAD 9x9: every tap clamps to the single pixel: C(d = 0) = 81 * |L - R|.
  const Image8 one_l = test::image_from_rows({{200}});
  const Image8 one_r = test::image_from_rows({{190}});
  kern::StereoParams p1x1 = make_params(1, 1, kern::kCostSad, 9, 3, kern::kAllPaths, 1, 2);
  const std::vector<uint32_t> c = cost_volume(one_l, one_r, p1x1);
  EXPECT_EQ(c, (std::vector<uint32_t>{810, 255 * 81, 255 * 81}));
  p1x1.median = 7;
  p1x1.lr_check = true;
  EXPECT_EQ(compute_disparity(one_l, one_r, p1x1), std::vector<uint16_t>{0});

  // 3x2 identical images with a 9x7 census window: cost 0 at d = 0 everywhere -> code 0.
  const unsigned seed = 6u;
  SCOPED_TRACE(testing::Message() << "seed " << seed);
  std::mt19937 rng(seed);
  const Image8 img = test::random_image(3, 2, rng);
  kern::StereoParams p = make_params(3, 2, kern::kCostCensus, 9, 4, kern::kAllPaths, 3, 20);
  p.window_h = 7;
  p.lr_check = true;
  p.median = 5;
  EXPECT_EQ(compute_disparity(img, img, p), std::vector<uint16_t>(6, 0));
}

TEST(ComputeDisparity, SingleDisparity) {
  // D = 1: every valid pixel has code 0, never invalid (dL = 0 <= x, dR = 0).
  const unsigned seed = 8u;
  SCOPED_TRACE(testing::Message() << "seed " << seed);
  std::mt19937 rng(seed);
  const Image8 l = test::random_image(7, 5, rng);
  const Image8 r = test::random_image(7, 5, rng);
  kern::StereoParams p = make_params(7, 5, kern::kCostCensus, 3, 1, kern::kAllPaths, 1, 4);
  p.lr_check = true;
  p.lr_tolerance = 0;
  EXPECT_EQ(compute_disparity(l, r, p), std::vector<uint16_t>(35, 0));
}

TEST(ValidateStereoParams, RejectsBadParameters) {
  const kern::StereoParams good = make_params(8, 6, kern::kCostCensus, 5, 16, kern::kForwardPaths, 3, 20);
  EXPECT_NO_THROW(validate_stereo_params(good));

  auto rejects = [&](auto change, const char* what) {
    kern::StereoParams p = good;
    change(p);
    EXPECT_THROW(validate_stereo_params(p), std::invalid_argument) << what;
  };
  rejects([](kern::StereoParams& p) { p.width_px = 0; }, "width 0");
  rejects([](kern::StereoParams& p) { p.height_px = -1; }, "negative height");
  rejects([](kern::StereoParams& p) { p.cost = 2; }, "unknown cost");
  rejects([](kern::StereoParams& p) { p.window_w = 4; }, "even window width");
  rejects([](kern::StereoParams& p) { p.window_h = 0; }, "window height 0");
  rejects(
      [](kern::StereoParams& p) {
        p.window_w = 9;
        p.window_h = 9;
      },
      "census 80 bits");
  rejects([](kern::StereoParams& p) { p.disparities = 0; }, "D 0");
  rejects([](kern::StereoParams& p) { p.disparities = 257; }, "D 257");
  rejects([](kern::StereoParams& p) { p.path_mask = 0; }, "no paths");
  rejects([](kern::StereoParams& p) { p.path_mask = 1u << 8; }, "unknown path bit");
  rejects([](kern::StereoParams& p) { p.p1 = 20; }, "P1 == P2");
  rejects([](kern::StereoParams& p) { p.p1 = 30; }, "P1 > P2");
  rejects([](kern::StereoParams& p) { p.p1 = -1; }, "negative P1");
  rejects([](kern::StereoParams& p) { p.lr_tolerance = -1; }, "negative tolerance");
  rejects([](kern::StereoParams& p) { p.median = 4; }, "median 4");
  rejects([](kern::StereoParams& p) { p.median = 9; }, "median 9");
  rejects(
      [](kern::StereoParams& p) {
        p.cost = kern::kCostSad;
        p.p2 = 0x7fffffff;
        p.path_mask = kern::kAllPaths;
      },
      "aggregate wider than 32 bits");

  auto accepts = [&](auto change, const char* what) {
    kern::StereoParams p = good;
    change(p);
    EXPECT_NO_THROW(validate_stereo_params(p)) << what;
  };
  accepts(
      [](kern::StereoParams& p) {
        p.window_w = 9;
        p.window_h = 7;
      },
      "census 62 bits");
  accepts(
      [](kern::StereoParams& p) {
        p.window_w = 5;
        p.window_h = 13;
      },
      "census 64 bits");
  accepts([](kern::StereoParams& p) { p.disparities = 256; }, "D 256");
  accepts([](kern::StereoParams& p) { p.disparities = 1; }, "D 1");
  accepts([](kern::StereoParams& p) { p.median = 1; }, "median 1 = off");
  accepts([](kern::StereoParams& p) { p.median = 7; }, "median 7");
  accepts([](kern::StereoParams& p) { p.p1 = 0; }, "P1 0");
  accepts([](kern::StereoParams& p) { p.parallel_units = 3; }, "PU does not matter");
}

}  // namespace
}  // namespace parallax::ref
