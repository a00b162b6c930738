// The avoidance stage (avoid.hpp).
#include "parallax/uav/avoid.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>

#include <ceres/ceres.h>
#include <opencv2/core/persistence.hpp>
#include <opencv2/imgproc.hpp>

#include "parallax/eval/dataset.hpp"

namespace parallax::uav {

// The names this file takes from the other rooms (one namespace per room).
using eval::InputError;

const char* to_string(Manoeuvre m) {
  switch (m) {
    case Manoeuvre::left:
      return "left";
    case Manoeuvre::right:
      return "right";
    case Manoeuvre::up:
      return "up";
    case Manoeuvre::down:
      return "down";
    default:
      return "fly_on";
  }
}

Rig load_rig(const std::string& path, int x0, int y0) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the calibration file");
  Rig r;
  const std::string ext = path.size() > 4 ? path.substr(path.size() - 4) : "";
  if (ext == ".yml" || ext == "yaml") {
    try {
      cv::FileStorage fs(path, cv::FileStorage::READ);
      if (!fs.isOpened()) throw InputError(path + ": not an OpenCV YAML file");
      for (const char* k : {"focal_px", "baseline_m", "cx_px", "cy_px"})
        if (fs[k].empty()) throw InputError(path + ": missing field '" + k + "'");
      r.focal_px = double(fs["focal_px"]);
      r.baseline_m = double(fs["baseline_m"]);
      r.cx_px = double(fs["cx_px"]) - x0;
      r.cy_px = double(fs["cy_px"]) - y0;
    } catch (const cv::Exception& e) {
      throw InputError(path + ": not a readable OpenCV YAML file: " + e.what());
    }
    return r;
  }
  // KITTI: "P_rect_02: 12 numbers" (cam_to_cam) or "P2: 12 numbers" (object calib).
  std::vector<double> p2, p3;
  std::string line;
  while (std::getline(in, line)) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::string key = line.substr(0, colon);
    std::istringstream ss(line.substr(colon + 1));
    std::vector<double> v;
    double x;
    while (ss >> x) v.push_back(x);
    if (v.size() != 12) continue;
    if (key == "P_rect_02" || key == "P2") p2 = v;
    if (key == "P_rect_03" || key == "P3") p3 = v;
  }
  if (p2.empty() || p3.empty())
    throw InputError(path + ": needs P_rect_02 and P_rect_03 (or P2 and P3) with 12 numbers");
  r.focal_px = p2[0];
  r.cx_px = p2[2] - x0;
  r.cy_px = p2[6] - y0;
  // P3[3] = -f * B (+ P2's own offset): B = (P2[3] - P3[3]) / f.
  r.baseline_m = (p2[3] - p3[3]) / p2[0];
  if (!(r.focal_px > 0) || !(r.baseline_m > 0)) throw InputError(path + ": focal length and baseline must be positive");
  return r;
}

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

struct LineResidual {
  double d, y;
  template <class T>
  bool operator()(const T* const ab, T* r) const {
    r[0] = T(y) - (ab[0] * T(d) + ab[1]);
    return true;
  }
};

// Whether a pixel at row y with disparity di is an obstacle pixel: inside the region of interest
// and the disparity range, and above the ground line by more than the tolerance (every such
// pixel when no ground was found).
struct ObstacleTest {
  const AvoidResult& res;
  const AvoidParams& p;
  int max_d, top;
  bool operator()(int y, int di) const {
    if (di < p.min_disparity_px || di >= max_d || y < top) return false;
    if (!res.ground_found) return true;
    return double(y) < res.ground_slope * di + res.ground_offset - p.ground_tolerance_px;
  }
};

// Calls f(y, x, di, d) for each valid pixel of rows top and below and columns x0 to x1 - 1, d its
// disparity (with the design's sub-pixel fraction, if any) and di that rounded to the nearest
// integer.
template <class F>
void for_each_valid_px(const cv::Mat& disp, const cv::Mat& valid, int top, int x0, int x1, F f) {
  for (int y = top; y < disp.rows; ++y) {
    const float* d = disp.ptr<float>(y);
    const uint8_t* v = valid.ptr<uint8_t>(y);
    for (int x = x0; x < x1; ++x)
      if (v[x]) f(y, x, int(std::lround(d[x])), d[x]);
  }
}

// V map over the region of interest (rows top and below): rows x disparities.
cv::Mat v_map_of(const cv::Mat& disp, const cv::Mat& valid, int max_d, int top, const AvoidParams& p) {
  cv::Mat v_map = cv::Mat::zeros(disp.rows, max_d, CV_32S);
  for_each_valid_px(disp, valid, top, 0, disp.cols, [&](int y, int, int di, float) {
    if (di >= p.min_disparity_px && di < max_d) ++v_map.at<int>(y, di);
  });
  return v_map;
}

