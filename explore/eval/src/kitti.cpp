// The KITTI 2015 and KITTI 2012 layouts: frame ids and file names, the image and GT folders,
// the frames that have GT of a kind, and where one frame's files and calibration are.
#include "parallax/eval/dataset.hpp"

#include <algorithm>

#include "dataset_internal.hpp"

namespace parallax::eval::dataset_detail {
namespace fs = std::filesystem;

namespace {

// "000001_10.png" -> "000001"; anything else -> "".
std::string kitti_id_of(const std::string& file_name) {
  const std::string suffix = "_10.png";
  if (file_name.size() != 6 + suffix.size()) return "";
  if (file_name.compare(6, suffix.size(), suffix) != 0) return "";
  const std::string id = file_name.substr(0, 6);
  return all_digits(id) ? id : "";
}

// The calibration file of a KITTI frame: KITTI 2015 calib_cam_to_cam/NNNNNN.txt, KITTI 2012
// calib/NNNNNN.txt.
fs::path kitti_calib_file(const Dataset& dataset, const std::string& id) {
  const char* dir = dataset.layout == DatasetLayout::kitti2012 ? "calib" : "calib_cam_to_cam";
  return dataset.frames_dir / dir / (id + ".txt");
}

}  // namespace

std::string kitti_file(const std::string& id) {
  return id + "_10.png";
}

// The default folders of a layout (KITTI 2012: the grey images).
KittiDirs kitti_dirs(DatasetLayout layout) {
  if (layout == DatasetLayout::kitti2012) return {"image_0", "image_1", "disp_noc", "disp_occ"};
  return {"image_2", "image_3", "disp_noc_0", "disp_occ_0"};
}

// The folders an opened KITTI dataset reads (KITTI 2012 may use colored_0/1).
KittiDirs kitti_dirs(const Dataset& dataset) {
  KittiDirs dirs = kitti_dirs(dataset.layout);
  if (!dataset.kitti_left_dir.empty()) {
    dirs.left = dataset.kitti_left_dir.c_str();
    dirs.right = dataset.kitti_right_dir.c_str();
  }
  return dirs;
}

const char* gt_dir_name(DatasetLayout layout, GtKind kind) {
  const KittiDirs dirs = kitti_dirs(layout);
  return kind == GtKind::noc ? dirs.noc : dirs.occ;
}

std::vector<std::string> kitti_gt_ids(const Dataset& dataset, GtKind kind) {
  const fs::path dir = dataset.frames_dir / gt_dir_name(dataset.layout, kind);
  std::vector<std::string> ids;
  if (!is_dir(dir)) return ids;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string id = kitti_id_of(it->path().filename().string());
    std::error_code type_ec;
    if (!id.empty() && it->is_regular_file(type_ec)) ids.push_back(id);
  }
  if (ec) throw InputError(dir.string() + ": cannot list the folder: " + ec.message());
  std::sort(ids.begin(), ids.end());
  return ids;
}

FrameRef kitti_frame_ref(const Dataset& dataset, const std::string& id, GtKind kind) {
  const KittiDirs dirs = kitti_dirs(dataset);
  FrameRef ref;
  ref.id = id;
  ref.layout = dataset.layout;
  ref.scene_kind = dataset.layout == DatasetLayout::kitti2012 ? "KITTI 2012" : "KITTI 2015";
  ref.left_path = dataset.frames_dir / dirs.left / kitti_file(id);
  ref.right_path = dataset.frames_dir / dirs.right / kitti_file(id);
  ref.gt_path = dataset.frames_dir / gt_dir_name(dataset.layout, kind) / kitti_file(id);
  ref.gt_kind = kind;
  ref.gt_format = GtFormat::png;
  ref.gt_divisor = 256.0;
  ref.gt_invalid_value = 0;
  const fs::path calib = kitti_calib_file(dataset, id);
  if (path_exists(calib)) ref.kitti_calib_path = calib;
  return ref;
}

}  // namespace parallax::eval::dataset_detail
