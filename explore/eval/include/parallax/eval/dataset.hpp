// Stereo datasets with ground-truth disparity: layout detection, frame listing and filtering,
// frame loading, the region of interest (ROI) and the dataset cropper. See docs/evaluation.md.
//
// Layouts, as the datasets are downloaded (DIR may be the dataset root or its `training/`
// subfolder):
//   KITTI 2015  image_2/ (left), image_3/ (right), GT disp_noc_0/, disp_occ_0/, NNNNNN_10.png;
//               calib_cam_to_cam/NNNNNN.txt (P_rect_02, P_rect_03) when present
//   KITTI 2012  image_0/ + image_1/ (grey) or else colored_0/ + colored_1/ (RGB), GT disp_noc/,
//               disp_occ/, NNNNNN_10.png; calib/NNNNNN.txt (P0, P1) when present
//   Middlebury  scene folders (DIR is one, or holds several):
//                 2014/2021: im0.png, im1.png, disp0GT.pfm or disp0.pfm (float, inf = no GT),
//                            calib.txt (ndisp, cam0, baseline, ...), mask0nocc.png (MiddEval3)
//                 2005/2006: view1.png, view5.png, disp1.png (8-bit, value / s with s = 1, 2, 3
//                            for full, half, third size; 0 = no GT), dmin.txt
//               or the legacy index pairs.tsv (one row per scene, d = value / divisor)
// KITTI GT is uint16 PNG, disparity = value / 256, 0 = no GT.
#pragma once

#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "parallax/eval/calibration.hpp"
#include "parallax/eval/input_error.hpp"