// Ground: a robust line row = a d + b through the V-map cells that vote for it; sets
// res.ground_found, ground_slope and ground_offset.
void fit_ground(AvoidResult& res, int max_d, int top, const AvoidParams& p) {
  const int H = res.v_map.rows;
  double ab[2] = {double(H - top) / double(max_d), double(top)};
  ceres::Problem problem;
  int points = 0;
  // One vote per disparity: the row where the V map peaks (the ground dominates each column of
  // the V map below the horizon; obstacles are outliers the Cauchy loss discounts).
  for (int d = p.min_disparity_px; d < max_d; ++d) {
    int best_y = -1, best = p.v_threshold - 1;
    for (int y = top; y < H; ++y) {
      const int c = res.v_map.at<int>(y, d);
      if (c > best) {
        best = c;
        best_y = y;
      }
    }
    if (best_y < 0) continue;
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<LineResidual, 1, 2>(new LineResidual{double(d), double(best_y)}),
        new ceres::CauchyLoss(2.0), ab);
    ++points;
  }
  if (points >= 8) {
    ceres::Solver::Options opt;
    opt.logging_type = ceres::SILENT;
    opt.max_num_iterations = 50;
    ceres::Solver::Summary sum;
    ceres::Solve(opt, &problem, &sum);
    // A ground plane seen from above rises in the image as it nears: the slope is positive.
    res.ground_found = ab[0] > 0.05 && std::isfinite(ab[0]) && std::isfinite(ab[1]);
    res.ground_slope = ab[0];
    res.ground_offset = ab[1];
  }
}

// U map of the obstacle pixels: disparities x columns.
cv::Mat u_map_of(const cv::Mat& disp, const cv::Mat& valid, int max_d, int top, const ObstacleTest& is_obstacle_px) {
  cv::Mat u_map = cv::Mat::zeros(max_d, disp.cols, CV_32S);
  for_each_valid_px(disp, valid, top, 0, disp.cols, [&](int y, int x, int di, float) {
    if (is_obstacle_px(y, di)) ++u_map.at<int>(di, x);
  });
  return u_map;
}

// The U map thresholded, dilated and smoothed.
cv::Mat u_binary_of(const cv::Mat& u_map, const AvoidParams& p) {
  cv::Mat bin = u_map >= p.u_threshold;
  if (p.dilate_px > 0)
    cv::dilate(bin, bin,
               cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * p.dilate_px + 1, 2 * p.dilate_px + 1)));
  if (p.gaussian_sigma_px > 0) {
    cv::GaussianBlur(bin, bin, cv::Size(0, 0), p.gaussian_sigma_px);
    bin = bin >= 128;
  }
  return bin;
}

// The obstacle of one U-map contour: its U-map box, ellipse and centroid, its rows in the image
// (the obstacle pixels of its columns and disparities) and its geometry through the rig. False
// when none of its pixels is an obstacle pixel.
bool obstacle_of(const std::vector<cv::Point>& c, const cv::Mat& disp, const cv::Mat& valid, int top,
                 const ObstacleTest& is_obstacle_px, const Rig& rig, const AvoidParams& p, Obstacle& o) {
  o.u_box = cv::boundingRect(c);
  o.ellipse = c.size() >= 5 ? cv::fitEllipse(c)
                            : cv::RotatedRect(cv::Point2f(float(o.u_box.x + o.u_box.width / 2.0),
                                                          float(o.u_box.y + o.u_box.height / 2.0)),
                                              cv::Size2f(float(o.u_box.width), float(o.u_box.height)), 0);
  const cv::Moments m = cv::moments(c);
  o.centroid = m.m00 > 0 ? cv::Point2f(float(m.m10 / m.m00), float(m.m01 / m.m00)) : o.ellipse.center;
  int y0 = disp.rows, y1 = -1;
  // The range: the nearest disparity bin the obstacle's pixels occupy (the U-map box is dilated
  // beyond them), refined by those pixels' own disparities: with sub-pixel codes
  // (subpixel_bits > 0) the mean of their fractions, with integer codes the bin itself.
  std::vector<double> bin_sum(std::size_t(o.u_box.height), 0.0);
  std::vector<int64_t> bin_count(std::size_t(o.u_box.height), 0);
  for_each_valid_px(disp, valid, top, o.u_box.x, o.u_box.x + o.u_box.width, [&](int y, int, int di, float d) {
    if (di >= o.u_box.y && di < o.u_box.y + o.u_box.height && is_obstacle_px(y, di)) {
      y0 = std::min(y0, y);
      y1 = std::max(y1, y);
      bin_sum[std::size_t(di - o.u_box.y)] += double(d);
      ++bin_count[std::size_t(di - o.u_box.y)];
    }
  });
  if (y1 < y0) return false;
  o.v_box = cv::Rect(o.u_box.y, y0, o.u_box.height, y1 - y0 + 1);
  o.reaches_roi_top = y0 <= top + 1;
  int near_bin = o.u_box.height - 1;
  while (near_bin > 0 && bin_count[std::size_t(near_bin)] == 0) --near_bin;
  const double d_bin = bin_count[std::size_t(near_bin)] > 0
                           ? bin_sum[std::size_t(near_bin)] / double(bin_count[std::size_t(near_bin)])
                           : double(o.u_box.y + near_bin);
  const double d_near = std::max(double(p.min_disparity_px), d_bin);
  const double z = rig.focal_px * rig.baseline_m / d_near;
  const double xc = o.u_box.x + o.u_box.width / 2.0, yc = y0 + (y1 - y0 + 1) / 2.0;
  o.centre_m = Eigen::Vector3d((xc - rig.cx_px) * z / rig.focal_px, (yc - rig.cy_px) * z / rig.focal_px, z);
  o.range_m = z;
  o.lateral_m = o.centre_m.x();
  o.width_m = double(o.u_box.width) * z / rig.focal_px;
  o.height_m = double(y1 - y0 + 1) * z / rig.focal_px;
  return true;
}

