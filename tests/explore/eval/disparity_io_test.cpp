// KITTI disparity PNG round trip, encoding rules, errors and the colour map; PFM reading (both
// byte orders, inf pixels, header variants, malformed files) against the tests' own writer.
#include "parallax/eval/disparity_io.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "parallax/eval/dataset.hpp"
#include "pfm_writer.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
namespace px = parallax::eval;

using parallax::test::TempDir;

TEST(DisparityIo, RoundTripKeepsValuesZeroAndInvalid) {
  TempDir dir;
  cv::Mat d = (cv::Mat_<float>(2, 4) << 0.0f, 1.5f, 63.75f, 255.99609375f,  //
               12.3f, 7.0f, 0.001f, 99.0f);
  cv::Mat m = (cv::Mat_<std::uint8_t>(2, 4) << 255, 255, 255, 255,  //
               255, 0, 255, 1);
  const fs::path file = dir.path() / "d.png";
  px::write_kitti_disparity(file, d, m);

  const cv::Mat raw = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(raw.type(), CV_16UC1);
  EXPECT_EQ(raw.at<std::uint16_t>(0, 0), 1);      // valid 0 -> 1
  EXPECT_EQ(raw.at<std::uint16_t>(0, 1), 384);    // 1.5 * 256
  EXPECT_EQ(raw.at<std::uint16_t>(0, 2), 16320);  // 63.75 * 256
  EXPECT_EQ(raw.at<std::uint16_t>(0, 3), 65535);
  EXPECT_EQ(raw.at<std::uint16_t>(1, 0), 3149);   // round(12.3 * 256 = 3148.8)
  EXPECT_EQ(raw.at<std::uint16_t>(1, 1), 0);      // invalid
  EXPECT_EQ(raw.at<std::uint16_t>(1, 2), 1);      // rounds to 0 but valid -> 1
  EXPECT_EQ(raw.at<std::uint16_t>(1, 3), 25344);  // any non-zero mask byte is valid

  const px::DisparityMap back = px::read_kitti_disparity(file);
  ASSERT_EQ(back.disparity_px.type(), CV_32FC1);
  ASSERT_EQ(back.valid_mask.type(), CV_8UC1);
  EXPECT_EQ(back.valid_mask.at<std::uint8_t>(0, 0), 255);
  EXPECT_FLOAT_EQ(back.disparity_px.at<float>(0, 0), 1.0f / 256.0f);
  EXPECT_FLOAT_EQ(back.disparity_px.at<float>(0, 1), 1.5f);
  EXPECT_FLOAT_EQ(back.disparity_px.at<float>(0, 2), 63.75f);
  EXPECT_FLOAT_EQ(back.disparity_px.at<float>(1, 0), 3149.0f / 256.0f);
  EXPECT_EQ(back.valid_mask.at<std::uint8_t>(1, 1), 0);
  EXPECT_FLOAT_EQ(back.disparity_px.at<float>(1, 1), 0.0f);
  EXPECT_EQ(back.valid_mask.at<std::uint8_t>(1, 3), 255);
}

TEST(DisparityIo, OutOfRangeValuesAreRejected) {
  TempDir dir;
  const cv::Mat m(1, 1, CV_8UC1, cv::Scalar(255));
  EXPECT_THROW(px::write_kitti_disparity(dir.path() / "a.png", cv::Mat(1, 1, CV_32FC1, cv::Scalar(256.0)), m),
               std::invalid_argument);
  EXPECT_THROW(px::write_kitti_disparity(dir.path() / "b.png", cv::Mat(1, 1, CV_32FC1, cv::Scalar(-1.0)), m),
               std::invalid_argument);
  // An invalid pixel may hold anything.
  px::write_kitti_disparity(dir.path() / "c.png", cv::Mat(1, 1, CV_32FC1, cv::Scalar(-1.0)),
                            cv::Mat(1, 1, CV_8UC1, cv::Scalar(0)));
}

