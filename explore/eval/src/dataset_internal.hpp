// Private to the dataset sources of explore/eval/src (not a public header): the helpers and the
// per-layout readers that dataset.cpp, roi.cpp, kitti.cpp, middlebury.cpp, frame.cpp and
// crop.cpp share. The public API is parallax/eval/dataset.hpp.
#pragma once

#include <cstddef>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "parallax/eval/dataset.hpp"

namespace parallax::eval::dataset_detail {

// ---------------------------------------------------------------------------------------------
// Common helpers (dataset.cpp)

// "640x360".
std::string size_text(int w, int h);
std::string size_text(const cv::Mat& m);

// Without throwing: false when the path cannot be inspected.
bool is_dir(const std::filesystem::path& p);
bool is_file(const std::filesystem::path& p);
bool path_exists(const std::filesystem::path& p);

// s cut at each sep; a trailing sep gives a trailing empty part.
std::vector<std::string> split(const std::string& s, char sep);
// True for a non-empty string of decimal digits.
bool all_digits(const std::string& s);

// Sub-folders of dir, sorted by name (hidden ones skipped).
std::vector<std::filesystem::path> sub_folders(const std::filesystem::path& dir);

// Selects among candidate frames (ids in dataset order; aliases: other accepted names of each
// frame, may be empty) by a filter. Returns indices into ids, in dataset order. `numeric` =
// KITTI rules (numbers, ranges), else exact names. `what` describes the candidates for errors.
std::vector<std::size_t> select_frames(const std::vector<std::string>& ids, const std::vector<std::string>& aliases,
                                       bool numeric, const std::string& filter, const std::string& what);

// ---------------------------------------------------------------------------------------------
// KITTI 2015 / 2012 (kitti.cpp)

// "000001" -> "000001_10.png".
std::string kitti_file(const std::string& id);

// Folder names of a KITTI layout.
struct KittiDirs {
  const char* left;
  const char* right;
  const char* noc;
  const char* occ;
};

// The default folders of a layout (KITTI 2012: the grey images).
KittiDirs kitti_dirs(DatasetLayout layout);
// The folders an opened KITTI dataset reads (KITTI 2012 may use colored_0/1).
KittiDirs kitti_dirs(const Dataset& dataset);
// The GT folder of a kind in a layout: disp_noc_0/, disp_occ_0/ (2015), disp_noc/, disp_occ/.
const char* gt_dir_name(DatasetLayout layout, GtKind kind);

// Ids of the frames of a KITTI dataset that have GT of a kind, sorted; empty if the GT folder
// is missing.
std::vector<std::string> kitti_gt_ids(const Dataset& dataset, GtKind kind);
// Where frame `id` of a KITTI dataset is (with its calibration file when there is one).
FrameRef kitti_frame_ref(const Dataset& dataset, const std::string& id, GtKind kind);

// ---------------------------------------------------------------------------------------------
// Middlebury 2014/2021, 2005/2006 and pairs.tsv (middlebury.cpp)

// Whether dir is a Middlebury scene folder: it holds any of the images or GT files of a
// 2014/2021 or 2005/2006 scene (a calib.txt or dmin.txt alone does not make a scene).
bool is_middlebury_scene(const std::filesystem::path& dir);
// The sub-folders of dir that are Middlebury scenes, sorted by name.
std::vector<std::filesystem::path> middlebury_scene_folders(const std::filesystem::path& dir);
// The scenes of an opened Middlebury dataset (Dataset::middlebury_source says where they
// are listed): pairs.tsv rows, the one scene folder, or the scene sub-folders.
std::vector<FrameRef> read_middlebury_scenes(const Dataset& dataset);
// The scene string of a Middlebury frame (for filter matching): "2003/teddy".
std::string middlebury_scene(const Dataset& dataset, const FrameRef& ref);
// Middlebury 2005/2006 disp1.png scale (1, 2, 3) by image height; 0 for any other height.
int middlebury_2006_scale(int image_height_px);

// ---------------------------------------------------------------------------------------------
// Frames (frame.cpp)

// Reads an image as stored (depth and channels unchanged); InputError naming the file when it
// is missing, a folder or undecodable.
cv::Mat read_raw(const std::filesystem::path& file, const char* role);

}  // namespace parallax::eval::dataset_detail