// The largest contours of the binary U map as obstacles, nearest first.
std::vector<Obstacle> find_obstacles(const cv::Mat& u_binary, const cv::Mat& disp, const cv::Mat& valid, int top,
                                     const ObstacleTest& is_obstacle_px, const Rig& rig, const AvoidParams& p) {
  std::vector<Obstacle> obstacles;
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(u_binary.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  std::sort(contours.begin(), contours.end(),
            [](const auto& a, const auto& b) { return cv::contourArea(a) > cv::contourArea(b); });
  for (const auto& c : contours) {
    if (int(obstacles.size()) >= p.max_obstacles) break;
    if (cv::contourArea(c) < p.min_area_cells) continue;
    Obstacle o;
    if (obstacle_of(c, disp, valid, top, is_obstacle_px, rig, p, o)) obstacles.push_back(o);
  }
  std::sort(obstacles.begin(), obstacles.end(),
            [](const Obstacle& a, const Obstacle& b) { return a.range_m < b.range_m; });
  return obstacles;
}

// Reactive planner: the nearest obstacle inside the corridor within the critical distance is
// passed on the side that needs the shortest displacement. Sets res.velocity_mps, manoeuvre, target.
void plan(AvoidResult& res, const AvoidParams& p) {
  const double clear = p.vehicle_radius_m + p.safety_margin_m;
  res.velocity_mps = Eigen::Vector3d(p.cruise_mps, 0, 0);
  for (std::size_t i = 0; i < res.obstacles.size(); ++i) {
    const Obstacle& o = res.obstacles[i];
    if (o.range_m > p.critical_distance_m) continue;
    const double left_edge = o.lateral_m - o.width_m / 2, right_edge = o.lateral_m + o.width_m / 2;
    const double top_edge = o.centre_m.y() - o.height_m / 2, bottom_edge = o.centre_m.y() + o.height_m / 2;
    if (left_edge > clear || right_edge < -clear || top_edge > clear || bottom_edge < -clear)
      continue;  // not in the way
    struct Option {
      Manoeuvre m;
      double displacement_m;
    };
    // The drone (at 0) must end `clear` beyond the edge it passes: x <= left_edge - clear, x >=
    // right_edge + clear, y <= top_edge - clear (up; y points down) or y >= bottom_edge + clear.
    std::vector<Option> options = {{Manoeuvre::left, clear - left_edge}, {Manoeuvre::right, clear + right_edge}};
    // Over the top only when the top was seen (not cut by the region of interest).
    if (!o.reaches_roi_top) options.push_back({Manoeuvre::up, clear - top_edge});
    // Below an obstacle that stands on the ground there is no way through.
    if (!res.ground_found) options.push_back({Manoeuvre::down, clear + bottom_edge});
    const auto best = std::min_element(options.begin(), options.end(), [](const Option& a, const Option& b) {
      return a.displacement_m < b.displacement_m;
    });
    res.manoeuvre = best->m;
    res.target = int(i);
    const double slow = std::clamp(o.range_m / p.critical_distance_m, 0.2, 1.0);
    res.velocity_mps = Eigen::Vector3d(p.cruise_mps * slow, 0, 0);
    if (best->m == Manoeuvre::left) res.velocity_mps.y() = -p.sidestep_mps;
    if (best->m == Manoeuvre::right) res.velocity_mps.y() = p.sidestep_mps;
    if (best->m == Manoeuvre::up) res.velocity_mps.z() = -p.sidestep_mps;
    if (best->m == Manoeuvre::down) res.velocity_mps.z() = p.sidestep_mps;
    break;
  }
}

}  // namespace

