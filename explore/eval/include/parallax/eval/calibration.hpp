// Camera calibration files shipped with stereo datasets (docs/evaluation.md section 1):
//   Middlebury 2014/2021  calib.txt: cam0=[f 0 cx; 0 f cy; 0 0 1], cam1=[...], doffs, baseline (mm),
//                         width, height, ndisp, vmin, vmax (and isint, dyavg, dymax, ignored)
//   Middlebury 2005/2006  dmin.txt: one integer
//   KITTI 2015            calib_cam_to_cam/NNNNNN.txt: P_rect_02, P_rect_03 (3x4, row-major)
//   KITTI 2012            calib/NNNNNN.txt: P0, P1 (P2, P3 for the colour cameras)
#pragma once

#include <filesystem>
#include <string>

#include "parallax/eval/input_error.hpp"

namespace parallax::eval {

// The geometry of a rectified stereo pair, in the left image's pixels. Depth of a pixel with
// disparity d: Z_m = focal_px * baseline_m / (d + doffs_px).
struct StereoCalibration {
  bool known = false;     // false: no calibration file was found (other fields 0)
  double focal_px = 0.0;  // focal length (fx; rectified pairs have fx = fy)
  double cx_px = 0.0;     // principal point of the left camera
  double cy_px = 0.0;
  double baseline_m = 0.0;       // distance between the two optical centres
  double doffs_px = 0.0;         // right cx - left cx (Middlebury's doffs; KITTI: 0)
  std::filesystem::path source;  // the file read
};

// A Middlebury 2014/2021 calib.txt.
struct MiddleburyCalib {
  StereoCalibration camera;  // from cam0, cam1 (or doffs) and baseline
  int ndisp = 0;             // bound on the scene's disparities: search 0 .. ndisp-1
  bool has_disparity_range = false;
  double vmin_px = 0.0;  // tight bounds of the GT disparities (when has_disparity_range)
  double vmax_px = 0.0;
  int width_px = 0;  // image size the file describes; 0 when the line is absent
  int height_px = 0;
  int width_line = 0;  // line numbers of those fields, for error messages (0 = absent)
  int height_line = 0;
};

// Reads a Middlebury calib.txt (lines key=value; blank lines ignored, unknown keys ignored).
// ndisp is required; cam0, cam1, doffs, baseline, width, height, vmin, vmax are optional but
// must parse when present. `camera.known` is set when cam0 and baseline are present. Throws
// InputError naming the file and the line (or the missing field): no ndisp, a line without
// '=', a value that is not a number, a matrix without 9 numbers, a non-positive focal length,
// baseline, ndisp, width or height.
MiddleburyCalib read_middlebury_calib(const std::filesystem::path& file);

// Reads a KITTI calibration file (lines "KEY: 12 numbers"): the left and right rectified
// projection matrices named left_key and right_key ("P_rect_02"/"P_rect_03" for KITTI 2015,
// "P0"/"P1" for KITTI 2012). focal = P[0], cx = P[2], cy = P[6], baseline = (Pl[3] - Pr[3]) / f
// (KITTI's translations are in metres). Lines with other keys are ignored. Throws InputError
// naming the file and the line (or the missing key): missing key, wrong number count, a value
// that is not a number, non-positive focal length or baseline.
StereoCalibration read_kitti_calib(const std::filesystem::path& file, const std::string& left_key,
                                   const std::string& right_key);

// Reads a Middlebury 2005/2006 dmin.txt: one integer, the number of pixels by which the pair was
// cropped (true disparity = stored disparity + dmin; used for depth, not for matching the pair
// as given). Throws InputError naming the file if it holds anything else.
int read_middlebury_dmin(const std::filesystem::path& file);

}  // namespace parallax::eval
