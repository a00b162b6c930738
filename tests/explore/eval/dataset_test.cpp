// Dataset layouts, frame lists and filters, frame loading and its errors, and the cropper, on
// small synthetic datasets written to a temporary folder; plus the shipped crop in data/.
#include "parallax/eval/dataset.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "parallax/eval/disparity_io.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
namespace px = parallax::eval;
using parallax::test::TempDir;

namespace {

constexpr int kW = 20;
constexpr int kH = 10;

// Deterministic colour image, different per frame and side.
cv::Mat colour_image(int w, int h, int seed) {
  cv::Mat m(h, w, CV_8UC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      m.at<cv::Vec3b>(y, x) =
          cv::Vec3b(static_cast<std::uint8_t>((x * 7 + seed) % 256), static_cast<std::uint8_t>((y * 13 + seed) % 256),
                    static_cast<std::uint8_t>((x + y + 3 * seed) % 256));
  return m;
}

// KITTI-encoded GT: value = 256 * (x + 1) + y, except column 0 which has no GT.
cv::Mat kitti_gt(int w, int h) {
  cv::Mat m(h, w, CV_16UC1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) m.at<std::uint16_t>(y, x) = static_cast<std::uint16_t>(x == 0 ? 0 : 256 * (x + 1) + y);
  return m;
}

void write(const fs::path& file, const cv::Mat& image) {
  fs::create_directories(file.parent_path());
  ASSERT_TRUE(cv::imwrite(file.string(), image)) << file;
}

// KITTI 2015 layout under root/training: frames 0, 1, 2, 46 with noc GT, frame 1 with occ.
void make_kitti2015(const fs::path& root, int w = kW, int h = kH) {
  const fs::path t = root / "training";
  for (int n : {0, 1, 2, 46}) {
    char id[16];
    std::snprintf(id, sizeof id, "%06d_10.png", n);
    write(t / "image_2" / id, colour_image(w, h, n));
    write(t / "image_3" / id, colour_image(w, h, n + 100));
    write(t / "disp_noc_0" / id, kitti_gt(w, h));
    if (n == 1) write(t / "disp_occ_0" / id, kitti_gt(w, h));
  }
  write(t / "image_2" / "000001_11.png", colour_image(w, h, 5));  // next frame: ignored
  std::ofstream(root / "LICENSE.txt") << "test licence\n";
}

// KITTI 2012 layout directly in root (no training/): grey frame 70.
void make_kitti2012(const fs::path& root) {
  cv::Mat grey(kH, kW, CV_8UC1, cv::Scalar(42));
  write(root / "image_0" / "000070_10.png", grey);
  write(root / "image_1" / "000070_10.png", grey);
  write(root / "disp_noc" / "000070_10.png", kitti_gt(kW, kH));
  write(root / "disp_occ" / "000070_10.png", kitti_gt(kW, kH));
}

// Middlebury layout: two scenes, divisor 4 and 16, invalid 0.
void make_middlebury(const fs::path& root) {
  cv::Mat gt(kH, kW, CV_8UC1);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) gt.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(x * 10);
  write(root / "2003" / "teddy" / "im2.png", colour_image(kW, kH, 1));
  write(root / "2003" / "teddy" / "im6.png", colour_image(kW, kH, 2));
  write(root / "2003" / "teddy" / "disp2.png", gt);
  write(root / "2001" / "tsukuba" / "im3.png", colour_image(kW, kH, 3));
  write(root / "2001" / "tsukuba" / "im4.png", colour_image(kW, kH, 4));
  write(root / "2001" / "tsukuba" / "disp3.pgm", gt);
  std::ofstream tsv(root / "pairs.tsv");
  tsv << "scene\tleft\tright\tgt_left\tgt_format\tdisparity = value / divisor\tinvalid\twidth\t"
         "height\tgt_density\n"
      << "2001/tsukuba\t2001/tsukuba/im3.png\t2001/tsukuba/im4.png\t2001/tsukuba/disp3.pgm\t"
         "pgm8\t16\t0\t"
      << kW << "\t" << kH << "\t0.9\n"
      << "2003/teddy\t2003/teddy/im2.png\t2003/teddy/im6.png\t2003/teddy/disp2.png\tpng8\t4\t0\t" << kW << "\t" << kH
      << "\t0.9\n";
}

std::vector<std::string> ids_of(const std::vector<px::FrameRef>& frames) {
  std::vector<std::string> ids;
  for (const px::FrameRef& f : frames) ids.push_back(f.id);
  return ids;
}

// Expects `call` to throw InputError whose message contains every one of `parts`.
template <typename Call>
void expect_input_error(Call call, const std::vector<std::string>& parts) {
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

}  // namespace

TEST(Dataset, DetectsKitti2015FromRootOrTraining) {
  TempDir dir;
  make_kitti2015(dir.path());
  for (const fs::path& given : {dir.path(), dir.path() / "training", dir.path() / "training/"}) {
    const px::Dataset ds = px::open_dataset(given);
    EXPECT_EQ(ds.layout, px::DatasetLayout::kitti2015) << given;
    EXPECT_EQ(ds.frames_dir, dir.path() / "training") << given;
    EXPECT_EQ(ds.root, dir.path()) << given;
  }
}

TEST(Dataset, ListsFramesByGtKindAndFilter) {
  TempDir dir;
  make_kitti2015(dir.path());
  const px::Dataset ds = px::open_dataset(dir.path());
  using V = std::vector<std::string>;
  EXPECT_EQ(ids_of(px::list_frames(ds, px::GtKind::noc)), (V{"000000", "000001", "000002", "000046"}));
  EXPECT_EQ(ids_of(px::list_frames(ds, px::GtKind::occ)), (V{"000001"}));
  EXPECT_EQ(ids_of(px::list_frames(ds, px::GtKind::noc, "all")).size(), 4u);
  EXPECT_EQ(ids_of(px::list_frames(ds, px::GtKind::noc, "46, 0-1")), (V{"000000", "000001", "000046"}));
  EXPECT_EQ(ids_of(px::list_frames(ds, px::GtKind::noc, "000002,2,1-2")), (V{"000001", "000002"}));
  EXPECT_EQ(ids_of(px::list_frames(ds, px::GtKind::noc, "1-40")), (V{"000001", "000002"}));
  const std::vector<px::FrameRef> f = px::list_frames(ds, px::GtKind::occ, "1");
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].gt_path, dir.path() / "training" / "disp_occ_0" / "000001_10.png");
  EXPECT_EQ(f[0].left_path, dir.path() / "training" / "image_2" / "000001_10.png");
  EXPECT_EQ(f[0].right_path, dir.path() / "training" / "image_3" / "000001_10.png");
}

