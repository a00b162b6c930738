// Layout detection and loading of the real datasets in ../shared/datasets (skipped when the
// folder is missing, e.g. on a user's machine).
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "parallax/eval/dataset.hpp"
#include "parallax/eval/metrics.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
namespace px = parallax::eval;
using parallax::test::TempDir;

namespace {

fs::path shared(const std::string& sub) {
  return fs::path(PARALLAX_SHARED_DATASETS) / sub;
}

#define SKIP_IF_MISSING(dir)                                                   \
  do {                                                                         \
    if (!fs::is_directory(dir)) GTEST_SKIP() << "no shared datasets: " << dir; \
  } while (false)

double max_gt(const px::Frame& f) {
  double max_px = 0.0;
  cv::minMaxLoc(f.gt_disparity_px, nullptr, &max_px, nullptr, nullptr, f.gt_mask);
  return max_px;
}

}  // namespace

TEST(SharedDatasets, Kitti2015) {
  const fs::path dir = shared("kitti2015");
  SKIP_IF_MISSING(dir);
  const px::Dataset ds = px::open_dataset(dir);
  EXPECT_EQ(ds.layout, px::DatasetLayout::kitti2015);
  EXPECT_EQ(px::open_dataset(dir / "training").frames_dir, ds.frames_dir);
  const std::vector<px::FrameRef> noc = px::list_frames(ds, px::GtKind::noc);
  ASSERT_EQ(noc.size(), 30u);
  EXPECT_EQ(noc.front().id, "000001");
  EXPECT_EQ(noc.back().id, "000030");
  const std::vector<px::FrameRef> occ = px::list_frames(ds, px::GtKind::occ);
  ASSERT_EQ(occ.size(), 3u);
  EXPECT_EQ(occ[0].id, "000000");
  EXPECT_EQ(occ[1].id, "000001");
  EXPECT_EQ(occ[2].id, "000046");
  EXPECT_EQ(px::list_frames(ds, px::GtKind::noc, "1-5,7").size(), 6u);
  EXPECT_THROW(px::list_frames(ds, px::GtKind::noc, "000046"), px::InputError);  // occ only

  const px::Frame f = px::load_frame(noc[0]);
  EXPECT_EQ(f.left.type(), CV_8UC1);
  EXPECT_EQ(f.left.size(), cv::Size(1242, 375));
  EXPECT_TRUE(f.converted_from_colour);
  EXPECT_FALSE(f.notes.empty());
  const double density = cv::countNonZero(f.gt_mask) / static_cast<double>(f.gt_mask.total());
  EXPECT_GT(density, 0.1);
  EXPECT_LT(density, 0.6);
  EXPECT_GT(max_gt(f), 30.0);
  EXPECT_LT(max_gt(f), 256.0);
  EXPECT_DOUBLE_EQ(f.gt_max_disparity_px, max_gt(f));
  EXPECT_FALSE(f.calibration.known);  // this copy has no calib_cam_to_cam/

  // The GT inside the default ROI: a perfect prediction scores 100 % everywhere.
  const px::Roi roi = px::resolve_roi(px::default_roi_size(ds.layout), f.left.cols, f.left.rows);
  const cv::Mat gt = px::crop_to_roi(f.gt_disparity_px, roi);
  const cv::Mat mask = px::crop_to_roi(f.gt_mask, roi);
  const px::DerivedMetrics m = px::derive_metrics(px::count_frame(gt, mask, gt, mask));
  EXPECT_DOUBLE_EQ(m.correct_3px_pct, 100.0);
  EXPECT_DOUBLE_EQ(m.density_gt_pct, 100.0);
  EXPECT_DOUBLE_EQ(m.d1_all_pct, 0.0);
}

TEST(SharedDatasets, Kitti2012) {
  const fs::path dir = shared("kitti2012");
  SKIP_IF_MISSING(dir);
  const px::Dataset ds = px::open_dataset(dir);
  EXPECT_EQ(ds.layout, px::DatasetLayout::kitti2012);
  for (const px::GtKind kind : {px::GtKind::noc, px::GtKind::occ}) {
    const std::vector<px::FrameRef> frames = px::list_frames(ds, kind, "70");
    ASSERT_EQ(frames.size(), 1u);
    EXPECT_EQ(frames[0].id, "000070");
    const px::Frame f = px::load_frame(frames[0]);
    EXPECT_EQ(f.left.size(), cv::Size(1241, 376));
    EXPECT_FALSE(f.converted_from_colour);  // image_0/1 are grey
    EXPECT_GT(cv::countNonZero(f.gt_mask), 50000);
    EXPECT_LT(max_gt(f), 256.0);
    // calib/000070.txt: P0 and P1 (the grey cameras), focal and baseline from the file.
    ASSERT_TRUE(f.calibration.known);
    EXPECT_NEAR(f.calibration.focal_px, 718.856, 1e-3);
    EXPECT_NEAR(f.calibration.cx_px, 607.1928, 1e-4);
    EXPECT_NEAR(f.calibration.baseline_m, 386.1448 / 718.856, 1e-6);
  }
}