AvoidResult avoid(const cv::Mat& disp, const cv::Mat& valid, int max_d, const Rig& rig, const AvoidParams& p) {
  CV_Assert(disp.type() == CV_32FC1 && valid.type() == CV_8UC1 && disp.size() == valid.size() && max_d > 0);
  AvoidResult res;
  const int top = disp.rows * p.horizon_rows_pct / 100;
  auto t0 = Clock::now();
  res.v_map = v_map_of(disp, valid, max_d, top, p);
  res.timings.uv_maps_ms += ms_since(t0);
  t0 = Clock::now();
  fit_ground(res, max_d, top, p);
  const ObstacleTest is_obstacle_px{res, p, max_d, top};
  res.timings.filtering_ms += ms_since(t0);
  t0 = Clock::now();
  res.u_map = u_map_of(disp, valid, max_d, top, is_obstacle_px);
  res.timings.uv_maps_ms += ms_since(t0);
  t0 = Clock::now();
  res.u_binary = u_binary_of(res.u_map, p);
  res.timings.filtering_ms += ms_since(t0);
  t0 = Clock::now();
  res.obstacles = find_obstacles(res.u_binary, disp, valid, top, is_obstacle_px, rig, p);
  res.timings.contours_ms += ms_since(t0);
  t0 = Clock::now();
  plan(res, p);
  res.timings.planning_ms += ms_since(t0);
  return res;
}

AvoidScore score_avoidance(const AvoidResult& design, const AvoidResult& ref) {
  AvoidScore s;
  s.predicted = int(design.obstacles.size());
  s.reference = int(ref.obstacles.size());
  std::vector<bool> used(ref.obstacles.size(), false);
  for (const auto& o : design.obstacles) {
    double best = 0;
    int best_j = -1;
    for (std::size_t j = 0; j < ref.obstacles.size(); ++j) {
      if (used[j]) continue;
      const cv::Rect inter = o.u_box & ref.obstacles[j].u_box;
      const double uni = double(o.u_box.area() + ref.obstacles[j].u_box.area() - inter.area());
      const double iou = uni > 0 ? double(inter.area()) / uni : 0.0;
      if (iou > best) {
        best = iou;
        best_j = int(j);
      }
    }
    if (best_j >= 0 && best >= 0.3) {
      used[std::size_t(best_j)] = true;
      ++s.matched;
      s.range_error_sum_m += std::fabs(o.range_m - ref.obstacles[std::size_t(best_j)].range_m);
    }
  }
  s.same_decision = design.manoeuvre == ref.manoeuvre;
  return s;
}

Rig kitti_default_rig(int x0, int y0) {
  Rig r;
  r.focal_px = 721.5377;
  r.baseline_m = 0.5327;
  r.cx_px = 609.5593 - x0;
  r.cy_px = 172.854 - y0;
  return r;
}

AvoidScore AvoidAccumulator::add(const cv::Mat& disp, const cv::Mat& valid, const cv::Mat& gt, const cv::Mat& gm,
                                 int max_d, const Rig& rig) {
  last_design_ = avoid(disp, valid, max_d, rig);
  last_reference_ = avoid(gt, gm, max_d, rig);
  const AvoidScore s = score_avoidance(last_design_, last_reference_);
  total_.predicted += s.predicted;
  total_.reference += s.reference;
  total_.matched += s.matched;
  total_.range_error_sum_m += s.range_error_sum_m;
  agree_ += s.same_decision ? 1 : 0;
  ++frames_;
  timing_sum_.uv_maps_ms += last_design_.timings.uv_maps_ms;
  timing_sum_.filtering_ms += last_design_.timings.filtering_ms;
  timing_sum_.contours_ms += last_design_.timings.contours_ms;
  timing_sum_.planning_ms += last_design_.timings.planning_ms;
  return s;
}

std::vector<std::pair<std::string, double>> AvoidAccumulator::metrics() const {
  return {{"obstacle_precision", total_.predicted ? 100.0 * total_.matched / total_.predicted : 0.0},
          {"obstacle_recall", total_.reference ? 100.0 * total_.matched / total_.reference : 0.0},
          {"range_error_m", total_.matched ? total_.range_error_sum_m / total_.matched : 0.0},
          {"decision_agreement_pct", frames_ ? 100.0 * agree_ / frames_ : 0.0},
          {"mean_ms_per_frame", frames_ ? timing_sum_.total_ms() / frames_ : 0.0}};
}

}  // namespace parallax::uav