TEST(Dataset, FilterErrors) {
  TempDir dir;
  make_kitti2015(dir.path());
  const px::Dataset ds = px::open_dataset(dir.path());
  expect_input_error([&] { px::list_frames(ds, px::GtKind::noc, "3"); }, {"000003", "3"});
  expect_input_error([&] { px::list_frames(ds, px::GtKind::occ, "2"); }, {"000002", "occ"});
  expect_input_error([&] { px::list_frames(ds, px::GtKind::noc, "10-20"); }, {"10-20"});
  expect_input_error([&] { px::list_frames(ds, px::GtKind::noc, "5-1"); }, {"5-1"});
  expect_input_error([&] { px::list_frames(ds, px::GtKind::noc, "teddy"); }, {"teddy"});
  expect_input_error([&] { px::list_frames(ds, px::GtKind::noc, "1,,2"); }, {"empty"});
  EXPECT_THROW(px::parse_gt_kind("all"), px::InputError);
  EXPECT_EQ(px::parse_gt_kind("occ"), px::GtKind::occ);
}

TEST(Dataset, LoadsKittiFrame) {
  TempDir dir;
  make_kitti2015(dir.path());
  const px::Dataset ds = px::open_dataset(dir.path());
  const px::Frame frame = px::load_frame(px::list_frames(ds, px::GtKind::noc, "46").at(0));
  EXPECT_EQ(frame.id, "000046");
  ASSERT_EQ(frame.left.type(), CV_8UC1);
  ASSERT_EQ(frame.right.type(), CV_8UC1);
  EXPECT_EQ(frame.left.cols, kW);
  EXPECT_EQ(frame.left.rows, kH);
  EXPECT_TRUE(frame.converted_from_colour);
  ASSERT_EQ(frame.notes.size(), 1u);
  EXPECT_NE(frame.notes[0].find("COLOR_BGR2GRAY"), std::string::npos);
  ASSERT_EQ(frame.gt_disparity_px.type(), CV_32FC1);
  ASSERT_EQ(frame.gt_mask.type(), CV_8UC1);
  EXPECT_EQ(frame.gt_mask.at<std::uint8_t>(3, 0), 0);
  EXPECT_EQ(frame.gt_mask.at<std::uint8_t>(3, 5), 255);
  EXPECT_FLOAT_EQ(frame.gt_disparity_px.at<float>(3, 5), (256.0f * 6 + 3) / 256.0f);
  // Grey conversion is OpenCV's.
  cv::Mat expected;
  cv::cvtColor(colour_image(kW, kH, 46), expected, cv::COLOR_BGR2GRAY);
  EXPECT_EQ(cv::norm(frame.left, expected, cv::NORM_INF), 0.0);
}

