// The KITTI 2015 crop shipped in data/kitti2015-640x360 is exactly what crop_dataset makes from
// ../shared/datasets/kitti2015. With PARALLAX_REGENERATE=1 this test rewrites the shipped crop
// instead of checking it (this is how data/kitti2015-640x360 was produced; see its README.md).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <string>

#include "parallax/eval/dataset.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
namespace px = parallax::eval;
using parallax::test::TempDir;

namespace {

// The recipe of the shipped crop.
const char* const kFrames = "1,5,10,20";
constexpr int kRoiW = 640;
constexpr int kRoiH = 360;

px::CropSummary make_crop(const fs::path& src, const fs::path& out) {
  return px::crop_dataset(src, kFrames, {px::GtKind::noc, px::GtKind::occ}, kRoiW, kRoiH, out);
}

// Relative paths of the regular files under dir.
std::set<std::string> files_under(const fs::path& dir) {
  std::set<std::string> files;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) files.insert(e.path().lexically_relative(dir).generic_string());
  }
  return files;
}

std::string bytes_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

TEST(ShippedCrop, Kitti2015At640x360MatchesAFreshCrop) {
  const fs::path src = fs::path(PARALLAX_SHARED_DATASETS) / "kitti2015";
  const fs::path shipped = fs::path(PARALLAX_DATA_DIR) / "kitti2015-640x360";
  if (!fs::is_directory(src)) GTEST_SKIP() << "no shared datasets: " << src;

  const char* regenerate = std::getenv("PARALLAX_REGENERATE");
  if (regenerate != nullptr && std::string(regenerate) == "1") {
    fs::remove_all(shipped / "training");  // no stale frames; README.md is kept
    const px::CropSummary s = make_crop(src, shipped);
    for (const fs::path& f : s.files_written) std::cout << "wrote " << f.string() << "\n";
    EXPECT_EQ(s.frame_ids.size(), 4u);
    return;
  }

  ASSERT_TRUE(fs::is_directory(shipped)) << shipped;
  TempDir fresh;
  make_crop(src, fresh.path());
  const std::set<std::string> expected = files_under(fresh.path());
  std::set<std::string> actual = files_under(shipped);
  actual.erase("README.md");
  EXPECT_EQ(actual, expected);
  EXPECT_EQ(expected.size(), 4u * 3u + 1u + 1u);  // 4 frames x (2 images + noc), 1 occ, LICENSE

  EXPECT_EQ(bytes_of(shipped / "LICENSE.txt"), bytes_of(fresh.path() / "LICENSE.txt"));
  // Images are compared decoded: PNG bytes may differ between zlib versions.
  for (const std::string& rel : expected) {
    if (fs::path(rel).extension() != ".png" || actual.count(rel) == 0) continue;
    const cv::Mat a = cv::imread((shipped / rel).string(), cv::IMREAD_UNCHANGED);
    const cv::Mat b = cv::imread((fresh.path() / rel).string(), cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(a.empty()) << rel;
    ASSERT_EQ(a.type(), b.type()) << rel;
    ASSERT_EQ(a.size(), b.size()) << rel;
    EXPECT_EQ(a.size(), cv::Size(kRoiW, kRoiH)) << rel;
    EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0) << rel;
  }
}
