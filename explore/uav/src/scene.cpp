// Synthetic scenes and their stereo rendering (scene.hpp).
#include "parallax/uav/scene.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
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

namespace parallax::explore {

namespace {

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
  try {
    s.name = n["name"] ? n["name"].as<std::string>() : std::filesystem::path(path).stem().string();
    if (!n["kind"]) throw InputError(path + ": missing field 'kind'");
    s.kind = n["kind"].as<std::string>();
    if (n["density_per_100m2"]) s.density_per_100m2 = n["density_per_100m2"].as<double>();
    if (n["gap_m"]) s.gap_m = n["gap_m"].as<double>();
    if (n["width_m"]) s.width_m = n["width_m"].as<double>();
    if (n["length_m"]) s.length_m = n["length_m"].as<double>();
  } catch (const YAML::Exception& e) {
    throw InputError(path + ": a field has the wrong type: " + e.what());
  }
  if (s.kind != "single-pole" && s.kind != "forest" && s.kind != "wall-gap" && s.kind != "corridor")
    throw InputError(path + ": field 'kind': '" + s.kind + "' is not single-pole, forest, wall-gap or corridor");
  if (!(s.length_m > 5)) throw InputError(path + ": field 'length_m' must exceed 5");
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
  if (s.kind == "single-pole") {
    sc.cylinders.push_back({uni(-0.5, 0.5), uni(15, 25), uni(0.15, 0.3), uni(4, 8)});
  } else if (s.kind == "forest") {
    // Trees in a 20 m wide strip, from 8 m on, at the given density (seeded Poisson count).
    const double area = 20.0 * (s.length_m - 8.0);
    std::poisson_distribution<int> count(s.density_per_100m2 * area / 100.0);
    const int n = count(rng);
    for (int i = 0; i < n; ++i) sc.cylinders.push_back({uni(-10, 10), uni(8, s.length_m), uni(0.15, 0.5), uni(5, 12)});
  } else if (s.kind == "wall-gap") {
    const double z = uni(18, 25), gap_x = uni(-2, 2), h = uni(3, 6);
    sc.boxes.push_back({-20, gap_x - s.gap_m / 2, z, z + 0.4, h});
    sc.boxes.push_back({gap_x + s.gap_m / 2, 20, z, z + 0.4, h});
  } else {  // corridor: two walls along the flight, with pillars in the way
    sc.boxes.push_back({-s.width_m / 2 - 0.5, -s.width_m / 2, 2, s.length_m, uni(4, 8)});
    sc.boxes.push_back({s.width_m / 2, s.width_m / 2 + 0.5, 2, s.length_m, uni(4, 8)});
    for (double z = 15; z < s.length_m - 5; z += uni(12, 18))
      sc.cylinders.push_back({uni(-s.width_m / 4, s.width_m / 4), z, 0.3, 6});
  }
  return sc;
}

namespace {

// Seeded value noise on a 2D surface parameter, several octaves: grey levels 25..230.
double hash01(uint32_t seed, int64_t i, int64_t j) {
  uint64_t h = seed ^ (uint64_t(i) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(j) * 0xC2B2AE3D27D4EB4Full);
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  return double(h & 0xFFFFFF) / double(0xFFFFFF);
}
double noise(uint32_t seed, double u, double v) {
  double sum = 0, amp = 0.5, freq = 8.0;
  for (int o = 0; o < 3; ++o) {
    const double x = u * freq, y = v * freq;
    const int64_t i = int64_t(std::floor(x)), j = int64_t(std::floor(y));
    const double fx = x - double(i), fy = y - double(j);
    const double a = hash01(seed + uint32_t(o), i, j), b = hash01(seed + uint32_t(o), i + 1, j);
    const double c = hash01(seed + uint32_t(o), i, j + 1), d = hash01(seed + uint32_t(o), i + 1, j + 1);
    sum += amp * ((a * (1 - fx) + b * fx) * (1 - fy) + (c * (1 - fx) + d * fx) * fy);
    amp *= 0.5;
    freq *= 2.0;
  }
  return 25.0 + 205.0 * std::clamp(sum / 0.875, 0.0, 1.0);
}

struct Hit {
  double t = std::numeric_limits<double>::infinity();
  double shade = 0;
};

// The nearest surface along origin + t dir (t > 0) and its grey level.
Hit cast(const Scene& sc, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  Hit h;
  if (d.y() > 1e-9) {  // ground y = 0 below the camera (o.y < 0)
    const double t = -o.y() / d.y();
    if (t > 0) {
      const Eigen::Vector3d p = o + t * d;
      h = {t, noise(sc.texture_seed, p.x() * 0.5, p.z() * 0.5) * 0.85};
    }
  }
  for (std::size_t k = 0; k < sc.cylinders.size(); ++k) {
    const Cylinder& c = sc.cylinders[k];
    const double ox = o.x() - c.x_m, oz = o.z() - c.z_m;
    const double a = d.x() * d.x() + d.z() * d.z(), b = 2 * (ox * d.x() + oz * d.z()),
                 cc = ox * ox + oz * oz - c.radius_m * c.radius_m;
    const double disc = b * b - 4 * a * cc;
    if (a < 1e-12 || disc < 0) continue;
    const double t = (-b - std::sqrt(disc)) / (2 * a);
    if (t <= 0 || t >= h.t) continue;
    const Eigen::Vector3d p = o + t * d;
    if (p.y() < -c.height_m || p.y() > 0) continue;
    const double ang = std::atan2(p.z() - c.z_m, p.x() - c.x_m);
    h = {t, noise(sc.texture_seed + 101 + uint32_t(k), ang * c.radius_m, p.y())};
  }
  for (std::size_t k = 0; k < sc.boxes.size(); ++k) {
    const Box& b = sc.boxes[k];
    const double lo[3] = {b.x0_m, -b.height_m, b.z0_m}, hi[3] = {b.x1_m, 0.0, b.z1_m};
    double t0 = 0, t1 = std::numeric_limits<double>::infinity();
    int axis = -1;
    bool miss = false;
    for (int i = 0; i < 3 && !miss; ++i) {
      if (std::fabs(d[i]) < 1e-12) {
        if (o[i] < lo[i] || o[i] > hi[i]) miss = true;
        continue;
      }
      double ta = (lo[i] - o[i]) / d[i], tb = (hi[i] - o[i]) / d[i];
      if (ta > tb) std::swap(ta, tb);
      if (ta > t0) {
        t0 = ta;
        axis = i;
      }
      t1 = std::min(t1, tb);
      if (t0 > t1) miss = true;
    }
    if (miss || axis < 0 || t0 <= 0 || t0 >= h.t) continue;
    const Eigen::Vector3d p = o + t0 * d;
    const double u = axis == 0 ? p.z() : p.x(), v = axis == 1 ? p.z() : p.y();
    h = {t0, noise(sc.texture_seed + 977 + uint32_t(k), u * 0.7, v * 0.7)};
  }
  return h;
}

}  // namespace

Rig scene_rig(int w, int h) {
  Rig r;
  r.focal_px = 721.5377 * double(w) / 640.0;
  r.baseline_m = 0.5327;
  r.cx_px = (w - 1) / 2.0;
  r.cy_px = (h - 1) / 2.0;
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

StereoFrame render(const Scene& sc, const Rig& rig, int w, int hgt, const Eigen::Vector3d& cam, double k1) {
  if (k1 != 0.0) {
    // The truth of the rectified pair, then the images through distorting lenses.
    StereoFrame f = render(sc, rig, w, hgt, cam, 0.0);
    const Eigen::Vector3d right_cam = cam + Eigen::Vector3d(rig.baseline_m, 0, 0);
    for (int v = 0; v < hgt; ++v)
      for (int u = 0; u < w; ++u) {
        const double xd = (u - rig.cx_px) / rig.focal_px, yd = (v - rig.cy_px) / rig.focal_px;
        double x = xd, y = yd;
        for (int it = 0; it < 8; ++it) {  // invert x_d = x (1 + k1 r^2)
          const double s = 1.0 + k1 * (x * x + y * y);
          x = xd / s;
          y = yd / s;
        }
        const Eigen::Vector3d dir(x, y, 1.0);
        const Hit hl = cast(sc, cam, dir), hr = cast(sc, right_cam, dir);
        f.left.at<uint8_t>(v, u) = std::isfinite(hl.t) ? uint8_t(std::lround(hl.shade)) : 200;
        f.right.at<uint8_t>(v, u) = std::isfinite(hr.t) ? uint8_t(std::lround(hr.shade)) : 200;
      }
    return f;
  }
  StereoFrame f;
  f.left = cv::Mat(hgt, w, CV_8U, cv::Scalar(200));
  f.right = cv::Mat(hgt, w, CV_8U, cv::Scalar(200));
  f.disparity_px = cv::Mat::zeros(hgt, w, CV_32F);
  f.valid_mask = cv::Mat::zeros(hgt, w, CV_8U);
  f.noc_mask = cv::Mat::zeros(hgt, w, CV_8U);
  cv::Mat right_disp = cv::Mat::zeros(hgt, w, CV_32F);
  const Eigen::Vector3d right_cam = cam + Eigen::Vector3d(rig.baseline_m, 0, 0);
  for (int v = 0; v < hgt; ++v)
    for (int u = 0; u < w; ++u) {
      const Eigen::Vector3d dir((u - rig.cx_px) / rig.focal_px, (v - rig.cy_px) / rig.focal_px, 1.0);
      const Hit hl = cast(sc, cam, dir), hr = cast(sc, right_cam, dir);
      if (std::isfinite(hl.t)) {
        f.left.at<uint8_t>(v, u) = uint8_t(std::lround(hl.shade));
        const double disp = rig.focal_px * rig.baseline_m / hl.t;  // t = depth: dir.z = 1
        if (disp < 255.0) {
          f.disparity_px.at<float>(v, u) = float(disp);
          f.valid_mask.at<uint8_t>(v, u) = 255;
        }
      }
      if (std::isfinite(hr.t)) {
        f.right.at<uint8_t>(v, u) = uint8_t(std::lround(hr.shade));
        right_disp.at<float>(v, u) = float(rig.focal_px * rig.baseline_m / hr.t);
      }
    }
  // Visible from the right camera: the right image at u - d sees (about) the same depth.
  for (int v = 0; v < hgt; ++v)
    for (int u = 0; u < w; ++u) {
      if (!f.valid_mask.at<uint8_t>(v, u)) continue;
      const float d = f.disparity_px.at<float>(v, u);
      const int ur = int(std::lround(float(u) - d));
      if (ur < 0 || ur >= w) continue;
      if (std::fabs(right_disp.at<float>(v, ur) - d) <= 1.0f) f.noc_mask.at<uint8_t>(v, u) = 255;
    }
  return f;
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

double clearance_m(const Scene& sc, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& c : sc.cylinders) {
    if (p.y() < -c.height_m) continue;
    best = std::min(best, std::hypot(p.x() - c.x_m, p.z() - c.z_m) - c.radius_m);
  }
  for (const auto& b : sc.boxes) {
    if (p.y() < -b.height_m) continue;
    const double dx = std::max({b.x0_m - p.x(), 0.0, p.x() - b.x1_m});
    const double dz = std::max({b.z0_m - p.z(), 0.0, p.z() - b.z1_m});
    const double outside = std::hypot(dx, dz);
    best = std::min(
        best, outside > 0 ? outside : -std::min({p.x() - b.x0_m, b.x1_m - p.x(), p.z() - b.z0_m, b.z1_m - p.z()}));
  }
  return best;
}

}  // namespace parallax::explore