TEST(Dataset, LoadErrorsNameTheFile) {
  TempDir dir;
  make_kitti2015(dir.path());
  const fs::path t = dir.path() / "training";
  const px::Dataset ds = px::open_dataset(dir.path());
  const std::vector<px::FrameRef> frames = px::list_frames(ds, px::GtKind::noc);

  fs::remove(t / "image_3" / "000000_10.png");
  expect_input_error([&] { px::load_frame(frames[0]); }, {(t / "image_3" / "000000_10.png").string(), "not found"});

  write(t / "image_3" / "000001_10.png", colour_image(kW - 2, kH, 0));
  expect_input_error([&] { px::load_frame(frames[1]); },
                     {(t / "image_3" / "000001_10.png").string(), "18x10", "20x10"});

  write(t / "disp_noc_0" / "000002_10.png", kitti_gt(kW, kH + 1));
  expect_input_error([&] { px::load_frame(frames[2]); }, {(t / "disp_noc_0" / "000002_10.png").string(), "20x11"});

  std::ofstream(t / "image_2" / "000046_10.png") << "not a png";
  expect_input_error([&] { px::load_frame(frames[3]); }, {(t / "image_2" / "000046_10.png").string(), "decoded"});
}

TEST(Dataset, UnknownLayoutAndMissingFolder) {
  TempDir dir;
  fs::create_directories(dir.path() / "training" / "image_2");  // no image_3
  expect_input_error([&] { px::open_dataset(dir.path()); }, {dir.path().string(), "layout"});
  expect_input_error([&] { px::open_dataset(dir.path() / "nope"); }, {"nope", "not found"});
  fs::create_directories(dir.path() / "training" / "image_3");
  // Layout found but no GT folder for the kind.
  const px::Dataset ds = px::open_dataset(dir.path());
  expect_input_error([&] { px::list_frames(ds, px::GtKind::noc); }, {"disp_noc_0"});
}

TEST(Dataset, Kitti2012GreyWithoutTraining) {
  TempDir dir;
  make_kitti2012(dir.path());
  const px::Dataset ds = px::open_dataset(dir.path());
  EXPECT_EQ(ds.layout, px::DatasetLayout::kitti2012);
  EXPECT_EQ(ds.frames_dir, dir.path());
  const std::vector<px::FrameRef> frames = px::list_frames(ds, px::GtKind::occ, "70");
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].gt_path, dir.path() / "disp_occ" / "000070_10.png");
  const px::Frame frame = px::load_frame(frames[0]);
  EXPECT_FALSE(frame.converted_from_colour);
  EXPECT_TRUE(frame.notes.empty());
  EXPECT_EQ(frame.left.at<std::uint8_t>(0, 0), 42);
}

