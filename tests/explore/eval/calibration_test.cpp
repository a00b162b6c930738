// Calibration files: Middlebury calib.txt and dmin.txt, KITTI 2015 calib_cam_to_cam and KITTI
// 2012 calib P matrices, written by the tests; errors name the file and the line or field.
#include "parallax/eval/calibration.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "temp_dir.hpp"

namespace fs = std::filesystem;
namespace px = parallax::eval;
using parallax::test::TempDir;

namespace {

fs::path write_text(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
  return file;
}

void expect_error(const std::function<void()>& call, const std::vector<std::string>& parts) {
  try {
    call();
    ADD_FAILURE() << "expected InputError";
  } catch (const px::InputError& e) {
    for (const std::string& part : parts)
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
          << "message '" << e.what() << "' lacks '" << part << "'";
  }
}

// A calib.txt in the Middlebury 2014 form (made-up numbers).
const char* kCalib2014 =
    "cam0=[1000.5 0 400.25; 0 1000.5 300.75; 0 0 1]\n"
    "cam1=[1000.5 0 430.25; 0 1000.5 300.75; 0 0 1]\n"
    "doffs=30\n"
    "baseline=150.5\n"
    "width=20\n"
    "height=10\n"
    "ndisp=96\n"
    "isint=0\n"
    "vmin=12\n"
    "vmax=80.5\n"
    "dyavg=0\n"
    "dymax=0\n";

}  // namespace

TEST(MiddleburyCalib, ParsesEveryField) {
  TempDir dir;
  const fs::path file = write_text(dir.path() / "calib.txt", kCalib2014);
  const px::MiddleburyCalib c = px::read_middlebury_calib(file);
  EXPECT_EQ(c.ndisp, 96);
  EXPECT_TRUE(c.has_disparity_range);
  EXPECT_DOUBLE_EQ(c.vmin_px, 12.0);
  EXPECT_DOUBLE_EQ(c.vmax_px, 80.5);
  EXPECT_EQ(c.width_px, 20);
  EXPECT_EQ(c.height_px, 10);
  EXPECT_EQ(c.width_line, 5);
  EXPECT_EQ(c.height_line, 6);
  ASSERT_TRUE(c.camera.known);
  EXPECT_DOUBLE_EQ(c.camera.focal_px, 1000.5);
  EXPECT_DOUBLE_EQ(c.camera.cx_px, 400.25);
  EXPECT_DOUBLE_EQ(c.camera.cy_px, 300.75);
  EXPECT_DOUBLE_EQ(c.camera.baseline_m, 0.1505);  // mm in the file
  EXPECT_DOUBLE_EQ(c.camera.doffs_px, 30.0);
  EXPECT_EQ(c.camera.source, file);
}

TEST(MiddleburyCalib, DoffsFromTheMatricesAndOptionalFields) {
  TempDir dir;
  // 2021-style spacing, no doffs line: cam1 cx - cam0 cx; no size, no vmin/vmax.
  const fs::path file = write_text(dir.path() / "calib.txt",
                                   "cam0=[1758.23 0 953.34; 0 1758.23 552.29; 0 0 1]\r\n"
                                   "cam1=[1758.23 0 953.34; 0 1758.23 552.29; 0 0 1]\r\n"
                                   "baseline=111.53\r\n\r\nndisp=290\r\n");
  const px::MiddleburyCalib c = px::read_middlebury_calib(file);
  EXPECT_EQ(c.ndisp, 290);
  EXPECT_FALSE(c.has_disparity_range);
  EXPECT_EQ(c.width_px, 0);
  EXPECT_DOUBLE_EQ(c.camera.doffs_px, 0.0);
  EXPECT_TRUE(c.camera.known);
  // ndisp alone: no camera.
  const px::MiddleburyCalib n = px::read_middlebury_calib(write_text(dir.path() / "n.txt", "ndisp=64\n"));
  EXPECT_FALSE(n.camera.known);
}

TEST(MiddleburyCalib, ErrorsNameTheFileAndLine) {
  TempDir dir;
  const fs::path no_ndisp =
      write_text(dir.path() / "a" / "calib.txt", "cam0=[1 0 2; 0 1 3; 0 0 1]\nbaseline=100\nwidth=20\n");
  expect_error([&] { px::read_middlebury_calib(no_ndisp); }, {no_ndisp.string(), "ndisp"});
  const fs::path bad_ndisp = write_text(dir.path() / "b.txt", "width=20\nndisp=many\n");
  expect_error([&] { px::read_middlebury_calib(bad_ndisp); }, {"b.txt line 2", "ndisp", "many"});
  const fs::path no_eq = write_text(dir.path() / "c.txt", "ndisp=64\nbaseline 100\n");
  expect_error([&] { px::read_middlebury_calib(no_eq); }, {"c.txt line 2", "key=value"});
  const fs::path short_cam = write_text(dir.path() / "d.txt", "cam0=[1 0 2; 0 1 3; 0 0]\nndisp=64\n");
  expect_error([&] { px::read_middlebury_calib(short_cam); }, {"d.txt line 1", "cam0", "9 numbers"});
  const fs::path zero_width = write_text(dir.path() / "e.txt", "ndisp=64\nwidth=0\n");
  expect_error([&] { px::read_middlebury_calib(zero_width); }, {"e.txt line 2", "width"});
  const fs::path half_range = write_text(dir.path() / "f.txt", "ndisp=64\nvmin=3\n");
  expect_error([&] { px::read_middlebury_calib(half_range); }, {"f.txt", "vmin", "vmax"});
  const fs::path neg_baseline = write_text(dir.path() / "g.txt", "ndisp=64\nbaseline=-5\n");
  expect_error([&] { px::read_middlebury_calib(neg_baseline); }, {"g.txt line 2", "baseline"});
  expect_error([&] { px::read_middlebury_calib(dir.path() / "none.txt"); }, {"none.txt", "not found"});
  expect_error([&] { px::read_middlebury_calib(dir.path() / "a"); }, {"folder"});
}

