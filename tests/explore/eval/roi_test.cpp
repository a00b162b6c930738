// Region-of-interest arithmetic: centred ROI, full, parsing, too-large errors.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "parallax/eval/dataset.hpp"

namespace px = parallax::eval;

TEST(Roi, CentredKittiDefault) {
  const px::Roi roi = px::centred_roi(1242, 375, 640, 360);
  EXPECT_EQ(roi.x0, 301);  // (1242 - 640) / 2
  EXPECT_EQ(roi.y0, 7);    // (375 - 360) / 2 = 7 (integer division)
  EXPECT_EQ(roi.width_px, 640);
  EXPECT_EQ(roi.height_px, 360);
}

TEST(Roi, OddMarginsRoundDown) {
  const px::Roi roi = px::centred_roi(11, 8, 4, 3);  // margins 7 and 5
  EXPECT_EQ(roi.x0, 3);
  EXPECT_EQ(roi.y0, 2);
  const px::Roi odd = px::centred_roi(1241, 376, 640, 360);  // KITTI 2012 size
  EXPECT_EQ(odd.x0, 300);
  EXPECT_EQ(odd.y0, 8);
  const px::Roi same = px::centred_roi(5, 5, 5, 5);
  EXPECT_EQ(same.x0, 0);
  EXPECT_EQ(same.y0, 0);
}

TEST(Roi, Full) {
  const px::Roi roi = px::full_roi(450, 375);
  EXPECT_EQ(roi.x0, 0);
  EXPECT_EQ(roi.y0, 0);
  EXPECT_EQ(roi.width_px, 450);
  EXPECT_EQ(roi.height_px, 375);
  const px::Roi resolved = px::resolve_roi(px::parse_roi_size("full"), 450, 375);
  EXPECT_EQ(resolved.width_px, 450);
  EXPECT_EQ(resolved.height_px, 375);
}

TEST(Roi, TooLargeIsAnError) {
  EXPECT_THROW(px::centred_roi(600, 375, 640, 360), px::InputError);
  EXPECT_THROW(px::centred_roi(1242, 300, 640, 360), px::InputError);
  EXPECT_THROW(px::centred_roi(1242, 375, 0, 360), px::InputError);
  try {
    px::centred_roi(600, 300, 640, 360);
    FAIL() << "expected InputError";
  } catch (const px::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("640x360"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("600x300"), std::string::npos) << e.what();
  }
}

TEST(Roi, ParseAndPrint) {
  const px::RoiSize s = px::parse_roi_size("640x360");
  EXPECT_FALSE(s.full);
  EXPECT_EQ(s.width_px, 640);
  EXPECT_EQ(s.height_px, 360);
  EXPECT_EQ(px::to_string(s), "640x360");
  EXPECT_TRUE(px::parse_roi_size("full").full);
  EXPECT_EQ(px::to_string(px::parse_roi_size("full")), "full");
  for (const char* bad : {"", "640", "640x", "x360", "0x10", "-5x3", "64ax3", "whole"}) {
    EXPECT_THROW(px::parse_roi_size(bad), px::InputError) << bad;
  }
  const px::RoiSize kitti = px::default_roi_size(px::DatasetLayout::kitti2015);
  EXPECT_EQ(kitti.width_px, 640);
  EXPECT_EQ(kitti.height_px, 360);
  EXPECT_TRUE(px::default_roi_size(px::DatasetLayout::middlebury).full);
}

TEST(Roi, CropIsAView) {
  cv::Mat image(5, 7, CV_8UC1);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 7; ++x) image.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(10 * y + x);
  const px::Roi roi = px::centred_roi(7, 5, 3, 2);  // x0 2, y0 1
  const cv::Mat crop = px::crop_to_roi(image, roi);
  ASSERT_EQ(crop.cols, 3);
  ASSERT_EQ(crop.rows, 2);
  EXPECT_EQ(crop.at<std::uint8_t>(0, 0), 12);
  EXPECT_EQ(crop.at<std::uint8_t>(1, 2), 24);
  EXPECT_THROW(px::crop_to_roi(image, px::Roi{5, 0, 3, 2}), std::invalid_argument);
}
