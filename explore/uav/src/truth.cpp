// The avoidance stage against the scene's obstacles (truth.hpp).
#include "parallax/uav/truth.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "parallax/eval/input_error.hpp"
#include "parallax/uav/json.hpp"

namespace parallax::uav {

// The names this file takes from the other rooms (one namespace per room).
using eval::InputError;

namespace {

// Distance (m) from a point to an obstacle's footprint (0 inside).
double footprint_distance(const TruthObstacle& t, double x, double z) {
  if (t.kind == "cylinder") return std::max(0.0, std::hypot(x - t.x_m, z - t.z_m) - t.radius_m);
  const double dx = std::max({t.x0_m - x, 0.0, x - t.x1_m}), dz = std::max({t.z0_m - z, 0.0, z - t.z1_m});
  return std::hypot(dx, dz);
}

// Whether the flight path (|x| <= half, 0 < z <= stop) meets the footprint.
bool blocks(const TruthObstacle& t, double half_m, double stop_m) {
  if (t.kind == "cylinder") {  // the circle reaches the rectangle [-half, half] x [0, stop]
    const double dx = std::max(std::fabs(t.x_m) - half_m, 0.0), dz = std::max({-t.z_m, 0.0, t.z_m - stop_m});
    return std::hypot(dx, dz) <= t.radius_m;
  }
  return t.z0_m <= stop_m && t.z1_m > 0 && t.x0_m <= half_m && t.x1_m >= -half_m;
}

int bin_of(double range_m) {
  const auto& bins = TruthAccumulator::range_bins();
  for (std::size_t i = 0; i < bins.size(); ++i)
    if (range_m >= bins[i].first && range_m < bins[i].second) return int(i);
  return -1;
}

}  // namespace

bool clip_to_view(TruthObstacle& t, const Rig& rig, int width_px, double max_range_m) {
  // The horizontal field of view as slopes x/z of its left and right edges.
  const double left = (0.0 - rig.cx_px) / rig.focal_px, right = (width_px - rig.cx_px) / rig.focal_px;
  auto inside = [&](double x, double z) { return z > 0.1 && z <= max_range_m && x >= left * z && x <= right * z; };
  double z_near = 1e9, x_near = 0;
  if (t.kind == "cylinder") {
    // The circle's outline, every 2 degrees: its nearest point in view.
    for (int k = 0; k < 180; ++k) {
      const double a = k * M_PI / 90.0, x = t.x_m + t.radius_m * std::sin(a), z = t.z_m - t.radius_m * std::cos(a);
      if (inside(x, z) && z < z_near) {
        z_near = z;
        x_near = x;
      }
    }
  } else {
    // The nearest depth at which the box's x range meets the wedge, and the point there nearest
    // the axis.
    for (double z = std::max(t.z0_m, 0.1); z <= std::min(t.z1_m, max_range_m); z += 0.05)
      if (t.x1_m >= left * z && t.x0_m <= right * z) {
        z_near = z;
        x_near = std::clamp(0.0, std::max(t.x0_m, left * z), std::min(t.x1_m, right * z));
        break;
      }
  }
  if (z_near > max_range_m) return false;
  t.range_m = z_near;
  t.lateral_m = x_near;
  return true;
}

std::vector<TruthObstacle> obstacles_in_view(const Scene& scene, const Rig& rig, int width_px,
                                             const Eigen::Vector3d& position_m, double max_range_m) {
  std::vector<TruthObstacle> out;
  int id = 0;
  for (const Cylinder& c : scene.cylinders) {
    TruthObstacle t;
    t.id = id++;
    t.kind = "cylinder";
    t.x_m = c.x_m - position_m.x();
    t.z_m = c.z_m - position_m.z();
    t.radius_m = c.radius_m;
    if (clip_to_view(t, rig, width_px, max_range_m)) out.push_back(t);
  }
  for (const Box& b : scene.boxes) {
    TruthObstacle t;
    t.id = id++;
    t.kind = "box";
    t.x0_m = b.x0_m - position_m.x();
    t.x1_m = b.x1_m - position_m.x();
    t.z0_m = b.z0_m - position_m.z();
    t.z1_m = b.z1_m - position_m.z();
    if (clip_to_view(t, rig, width_px, max_range_m)) out.push_back(t);
  }
  return out;
}

void write_truth(const std::string& path, const std::vector<std::vector<TruthObstacle>>& frames) {
  nlohmann::json j;
  j["frames"] = nlohmann::json::array();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    char id[32];
    std::snprintf(id, sizeof id, "%06zu", i);
    const nlohmann::json list = frames[i];  // each obstacle's form (json.hpp)
    j["frames"].push_back({{"frame", id}, {"obstacles", list}});
  }
  std::ofstream out(path);
  out << j.dump(1) << "\n";
  if (!out) throw InputError(path + ": cannot write the obstacle list");
}

std::map<std::string, std::vector<TruthObstacle>> read_truth(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the obstacle list");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path + ": not JSON (" + std::string(e.what()) + ")");
  }
  std::map<std::string, std::vector<TruthObstacle>> out;
  if (!j.is_object() || !j.contains("frames") || !j["frames"].is_array())
    throw InputError(path + ": expected {\"frames\": [...]}");
  for (const auto& f : j["frames"]) {
    const std::string where = path + ": frames[" + std::to_string(out.size()) + "]";
    try {
      std::vector<TruthObstacle>& list = out[f.at("frame").get<std::string>()];
      for (const auto& o : f.at("obstacles")) {
        TruthObstacle t;
        t.id = o.at("id").get<int>();
        t.kind = o.at("kind").get<std::string>();
        t.range_m = o.at("range_m").get<double>();
        t.lateral_m = o.at("lateral_m").get<double>();
        if (t.kind == "cylinder") {
          t.x_m = o.at("x_m").get<double>();
          t.z_m = o.at("z_m").get<double>();
          t.radius_m = o.at("radius_m").get<double>();
        } else if (t.kind == "box") {
          t.x0_m = o.at("x0_m").get<double>();
          t.x1_m = o.at("x1_m").get<double>();
          t.z0_m = o.at("z0_m").get<double>();
          t.z1_m = o.at("z1_m").get<double>();
        } else {
          throw InputError(where + ": kind '" + t.kind + "' is not cylinder or box");
        }
        list.push_back(t);
      }
    } catch (const nlohmann::json::exception& e) {
      throw InputError(where + ": " + std::string(e.what()));
    }
  }
  return out;
}