TEST(KittiCalib, Kitti2015CamToCam) {
  TempDir dir;
  // calib_cam_to_cam layout: other keys (K_02, S_rect_02, ...) around the P_rect lines.
  const fs::path file = write_text(dir.path() / "calib_cam_to_cam" / "000001.txt",
                                   "calib_time: 09-Jan-2012 13:57:47\n"
                                   "corner_dist: 9.950000e-02\n"
                                   "S_02: 1.392000e+03 5.120000e+02\n"
                                   "K_02: 9.597910e+02 0.000000e+00 6.960217e+02 0.000000e+00 9.569251e+02 "
                                   "2.241806e+02 0.000000e+00 0.000000e+00 1.000000e+00\n"
                                   "P_rect_02: 7.000000e+02 0.000000e+00 6.000000e+02 4.000000e+01 0.000000e+00 "
                                   "7.000000e+02 1.800000e+02 2.000000e-01 0.000000e+00 0.000000e+00 1.000000e+00 "
                                   "3.000000e-03\n"
                                   "P_rect_03: 7.000000e+02 0.000000e+00 6.000000e+02 -3.380000e+02 0.000000e+00 "
                                   "7.000000e+02 1.800000e+02 2.000000e+00 0.000000e+00 0.000000e+00 1.000000e+00 "
                                   "5.000000e-03\n");
  const px::StereoCalibration c = px::read_kitti_calib(file, "P_rect_02", "P_rect_03");
  ASSERT_TRUE(c.known);
  EXPECT_DOUBLE_EQ(c.focal_px, 700.0);
  EXPECT_DOUBLE_EQ(c.cx_px, 600.0);
  EXPECT_DOUBLE_EQ(c.cy_px, 180.0);
  EXPECT_DOUBLE_EQ(c.baseline_m, (40.0 + 338.0) / 700.0);
  EXPECT_DOUBLE_EQ(c.doffs_px, 0.0);
  EXPECT_EQ(c.source, file);
}

TEST(KittiCalib, Kitti2012AndErrors) {
  TempDir dir;
  const std::string p0 = "P0: 7.2e+02 0 6.1e+02 0 0 7.2e+02 1.8e+02 0 0 0 1 0\n";
  const std::string p1 = "P1: 7.2e+02 0 6.1e+02 -3.6e+02 0 7.2e+02 1.8e+02 0 0 0 1 0\n";
  const fs::path ok = write_text(dir.path() / "calib" / "000070.txt", p0 + p1);
  const px::StereoCalibration c = px::read_kitti_calib(ok, "P0", "P1");
  EXPECT_DOUBLE_EQ(c.focal_px, 720.0);
  EXPECT_DOUBLE_EQ(c.baseline_m, 0.5);

  const fs::path missing = write_text(dir.path() / "m.txt", p0);
  expect_error([&] { px::read_kitti_calib(missing, "P0", "P1"); }, {"m.txt", "no P1 line"});
  const fs::path eleven = write_text(dir.path() / "n.txt", p0 + "P1: 1 2 3 4 5 6 7 8 9 10 11\n");
  expect_error([&] { px::read_kitti_calib(eleven, "P0", "P1"); }, {"n.txt line 2", "P1", "12 numbers", "got 11"});
  const fs::path word = write_text(dir.path() / "w.txt", "P0: 1 2 x 4 5 6 7 8 9 10 11 12\n" + p1);
  expect_error([&] { px::read_kitti_calib(word, "P0", "P1"); }, {"w.txt line 1", "P0", "not a number"});
  const fs::path swapped = write_text(dir.path() / "s.txt", p1.substr(0, 1) + "0" + p1.substr(2) + "P1" + p0.substr(2));
  expect_error([&] { px::read_kitti_calib(swapped, "P0", "P1"); }, {"s.txt line 2", "baseline"});
}

TEST(MiddleburyDmin, OneInteger) {
  TempDir dir;
  EXPECT_EQ(px::read_middlebury_dmin(write_text(dir.path() / "dmin.txt", "230\n")), 230);
  const fs::path bad = write_text(dir.path() / "bad" / "dmin.txt", "230 12\n");
  expect_error([&] { px::read_middlebury_dmin(bad); }, {bad.string(), "one integer"});
}
