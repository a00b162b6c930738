// What a design shows beside its figures: its maps on one frame, its avoidance stage on them and
// one flight through a scenario. Computed here (explore: the design is run, the scene flown) as
// options of the point request; reports/ only draws them.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace parallax::design {

// The avoidance stage on one disparity map (docs/avoidance.md): its U and V maps (CV_32S counts,
// D x W and H x D), the obstacles it found (nearest first) and the ground line it fitted.
struct AvoidanceView {
  struct Obstacle {
    cv::Rect u_box;           // U map: x = image column, y = disparity
    cv::Rect v_box;           // V map: x = disparity, y = image row
    cv::RotatedRect ellipse;  // fitted to the U-map contour
    double range_m = 0;
  };
  cv::Mat u_map, v_map;
  std::vector<Obstacle> obstacles;
  bool ground_found = false;
  double ground_slope = 0, ground_offset = 0;  // V map: row = slope * d + offset
  int max_disparity = 0;                       // the V map's disparity axis
};

// The design on one frame of a dataset, cropped to its region of interest.
struct FrameView {
  std::string frame_id;
  cv::Mat left_grey;                    // CV_8U
  cv::Mat disparity_px, valid_mask;     // CV_32F, CV_8U (255 = valid)
  cv::Mat gt_px, gt_mask;               // the ground truth on the same region
  cv::Mat disparity_colour, gt_colour;  // BGR, coloured on the design's disparity range
  AvoidanceView avoidance;
};

// One flight (seed 1) seen from above, and a few of its frames with the design's disparity.
struct FlightView {
  struct Cylinder {
    double x_m, z_m, radius_m;
  };
  struct Box {
    double x0_m, x1_m, z0_m, z1_m;
  };
  struct Frame {
    int index = 0;
    cv::Mat left_grey, disparity_colour;
  };
  std::string scenario;
  double speed_mps = 0;
  std::string outcome;  // to_string(Outcome)
  bool collided = false;
  double min_clearance_m = 0, goal_z_m = 0;
  std::vector<Cylinder> cylinders;
  std::vector<Box> boxes;
  std::vector<cv::Point2d> trajectory_xz_m;  // x across, z forward
  std::vector<Frame> frames;                 // start, middle, end
};

}  // namespace parallax::design
