// The dataset cropper crop_dataset: the centred ROI of the frames of a KITTI 2015 or 2012
// dataset, written as a KITTI 2015 dataset (images, GT values unchanged, LICENSE.txt).
#include "parallax/eval/dataset.hpp"

#include <fstream>
#include <map>
#include <set>
#include <stdexcept>
#include <system_error>

#include "dataset_internal.hpp"
#include "parallax/eval/disparity_io.hpp"

namespace parallax::eval {
namespace fs = std::filesystem;
using dataset_detail::gt_dir_name;
using dataset_detail::is_file;
using dataset_detail::kitti_dirs;
using dataset_detail::kitti_file;
using dataset_detail::kitti_gt_ids;
using dataset_detail::KittiDirs;
using dataset_detail::read_raw;
using dataset_detail::select_frames;
using dataset_detail::size_text;

CropSummary crop_dataset(const fs::path& src_dir, const std::string& frame_filter, const std::vector<GtKind>& gt_kinds,
                         int roi_w, int roi_h, const fs::path& out_dir) {
  const Dataset dataset = open_dataset(src_dir);
  if (dataset.layout == DatasetLayout::middlebury) {
    throw InputError(src_dir.string() + ": crop_dataset supports KITTI datasets only");
  }
  if (gt_kinds.empty()) throw InputError("crop_dataset: no ground-truth kind given");

  // Frames with at least one of the requested GT kinds, then the filter.
  std::set<GtKind> kinds(gt_kinds.begin(), gt_kinds.end());
  std::map<GtKind, std::set<std::string>> has_gt;
  std::set<std::string> union_ids;
  for (GtKind kind : kinds) {
    for (const std::string& id : kitti_gt_ids(dataset, kind)) {
      has_gt[kind].insert(id);
      union_ids.insert(id);
    }
  }
  const std::vector<std::string> ids(union_ids.begin(), union_ids.end());
  if (ids.empty()) throw InputError(src_dir.string() + ": no frame with the requested GT");
  const std::string what = to_string(dataset.layout) + " dataset " + dataset.frames_dir.string();
  const std::vector<std::size_t> chosen = select_frames(ids, {}, true, frame_filter, what);

  const KittiDirs src = kitti_dirs(dataset);
  const KittiDirs dst = kitti_dirs(DatasetLayout::kitti2015);
  const fs::path out_frames = out_dir / "training";
  std::error_code ec;
  for (const char* sub : {dst.left, dst.right}) {
    fs::create_directories(out_frames / sub, ec);
    if (ec) throw InputError((out_frames / sub).string() + ": " + ec.message());
  }
  for (GtKind kind : kinds) {
    fs::create_directories(out_frames / gt_dir_name(DatasetLayout::kitti2015, kind), ec);
    if (ec) throw InputError(out_frames.string() + ": " + ec.message());
  }

  CropSummary summary;
  for (std::size_t index : chosen) {
    const std::string& id = ids[index];
    const std::string name = kitti_file(id);
    const fs::path left_path = dataset.frames_dir / src.left / name;
    const fs::path right_path = dataset.frames_dir / src.right / name;
    const cv::Mat left = read_raw(left_path, "left image");
    const cv::Mat right = read_raw(right_path, "right image");
    if (right.size() != left.size()) {
      throw InputError(right_path.string() + ": right image is " + size_text(right) + " but the left image " +
                       left_path.string() + " is " + size_text(left));
    }
    const Roi roi = centred_roi(left.cols, left.rows, roi_w, roi_h);
    struct Output {
      cv::Mat image;
      fs::path file;
    };
    std::vector<Output> outputs = {{crop_to_roi(left, roi).clone(), out_frames / dst.left / name},
                                   {crop_to_roi(right, roi).clone(), out_frames / dst.right / name}};
    for (GtKind kind : kinds) {
      if (has_gt[kind].count(id) == 0) continue;
      const fs::path gt_path = dataset.frames_dir / gt_dir_name(dataset.layout, kind) / name;
      const cv::Mat gt = read_raw(gt_path, "ground-truth");
      if (gt.type() != CV_16UC1) {
        throw InputError(gt_path.string() + ": ground truth must be a 16-bit single-channel PNG");
      }
      if (gt.size() != left.size()) {
        throw InputError(gt_path.string() + ": ground truth is " + size_text(gt) + " but the left image " +
                         left_path.string() + " is " + size_text(left));
      }
      // Raw uint16 values are copied unchanged: the crop's GT is bit-identical to the source.
      outputs.push_back(
          {crop_to_roi(gt, roi).clone(), out_frames / gt_dir_name(DatasetLayout::kitti2015, kind) / name});
    }
    for (const Output& o : outputs) {
      write_png(o.file, o.image);
      summary.files_written.push_back(o.file);
    }
    summary.frame_ids.push_back(id);
  }

  const fs::path licence = dataset.root / "LICENSE.txt";
  if (is_file(licence)) {
    // Copied by content (not fs::copy_file) so that the copy gets ordinary permissions and
    // a later run can overwrite it even when the source is read-only.
    const fs::path target = out_dir / "LICENSE.txt";
    std::ifstream in(licence, std::ios::binary);
    if (!in) throw InputError(licence.string() + ": cannot be read");
    fs::remove(target, ec);
    std::ofstream out(target, std::ios::binary);
    out << in.rdbuf();
    out.close();
    if (!out) throw InputError(target.string() + ": cannot write a copy of " + licence.string());
    summary.files_written.push_back(target);
  }
  return summary;
}

}  // namespace parallax::eval
