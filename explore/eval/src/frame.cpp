// Loading a dataset frame: the images as grey, the ground truth decoded by its format (KITTI
// and pairs.tsv integer PNGs, Middlebury 2005/2006 disp1.png by image size, PFM), MiddEval3's
// non-occlusion mask, the calibration; and the check of a design's disparity range on a frame.
#include "parallax/eval/dataset.hpp"

#include <algorithm>
#include <cstdint>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "dataset_internal.hpp"
#include "parallax/eval/disparity_io.hpp"

namespace parallax::eval {
namespace fs = std::filesystem;

namespace dataset_detail {
namespace {

void require_file(const fs::path& file, const char* role) {
  if (is_dir(file)) {
    throw InputError(file.string() + ": " + role + " path is a folder, expected a file");
  }
  if (!is_file(file)) throw InputError(file.string() + ": " + role + " file not found");
}

}  // namespace

cv::Mat read_raw(const fs::path& file, const char* role) {
  require_file(file, role);
  cv::Mat image = decode_image_file(file, role);
  if (image.empty()) {
    throw InputError(file.string() + ": " + role + " file cannot be decoded as an image");
  }
  return image;
}

}  // namespace dataset_detail

using dataset_detail::middlebury_2006_scale;
using dataset_detail::read_raw;
using dataset_detail::size_text;

namespace {

// Reads an 8-bit image as grey; sets `converted` when it had colour.
cv::Mat read_grey(const fs::path& file, const char* role, bool& converted) {
  cv::Mat image = read_raw(file, role);
  if (image.depth() != CV_8U) {
    throw InputError(file.string() + ": " + role + " image has " + std::to_string(8 * image.elemSize1()) +
                     "-bit samples, expected 8-bit");
  }
  if (image.channels() == 1) return image;
  cv::Mat grey;
  if (image.channels() == 3) {
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  } else if (image.channels() == 4) {
    cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
  } else {
    throw InputError(file.string() + ": " + role + " image has " + std::to_string(image.channels()) +
                     " channels, expected 1, 3 or 4");
  }
  converted = true;
  return grey;
}

// Ground truth of an integer image (KITTI, pairs.tsv, Middlebury 2005/2006) into the frame.
void decode_integer_gt(const FrameRef& ref, Frame& frame, std::ostringstream& note) {
  const cv::Mat gt = read_raw(ref.gt_path, "ground-truth");
  const bool kitti = ref.layout != DatasetLayout::middlebury;
  if (kitti && gt.type() != CV_16UC1) {
    throw InputError(ref.gt_path.string() + ": ground truth is a " + std::to_string(gt.channels()) + "-channel " +
                     std::to_string(8 * gt.elemSize1()) +
                     "-bit image, but KITTI disparity PNGs are 16-bit single-channel "
                     "(disparity = value / 256, 0 = no GT)");
  }
  if (gt.channels() != 1 || (gt.depth() != CV_8U && gt.depth() != CV_16U)) {
    throw InputError(ref.gt_path.string() +
                     ": ground truth must be a single-channel 8- or "
                     "16-bit image, got " +
                     std::to_string(gt.channels()) + " channel(s) of " + std::to_string(8 * gt.elemSize1()) + " bits");
  }
  if (gt.size() != frame.left.size()) {
    throw InputError(ref.gt_path.string() + ": ground truth is " + size_text(gt) + " but the left image " +
                     ref.left_path.string() + " is " + size_text(frame.left));
  }
  double divisor = ref.gt_divisor;
  if (ref.gt_format == GtFormat::png_by_size) {
    if (gt.depth() != CV_8U) {
      throw InputError(ref.gt_path.string() + ": a Middlebury 2005/2006 disparity map is 8-bit, this one is 16-bit");
    }
    const int scale = middlebury_2006_scale(frame.left.rows);
    if (scale == 0) {
      throw InputError(ref.left_path.string() + ": image height " + std::to_string(frame.left.rows) +
                       " px is none of the Middlebury 2005/2006 sizes (full 1110, half 555, "
                       "third 370 rows), so the scale of " +
                       ref.gt_path.filename().string() + " is unknown");
    }
    divisor = scale;
    static const char* const kSizes[] = {"", "full", "half", "third"};
    note << ref.scene_kind << " ground truth " << ref.gt_path.filename().string() << " at " << kSizes[scale]
         << " size: disparity = value / " << scale
         << ", 0 = no GT; it serves both noc and occ (dmin.txt, the offset by which the pair "
            "was cropped, is not added: the GT is relative to the images as given)";
  }
  cv::Mat values;
  gt.convertTo(values, CV_32S);
  frame.gt_disparity_px = cv::Mat(gt.size(), CV_32FC1);
  frame.gt_mask = cv::Mat(gt.size(), CV_8UC1);
  for (int y = 0; y < gt.rows; ++y) {
    const std::int32_t* v = values.ptr<std::int32_t>(y);
    float* d = frame.gt_disparity_px.ptr<float>(y);
    std::uint8_t* ok = frame.gt_mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < gt.cols; ++x) {
      const bool has_gt = v[x] != ref.gt_invalid_value;
      ok[x] = has_gt ? 255 : 0;
      d[x] = has_gt ? static_cast<float>(static_cast<double>(v[x]) / divisor) : 0.0f;
    }
  }
  if (ref.gt_format == GtFormat::png && ref.layout == DatasetLayout::middlebury) {
    note << "frame " << ref.id << ": Middlebury GT " << ref.gt_path.filename().string() << " (disparity = value / "
         << ref.gt_divisor << ", value " << ref.gt_invalid_value << " = no GT) serves both noc and occ";
  }
}

// Ground truth of a PFM file (Middlebury 2014/2021, pairs.tsv rows with a .pfm GT).
void decode_pfm_gt(const FrameRef& ref, Frame& frame, std::ostringstream& note) {
  DisparityMap gt = read_pfm_disparity(ref.gt_path);
  if (gt.disparity_px.size() != frame.left.size()) {
    throw InputError(ref.gt_path.string() + ": ground truth is " + size_text(gt.disparity_px) + " but the left image " +
                     ref.left_path.string() + " is " + size_text(frame.left));
  }
  if (ref.gt_divisor != 1.0) gt.disparity_px /= ref.gt_divisor;
  frame.gt_disparity_px = gt.disparity_px;
  frame.gt_mask = gt.valid_mask;
  note << (ref.scene_kind.empty() ? "Middlebury" : ref.scene_kind) << " ground truth "
       << ref.gt_path.filename().string() << " (float PFM, inf = no GT)";
  if (ref.gt_divisor != 1.0) note << " divided by " << ref.gt_divisor;
  if (!ref.noc_mask_path.empty()) {
    note << ": occ uses every pixel with GT, noc only those that " << ref.noc_mask_path.filename().string()
         << " marks non-occluded (255)";
  } else {
    note << " serves both noc and occ";
  }
}

// MiddEval3's mask0nocc.png: 255 = non-occluded, 128 = occluded, 0 = no GT.
void apply_noc_mask(const FrameRef& ref, Frame& frame) {
  const cv::Mat mask = read_raw(ref.noc_mask_path, "non-occlusion mask");
  if (mask.type() != CV_8UC1) {
    throw InputError(ref.noc_mask_path.string() + ": non-occlusion mask must be an 8-bit single-channel image");
  }
  if (mask.size() != frame.left.size()) {
    throw InputError(ref.noc_mask_path.string() + ": non-occlusion mask is " + size_text(mask) +
                     " but the left image " + ref.left_path.string() + " is " + size_text(frame.left));
  }
  for (int y = 0; y < mask.rows; ++y) {
    const std::uint8_t* m = mask.ptr<std::uint8_t>(y);
    std::uint8_t* ok = frame.gt_mask.ptr<std::uint8_t>(y);
    float* d = frame.gt_disparity_px.ptr<float>(y);
    for (int x = 0; x < mask.cols; ++x) {
      if (m[x] != 255) {
        ok[x] = 0;
        d[x] = 0.0f;
      }
    }
  }
}

}  // namespace

