// Synthetic scenes and their stereo rendering (scene.hpp).
#include "parallax/uav/scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/persistence.hpp>
#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/yaml.h>

#include "parallax/config/config.hpp"

#include "parallax/eval/dataset.hpp"
#include "parallax/eval/disparity_io.hpp"

namespace parallax::res::data {  // configs/scenarios/*.yaml, compiled in (cmake/embed.cmake)
extern const char* const* const scenario_files;
extern const char* const* const scenario_texts;
extern const int scenario_count;
}  // namespace parallax::res::data

namespace parallax::uav {

// The names this file takes from the other rooms (one namespace per room).
using eval::InputError;
using eval::write_kitti_disparity;
using eval::write_png;

namespace {

// Reads the fields of a mapping into doubles/ints/bools; an unknown key is an error naming it.
struct FieldReader {
  const YAML::Node& node;
  std::string where;
  std::vector<std::string> known;
  template <typename T>
  void get(const char* key, T& out) {
    known.emplace_back(key);
    if (!node[key]) return;
    try {
      out = node[key].as<T>();
    } catch (const YAML::Exception&) {
      throw InputError(where + "field '" + key + "' has the wrong type");
    }
  }
  void reject_unknown() const {
    for (const auto& kv : node) {
      if (!kv.first.IsScalar()) throw InputError(where + "a field name must be a plain word, not a list or mapping");
      const std::string k = kv.first.as<std::string>();
      if (std::find(known.begin(), known.end(), k) == known.end()) {
        std::string list;
        for (const auto& n : known) list += (list.empty() ? "" : ", ") + n;
        throw InputError(where + "unknown field '" + k + "' (known: " + list + ")");
      }
    }
  }
};

void check_range(const std::string& path, const char* field, double v, double lo, double hi) {
  if (!(v >= lo && v <= hi))
    throw InputError(path + ": field '" + field + "' = " + std::to_string(v) + " is outside [" + std::to_string(lo) +
                     ", " + std::to_string(hi) + "]");
}

void parse_rig(const YAML::Node& n, const std::string& path, RigSpec& r) {
  if (!n.IsMap()) throw InputError(path + ": field 'rig' must be a mapping (baseline_m, hfov_deg, ...)");
  FieldReader f{n, path + ": rig: ", {}};
  f.get("baseline_m", r.baseline_m);
  f.get("hfov_deg", r.hfov_deg);
  f.get("width_px", r.width_px);
  f.get("height_px", r.height_px);
  f.get("mount_pitch_deg", r.mount_pitch_deg);
  f.get("altitude_m", r.altitude_m);
  f.reject_unknown();
  check_range(path, "rig.baseline_m", r.baseline_m, 0.01, 5.0);
  check_range(path, "rig.hfov_deg", r.hfov_deg, 10.0, 150.0);
  check_range(path, "rig.width_px", r.width_px, 32, 4096);
  check_range(path, "rig.height_px", r.height_px, 16, 4096);
  check_range(path, "rig.mount_pitch_deg", r.mount_pitch_deg, -45.0, 45.0);
  check_range(path, "rig.altitude_m", r.altitude_m, 0.5, 50.0);
}

void parse_imaging(const YAML::Node& n, const std::string& path, Imaging& im) {
  if (!n.IsMap()) throw InputError(path + ": field 'imaging' must be a mapping (right_gain, noise_grey, ...)");
  FieldReader f{n, path + ": imaging: ", {}};
  f.get("right_gain", im.right_gain);
  f.get("right_offset_grey", im.right_offset_grey);
  f.get("noise_grey", im.noise_grey);
  f.get("antialias", im.antialias);
  f.reject_unknown();
  check_range(path, "imaging.right_gain", im.right_gain, 0.25, 4.0);
  check_range(path, "imaging.right_offset_grey", im.right_offset_grey, -128.0, 128.0);
  check_range(path, "imaging.noise_grey", im.noise_grey, 0.0, 50.0);
}

// A scenario from its YAML text; `path` names it in errors (and gives the default name).
Scenario parse_scenario(const std::string& text, const std::string& path) {
  YAML::Node n;
  try {
    n = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(path + ": not valid YAML: " + e.what());
  }
  if (!n.IsMap()) throw InputError(path + ": expected a mapping of scenario fields (kind, ...)");
  Scenario s;
  s.name = std::filesystem::path(path).stem().string();
  FieldReader f{n, path + ": ", {}};
  f.get("name", s.name);
  f.get("kind", s.kind);
  f.get("density_per_100m2", s.density_per_100m2);
  f.get("branches_per_tree", s.branches_per_tree);
  f.get("gap_m", s.gap_m);
  f.get("width_m", s.width_m);
  f.get("length_m", s.length_m);
  f.get("bound_half_width_m", s.bound_half_width_m);
  f.get("walls", s.walls);
  f.known.emplace_back("rig");
  f.known.emplace_back("imaging");
  f.reject_unknown();
  if (n["rig"]) parse_rig(n["rig"], path, s.rig);
  if (n["imaging"]) parse_imaging(n["imaging"], path, s.imaging);
  if (!n["kind"]) throw InputError(path + ": missing field 'kind'");
  if (s.kind != "single-pole" && s.kind != "forest" && s.kind != "wall-gap" && s.kind != "corridor")
    throw InputError(path + ": field 'kind': '" + s.kind + "' is not single-pole, forest, wall-gap or corridor");
  if (s.walls != "textured" && s.walls != "plain" && s.walls != "stripes")
    throw InputError(path + ": field 'walls': '" + s.walls + "' is not textured, plain or stripes");
  if (!(s.length_m > 5)) throw InputError(path + ": field 'length_m' must exceed 5");
  check_range(path, "density_per_100m2", s.density_per_100m2, 0.0, 50.0);
  check_range(path, "branches_per_tree", s.branches_per_tree, 0.0, 20.0);
  check_range(path, "bound_half_width_m", s.bound_half_width_m, 0.0, 1000.0);
  return s;
}

// The shipped scenario of that name (-1: none).
int builtin_index(const std::string& name) {
  for (int i = 0; i < res::data::scenario_count; ++i)
    if (std::filesystem::path(res::data::scenario_files[i]).stem().string() == name) return i;
  return -1;
}

// A name, not a path: no folder, no extension.
bool plain_name(const std::string& s) {
  return !s.empty() && s.find('/') == std::string::npos && s.find('.') == std::string::npos;
}

}  // namespace

std::vector<std::string> builtin_scenarios() {
  std::vector<std::string> names;
  for (int i = 0; i < res::data::scenario_count; ++i)
    names.push_back(std::filesystem::path(res::data::scenario_files[i]).stem().string());
  return names;
}

std::string scenario_option_help() {
  std::string names;
  for (const std::string& n : builtin_scenarios()) names += (names.empty() ? "" : ", ") + n;
  return "Scenario: a shipped one by name (" + names + ") or a file, e.g. my/scene.yaml";
}

Scenario load_scenario(const std::string& name_or_path) {
  const int builtin =
      plain_name(name_or_path) && !std::filesystem::exists(name_or_path) ? builtin_index(name_or_path) : -1;
  if (builtin >= 0) return parse_scenario(res::data::scenario_texts[builtin], res::data::scenario_files[builtin]);
  if (plain_name(name_or_path) && !std::filesystem::exists(name_or_path)) {
    std::string known;
    for (const std::string& n : builtin_scenarios()) known += (known.empty() ? "" : ", ") + n;
    throw InputError("scenario '" + name_or_path +
                     "': no such file and no shipped scenario of that name (shipped: " + known + ")");
  }
  std::string text;
  try {
    text = config::read_text_file(name_or_path, "scenario file");
  } catch (const config::ConfigError& e) {
    throw InputError(e.what());
  }
  return parse_scenario(text, name_or_path);
}

std::string scenario_reference(const std::string& name_or_path) {
  if (plain_name(name_or_path) && !std::filesystem::exists(name_or_path) && builtin_index(name_or_path) >= 0)
    return name_or_path;
  return std::filesystem::absolute(name_or_path).lexically_normal().string();
}

Scene generate_scene(const Scenario& s, uint32_t seed) {
  std::mt19937 rng(seed);
  auto uni = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  Scene sc;
  sc.texture_seed = seed * 2654435761u + 1;
  sc.goal_z_m = s.length_m;
  if (s.bound_half_width_m > 0) sc.bound_half_width_m = s.bound_half_width_m;
  const Surface walls = s.walls == "plain"     ? Surface::plain
                        : s.walls == "stripes" ? Surface::stripes
                                               : Surface::textured;
  if (s.kind == "single-pole") {
    sc.cylinders.push_back({uni(-0.5, 0.5), uni(15, 25), uni(0.15, 0.3), uni(4, 8)});
  } else if (s.kind == "forest") {
    // Trees in a 20 m wide strip, from 8 m on, at the given density (seeded Poisson count).
    const double area = 20.0 * (s.length_m - 8.0);
    std::poisson_distribution<int> count(s.density_per_100m2 * area / 100.0);
    const int n = count(rng);
    for (int i = 0; i < n; ++i) sc.cylinders.push_back({uni(-10, 10), uni(8, s.length_m), uni(0.15, 0.5), uni(5, 12)});
    // Thin branches from the trunks across the flight band (their own stream: the trees of a
    // seed do not depend on them).
    std::mt19937 brng(seed ^ 0x5bd1e995u);
    auto buni = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(brng); };
    std::poisson_distribution<int> per_tree(std::max(s.branches_per_tree, 1e-9));
    for (const Cylinder& c : sc.cylinders) {
      const int k = s.branches_per_tree > 0 ? per_tree(brng) : 0;
      for (int j = 0; j < k; ++j) {
        const double heading = buni(-M_PI, M_PI);
        sc.branches.push_back({c.x_m + c.radius_m * std::sin(heading), c.z_m + c.radius_m * std::cos(heading),
                               buni(s.rig.altitude_m - 1.0, s.rig.altitude_m + 1.2), heading, buni(0.8, 2.5),
                               buni(0.02, 0.05)});
      }
    }
  } else if (s.kind == "wall-gap") {
    const double z = uni(18, 25), gap_x = uni(-2, 2), h = uni(3, 6);
    sc.boxes.push_back({-20, gap_x - s.gap_m / 2, z, z + 0.4, h, walls});
    sc.boxes.push_back({gap_x + s.gap_m / 2, 20, z, z + 0.4, h, walls});
  } else {  // corridor: two walls along the flight, with pillars in the way
    sc.boxes.push_back({-s.width_m / 2 - 0.5, -s.width_m / 2, 2, s.length_m, uni(4, 8), walls});
    sc.boxes.push_back({s.width_m / 2, s.width_m / 2 + 0.5, 2, s.length_m, uni(4, 8), walls});
    for (double z = 15; z < s.length_m - 5; z += uni(12, 18))
      sc.cylinders.push_back({uni(-s.width_m / 4, s.width_m / 4), z, 0.3, 6});
  }
  return sc;
}