namespace parallax::eval {

// ---------------------------------------------------------------------------------------------
// Region of interest

// A rectangle of an image, in pixels. Always inside the image it was made for.
struct Roi {
  int x0 = 0;
  int y0 = 0;
  int width_px = 0;
  int height_px = 0;
};

// The ROI of size roi_w x roi_h centred in an image_w x image_h image:
// x0 = (image_w - roi_w) / 2, y0 = (image_h - roi_h) / 2 (integer division, so an odd margin
// puts the extra pixel on the right/bottom). Throws InputError if the ROI is larger than the
// image or not positive.
Roi centred_roi(int image_w, int image_h, int roi_w, int roi_h);

// The whole image as a ROI.
Roi full_roi(int image_w, int image_h);

// A requested ROI size: either "full" (the whole image) or width x height, centred.
struct RoiSize {
  bool full = true;
  int width_px = 0;   // meaningful only when !full
  int height_px = 0;  // meaningful only when !full
};

// KITTI default: the seed paper's centred 640x360 region.
constexpr int kKittiRoiWidthPx = 640;
constexpr int kKittiRoiHeightPx = 360;

// Parses "full" or "WxH" (e.g. "640x360"). Throws InputError on anything else.
RoiSize parse_roi_size(const std::string& text);
// "full" or "640x360".
std::string to_string(const RoiSize& size);
// The ROI for one image: full_roi or centred_roi.
Roi resolve_roi(const RoiSize& size, int image_w, int image_h);

// A view (no copy, shares the pixels) of the ROI of an image. Throws std::invalid_argument if
// the ROI does not fit in the image.
cv::Mat crop_to_roi(const cv::Mat& image, const Roi& roi);

// ---------------------------------------------------------------------------------------------
// Datasets

enum class DatasetLayout { kitti2015, kitti2012, middlebury };
// Ground-truth kind: `noc` = non-occluded pixels only, `occ` = all pixels with GT.
// Middlebury has a single GT map per scene; both kinds select it, except that `noc` applies a
// MiddEval3 scene's mask0nocc.png (255 = non-occluded) when the scene has one.
enum class GtKind { noc, occ };

std::string to_string(DatasetLayout layout);    // "kitti2015", "kitti2012", "middlebury"
std::string to_string(GtKind kind);             // "noc", "occ"
GtKind parse_gt_kind(const std::string& text);  // "noc" | "occ"; throws InputError otherwise

// The default ROI of a layout: KITTI 640x360 centred, Middlebury full.
RoiSize default_roi_size(DatasetLayout layout);

// How a ground-truth file encodes disparities.
enum class GtFormat {
  png,          // 8- or 16-bit PNG/PGM: d = value / gt_divisor, value gt_invalid_value = no GT
                // (KITTI: 16-bit only, divisor 256, invalid 0)
  png_by_size,  // Middlebury 2005/2006 disp1.png, 8-bit: d = value / s where s = 1, 2 or 3 for
                // the full (1110 rows), half (555) or third (370) size images; 0 = no GT
  pfm,          // grey PFM: d = value / gt_divisor, non-finite values (inf) = no GT
};

// Where one frame's files are and how its GT is encoded.
struct FrameRef {
  std::string id;  // KITTI: "000001"; Middlebury: the scene's folder name, e.g. "teddy"
  DatasetLayout layout = DatasetLayout::kitti2015;
  std::filesystem::path left_path;
  std::filesystem::path right_path;
  std::filesystem::path gt_path;
  GtKind gt_kind = GtKind::noc;
  GtFormat gt_format = GtFormat::png;
  double gt_divisor = 256.0;
  int gt_invalid_value = 0;          // GtFormat::png only
  int expected_width_px = 0;         // from pairs.tsv or calib.txt when given there, else 0 (unchecked)
  int expected_height_px = 0;        // idem
  std::string expected_size_source;  // "pairs.tsv" or "<calib.txt> line N", for errors
  // MiddEval3 mask0nocc.png (255 = non-occluded) applied to noc GT; empty = none.
  std::filesystem::path noc_mask_path;
  // KITTI calibration file, read by load_frame; empty = none (the frame's calibration unknown).
  std::filesystem::path kitti_calib_path;
  // Middlebury 2014/2021: from calib.txt when the scene has one (read by open_dataset).
  int ndisp = 0;                  // the scene's disparity bound, 0 = unknown
  StereoCalibration calibration;  // known = false when there is no calibration
  // Middlebury 2005/2006: dmin.txt (the pair is cropped by it; 0 when absent). Not applied to
  // the GT, which is relative to the images as given.
  int dmin_px = 0;
  std::string scene_kind;  // e.g. "KITTI 2015", "Middlebury 2014/2021", "Middlebury 2005/2006"
};

// An opened dataset. Use open_dataset() to make one.
struct Dataset {
  std::filesystem::path root;        // DIR as given, minus a trailing `training/`
  std::filesystem::path frames_dir;  // the folder holding the layout (root or root/training)
  DatasetLayout layout = DatasetLayout::kitti2015;
  // KITTI only: the image folders read (KITTI 2012: image_0/1, or colored_0/1 without them).
  std::string kitti_left_dir;
  std::string kitti_right_dir;
  // Middlebury only: one FrameRef per scene (gt_kind unset), in pairs.tsv order or by folder
  // name. Scenes without a GT file are listed with an empty gt_path (list_frames skips them).
  std::vector<FrameRef> middlebury_scenes;
  std::string middlebury_source;  // "pairs.tsv", "scene folder" or "scene folders"
};

// Detects the layout of DIR (or DIR/training). Middlebury scene folders are checked when opened:
// a scene with a left image, a right image or a GT file must have the other images, its GT file
// must not be a folder, its calib.txt must parse (ndisp required). Throws InputError naming DIR
// if it does not exist or matches no layout, or naming the file (and line) that is malformed
// or missing.
Dataset open_dataset(const std::filesystem::path& dir);

// The frames having GT of the given kind, in id order (KITTI), pairs.tsv order or folder name
// order (Middlebury), restricted by a frame filter:
//   ""  or "all"        every frame
//   "1-5,7,000046"      KITTI: numbers (zero-padded to 6 digits) or full 6-digit ids, and
//                       inclusive ranges a-b. A single id must name an existing frame with that
//                       GT kind; a range selects the existing frames it covers and must cover
//                       at least one.
//   "teddy,2001/venus"  Middlebury: scene names, with or without the year folder (pairs.tsv).
// Each frame appears once, in dataset order, whatever the filter order. Throws InputError
// naming the filter item and the dataset on a frame that does not exist or a malformed item,
// and naming the dataset when no frame has GT of the kind.
std::vector<FrameRef> list_frames(const Dataset& dataset, GtKind gt_kind, const std::string& frame_filter = "");

// One loaded frame, whole images (crop with crop_to_roi).
struct Frame {
  std::string id;
  cv::Mat left;                        // CV_8UC1
  cv::Mat right;                       // CV_8UC1, same size as left
  cv::Mat gt_disparity_px;             // CV_32FC1, same size as left; 0 where there is no GT
  cv::Mat gt_mask;                     // CV_8UC1, 255 = GT present, 0 = none
  bool converted_from_colour = false;  // left/right were colour and converted to grey
  std::vector<std::string> notes;      // human-readable facts for the CLI to print
  double gt_max_disparity_px = 0.0;    // largest GT disparity (a loaded frame has GT pixels)
  int ndisp = 0;                       // the scene's disparity bound (calib.txt), 0 = unknown
  StereoCalibration calibration;       // known = false when the dataset has none for the frame
  int dmin_px = 0;                     // Middlebury 2005/2006 dmin.txt, else 0
};

// Loads a frame. Colour images are converted with cv::cvtColor(COLOR_BGR2GRAY) (BGRA2GRAY for
// 4 channels) and the fact is recorded in `notes`. Throws InputError naming the file on: missing
// or undecodable file or a folder in its place, 16-bit or otherwise unsupported images,
// left/right size mismatch, GT of another size than the left image (or than pairs.tsv or
// calib.txt declares), GT not single-channel, a KITTI GT that is not 16-bit, a Middlebury
// 2005/2006 image height that is not a full, half or third size, a malformed PFM or KITTI
// calibration file, and GT without a single valid pixel (nothing to score against).
Frame load_frame(const FrameRef& frame);

// Whether a design searching disparities min_disparity .. min_disparity + disparities - 1 covers
// a frame's far end: "" when it does, else a warning naming the frame, how far its disparities
// reach (the scene's ndisp when known, the largest GT disparity inside the ROI) and the share of
// its GT pixels inside the ROI at or beyond min_disparity + disparities (which the design cannot
// match).
std::string disparity_range_warning(const Frame& frame, const Roi& roi, int disparities, int min_disparity = 0);

// ---------------------------------------------------------------------------------------------
// Cropping a dataset

struct CropSummary {
  std::vector<std::string> frame_ids;                // frames written, dataset order
  std::vector<std::filesystem::path> files_written;  // every file written, including LICENSE
};

// Writes the centred roi_w x roi_h crop of the selected frames of a KITTI dataset (2015 or
// 2012) to out_dir/training/ in the KITTI 2015 layout: image_2/, image_3/ (the source pixels,
// colour kept, PNG), and for each kind in gt_kinds disp_noc_0/ and/or disp_occ_0/ (uint16 PNG,
// the source values unchanged) for the frames that have that GT. The frames are those that
// have at least one of the GT kinds, restricted by frame_filter (as in list_frames). Each
// frame's ROI is centred in its own image. Copies LICENSE.txt from the source root to out_dir
// when there is one. Existing files are overwritten; nothing else in out_dir is touched.
// The result is itself a valid KITTI 2015 dataset whose images are the ROI (use ROI "full").
// Throws InputError on bad input (as load_frame; Middlebury sources are not supported) and
// std::runtime_error naming the file on a failed write.
CropSummary crop_dataset(const std::filesystem::path& src_dir, const std::string& frame_filter,
                         const std::vector<GtKind>& gt_kinds, int roi_w, int roi_h,
                         const std::filesystem::path& out_dir);

}  // namespace parallax::eval
