// The dataset layouts as users download them, on small files the tests write: Middlebury
// 2014/2021 scenes (PFM GT, calib.txt), a folder of scenes, Middlebury 2005/2006 scenes (disp1.png
// scaled by the image size, dmin.txt), MiddEval3's non-occlusion mask, KITTI 2012 colored_0/1,
// KITTI calibration files, the legacy pairs.tsv with a PFM row; the errors on bad input; the
// design-D warning; scoring saved predictions of Middlebury scenes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "parallax/eval/dataset.hpp"
#include "parallax/eval/disparity_io.hpp"
#include "parallax/eval/evaluate.hpp"
#include "pfm_writer.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
namespace px = parallax::eval;
using parallax::test::TempDir;

namespace {

constexpr int kW = 20;
constexpr int kH = 10;
const float kInf = std::numeric_limits<float>::infinity();

cv::Mat colour_image(int w, int h, int seed) {
  cv::Mat m(h, w, CV_8UC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      m.at<cv::Vec3b>(y, x) =
          cv::Vec3b(static_cast<std::uint8_t>((x * 7 + seed) % 256), static_cast<std::uint8_t>((y * 13 + seed) % 256),
                    static_cast<std::uint8_t>((x + y + 3 * seed) % 256));
  return m;
}

void write(const fs::path& file, const cv::Mat& image) {
  fs::create_directories(file.parent_path());
  ASSERT_TRUE(cv::imwrite(file.string(), image)) << file;
}

fs::path write_text(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
  return file;
}

// Float GT: d = x + y / 4 + 0.5, inf in column 0 and at (2, 7).
cv::Mat pfm_gt(int w, int h) {
  cv::Mat m(h, w, CV_32FC1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      m.at<float>(y, x) = x == 0 ? kInf : static_cast<float>(x) + static_cast<float>(y) / 4.0f + 0.5f;
  m.at<float>(2, 7) = kInf;
  return m;
}

std::string calib_text(int w, int h, int ndisp) {
  return "cam0=[500 0 10.5; 0 500 5.25; 0 0 1]\ncam1=[500 0 12.5; 0 500 5.25; 0 0 1]\n"
         "doffs=2\nbaseline=120\nwidth=" +
         std::to_string(w) + "\nheight=" + std::to_string(h) + "\nndisp=" + std::to_string(ndisp) +
         "\nisint=0\nvmin=1\nvmax=21\ndyavg=0\ndymax=0\n";
}

// A Middlebury 2014/2021 scene: im0.png, im1.png, GT (disp0.pfm or disp0GT.pfm), calib.txt.
void make_scene_2014(const fs::path& dir, bool little_endian = true, const char* gt_name = "disp0.pfm",
                     int ndisp = 32) {
  write(dir / "im0.png", colour_image(kW, kH, 1));
  write(dir / "im1.png", colour_image(kW, kH, 2));
  parallax::test::write_pfm(dir / gt_name, pfm_gt(kW, kH), little_endian);
  write_text(dir / "calib.txt", calib_text(kW, kH, ndisp));
}

// A Middlebury 2005/2006 scene of the given height (370 = third size): disp1.png value = 3 * x
// for the third size (disparity x), 0 in column 0; dmin.txt.
void make_scene_2006(const fs::path& dir, int h, int value_per_column, int dmin) {
  constexpr int w = 12;
  write(dir / "view1.png", colour_image(w, h, 3));
  write(dir / "view5.png", colour_image(w, h, 4));
  cv::Mat gt(h, w, CV_8UC1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) gt.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(value_per_column * x);
  write(dir / "disp1.png", gt);
  write_text(dir / "dmin.txt", std::to_string(dmin) + "\n");
}

cv::Mat kitti_gt(int w, int h) {
  cv::Mat m(h, w, CV_16UC1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) m.at<std::uint16_t>(y, x) = static_cast<std::uint16_t>(x == 0 ? 0 : 256 * (x + 1) + y);
  return m;
}

std::vector<std::string> ids_of(const std::vector<px::FrameRef>& frames) {
  std::vector<std::string> ids;
  for (const px::FrameRef& f : frames) ids.push_back(f.id);
  return ids;
}

void expect_input_error(const std::function<void()>& call, const std::vector<std::string>& parts) {
  try {
    call();
    ADD_FAILURE() << "expected InputError";
  } catch (const px::InputError& e) {
    for (const std::string& part : parts) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
          << "message '" << e.what() << "' lacks '" << part << "'";
    }
  }
}

px::Frame load_only(const fs::path& dir, px::GtKind kind = px::GtKind::noc) {
  const px::Dataset ds = px::open_dataset(dir);
  const std::vector<px::FrameRef> frames = px::list_frames(ds, kind);
  EXPECT_EQ(frames.size(), 1u);
  return px::load_frame(frames.at(0));
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Middlebury 2014/2021

TEST(Middlebury2014, OneSceneFolder) {
  TempDir dir;
  const fs::path scene = dir.path() / "Adirondack-perfect";
  make_scene_2014(scene);
  const px::Dataset ds = px::open_dataset(scene);
  EXPECT_EQ(ds.layout, px::DatasetLayout::middlebury);
  EXPECT_EQ(ds.middlebury_source, "scene folder");
  const std::vector<px::FrameRef> frames = px::list_frames(ds, px::GtKind::occ);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].id, "Adirondack-perfect");
  EXPECT_EQ(frames[0].gt_path, scene / "disp0.pfm");
  EXPECT_EQ(frames[0].ndisp, 32);
  EXPECT_TRUE(px::default_roi_size(ds.layout).full);

  const px::Frame f = px::load_frame(frames[0]);
  ASSERT_EQ(f.gt_disparity_px.type(), CV_32FC1);
  EXPECT_EQ(f.gt_disparity_px.size(), cv::Size(kW, kH));
  EXPECT_EQ(f.gt_mask.at<std::uint8_t>(4, 0), 0);  // inf
  EXPECT_EQ(f.gt_mask.at<std::uint8_t>(2, 7), 0);  // inf
  EXPECT_EQ(f.gt_disparity_px.at<float>(2, 7), 0.0f);
  EXPECT_EQ(f.gt_mask.at<std::uint8_t>(2, 8), 255);
  EXPECT_FLOAT_EQ(f.gt_disparity_px.at<float>(3, 5), 5.0f + 0.75f + 0.5f);  // top row first
  EXPECT_EQ(cv::countNonZero(f.gt_mask), kW * kH - kH - 1);
  EXPECT_FLOAT_EQ(static_cast<float>(f.gt_max_disparity_px), 19.0f + 9.0f / 4.0f + 0.5f);
  EXPECT_TRUE(f.converted_from_colour);
  EXPECT_EQ(f.ndisp, 32);
  ASSERT_TRUE(f.calibration.known);
  EXPECT_DOUBLE_EQ(f.calibration.focal_px, 500.0);
  EXPECT_DOUBLE_EQ(f.calibration.cx_px, 10.5);
  EXPECT_DOUBLE_EQ(f.calibration.baseline_m, 0.12);
  EXPECT_DOUBLE_EQ(f.calibration.doffs_px, 2.0);
  bool pfm_note = false;
  for (const std::string& n : f.notes) pfm_note = pfm_note || n.find("float PFM, inf = no GT") != std::string::npos;
  EXPECT_TRUE(pfm_note);

  // The training/ subfolder rule applies too.
  TempDir holder;
  make_scene_2014(holder.path() / "training" / "Piano", false, "disp0GT.pfm");
  EXPECT_EQ(ids_of(px::list_frames(px::open_dataset(holder.path()), px::GtKind::noc)),
            (std::vector<std::string>{"Piano"}));
}

TEST(Middlebury2014, FolderOfScenesBothByteOrders) {
  TempDir dir;
  make_scene_2014(dir.path() / "Piano", /*little_endian=*/false, "disp0GT.pfm", 64);
  make_scene_2014(dir.path() / "Adirondack", /*little_endian=*/true, "disp0.pfm", 32);
  fs::create_directories(dir.path() / "notes");  // not a scene: ignored
  // A test scene (no GT): opened, but not listed.
  write(dir.path() / "Zz-test" / "im0.png", colour_image(kW, kH, 5));
  write(dir.path() / "Zz-test" / "im1.png", colour_image(kW, kH, 6));
  const px::Dataset ds = px::open_dataset(dir.path());
  EXPECT_EQ(ds.middlebury_source, "scene folders");
  EXPECT_EQ(ds.middlebury_scenes.size(), 3u);
  using V = std::vector<std::string>;
  EXPECT_EQ(ids_of(px::list_frames(ds, px::GtKind::noc)), (V{"Adirondack", "Piano"}));
  EXPECT_EQ(ids_of(px::list_frames(ds, px::GtKind::noc, "Piano")), (V{"Piano"}));
  expect_input_error([&] { px::list_frames(ds, px::GtKind::noc, "Zz-test"); }, {"Zz-test"});
  const px::Frame a = px::load_frame(px::list_frames(ds, px::GtKind::noc, "Adirondack").at(0));
  const px::Frame p = px::load_frame(px::list_frames(ds, px::GtKind::noc, "Piano").at(0));
  EXPECT_EQ(cv::norm(a.gt_disparity_px, p.gt_disparity_px, cv::NORM_INF), 0.0);  // same values
  EXPECT_EQ(cv::norm(a.gt_mask, p.gt_mask, cv::NORM_INF), 0.0);
  EXPECT_EQ(p.ndisp, 64);

  // A dataset whose sub-folders hold scene folders (MiddEval3/trainingQ): the error says so.
  TempDir nested;
  make_scene_2014(nested.path() / "trainingQ" / "Piano");
  expect_input_error([&] { px::open_dataset(nested.path()); }, {"layout", "trainingQ", "give one"});
}

TEST(Middlebury2014, MiddEval3NonOcclusionMask) {
  TempDir dir;
  make_scene_2014(dir.path());
  cv::Mat mask(kH, kW, CV_8UC1, cv::Scalar(255));
  mask.at<std::uint8_t>(5, 5) = 128;  // occluded
  mask.at<std::uint8_t>(5, 6) = 0;    // no GT
  write(dir.path() / "mask0nocc.png", mask);
  const px::Frame occ = load_only(dir.path(), px::GtKind::occ);
  const px::Frame noc = load_only(dir.path(), px::GtKind::noc);
  EXPECT_EQ(occ.gt_mask.at<std::uint8_t>(5, 5), 255);
  EXPECT_EQ(noc.gt_mask.at<std::uint8_t>(5, 5), 0);
  EXPECT_EQ(noc.gt_mask.at<std::uint8_t>(5, 6), 0);
  EXPECT_EQ(cv::countNonZero(occ.gt_mask) - cv::countNonZero(noc.gt_mask), 2);
}

TEST(Middlebury2014, ErrorsNameTheFile) {
  TempDir dir;
  const fs::path s = dir.path() / "scene";

  make_scene_2014(s);
  fs::remove(s / "im1.png");
  expect_input_error([&] { px::open_dataset(s); }, {(s / "im1.png").string(), "not found", "im0.png, im1.png"});
  expect_input_error([&] { px::open_dataset(dir.path()); }, {(s / "im1.png").string()});  // as a folder of scenes

  make_scene_2014(s);
  write_text(s / "calib.txt", "cam0=[500 0 10.5; 0 500 5.25; 0 0 1]\nbaseline=120\nwidth=20\nheight=10\n");
  expect_input_error([&] { px::open_dataset(s); }, {(s / "calib.txt").string(), "ndisp"});

  make_scene_2014(s);
  write_text(s / "calib.txt", calib_text(kW + 1, kH, 32));
  expect_input_error([&] { load_only(s); }, {(s / "im0.png").string(), "calib.txt lines 5-6", "21x10", "20x10"});

  make_scene_2014(s);
  parallax::test::write_pfm(s / "disp0.pfm", pfm_gt(kW, kH + 2), true);
  expect_input_error([&] { load_only(s); }, {(s / "disp0.pfm").string(), "20x12", "im0.png", "20x10"});

  make_scene_2014(s);
  const std::string bytes = parallax::test::pfm_bytes(pfm_gt(kW, kH), true);
  parallax::test::write_bytes(s / "disp0.pfm", bytes.substr(0, bytes.size() - 40));
  expect_input_error([&] { load_only(s); }, {(s / "disp0.pfm").string(), "truncated"});

  parallax::test::write_bytes(s / "disp0.pfm", "P5\n20 10\n255\n" + std::string(200, 'x'));
  expect_input_error([&] { load_only(s); }, {(s / "disp0.pfm").string(), "not a PFM"});

  fs::remove(s / "disp0.pfm");
  fs::create_directories(s / "disp0.pfm");
  expect_input_error([&] { px::open_dataset(s); }, {(s / "disp0.pfm").string(), "folder"});
  fs::remove_all(s / "disp0.pfm");

  // All inf: no valid pixel, a clear message rather than a nan %.
  parallax::test::write_pfm(s / "disp0.pfm", cv::Mat(kH, kW, CV_32FC1, cv::Scalar(kInf)), true);
  expect_input_error([&] { load_only(s); }, {(s / "disp0.pfm").string(), "no valid pixel", "inf"});

  // Only test scenes: nothing to list.
  fs::remove(s / "disp0.pfm");
  expect_input_error([&] { px::list_frames(px::open_dataset(s), px::GtKind::noc); },
                     {s.string(), "no Middlebury scene with ground truth"});
}

// ---------------------------------------------------------------------------------------------
// Middlebury 2005/2006

TEST(Middlebury2006, DisparityScaledByImageSizeAndDmin) {
  TempDir dir;
  make_scene_2006(dir.path() / "Aloe", 370, 3, 270);     // third size: value / 3
  make_scene_2006(dir.path() / "Baby1", 555, 2, 300);    // half size: value / 2
  make_scene_2006(dir.path() / "Cloth1", 1110, 1, 210);  // full size: value / 1
  const px::Dataset ds = px::open_dataset(dir.path());
  EXPECT_EQ(ds.layout, px::DatasetLayout::middlebury);
  using V = std::vector<std::string>;
  EXPECT_EQ(ids_of(px::list_frames(ds, px::GtKind::noc)), (V{"Aloe", "Baby1", "Cloth1"}));
  for (const px::FrameRef& ref : px::list_frames(ds, px::GtKind::occ)) {
    const px::Frame f = px::load_frame(ref);
    EXPECT_EQ(f.gt_mask.at<std::uint8_t>(7, 0), 0) << ref.id;  // value 0 = unknown
    EXPECT_EQ(f.gt_mask.at<std::uint8_t>(7, 4), 255) << ref.id;
    EXPECT_FLOAT_EQ(f.gt_disparity_px.at<float>(7, 4), 4.0f) << ref.id;  // column x = x px
    EXPECT_FLOAT_EQ(static_cast<float>(f.gt_max_disparity_px), 11.0f) << ref.id;
    EXPECT_EQ(f.ndisp, 0) << ref.id;
    EXPECT_FALSE(f.calibration.known) << ref.id;
  }
  const px::Frame aloe = px::load_frame(px::list_frames(ds, px::GtKind::noc, "Aloe").at(0));
  EXPECT_EQ(aloe.dmin_px, 270);
  bool note = false;
  for (const std::string& n : aloe.notes)
    note = note || (n.find("third size") != std::string::npos && n.find("value / 3") != std::string::npos);
  EXPECT_TRUE(note);

  // One scene folder given directly; no dmin.txt is fine.
  fs::remove(dir.path() / "Baby1" / "dmin.txt");
  EXPECT_EQ(load_only(dir.path() / "Baby1").dmin_px, 0);
}

TEST(Middlebury2006, Errors) {
  TempDir dir;
  const fs::path s = dir.path() / "Art";
  make_scene_2006(s, 100, 3, 200);  // not a Middlebury size
  expect_input_error([&] { load_only(s); }, {(s / "view1.png").string(), "100", "370", "disp1.png"});

  make_scene_2006(s, 370, 3, 200);
  write_text(s / "dmin.txt", "two hundred\n");
  expect_input_error([&] { px::open_dataset(s); }, {(s / "dmin.txt").string(), "one integer"});

  make_scene_2006(s, 370, 3, 200);
  fs::remove(s / "view5.png");
  expect_input_error([&] { px::open_dataset(s); }, {(s / "view5.png").string(), "not found", "view1.png, view5.png"});

  make_scene_2006(s, 370, 0, 200);  // every value 0
  expect_input_error([&] { load_only(s); }, {(s / "disp1.png").string(), "no valid pixel", "0 = no GT"});
}

// ---------------------------------------------------------------------------------------------
// Legacy pairs.tsv: a PFM row with 'inf'

TEST(PairsTsv, PfmRowWithInf) {
  TempDir dir;
  make_scene_2014(dir.path() / "2014" / "Piano");
  const std::string header = "scene\tleft\tright\tgt_left\tgt_format\tdivisor\tinvalid\twidth\theight\n";
  write_text(
      dir.path() / "pairs.tsv",
      header + "2014/Piano\t2014/Piano/im0.png\t2014/Piano/im1.png\t2014/Piano/disp0.pfm\tpfm\t1\tinf\t20\t10\n");
  const px::Frame f = load_only(dir.path());
  EXPECT_EQ(f.id, "Piano");
  EXPECT_EQ(f.gt_mask.at<std::uint8_t>(2, 7), 0);
  EXPECT_FLOAT_EQ(f.gt_disparity_px.at<float>(3, 5), 6.25f);

  write_text(dir.path() / "pairs.tsv",
             header + "2014/Piano\t2014/Piano/im0.png\t2014/Piano/im1.png\t2014/Piano/disp0.pfm\tpfm\t1\t0\t20\t10\n");
  expect_input_error([&] { px::open_dataset(dir.path()); }, {"pairs.tsv line 2", "invalid", "inf"});
  write(dir.path() / "2014" / "Piano" / "disp0.png", cv::Mat(kH, kW, CV_8UC1, cv::Scalar(4)));
  write_text(
      dir.path() / "pairs.tsv",
      header + "2014/Piano\t2014/Piano/im0.png\t2014/Piano/im1.png\t2014/Piano/disp0.png\tpng8\t4\tinf\t20\t10\n");
  expect_input_error([&] { px::open_dataset(dir.path()); }, {"pairs.tsv line 2", "'inf'", "PFM", "disp0.png"});
}

// ---------------------------------------------------------------------------------------------
// KITTI

TEST(Kitti2012, ColouredPairsAndCalibration) {
  TempDir dir;
  const fs::path t = dir.path() / "training";
  write(t / "colored_0" / "000070_10.png", colour_image(kW, kH, 7));
  write(t / "colored_1" / "000070_10.png", colour_image(kW, kH, 8));
  write(t / "disp_noc" / "000070_10.png", kitti_gt(kW, kH));
  write(t / "disp_occ" / "000070_10.png", kitti_gt(kW, kH));
  write_text(t / "calib" / "000070.txt",
             "P0: 7.2e+02 0 6.1e+02 0 0 7.2e+02 1.8e+02 0 0 0 1 0\n"
             "P1: 7.2e+02 0 6.1e+02 -3.6e+02 0 7.2e+02 1.8e+02 0 0 0 1 0\n"
             "P2: 7.2e+02 0 6.1e+02 4.5e+01 0 7.2e+02 1.8e+02 -1e-01 0 0 1 3e-03\n"
             "P3: 7.2e+02 0 6.1e+02 -3.3e+02 0 7.2e+02 1.8e+02 2.3 0 0 1 4e-03\n");
  const px::Dataset ds = px::open_dataset(dir.path());
  EXPECT_EQ(ds.layout, px::DatasetLayout::kitti2012);
  EXPECT_EQ(ds.kitti_left_dir, "colored_0");
  const std::vector<px::FrameRef> frames = px::list_frames(ds, px::GtKind::noc, "70");
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].left_path, t / "colored_0" / "000070_10.png");
  EXPECT_EQ(frames[0].right_path, t / "colored_1" / "000070_10.png");
  const px::Frame f = px::load_frame(frames[0]);
  EXPECT_TRUE(f.converted_from_colour);
  ASSERT_TRUE(f.calibration.known);
  EXPECT_DOUBLE_EQ(f.calibration.focal_px, 720.0);
  EXPECT_DOUBLE_EQ(f.calibration.cx_px, 610.0);
  EXPECT_DOUBLE_EQ(f.calibration.baseline_m, 0.5);  // P0/P1, not P2/P3
  EXPECT_EQ(f.calibration.source, t / "calib" / "000070.txt");
  EXPECT_FLOAT_EQ(static_cast<float>(f.gt_max_disparity_px), (256.0f * 20 + 9) / 256.0f);

  // Grey folders win when both are there; the crop copies what is read.
  write(t / "image_0" / "000070_10.png", cv::Mat(kH, kW, CV_8UC1, cv::Scalar(42)));
  write(t / "image_1" / "000070_10.png", cv::Mat(kH, kW, CV_8UC1, cv::Scalar(43)));
  EXPECT_EQ(px::open_dataset(dir.path()).kitti_left_dir, "image_0");
  EXPECT_FALSE(
      px::load_frame(px::list_frames(px::open_dataset(dir.path()), px::GtKind::noc).at(0)).converted_from_colour);
  fs::remove_all(t / "image_0");
  fs::remove_all(t / "image_1");
  TempDir out;
  px::crop_dataset(dir.path(), "", {px::GtKind::noc}, 8, 4, out.path());
  const cv::Mat cropped = cv::imread((out.path() / "training/image_2/000070_10.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(cropped.type(), CV_8UC3);

  // A malformed calibration file: the error names the file and the line.
  write_text(t / "calib" / "000070.txt", "P0: 7.2e+02 0 6.1e+02 0 0 7.2e+02 1.8e+02 0 0 0 1 0\nP1: 1 2 3\n");
  expect_input_error([&] { px::load_frame(frames[0]); }, {"000070.txt line 2", "P1", "12 numbers"});
}

TEST(Kitti2015, CalibrationAndGroundTruthChecks) {
  TempDir dir;
  const fs::path t = dir.path() / "training";
  for (const char* id : {"000001_10.png", "000002_10.png", "000003_10.png"}) {
    write(t / "image_2" / id, colour_image(kW, kH, 1));
    write(t / "image_3" / id, colour_image(kW, kH, 2));
    write(t / "disp_noc_0" / id, kitti_gt(kW, kH));
  }
  write_text(t / "calib_cam_to_cam" / "000001.txt",
             "P_rect_02: 7e+02 0 6e+02 4e+01 0 7e+02 1.8e+02 0 0 0 1 0\n"
             "P_rect_03: 7e+02 0 6e+02 -3.1e+02 0 7e+02 1.8e+02 0 0 0 1 0\n");
  const px::Dataset ds = px::open_dataset(dir.path());
  const std::vector<px::FrameRef> frames = px::list_frames(ds, px::GtKind::noc);
  ASSERT_EQ(frames.size(), 3u);
  const px::Frame f1 = px::load_frame(frames[0]);
  ASSERT_TRUE(f1.calibration.known);
  EXPECT_DOUBLE_EQ(f1.calibration.baseline_m, 0.5);
  EXPECT_DOUBLE_EQ(f1.calibration.cy_px, 180.0);
  EXPECT_FALSE(px::load_frame(frames[1]).calibration.known);  // no calibration file

  // An 8-bit PNG where KITTI's 16-bit disparity PNG belongs.
  write(t / "disp_noc_0" / "000002_10.png", cv::Mat(kH, kW, CV_8UC1, cv::Scalar(9)));
  expect_input_error([&] { px::load_frame(frames[1]); },
                     {(t / "disp_noc_0" / "000002_10.png").string(), "8-bit", "16-bit"});
  // All-zero GT.
  write(t / "disp_noc_0" / "000003_10.png", cv::Mat(kH, kW, CV_16UC1, cv::Scalar(0)));
  expect_input_error([&] { px::load_frame(frames[2]); },
                     {(t / "disp_noc_0" / "000003_10.png").string(), "no valid pixel", "000003"});
  // A GT path that is a folder.
  fs::remove(t / "disp_noc_0" / "000003_10.png");
  fs::create_directories(t / "disp_noc_0" / "000003_10.png");
  expect_input_error([&] { px::load_frame(frames[2]); }, {(t / "disp_noc_0" / "000003_10.png").string(), "folder"});
}

// ---------------------------------------------------------------------------------------------
// The design's D against the scene's disparities

TEST(DisparityRange, WarningNamesFrameAndShare) {
  TempDir dir;
  make_scene_2014(dir.path(), true, "disp0.pfm", /*ndisp=*/32);
  px::Frame f = load_only(dir.path());
  const px::Roi full = px::full_roi(kW, kH);
  EXPECT_EQ(px::disparity_range_warning(f, full, 32), "");  // GT max 21.75, ndisp 32
  const std::string w = px::disparity_range_warning(f, full, 16);
  EXPECT_NE(w.find("frame " + f.id), std::string::npos) << w;
  EXPECT_NE(w.find("ndisp is 32"), std::string::npos) << w;
  EXPECT_NE(w.find("21.8 px"), std::string::npos) << w;
  EXPECT_NE(w.find("D = 16"), std::string::npos) << w;
  // GT >= 16: columns 16..19 below some rows, counted exactly.
  std::int64_t beyond = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 1; x < kW; ++x)
      if (f.gt_mask.at<std::uint8_t>(y, x) != 0 && f.gt_disparity_px.at<float>(y, x) >= 16.0f) ++beyond;
  EXPECT_NE(w.find("(" + std::to_string(beyond) + " of " + std::to_string(cv::countNonZero(f.gt_mask)) + ")"),
            std::string::npos)
      << w;
  // The scene's bound alone (GT inside the ROI is small) still warns.
  const std::string bound = px::disparity_range_warning(f, px::Roi{0, 0, 5, 5}, 24);
  EXPECT_NE(bound.find("ndisp is 32"), std::string::npos) << bound;
  f.ndisp = 0;
  EXPECT_EQ(px::disparity_range_warning(f, px::Roi{0, 0, 5, 5}, 24), "");
}