double truth_tolerance_m(double depth_m, const Rig& rig, const TruthScoreParams& p) {
  const double sigma_z = depth_m * depth_m * p.sigma_disparity_px / (rig.focal_px * rig.baseline_m);
  return std::max(p.min_tolerance_m, p.k_sigma * sigma_z);
}

const std::vector<std::pair<double, double>>& TruthAccumulator::range_bins() {
  static const std::vector<std::pair<double, double>> bins = {{0, 5}, {5, 10}, {10, 20}, {20, 40}};
  return bins;
}

void TruthAccumulator::add(const std::vector<Obstacle>& det, const std::vector<TruthObstacle>& truth, const Rig& rig) {
  if (seen_.empty()) {
    seen_.assign(range_bins().size(), 0);
    detected_.assign(range_bins().size(), 0);
  }
  ++frames_;
  // Nearest obstacles first; each takes the closest unused detection within its tolerance.
  std::vector<std::size_t> order(truth.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return truth[a].range_m < truth[b].range_m; });
  std::vector<bool> used(det.size(), false);
  for (std::size_t k : order) {
    const TruthObstacle& t = truth[k];
    ever_seen_[t.id] = true;
    const int bin = bin_of(t.range_m);
    if (bin >= 0) ++seen_[std::size_t(bin)];
    const double tol = truth_tolerance_m(t.range_m, rig, p_);
    int best = -1;
    double best_d = tol;
    for (std::size_t i = 0; i < det.size(); ++i) {
      if (used[i]) continue;
      const double d = footprint_distance(t, det[i].lateral_m, det[i].range_m);
      if (d <= best_d) {
        best_d = d;
        best = int(i);
      }
    }
    if (best < 0) continue;
    used[std::size_t(best)] = true;
    ++matches_;
    range_error_sum_m_ += std::fabs(det[std::size_t(best)].range_m - t.range_m);
    if (bin >= 0) ++detected_[std::size_t(bin)];
    if (first_detection_m_.count(t.id) == 0) first_detection_m_[t.id] = t.range_m;
  }
  // A false positive lies near no obstacle at all (a long wall seen as several blobs is matched
  // once, and its other blobs are not false).
  for (std::size_t i = 0; i < det.size(); ++i) {
    if (used[i]) continue;
    bool near = false;
    for (const TruthObstacle& t : truth)
      near = near || footprint_distance(t, det[i].lateral_m, det[i].range_m) <= truth_tolerance_m(t.range_m, rig, p_);
    false_positives_ += near ? 0 : 1;
  }
  // Blocked within the stopping distance: by the scene, and by the detections.
  bool truth_blocked = false, design_blocked = false;
  for (const TruthObstacle& t : truth) truth_blocked = truth_blocked || blocks(t, p_.corridor_half_m, p_.stopping_m);
  for (const Obstacle& o : det)
    design_blocked =
        design_blocked || (o.range_m <= p_.stopping_m && std::fabs(o.lateral_m) - o.width_m / 2 <= p_.corridor_half_m);
  blocked_agree_ += truth_blocked == design_blocked ? 1 : 0;
  missed_blocks_ += truth_blocked && !design_blocked ? 1 : 0;
  false_blocks_ += !truth_blocked && design_blocked ? 1 : 0;
}

std::vector<std::pair<std::string, double>> TruthAccumulator::metrics() const {
  std::vector<std::pair<std::string, double>> m;
  const auto& bins = range_bins();
  for (std::size_t i = 0; i < bins.size(); ++i) {
    char name[48];
    std::snprintf(name, sizeof name, "detection_pct_%.0f_%.0fm", bins[i].first, bins[i].second);
    const bool any = i < seen_.size() && seen_[i] > 0;
    m.emplace_back(name, any ? 100.0 * detected_[i] / seen_[i] : -1.0);
  }
  std::vector<double> first;
  for (const auto& kv : first_detection_m_) first.push_back(kv.second);
  std::sort(first.begin(), first.end());
  const std::size_t n = first.size();
  const double median = n == 0 ? 0.0 : n % 2 == 1 ? first[n / 2] : 0.5 * (first[n / 2 - 1] + first[n / 2]);
  m.emplace_back("false_positives_per_frame", frames_ ? double(false_positives_) / frames_ : 0.0);
  m.emplace_back("range_error_m", matches_ ? range_error_sum_m_ / matches_ : 0.0);
  m.emplace_back("first_detection_range_m", median);
  m.emplace_back("never_detected", double(ever_seen_.size() - first_detection_m_.size()));
  m.emplace_back("blocked_agreement_pct", frames_ ? 100.0 * blocked_agree_ / frames_ : 0.0);
  m.emplace_back("missed_blocks", missed_blocks_);
  m.emplace_back("false_blocks", false_blocks_);
  m.emplace_back("frames", frames_);
  return m;
}

}  // namespace parallax::uav
