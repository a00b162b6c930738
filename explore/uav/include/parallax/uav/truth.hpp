// The avoidance stage scored against the obstacles a rendered scene really holds (docs/avoidance.md):
// `scene` writes each frame's obstacles in view (obstacles.json), `avoid` matches its detections
// to them in 3D with a tolerance from the stereo depth error, sigma_Z = Z^2 sigma_d / (f B).
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "parallax/uav/avoid.hpp"
#include "parallax/uav/scene.hpp"

namespace parallax::uav {

// One obstacle of the scene as a camera sees it, in the camera's horizontal coordinates (x right,
// z forward, m; the scene command's cameras look along +z): a circle (trees, poles, pillars) or
// a rectangle (walls). Branches (2-5 cm) are not listed: the stage's U map cannot resolve them.
struct TruthObstacle {
  int id = 0;                                     // the obstacle's index in the scene: the same over frames
  std::string kind;                               // cylinder | box
  double x_m = 0, z_m = 0, radius_m = 0;          // cylinder
  double x0_m = 0, x1_m = 0, z0_m = 0, z1_m = 0;  // box
  double range_m = 0, lateral_m = 0;              // its nearest point
};

// Whether any part of an obstacle (in camera coordinates) lies in the horizontal field of view of
// an image width_px wide through `rig`, between 0.1 m and max_range_m deep; if so its range_m and
// lateral_m become those of its nearest point in view.
bool clip_to_view(TruthObstacle& t, const Rig& rig, int width_px, double max_range_m);
// The obstacles of `scene` in view of a camera at `position_m` looking along +z (clip_to_view).
std::vector<TruthObstacle> obstacles_in_view(const Scene& scene, const Rig& rig, int width_px,
                                             const Eigen::Vector3d& position_m, double max_range_m);

// obstacles.json: {"frames": [{"frame": "000000", "obstacles": [...]}, ...]} with the fields above.
void write_truth(const std::string& path, const std::vector<std::vector<TruthObstacle>>& frames);
// Frame id -> its obstacles. Throws InputError naming the file and the field.
std::map<std::string, std::vector<TruthObstacle>> read_truth(const std::string& path);

struct TruthScoreParams {
  double sigma_disparity_px = 0.5;  // the design's disparity error (one sigma)
  double k_sigma = 3.0;             // a detection matches within k sigma_Z ...
  double min_tolerance_m = 0.5;     // ... and never less than this
  double corridor_half_m = 1.0;     // vehicle radius + margin: what blocks the flight path
  double stopping_m = 5.0;          // the distance the vehicle needs to stop (set by the caller)
};

// The tolerance a detection at depth Z gets: max(min_tolerance, k Z^2 sigma_d / (f B)).
double truth_tolerance_m(double depth_m, const Rig& rig, const TruthScoreParams& p);

// Scores over a sequence of frames (taken in order: the first-detection range is that of the first
// frame that detects an obstacle). Each obstacle, nearest first, takes the nearest unused detection
// within its tolerance; a detection within no obstacle's tolerance is a false positive.
class TruthAccumulator {
 public:
  explicit TruthAccumulator(const TruthScoreParams& p = {}) : p_(p) {}
  void add(const std::vector<Obstacle>& detections, const std::vector<TruthObstacle>& truth, const Rig& rig);
  // detection_pct_<bin> (by the obstacle's range: 0-5, 5-10, 10-20, 20-40 m), false_positives_per_frame,
  // range_error_m (mean |detected - true range| of matches), first_detection_range_m (median),
  // never_detected, blocked_agreement_pct, missed_blocks, false_blocks, frames.
  std::vector<std::pair<std::string, double>> metrics() const;
  static const std::vector<std::pair<double, double>>& range_bins();

 private:
  TruthScoreParams p_;
  int frames_ = 0, false_positives_ = 0, matches_ = 0, blocked_agree_ = 0, missed_blocks_ = 0, false_blocks_ = 0;
  double range_error_sum_m_ = 0;
  std::vector<int> seen_, detected_;  // per range bin
  std::map<int, double> first_detection_m_;
  std::map<int, bool> ever_seen_;
};

}  // namespace parallax::uav