Frame load_frame(const FrameRef& ref) {
  Frame frame;
  frame.id = ref.id;
  bool left_colour = false;
  bool right_colour = false;
  frame.left = read_grey(ref.left_path, "left image", left_colour);
  frame.right = read_grey(ref.right_path, "right image", right_colour);
  if (frame.right.size() != frame.left.size()) {
    throw InputError(ref.right_path.string() + ": right image is " + size_text(frame.right) + " but the left image " +
                     ref.left_path.string() + " is " + size_text(frame.left));
  }
  if (ref.expected_width_px > 0 && ref.expected_height_px > 0 &&
      (frame.left.cols != ref.expected_width_px || frame.left.rows != ref.expected_height_px)) {
    throw InputError(ref.left_path.string() + ": left image is " + size_text(frame.left) + " but " +
                     (ref.expected_size_source.empty() ? std::string("the dataset") : ref.expected_size_source) +
                     " declares " + size_text(ref.expected_width_px, ref.expected_height_px));
  }
  if (left_colour || right_colour) {
    frame.converted_from_colour = true;
    frame.notes.push_back("frame " + ref.id + ": colour images converted to grey with cv::cvtColor(COLOR_BGR2GRAY)");
  }
  if (ref.layout == DatasetLayout::kitti2012 && ref.left_path.parent_path().filename() == "colored_0") {
    frame.notes.push_back(
        "KITTI 2012: no image_0/ + image_1/, so the colour pairs colored_0/ + colored_1/ are "
        "read (the same cameras)");
  }

  std::ostringstream note;
  if (ref.gt_format == GtFormat::pfm) {
    decode_pfm_gt(ref, frame, note);
  } else {
    decode_integer_gt(ref, frame, note);
  }
  if (ref.gt_kind == GtKind::noc && !ref.noc_mask_path.empty()) apply_noc_mask(ref, frame);
  if (!note.str().empty()) frame.notes.push_back(note.str());

  if (cv::countNonZero(frame.gt_mask) == 0) {
    throw InputError(ref.gt_path.string() + ": ground truth has no valid pixel (" +
                     (ref.gt_format == GtFormat::pfm ? std::string("every value is inf")
                                                     : "every value is " + std::to_string(ref.gt_invalid_value)) +
                     " = no GT" +
                     (ref.gt_kind == GtKind::noc && !ref.noc_mask_path.empty()
                          ? std::string(" after the non-occlusion mask")
                          : std::string()) +
                     "): nothing to score frame " + ref.id + " against");
  }
  cv::minMaxLoc(frame.gt_disparity_px, nullptr, &frame.gt_max_disparity_px, nullptr, nullptr, frame.gt_mask);

  frame.ndisp = ref.ndisp;
  frame.calibration = ref.calibration;
  frame.dmin_px = ref.dmin_px;
  if (!ref.kitti_calib_path.empty()) {
    frame.calibration = ref.layout == DatasetLayout::kitti2012
                            ? read_kitti_calib(ref.kitti_calib_path, "P0", "P1")
                            : read_kitti_calib(ref.kitti_calib_path, "P_rect_02", "P_rect_03");
  }
  return frame;
}