Rig scene_rig(int w, int h) {
  Rig r;
  r.focal_px = 721.5377 * double(w) / 640.0;
  r.baseline_m = 0.5327;
  r.cx_px = (w - 1) / 2.0;
  r.cy_px = (h - 1) / 2.0;
  return r;
}

RigSpec scaled_rig(const RigSpec& spec, int width_px) {
  if (width_px <= 0) return spec;
  RigSpec r = spec;
  r.height_px = std::max(16, int(std::lround(double(spec.height_px) * width_px / spec.width_px)));
  r.width_px = width_px;
  return r;
}

Rig rig_of(const RigSpec& spec, int roi_w, int roi_h) {
  if (roi_w > spec.width_px || roi_h > spec.height_px)
    throw InputError("the design's region of interest " + std::to_string(roi_w) + "x" + std::to_string(roi_h) +
                     " exceeds the scenario's sensor " + std::to_string(spec.width_px) + "x" +
                     std::to_string(spec.height_px));
  Rig r;
  r.focal_px = 0.5 * spec.width_px / std::tan(0.5 * spec.hfov_deg * M_PI / 180.0);
  r.baseline_m = spec.baseline_m;
  // The sensor's centre in the centred window's coordinates (the window starts at a whole pixel).
  const int x0 = (spec.width_px - roi_w) / 2, y0 = (spec.height_px - roi_h) / 2;
  r.cx_px = (spec.width_px - 1) / 2.0 - x0;
  r.cy_px = (spec.height_px - 1) / 2.0 - y0;
  return r;
}

