// Synthetic stereo scenes for closed-loop flights (issue 8, docs/flight.md): a seeded generator of
// ground, poles and trees (vertical cylinders), buildings and walls (boxes) with random textures,
// and a ray-casting renderer of a rectified rig that gives left/right grey images and the exact
// dense disparity; scenes export in KITTI's layout so that they double as a dataset.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "parallax/uav/avoid.hpp"

namespace parallax::explore {

// World frame: x right, y down, z forward (the camera's at the start); the ground is y = 0 and
// everything stands on it (heights are negative y).
struct Cylinder {
  double x_m, z_m, radius_m, height_m;
};
struct Box {
  double x0_m, x1_m, z0_m, z1_m, height_m;
};
struct Scene {
  std::vector<Cylinder> cylinders;
  std::vector<Box> boxes;
  uint32_t texture_seed = 1;
  double goal_z_m = 60.0;  // the flight's goal: straight ahead
};

// A scenario family (configs/scenarios/*.yaml): kind single-pole | forest | wall-gap | corridor
// with its parameters. Throws InputError naming the file and field.
struct Scenario {
  std::string name, kind;
  double density_per_100m2 = 2.0;  // forest
  double gap_m = 3.0;              // wall-gap
  double width_m = 6.0;            // corridor
  double length_m = 60.0;
};
// A scenario by file path, or by the name of a shipped one (configs/scenarios/<name>.yaml,
// compiled in: builtin_scenarios()) when no such file exists. InputError names both when neither.
Scenario load_scenario(const std::string& name_or_path);
std::vector<std::string> builtin_scenarios();
// How a sweep records the scenario: a shipped scenario's name as given, a file's absolute path.
std::string scenario_reference(const std::string& name_or_path);
Scene generate_scene(const Scenario& s, uint32_t seed);

struct StereoFrame {
  cv::Mat left, right;   // CV_8U
  cv::Mat disparity_px;  // CV_32F, exact, left image
  cv::Mat valid_mask;    // CV_8U: 255 where a surface was hit (the sky is invalid)
  cv::Mat noc_mask;      // CV_8U: valid and visible from the right camera
};
// The rig of the synthetic scenes: KITTI 2015's focal length at 640 px scaled to the width, its
// baseline, the principal point at the image centre. (The camera flies 1.6 m above the ground.)
Rig scene_rig(int width_px, int height_px);

// Renders the rig (image size, f, B, c) with its left camera at `camera_m` (world frame).
// radial_k1 != 0: the images are those of lenses with radial distortion k1 (x_d = x (1 + k1 r^2)
// in normalised coordinates); the disparity stays that of the rectified, undistorted pair, which
// rectification_maps() recovers.
StereoFrame render(const Scene& scene, const Rig& rig, int width_px, int height_px, const Eigen::Vector3d& camera_m,
                   double radial_k1 = 0.0);
// The remap tables (for every rectified pixel, its source position in the distorted image) of
// such lenses, as cv::initUndistortRectifyMap writes them; saved as OpenCV YAML with map_x/map_y,
// the format the rectify stage's configuration reads (rectify_maps_left/right).
void write_rectification_maps(const Rig& rig, int width_px, int height_px, double radial_k1, const std::string& path);

// Writes frames as KITTI 2015 training data: image_2, image_3, disp_noc_0, disp_occ_0.
void export_kitti(const std::vector<StereoFrame>& frames, const std::string& dir);

// Clearance from a point to the scene's obstacles (negative inside one), m.
double clearance_m(const Scene& scene, const Eigen::Vector3d& p);

}  // namespace parallax::explore