TEST(DisparityRange, EvaluateWarnsOnce) {
  TempDir dir;
  make_scene_2014(dir.path() / "A", true, "disp0.pfm", 32);
  make_scene_2014(dir.path() / "B", false, "disp0.pfm", 48);
  const px::Dataset ds = px::open_dataset(dir.path());
  const px::MatcherFactory zero = [] {
    return [](const cv::Mat& l, const cv::Mat&) {
      return px::DisparityMap{cv::Mat(l.size(), CV_32FC1, cv::Scalar(0)), cv::Mat(l.size(), CV_8UC1, cv::Scalar(255))};
    };
  };
  px::EvalOptions opt;
  opt.design_disparities = 16;
  const px::EvalResult r = px::evaluate(ds, px::RoiSize{}, zero, opt);
  int warnings = 0;
  for (const std::string& n : r.notes) {
    if (n.rfind("warning: ", 0) != 0) continue;
    ++warnings;
    EXPECT_NE(n.find("2 of 2 frames"), std::string::npos) << n;
  }
  EXPECT_EQ(warnings, 1);
  opt.design_disparities = 64;
  for (const std::string& n : px::evaluate(ds, px::RoiSize{}, zero, opt).notes)
    EXPECT_EQ(n.rfind("warning: ", 0), std::string::npos) << n;
}

// ---------------------------------------------------------------------------------------------
// Scoring saved predictions of Middlebury scenes (named <id>_10.png as eval --save writes them)

TEST(ScorePredictions, MiddleburyScenesByFrameId) {
  TempDir dir;
  TempDir pred;
  make_scene_2014(dir.path() / "A");
  make_scene_2014(dir.path() / "B");
  const px::Dataset ds = px::open_dataset(dir.path());
  for (const px::FrameRef& ref : px::list_frames(ds, px::GtKind::noc)) {
    const px::Frame f = px::load_frame(ref);
    px::write_kitti_disparity(pred.path() / (ref.id + "_10.png"), f.gt_disparity_px, f.gt_mask);
  }
  px::EvalOptions opt;
  const px::EvalResult r = px::score_predictions(pred.path(), ds, px::RoiSize{}, opt);
  ASSERT_EQ(r.frames.size(), 2u);
  EXPECT_DOUBLE_EQ(r.pooled.metrics.correct_3px_pct, 100.0);
  fs::remove(pred.path() / "B_10.png");
  expect_input_error([&] { px::score_predictions(pred.path(), ds, px::RoiSize{}, opt); },
                     {(pred.path() / "B_10.png").string(), "frame B"});
}