void write_rectification_maps(const Rig& rig, int w, int h, double k1, const std::string& path) {
  const cv::Mat K = (cv::Mat_<double>(3, 3) << rig.focal_px, 0, rig.cx_px, 0, rig.focal_px, rig.cy_px, 0, 0, 1);
  const cv::Mat dist = (cv::Mat_<double>(1, 5) << k1, 0, 0, 0, 0);
  cv::Mat mx, my;
  cv::initUndistortRectifyMap(K, dist, cv::Mat::eye(3, 3, CV_64F), K, cv::Size(w, h), CV_32FC1, mx, my);
  try {
    cv::FileStorage fs(path, cv::FileStorage::WRITE);
    if (!fs.isOpened()) throw InputError(path + ": cannot write");
    fs << "map_x" << mx << "map_y" << my;
  } catch (const cv::Exception& e) {
    throw InputError(path + ": cannot write the remap tables: " + e.what());
  }
}

void export_kitti(const std::vector<StereoFrame>& frames, const std::string& dir) {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(dir) / "training";
  for (const char* sub : {"image_2", "image_3", "disp_noc_0", "disp_occ_0"}) {
    std::error_code ec;
    fs::create_directories(root / sub, ec);
    if (ec) throw InputError((root / sub).string() + ": cannot create the folder: " + ec.message());
  }
  for (std::size_t i = 0; i < frames.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "%06zu_10.png", i);
    const StereoFrame& f = frames[i];
    write_png(root / "image_2" / name, f.left);
    write_png(root / "image_3" / name, f.right);
    write_kitti_disparity(root / "disp_occ_0" / name, f.disparity_px, f.valid_mask);
    write_kitti_disparity(root / "disp_noc_0" / name, f.disparity_px, f.noc_mask);
  }
}