TEST(DisparityIo, ReadErrorsNameTheFile) {
  TempDir dir;
  const fs::path missing = dir.path() / "missing.png";
  try {
    px::read_kitti_disparity(missing);
    FAIL() << "expected InputError";
  } catch (const px::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  const fs::path eight_bit = dir.path() / "eight.png";
  ASSERT_TRUE(cv::imwrite(eight_bit.string(), cv::Mat(3, 3, CV_8UC1, cv::Scalar(7))));
  try {
    px::read_kitti_disparity(eight_bit);
    FAIL() << "expected InputError";
  } catch (const px::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(eight_bit.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("16-bit"), std::string::npos) << e.what();
  }
  const fs::path garbage = dir.path() / "garbage.png";
  std::ofstream(garbage) << "not a png";
  EXPECT_THROW(px::read_kitti_disparity(garbage), px::InputError);
}

TEST(DisparityIo, WriteErrorNamesTheFile) {
  TempDir dir;
  const fs::path bad = dir.path() / "no_such_folder" / "d.png";
  try {
    px::write_kitti_disparity(bad, cv::Mat(1, 1, CV_32FC1, cv::Scalar(1.0)), cv::Mat(1, 1, CV_8UC1, cv::Scalar(255)));
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << e.what();
  }
}

TEST(DisparityIo, ColourMapRedNearBlueFarBlackInvalid) {
  const cv::Mat d = (cv::Mat_<float>(1, 5) << 0.0f, 64.0f, 100.0f, 32.0f, 10.0f);
  const cv::Mat m = (cv::Mat_<std::uint8_t>(1, 5) << 255, 255, 255, 255, 0);
  const cv::Mat c = px::colourize_disparity(d, m, 64.0);
  ASSERT_EQ(c.type(), CV_8UC3);
  ASSERT_EQ(c.size(), d.size());
  EXPECT_EQ(c.at<cv::Vec3b>(0, 0), cv::Vec3b(255, 0, 0));  // BGR blue: far
  EXPECT_EQ(c.at<cv::Vec3b>(0, 1), cv::Vec3b(0, 0, 255));  // red: near
  EXPECT_EQ(c.at<cv::Vec3b>(0, 2), cv::Vec3b(0, 0, 255));  // clamped
  EXPECT_EQ(c.at<cv::Vec3b>(0, 3), cv::Vec3b(0, 255, 0));  // middle: hue 120, green
  EXPECT_EQ(c.at<cv::Vec3b>(0, 4), cv::Vec3b(0, 0, 0));    // invalid: black
  EXPECT_THROW(px::colourize_disparity(d, m, 0.0), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// PFM

namespace {

// 3 wide, 2 high; (row 0, col 1) and (row 1, col 2) unknown.
cv::Mat pfm_sample() {
  const float inf = std::numeric_limits<float>::infinity();
  return (cv::Mat_<float>(2, 3) << 1.5f, inf, 270.25f,  //
          0.0f, 33.0f, inf);
}

std::string error_of(const std::function<void()>& call) {
  try {
    call();
  } catch (const px::InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

}  // namespace

TEST(Pfm, ReadsBothByteOrdersTopRowFirstWithInf) {
  TempDir dir;
  for (const bool little : {true, false}) {
    const fs::path file = dir.path() / (little ? "le.pfm" : "be.pfm");
    parallax::test::write_pfm(file, pfm_sample(), little);
    const cv::Mat m = px::read_pfm(file);
    ASSERT_EQ(m.type(), CV_32FC1) << file;
    ASSERT_EQ(m.size(), cv::Size(3, 2)) << file;
    EXPECT_EQ(m.at<float>(0, 0), 1.5f) << file;  // the file's last row is the image's first
    EXPECT_TRUE(std::isinf(m.at<float>(0, 1))) << file;
    EXPECT_EQ(m.at<float>(0, 2), 270.25f) << file;
    EXPECT_EQ(m.at<float>(1, 0), 0.0f) << file;
    EXPECT_EQ(m.at<float>(1, 1), 33.0f) << file;
    EXPECT_TRUE(std::isinf(m.at<float>(1, 2))) << file;

    const px::DisparityMap d = px::read_pfm_disparity(file);
    EXPECT_EQ(d.valid_mask.at<std::uint8_t>(0, 1), 0);
    EXPECT_EQ(d.disparity_px.at<float>(0, 1), 0.0f);
    EXPECT_EQ(d.valid_mask.at<std::uint8_t>(1, 0), 255);  // 0 is a valid disparity in a PFM
    EXPECT_EQ(d.disparity_px.at<float>(1, 1), 33.0f);
    EXPECT_EQ(cv::countNonZero(d.valid_mask), 4);
  }
}

TEST(Pfm, HeaderLayoutsAndScaleMagnitude) {
  TempDir dir;
  const cv::Mat v = pfm_sample();
  // One line for the size, a scale of any magnitude, CRLF-free single whitespace before data.
  const fs::path a = dir.path() / "a.pfm";
  parallax::test::write_bytes(a, parallax::test::pfm_bytes(v, true, "Pf 3 2 -0.003906\n"));
  EXPECT_EQ(px::read_pfm(a).at<float>(0, 2), 270.25f);
  const fs::path b = dir.path() / "b.pfm";
  parallax::test::write_bytes(b, parallax::test::pfm_bytes(v, false, "Pf\n3\n2\n1.0\n"));
  EXPECT_EQ(px::read_pfm(b).at<float>(1, 1), 33.0f);
  // Trailing bytes after the pixels are ignored.
  const fs::path c = dir.path() / "c.pfm";
  parallax::test::write_bytes(c, parallax::test::pfm_bytes(v, true) + "\n");
  EXPECT_EQ(px::read_pfm(c).at<float>(0, 0), 1.5f);
}

TEST(Pfm, ErrorsNameTheFileAndTheField) {
  TempDir dir;
  const cv::Mat v = pfm_sample();
  const std::string good = parallax::test::pfm_bytes(v, true);
  struct Case {
    const char* name;
    std::string bytes;
    std::vector<std::string> parts;
  };
  const std::vector<Case> cases = {
      {"truncated.pfm", good.substr(0, good.size() - 5), {"truncated", "24 bytes", "19"}},
      {"p6.pfm", "P6\n3 2\n255\n" + std::string(18, 'x'), {"not a PFM", "'P6"}},
      {"colour.pfm", "PF\n3 2\n-1\n" + std::string(72, '\0'), {"colour PFM", "Pf"}},
      {"width.pfm", parallax::test::pfm_bytes(v, true, "Pf\nthree 2\n-1\n"), {"width", "three"}},
      {"height.pfm", parallax::test::pfm_bytes(v, true, "Pf\n3 0\n-1\n"), {"height", "'0'"}},
      {"scale.pfm", parallax::test::pfm_bytes(v, true, "Pf\n3 2\n0\n"), {"scale", "'0'"}},
      {"short.pfm", "Pf\n3", {"height"}},
      {"empty.pfm", "", {"not a PFM"}},
  };
  for (const Case& c : cases) {
    const fs::path file = dir.path() / c.name;
    parallax::test::write_bytes(file, c.bytes);
    const std::string message = error_of([&] { px::read_pfm(file); });
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    for (const std::string& part : c.parts)
      EXPECT_NE(message.find(part), std::string::npos) << c.name << ": " << message;
  }
  const std::string missing = error_of([&] { px::read_pfm(dir.path() / "none.pfm"); });
  EXPECT_NE(missing.find("not found"), std::string::npos) << missing;
  fs::create_directories(dir.path() / "folder.pfm");
  const std::string folder = error_of([&] { px::read_pfm(dir.path() / "folder.pfm"); });
  EXPECT_NE(folder.find("folder"), std::string::npos) << folder;
}