TEST(Dataset, MiddleburyPairsTsv) {
  TempDir dir;
  make_middlebury(dir.path());
  const px::Dataset ds = px::open_dataset(dir.path());
  EXPECT_EQ(ds.layout, px::DatasetLayout::middlebury);
  using V = std::vector<std::string>;
  EXPECT_EQ(ids_of(px::list_frames(ds, px::GtKind::noc)), (V{"tsukuba", "teddy"}));
  EXPECT_EQ(ids_of(px::list_frames(ds, px::GtKind::occ, "teddy")), (V{"teddy"}));
  EXPECT_EQ(ids_of(px::list_frames(ds, px::GtKind::noc, "2003/teddy,tsukuba")), (V{"tsukuba", "teddy"}));
  expect_input_error([&] { px::list_frames(ds, px::GtKind::noc, "cones"); }, {"cones"});
  expect_input_error([&] { px::list_frames(ds, px::GtKind::noc, "1-2"); }, {"1-2"});

  const px::Frame teddy = px::load_frame(px::list_frames(ds, px::GtKind::noc, "teddy").at(0));
  EXPECT_EQ(teddy.gt_mask.at<std::uint8_t>(0, 0), 0);  // value 0 = invalid
  EXPECT_EQ(teddy.gt_mask.at<std::uint8_t>(0, 3), 255);
  EXPECT_FLOAT_EQ(teddy.gt_disparity_px.at<float>(0, 3), 30.0f / 4.0f);
  const px::Frame tsukuba = px::load_frame(px::list_frames(ds, px::GtKind::noc, "tsukuba").at(0));
  EXPECT_FLOAT_EQ(tsukuba.gt_disparity_px.at<float>(0, 3), 30.0f / 16.0f);
  EXPECT_EQ(tsukuba.notes.size(), 2u);  // colour conversion, GT encoding
}

TEST(Dataset, MiddleburyErrors) {
  TempDir dir;
  make_middlebury(dir.path());
  std::ofstream(dir.path() / "pairs.tsv") << "scene\tleft\tright\n2001/x\ta.png\tb.png\n";
  expect_input_error([&] { px::open_dataset(dir.path()); }, {"pairs.tsv", "gt_left"});
  std::ofstream(dir.path() / "pairs.tsv")
      << "scene\tleft\tright\tgt_left\tdivisor\tinvalid\n2001/x\ta.png\tb.png\tc.png\tfour\t0\n";
  expect_input_error([&] { px::open_dataset(dir.path()); }, {"pairs.tsv line 2", "four"});
  std::ofstream(dir.path() / "pairs.tsv")
      << "scene\tleft\tright\tgt_left\tdivisor\tinvalid\twidth\theight\n"
      << "2003/teddy\t2003/teddy/im2.png\t2003/teddy/im6.png\t2003/teddy/disp2.png\t4\t0\t" << kW + 1 << "\t" << kH
      << "\n";
  const px::Dataset ds = px::open_dataset(dir.path());
  expect_input_error([&] { px::load_frame(px::list_frames(ds, px::GtKind::noc).at(0)); },
                     {"im2.png", "pairs.tsv", "21x10"});
}