void write_kitti_calibration(const Rig& rig, int frames, const std::string& dir) {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(dir) / "training" / "calib_cam_to_cam";
  std::error_code ec;
  fs::create_directories(root, ec);
  if (ec) throw InputError(root.string() + ": cannot create the folder: " + ec.message());
  for (int i = 0; i < frames; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "%06d.txt", i);
    std::ofstream out(root / name);
    char line[256];
    for (int cam = 2; cam <= 3; ++cam) {
      std::snprintf(line, sizeof line, "P_rect_0%d: %.6f 0 %.6f %.6f 0 %.6f %.6f 0 0 0 1 0\n", cam, rig.focal_px,
                    rig.cx_px, cam == 2 ? 0.0 : -rig.focal_px * rig.baseline_m, rig.focal_px, rig.cy_px);
      out << line;
    }
    if (!out) throw InputError((root / name).string() + ": cannot write the calibration");
  }
}

namespace {

// The distance from a point to the nearest obstacle's surface (negative inside a wall); with
// `name`, what that obstacle is.
double nearest(const Scene& sc, const Eigen::Vector3d& p, std::string* name) {
  double best = std::numeric_limits<double>::infinity();
  char text[160] = "nothing";
  auto take = [&](double d) {
    if (d >= best) return false;
    best = d;
    return name != nullptr;
  };
  for (const auto& c : sc.cylinders)
    if (p.y() >= -c.height_m && take(std::hypot(p.x() - c.x_m, p.z() - c.z_m) - c.radius_m))
      std::snprintf(text, sizeof text, "tree r %.2f m at (x %.2f, z %.2f)", c.radius_m, c.x_m, c.z_m);
  for (const auto& br : sc.branches) {
    const Eigen::Vector3d a(br.x_m, -br.height_m, br.z_m), ax(std::sin(br.heading_rad), 0, std::cos(br.heading_rad));
    const double s = std::clamp((p - a).dot(ax), 0.0, br.length_m);
    if (take((p - (a + s * ax)).norm() - br.radius_m))
      std::snprintf(text, sizeof text, "branch (r %.3f m, %.2f m up) from (x %.2f, z %.2f)", br.radius_m, br.height_m,
                    br.x_m, br.z_m);
  }
  for (const auto& b : sc.boxes) {
    if (p.y() < -b.height_m) continue;
    const double dx = std::max({b.x0_m - p.x(), 0.0, p.x() - b.x1_m});
    const double dz = std::max({b.z0_m - p.z(), 0.0, p.z() - b.z1_m});
    const double outside = std::hypot(dx, dz);
    if (take(outside > 0 ? outside : -std::min({p.x() - b.x0_m, b.x1_m - p.x(), p.z() - b.z0_m, b.z1_m - p.z()})))
      std::snprintf(text, sizeof text, "wall x %.1f..%.1f z %.1f..%.1f", b.x0_m, b.x1_m, b.z0_m, b.z1_m);
  }
  if (name != nullptr) *name = text;
  return best;
}

}  // namespace

double clearance_m(const Scene& sc, const Eigen::Vector3d& p) {
  return nearest(sc, p, nullptr);
}

std::string nearest_obstacle(const Scene& sc, const Eigen::Vector3d& p) {
  std::string name;
  nearest(sc, p, &name);
  return name;
}

}  // namespace parallax::uav
