// The avoidance stage (docs/avoidance.md): CPU code that turns a disparity map into obstacles and a
// velocity setpoint, as the seed system's processor does. U map (per column, a histogram of
// disparities) and V map (per row); the ground plane from the V map by a robust line fit (Ceres,
// Cauchy loss); obstacles as the largest contours of the thresholded, dilated, smoothed U map of
// the non-ground pixels, with their rows from the V map; cylinders in camera coordinates through
// the rig model (Eigen); a reactive planner; MAVLink 2 output.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace parallax::uav {

// Pinhole stereo rig of the processed image (the ROI): focal length and principal point in px,
// baseline in m.
struct Rig {
  double focal_px = 721.5377;
  double baseline_m = 0.5327;
  double cx_px = 308.5593;  // KITTI 2015's P2 for the centred 640x360 crop of 1242x375
  double cy_px = 165.354;
};
// KITTI calib_cam_to_cam / object-style calib files (P_rect_02 / P2 and P_rect_03 / P3 lines) or an
// OpenCV YAML (focal_px, baseline_m, cx_px, cy_px). The principal point is shifted by the ROI's
// origin (x0, y0). Throws InputError naming the file and the missing field.
Rig load_rig(const std::string& path, int roi_x0_px, int roi_y0_px);

struct AvoidParams {
  int horizon_rows_pct = 35;       // ROI: the top rows left out (cluttered horizon and sky)
  int min_disparity_px = 6;        // farther than f*B/6 ~ 64 m is not an obstacle
  int u_threshold = 18;            // U-map cell count that marks an obstacle column (px of height)
  int v_threshold = 8;             // V-map cell count that votes for the ground line
  double ground_tolerance_px = 6;  // rows within this of the ground line are ground
  int dilate_px = 3;
  double gaussian_sigma_px = 1.0;
  int max_obstacles = 5;
  int min_area_cells = 12;  // contours smaller than this in the U map are noise
  // Planner.
  double critical_distance_m = 12.0;
  double safety_margin_m = 1.0;
  double vehicle_radius_m = 0.5;
  double cruise_mps = 3.0;
  double sidestep_mps = 1.5;
};

struct Obstacle {
  cv::Rect u_box;                     // in the U map: x = image column, y = disparity
  cv::Rect v_box;                     // in the V map: x = disparity, y = image row
  cv::RotatedRect ellipse;            // fitted to the U-map contour
  cv::Point2f centroid;               // U-map centroid (column, disparity)
  Eigen::Vector3d centre_m{0, 0, 0};  // camera frame: x right, y down, z forward
  double range_m = 0, lateral_m = 0, width_m = 0, height_m = 0;
  bool reaches_roi_top = false;  // its top is cut by the region of interest: its height is unknown
};

enum class Manoeuvre { fly_on, left, right, up, down };
const char* to_string(Manoeuvre m);

struct AvoidTimings {
  double uv_maps_ms = 0, filtering_ms = 0, contours_ms = 0, planning_ms = 0;
  double total_ms() const { return uv_maps_ms + filtering_ms + contours_ms + planning_ms; }
};

struct AvoidResult {
  cv::Mat u_map, v_map;                        // CV_32S counts: D x W and H x D
  cv::Mat u_binary;                            // after threshold, dilation, smoothing
  double ground_slope = 0, ground_offset = 0;  // V map: row = slope * d + offset
  bool ground_found = false;
  std::vector<Obstacle> obstacles;  // nearest first
  Manoeuvre manoeuvre = Manoeuvre::fly_on;
  int target = -1;                        // obstacle the manoeuvre avoids
  Eigen::Vector3d velocity_mps{0, 0, 0};  // body frame: x forward, y right, z down (MAV_FRAME_BODY_NED)
  AvoidTimings timings;
};

// disparity_px (CV_32F) with valid_mask (CV_8U, 255 = valid); disparities up to max_disparity.
AvoidResult avoid(const cv::Mat& disparity_px, const cv::Mat& valid_mask, int max_disparity, const Rig& rig,
                  const AvoidParams& p = {});

// Matching obstacles of a design against those found on the ground truth (U-map box overlap,
// IoU >= 0.3).
struct AvoidScore {
  int predicted = 0, reference = 0, matched = 0;
  double range_error_sum_m = 0;
  bool same_decision = false;
};
AvoidScore score_avoidance(const AvoidResult& design, const AvoidResult& reference);

// KITTI 2015's left colour camera (P_rect_02) for a processed region whose origin in the full
// image is (x0, y0): the default rig of the shipped data.
Rig kitti_default_rig(int roi_x0_px, int roi_y0_px);

// Scores of the avoidance stage over many frames: obstacle_precision, obstacle_recall (percent),
// range_error_m, decision_agreement_pct, mean_ms_per_frame (of the design's stage).
class AvoidAccumulator {
 public:
  // Runs the stage on both maps of one frame, scores the design's against the ground truth's,
  // and returns that frame's score; last_design()/last_reference() keep the two results.
  AvoidScore add(const cv::Mat& disparity_px, const cv::Mat& valid_mask, const cv::Mat& gt_px, const cv::Mat& gt_mask,
                 int max_disparity, const Rig& rig);
  std::vector<std::pair<std::string, double>> metrics() const;
  const AvoidResult& last_design() const { return last_design_; }
  const AvoidResult& last_reference() const { return last_reference_; }
  const AvoidTimings& timing_sum() const { return timing_sum_; }  // of the design's stage
  int frames() const { return frames_; }

 private:
  AvoidScore total_;
  int agree_ = 0, frames_ = 0;
  AvoidTimings timing_sum_;
  AvoidResult last_design_, last_reference_;
};

}  // namespace parallax::uav