// The same frame read from colored_0/ + colored_1/ alone (as when only the colour archive is
// unpacked): the colour cameras are the grey ones, their grey conversion matches image_0.
TEST(SharedDatasets, Kitti2012ColouredOnly) {
  const fs::path dir = shared("kitti2012");
  SKIP_IF_MISSING(dir);
  TempDir tmp;
  const fs::path t = tmp.path() / "training";
  fs::create_directories(t);
  for (const char* sub : {"colored_0", "colored_1", "disp_noc", "disp_occ", "calib"})
    fs::create_directory_symlink(dir / "training" / sub, t / sub);
  const px::Dataset ds = px::open_dataset(tmp.path());
  EXPECT_EQ(ds.layout, px::DatasetLayout::kitti2012);
  EXPECT_EQ(ds.kitti_left_dir, "colored_0");
  const px::Frame colour = px::load_frame(px::list_frames(ds, px::GtKind::noc).at(0));
  EXPECT_TRUE(colour.converted_from_colour);
  const px::Frame grey = px::load_frame(px::list_frames(px::open_dataset(dir), px::GtKind::noc).at(0));
  ASSERT_EQ(colour.left.size(), grey.left.size());
  cv::Mat diff;
  cv::absdiff(colour.left, grey.left, diff);
  EXPECT_LT(cv::mean(diff)[0], 1.0);  // same viewpoint (a shifted camera would differ widely)
  EXPECT_EQ(cv::norm(colour.gt_disparity_px, grey.gt_disparity_px, cv::NORM_INF), 0.0);
  EXPECT_DOUBLE_EQ(colour.calibration.baseline_m, grey.calibration.baseline_m);
}

// The shared Middlebury copy holds the 2001 and 2003 scenes in their own file names (im2/im6,
// disp2.png, ...; no 2005/2006 or 2014/2021 scene) indexed by the legacy pairs.tsv.
TEST(SharedDatasets, Middlebury) {
  const fs::path dir = shared("middlebury");
  SKIP_IF_MISSING(dir);
  const px::Dataset ds = px::open_dataset(dir);
  EXPECT_EQ(ds.layout, px::DatasetLayout::middlebury);
  EXPECT_EQ(ds.middlebury_source, "pairs.tsv");
  const std::vector<px::FrameRef> frames = px::list_frames(ds, px::GtKind::noc);
  ASSERT_EQ(frames.size(), 4u);
  EXPECT_EQ(frames[0].id, "tsukuba");
  EXPECT_EQ(frames[3].id, "teddy");

  const px::Frame teddy = px::load_frame(px::list_frames(ds, px::GtKind::occ, "teddy").at(0));
  EXPECT_EQ(teddy.left.size(), cv::Size(450, 375));
  EXPECT_TRUE(teddy.converted_from_colour);
  // 8-bit value / 4: the file's largest value is 211, so 52.75 px (not 255 / 4 = 63.75).
  EXPECT_DOUBLE_EQ(max_gt(teddy), 211.0 / 4.0);
  const double density = cv::countNonZero(teddy.gt_mask) / static_cast<double>(teddy.gt_mask.total());
  EXPECT_NEAR(density, 0.9798, 0.001);  // gt_density column of pairs.tsv

  const px::Frame tsukuba = px::load_frame(px::list_frames(ds, px::GtKind::noc, "2001/tsukuba").at(0));
  EXPECT_EQ(tsukuba.left.size(), cv::Size(384, 288));
  EXPECT_DOUBLE_EQ(max_gt(tsukuba), 224.0 / 16.0);  // value / 16

  const px::Frame cones = px::load_frame(px::list_frames(ds, px::GtKind::noc, "cones").at(0));
  EXPECT_DOUBLE_EQ(max_gt(cones), 220.0 / 4.0);
  const px::Frame venus = px::load_frame(px::list_frames(ds, px::GtKind::noc, "venus").at(0));
  EXPECT_DOUBLE_EQ(max_gt(venus), 158.0 / 8.0);
  EXPECT_EQ(cv::countNonZero(venus.gt_mask), static_cast<int>(venus.gt_mask.total()));  // 1.0
}
