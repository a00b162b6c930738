// Synthetic stereo scenes for closed-loop flights (issue 8, docs/flight.md): a seeded generator of
// ground, poles and trees (vertical cylinders), buildings and walls (boxes) with random textures,
// and a ray-casting renderer of a rectified rig that gives left/right grey images and the exact
// dense disparity; scenes export in KITTI's layout so that they double as a dataset.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "parallax/uav/avoid.hpp"

namespace parallax::uav {

// World frame: x right, y down, z forward (the camera's at the start); the ground is y = 0 and
// everything stands on it (heights are negative y).
// How a surface is painted: seeded multi-octave value noise (textured), one grey level (plain:
// nothing for a matcher to find) or a periodic pattern of `stripe_period_m` (stripes: every
// period matches equally well).
enum class Surface : uint8_t { textured, plain, stripes };
struct Cylinder {
  double x_m, z_m, radius_m, height_m;
  Surface surface = Surface::textured;
};
struct Box {
  double x0_m, x1_m, z0_m, z1_m, height_m;
  Surface surface = Surface::textured;
};
// A thin horizontal branch: from (x_m, -height_m, z_m) along the ground-plane heading angle
// (0 = +z, pi/2 = +x) for length_m, radius_m thick.
struct Branch {
  double x_m, z_m, height_m, heading_rad, length_m, radius_m;
};
struct Scene {
  std::vector<Cylinder> cylinders;
  std::vector<Box> boxes;
  std::vector<Branch> branches;
  uint32_t texture_seed = 1;
  double stripe_period_m = 0.25;
  double goal_z_m = 60.0;  // the flight's goal: crossing z = goal_z_m ...
  // ... within |x| <= bound_half_width_m; leaving that strip ends a flight as out of bounds.
  double bound_half_width_m = 1e9;
};

// The stereo rig a scenario flies (docs/flight.md): a rectified pair `baseline_m` apart whose
// sensors are width_px x height_px with a horizontal field of view of hfov_deg, mounted
// mount_pitch_deg above the body's forward axis (positive: looking up), flown altitude_m above the
// ground. The default is a UAV's rig, not KITTI's car rig.
struct RigSpec {
  double baseline_m = 0.30;
  double hfov_deg = 60.0;
  int width_px = 640, height_px = 360;
  double mount_pitch_deg = 0.0;
  double altitude_m = 1.6;
};
// The cameras' imperfections: the right camera's gain and offset against the left's, Gaussian
// read noise (grey levels, both cameras) and anti-aliasing (4 samples on object edges, texture
// octaves faded once finer than the pixel's footprint).
struct Imaging {
  double right_gain = 1.0, right_offset_grey = 0.0, noise_grey = 0.0;
  bool antialias = true;
};

// A scenario family (configs/scenarios/*.yaml): kind single-pole | forest | wall-gap | corridor
// with its parameters, its rig and its imaging. Throws InputError naming the file and field.
struct Scenario {
  std::string name, kind;
  double density_per_100m2 = 2.0;  // forest
  double branches_per_tree = 0.0;  // forest: thin branches across the flight band
  double gap_m = 3.0;              // wall-gap
  double width_m = 6.0;            // corridor
  double length_m = 60.0;
  double bound_half_width_m = 0.0;  // > 0: leaving |x| <= this ends the flight (forest: its strip)
  std::string walls = "textured";   // wall-gap and corridor walls: textured | plain | stripes
  RigSpec rig;
  Imaging imaging;
};
// A scenario by file path, or by the name of a shipped one (configs/scenarios/<name>.yaml,
// compiled in: builtin_scenarios()) when no such file exists. InputError names both when neither.
Scenario load_scenario(const std::string& name_or_path);
std::vector<std::string> builtin_scenarios();
// The --scenario option's help: the shipped names, or a file.
std::string scenario_option_help();
// How a sweep records the scenario: a shipped scenario's name as given, a file's absolute path.
std::string scenario_reference(const std::string& name_or_path);
Scene generate_scene(const Scenario& s, uint32_t seed);

struct StereoFrame {
  cv::Mat left, right;   // CV_8U
  cv::Mat disparity_px;  // CV_32F, exact, left image
  cv::Mat valid_mask;    // CV_8U: 255 where a surface was hit (the sky is invalid)
  cv::Mat noc_mask;      // CV_8U: valid and visible from the right camera
};
// A KITTI-like car rig: KITTI 2015's focal length at 640 px scaled to the width, its
// baseline, the principal point at the image centre (the tests' and old datasets' rig).
Rig scene_rig(int width_px, int height_px);
// The rig of a RigSpec for the processed window: f from the field of view over the sensor width,
// the principal point at the sensor's centre, shifted to a centred roi_width x roi_height window
// (the design's region of interest). InputError when the window exceeds the sensor.
Rig rig_of(const RigSpec& spec, int roi_width_px, int roi_height_px);
// The whole rig scaled to a sensor width_px wide (height in proportion, at least 16 rows; the
// field of view kept); width_px <= 0 returns it unchanged.
RigSpec scaled_rig(const RigSpec& spec, int width_px);

// Where the left camera is and where it looks: yaw about the vertical (0 = +z, positive towards
// +x), pitch (positive: looking up). The right camera sits baseline_m along the left's x axis.
struct CameraPose {
  Eigen::Vector3d position_m{0, -1.6, 0};
  double yaw_rad = 0, pitch_rad = 0;
};
// The camera's axes in the world: columns x (right), y (down), z (forward).
Eigen::Matrix3d camera_axes(const CameraPose& pose);

// Renders the rig (image size, f, B, c) with its left camera at `camera_m` (world frame).
// radial_k1 != 0: the images are those of lenses with radial distortion k1 (x_d = x (1 + k1 r^2)
// in normalised coordinates); the disparity stays that of the rectified, undistorted pair, which
// rectification_maps() recovers.
StereoFrame render(const Scene& scene, const Rig& rig, int width_px, int height_px, const Eigen::Vector3d& camera_m,
                   double radial_k1 = 0.0);
// Which grey images render() draws: both, or the left alone (`right` left empty; the truth still
// covers both cameras), for a consumer of the left image and the exact disparity only, such as
// the oracle flight.
enum class GreyImages { both, left_only };
// Renders the rig at a pose (yaw, pitch) with the imaging's anti-aliasing; gain and noise are the
// sensor's (apply_sensor).
StereoFrame render(const Scene& scene, const Rig& rig, int width_px, int height_px, const CameraPose& pose,
                   bool antialias, GreyImages grey = GreyImages::both);
// The sensor on rendered images: the right camera's gain and offset, then read noise from `rng`.
// An empty right image takes its share of `rng` all the same, so the generator leaves in the
// state it would with both images (the frames after it get the same noise).
void apply_sensor(StereoFrame& frame, const Imaging& imaging, std::mt19937& rng);
// The remap tables (for every rectified pixel, its source position in the distorted image) of
// such lenses, as cv::initUndistortRectifyMap writes them; saved as OpenCV YAML with map_x/map_y,
// the format the rectify stage's configuration reads (rectify_maps_left/right).
void write_rectification_maps(const Rig& rig, int width_px, int height_px, double radial_k1, const std::string& path);

// Writes frames as KITTI 2015 training data: image_2, image_3, disp_noc_0, disp_occ_0.
void export_kitti(const std::vector<StereoFrame>& frames, const std::string& dir);
// training/calib_cam_to_cam/NNNNNN.txt for frames 0..frames-1: KITTI's rectified projections
// P_rect_02 = [f 0 cx 0; 0 f cy 0; 0 0 1 0] and P_rect_03 with -f B, which `eval` and `avoid`
// read as the frames' own calibration.
void write_kitti_calibration(const Rig& rig, int frames, const std::string& dir);

// Clearance from a point to the scene's obstacles (negative inside one), m: trunks, boxes and
// branches.
double clearance_m(const Scene& scene, const Eigen::Vector3d& p);
// The obstacle nearest a point, named for a report: "tree r 0.25 m at (x 1.20, z 30.5)", "branch
// (r 0.03 m, 2.10 m up) of the tree at ...", "wall x -3.0..3.0 z 20.0..20.4".
std::string nearest_obstacle(const Scene& scene, const Eigen::Vector3d& p);

}  // namespace parallax::uav
