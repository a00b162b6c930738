// The flight's planner (docs/flight.md): obstacles kept over frames in a vehicle-centred occupancy
// map (a rolling grid, in the spirit of 3DVFH+'s histogram and NanoMap's memory of past views)
// and a direction search over that map: only directions the cameras have seen, checked along the
// path for the vehicle's width, a speed from which it can still stop in the free distance, and
// hysteresis against left/right flips.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "parallax/uav/avoid.hpp"
#include "parallax/uav/scene.hpp"
#include "parallax/uav/vehicle.hpp"

namespace parallax::uav {

struct MapParams {
  double cell_m = 0.2;
  int size_cells = 256;         // the window around the vehicle (51.2 m at 0.2 m)
  double band_m = 0.6;          // points within this of the vehicle's altitude are obstacles
  double max_range_m = 25.0;    // farther points and free space are not trusted
  double min_disparity_px = 2;  // nor disparities under this
  // The image's border rows and columns are not trusted: a design's windows (census, median) and
  // its paths' starts are incomplete there.
  int border_px = 4;
  // The top rows more: a raster-order matcher's paths from above (top, top-left, top-right) start
  // at row 0, so its first rows are aggregated over the left-to-right path alone, and trunks cut
  // by the image's top edge come out with wild disparities there (seen at 1.5-2 m in the forest).
  int top_border_px = 12;
  int min_hits = 4;  // samples of one frame that make a cell's hit ...
  // ... from at least this fraction of the image columns the cell spans at its range
  double min_column_fraction = 0.25;
  // Texture confidence: disparities where the left image's mean horizontal gradient over 5x5
  // (grey levels per pixel) is under this are not trusted: a matcher fills textureless regions
  // (the sky) and horizontal edges (the horizon) from their neighbours.
  double min_texture_grey = 2.0;
  int hit_gain = 4, miss_loss = 1, occupied_at = 6, log_odds_max = 24, log_odds_min = -12;
};

// A vehicle-centred 2D occupancy grid of the flight band: cells hold hit/miss log-odds and whether
// the cameras ever saw them; storage is a ring indexed by world cell, so the window follows the
// vehicle without copying and cells leaving it are forgotten.
class LocalMap {
 public:
  enum class Cell : uint8_t { unknown, free, occupied };
  explicit LocalMap(const MapParams& p = {});
  // Declares a disk free and seen (the take-off area).
  void clear_disk(double x_m, double z_m, double radius_m);
  // One frame: points of the disparity map (CV_32F, valid_mask CV_8U 255) through the rig at the
  // pose of capture; within band_m of the camera's altitude they are hits, and the space in
  // front of each column's nearest hit (or its farthest trusted point) is a miss.
  // left_grey (CV_8U, optional): the left image, for the texture confidence.
  // hits (optional): CV_8U, 255 at the pixels taken as obstacle points, 128 at the other trusted ones.
  void integrate(const cv::Mat& disparity_px, const cv::Mat& valid_mask, const Rig& rig, const CameraPose& pose,
                 const cv::Mat& left_grey = cv::Mat(), cv::Mat* hits = nullptr);
  Cell at(double x_m, double z_m) const;
  const MapParams& params() const { return p_; }
  // The window as a picture, +z up: unknown grey, free white, occupied black, the vehicle red.
  cv::Mat picture() const;

 private:
  struct Slot {
    int32_t ix = INT32_MIN, iz = INT32_MIN;
    int16_t log_odds = 0;
    bool seen = false;
  };
  Slot* slot(int32_t ix, int32_t iz, bool create);
  const Slot* slot(int32_t ix, int32_t iz) const;
  int32_t index(double m) const { return int32_t(std::floor(m / p_.cell_m)); }
  MapParams p_;
  std::vector<Slot> slots_;
  std::vector<int32_t> frame_hits_;    // per slot, this frame's hit count
  std::vector<int32_t> frame_cols_;    // ... the columns the hits came from
  std::vector<int32_t> frame_last_u_;  // ... the last of them
  double centre_x_m_ = 0, centre_z_m_ = 0;
};

struct PlannerParams {
  double cruise_mps = 5.0;
  double brake_mps2 = 2.4;       // the deceleration planned with (0.8 MPC_ACC_HOR)
  double reaction_s = 0.1;       // latency + stage + frame + the jerk-limited brake onset: set by the loop
  double safety_m = 0.9;         // vehicle radius + margin: occupied cells this near a path block it
  double unseen_margin_m = 0.6;  // unseen cells this near a path block it (a textureless wall is unseen)
  double horizon_m = 20.0;       // how far a direction is checked
  double span_deg = 90.0;        // candidates within this of the path's bearing ...
  double step_deg = 5.0;         // ... at this spacing
  double hysteresis = 0.1;       // a new direction must beat the current by this x cruise
  double short_cost = 0.5;       // x cruise for a course free for none of the horizon
  double turn_cost = 0.25;       // x cruise per rad of change from the current direction
  double stop_margin_m = 1.0;    // kept when stopping: the loop's slow final approach to zero
  double rollout_s = 2.0;        // each candidate flown this long through the vehicle model
  double unseen_cost = 1.0;      // a path's cost per metre through unseen cells (x seen ones)
  double lookahead_m = 3.0;      // a course's descent of the cost to the goal is taken over this
  // Recovery from a stop (braking, slower than still_mps, for stuck_plans plans in a row, ~1 s at
  // the seed design's 29 Hz): the route then keeps safety_m beyond recovery_near_m of the vehicle's
  // surroundings, candidates cover the whole circle, and a vehicle still stopped turns on the spot
  // by scan_step_deg at a time (to see what its map lacks), then flies the best flyable direction
  // even away from the goal; recovery ends recovery_m from where it began.
  int stuck_plans = 30;
  double still_mps = 0.3;
  double recovery_near_m = 0.5;
  double scan_step_deg = 60.0;
  double recovery_m = 3.0;
  VehicleParams vehicle;  // the model the rollouts use (the vehicle's own)
  double bound_half_width_m = 1e9;
  Eigen::Vector2d goal_xz{0, 60};
};

struct Plan {
  Eigen::Vector3d velocity_mps{0, 0, 0};  // world frame, horizontal
  double yaw_rad = 0;
  double heading_rad = 0, free_m = 0;
  bool braking = false;  // no direction is free enough: stop and look
};

class Planner {
 public:
  explicit Planner(const PlannerParams& p) : p_(p) {}
  Plan plan(const LocalMap& map, const VehicleState& s);
  // How often the chosen direction swapped sides of the goal's bearing (by more than 10 degrees).
  int flips() const { return flips_; }
  // How often the vehicle stopped long enough to start a recovery.
  int recoveries() const { return recoveries_; }
  // The free distance along a heading from a point: where the path first comes within safety_m
  // of an occupied cell (or nearer than it starts), enters an unseen cell, or enters the bounds'
  // margin (or goes deeper into it); capped at horizon_m.
  double free_distance(const LocalMap& map, const Eigen::Vector3d& from, double heading_rad) const;

 private:
  // The recovery from a stop (PlannerParams): the plan's braking, yaw and setpoint while it lasts.
  void recover(Plan& plan, const VehicleState& s, double flyable_heading, double flyable_mps, double flyable_free_m);
  PlannerParams p_;
  bool recovery_ = false;
  Eigen::Vector2d recovery_from_xz_{0, 0};
  int stuck_plans_ = 0, scan_steps_ = 0, recoveries_ = 0;
  double scan_yaw_ = 0;
  double heading_ = 0;
  bool has_heading_ = false;
  int side_ = 0, flips_ = 0;
};

}  // namespace parallax::uav