TEST(Crop, WritesKitti2015LayoutWithCentredRoi) {
  TempDir src;
  TempDir out_holder;
  make_kitti2015(src.path(), 21, 11);
  const fs::path out = out_holder.path() / "crop";
  const px::CropSummary s =
      px::crop_dataset(src.path() / "training", "1,46", {px::GtKind::noc, px::GtKind::occ}, 10, 6, out);
  EXPECT_EQ(s.frame_ids, (std::vector<std::string>{"000001", "000046"}));
  EXPECT_EQ(s.files_written.size(), 3u + 4u + 1u);  // frame 1: 4 files, 46: 3, LICENSE
  EXPECT_TRUE(fs::is_regular_file(out / "LICENSE.txt"));
  EXPECT_FALSE(fs::exists(out / "training" / "disp_occ_0" / "000046_10.png"));

  const px::Roi roi = px::centred_roi(21, 11, 10, 6);  // x0 5, y0 2
  const cv::Mat left = cv::imread((out / "training/image_2/000046_10.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(left.type(), CV_8UC3);  // colour kept
  EXPECT_EQ(cv::norm(left, px::crop_to_roi(colour_image(21, 11, 46), roi), cv::NORM_INF), 0.0);
  const cv::Mat gt = cv::imread((out / "training/disp_occ_0/000001_10.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(gt.type(), CV_16UC1);
  EXPECT_EQ(cv::norm(gt, px::crop_to_roi(kitti_gt(21, 11), roi), cv::NORM_INF), 0.0);

  // The crop is itself a dataset whose full ROI is the crop.
  const px::Dataset cropped = px::open_dataset(out);
  EXPECT_EQ(cropped.layout, px::DatasetLayout::kitti2015);
  EXPECT_EQ(px::list_frames(cropped, px::GtKind::noc).size(), 2u);
  const px::Frame f = px::load_frame(px::list_frames(cropped, px::GtKind::occ).at(0));
  EXPECT_EQ(f.left.cols, 10);
  EXPECT_EQ(f.left.rows, 6);
  const px::Roi centred = px::centred_roi(f.left.cols, f.left.rows, 10, 6);
  EXPECT_EQ(centred.x0, 0);
  EXPECT_EQ(centred.y0, 0);
}

TEST(Crop, Errors) {
  TempDir src;
  TempDir out;
  make_kitti2015(src.path());
  expect_input_error([&] { px::crop_dataset(src.path(), "", {px::GtKind::noc}, 30, 6, out.path()); }, {"larger"});
  expect_input_error([&] { px::crop_dataset(src.path(), "2", {px::GtKind::occ}, 5, 5, out.path()); }, {"000002"});
  TempDir mb;
  make_middlebury(mb.path());
  expect_input_error([&] { px::crop_dataset(mb.path(), "", {px::GtKind::noc}, 5, 5, out.path()); }, {"KITTI"});
}

TEST(Crop, Kitti2012BecomesKitti2015Layout) {
  TempDir src;
  TempDir out;
  make_kitti2012(src.path());
  px::crop_dataset(src.path(), "", {px::GtKind::noc}, 8, 4, out.path());
  const px::Dataset ds = px::open_dataset(out.path());
  EXPECT_EQ(ds.layout, px::DatasetLayout::kitti2015);
  const px::Frame f = px::load_frame(px::list_frames(ds, px::GtKind::noc, "70").at(0));
  EXPECT_EQ(f.left.size(), cv::Size(8, 4));
  EXPECT_FALSE(f.converted_from_colour);
}

// The crop shipped in data/ is a valid 640x360 KITTI 2015 dataset.
TEST(ShippedData, Kitti2015Crop640x360Loads) {
  const fs::path dir = fs::path(PARALLAX_DATA_DIR) / "kitti2015-640x360";
  ASSERT_TRUE(fs::is_directory(dir)) << dir;
  EXPECT_TRUE(fs::is_regular_file(dir / "LICENSE.txt"));
  EXPECT_TRUE(fs::is_regular_file(dir / "README.md"));
  const px::Dataset ds = px::open_dataset(dir);
  EXPECT_EQ(ds.layout, px::DatasetLayout::kitti2015);
  using V = std::vector<std::string>;
  EXPECT_EQ(ids_of(px::list_frames(ds, px::GtKind::noc)), (V{"000001", "000005", "000010", "000020"}));
  EXPECT_EQ(ids_of(px::list_frames(ds, px::GtKind::occ)), (V{"000001"}));
  for (const px::GtKind kind : {px::GtKind::noc, px::GtKind::occ}) {
    for (const px::FrameRef& ref : px::list_frames(ds, kind)) {
      const px::Frame f = px::load_frame(ref);
      EXPECT_EQ(f.left.size(), cv::Size(640, 360)) << ref.id;
      EXPECT_GT(cv::countNonZero(f.gt_mask), 10000) << ref.id;
    }
  }
}