std::string disparity_range_warning(const Frame& frame, const Roi& roi, int disparities, int min_disparity) {
  if (disparities <= 0) return "";
  const int end = min_disparity + disparities;
  const cv::Mat gt = crop_to_roi(frame.gt_disparity_px, roi);
  const cv::Mat mask = crop_to_roi(frame.gt_mask, roi);
  std::int64_t gt_pixels = 0;
  std::int64_t beyond = 0;
  double max_px = 0.0;
  for (int y = 0; y < gt.rows; ++y) {
    const float* d = gt.ptr<float>(y);
    const std::uint8_t* ok = mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < gt.cols; ++x) {
      if (ok[x] == 0) continue;
      ++gt_pixels;
      max_px = std::max(max_px, static_cast<double>(d[x]));
      if (d[x] >= static_cast<float>(end)) ++beyond;
    }
  }
  const bool ndisp_beyond = frame.ndisp > end;
  if (beyond == 0 && !ndisp_beyond) return "";
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(1);
  out << "frame " << frame.id << ": the design's D = " << disparities << " searches " << min_disparity << "-" << end - 1
      << " px, but ";
  if (frame.ndisp > 0) out << "the scene's ndisp is " << frame.ndisp << " (calib.txt) and ";
  out << "its ground truth inside the ROI reaches " << max_px << " px: ";
  if (beyond > 0) {
    out << 100.0 * static_cast<double>(beyond) / static_cast<double>(std::max<std::int64_t>(gt_pixels, 1))
        << " % of the ground-truth pixels (" << beyond << " of " << gt_pixels << ") are out of its reach";
  } else {
    out << "no ground-truth pixel is out of its reach, but the scene's bound is";
  }
  return out.str();
}

}  // namespace parallax::eval
