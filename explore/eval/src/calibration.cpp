// Calibration files of stereo datasets: Middlebury calib.txt and dmin.txt, KITTI P matrices.
#include "parallax/eval/calibration.hpp"
#include "parallax/eval/text_util.hpp"

#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <system_error>
#include <vector>

namespace parallax::eval {
using detail::trim;
namespace fs = std::filesystem;

namespace {

// Opens a text file for reading; InputError naming it when it is missing, a folder or unreadable.
std::ifstream open_text(const fs::path& file, const char* role) {
  std::error_code ec;
  if (fs::is_directory(file, ec)) {
    throw InputError(file.string() + ": " + role + " is a folder, expected a file");
  }
  if (!fs::is_regular_file(file, ec)) throw InputError(file.string() + ": " + role + " not found");
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": " + role + " cannot be read");
  return in;
}

// Whitespace-separated numbers; false when a token is not a finite number.
bool parse_numbers(const std::string& text, std::vector<double>& out) {
  std::istringstream in(text);
  std::string token;
  out.clear();
  while (in >> token) {
    try {
      std::size_t used = 0;
      const double v = std::stod(token, &used);
      if (used != token.size() || !std::isfinite(v)) return false;
      out.push_back(v);
    } catch (const std::exception&) {
      return false;
    }
  }
  return true;
}

double parse_one_number(const std::string& text, const std::string& where) {
  std::vector<double> v;
  if (!parse_numbers(text, v) || v.size() != 1) {
    throw InputError(where + ": '" + text + "' is not a number");
  }
  return v[0];
}

int parse_positive_int(const std::string& text, const std::string& where) {
  const double v = parse_one_number(text, where);
  if (!(v >= 1.0) || v != std::floor(v) || v > 1e9) {
    throw InputError(where + ": '" + text + "' is not a positive integer");
  }
  return static_cast<int>(v);
}

// "[f 0 cx; 0 f cy; 0 0 1]" -> 9 numbers, row-major.
std::vector<double> parse_matrix3(const std::string& text, const std::string& where) {
  std::string t = trim(text);
  if (t.size() < 2 || t.front() != '[' || t.back() != ']') {
    throw InputError(where + ": expected a matrix [f 0 cx; 0 f cy; 0 0 1], got '" + text + "'");
  }
  t = t.substr(1, t.size() - 2);
  for (char& c : t)
    if (c == ';' || c == ',') c = ' ';
  std::vector<double> m;
  if (!parse_numbers(t, m) || m.size() != 9) {
    throw InputError(where + ": expected 9 numbers [f 0 cx; 0 f cy; 0 0 1], got '" + text + "'");
  }
  return m;
}

}  // namespace

MiddleburyCalib read_middlebury_calib(const fs::path& file) {
  std::ifstream in = open_text(file, "calibration file");
  MiddleburyCalib calib;
  calib.camera.source = file;
  std::vector<double> cam0;
  std::vector<double> cam1;
  bool has_doffs = false;
  bool has_baseline = false;
  int ndisp_line = 0;
  int vmin_line = 0;
  int vmax_line = 0;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    const std::string where = file.string() + " line " + std::to_string(line_number);
    const std::size_t eq = t.find('=');
    if (eq == std::string::npos) throw InputError(where + ": expected key=value, got '" + t + "'");
    const std::string key = trim(t.substr(0, eq));
    const std::string value = trim(t.substr(eq + 1));
    const std::string field = where + ", " + key;
    if (key == "cam0") {
      cam0 = parse_matrix3(value, field);
    } else if (key == "cam1") {
      cam1 = parse_matrix3(value, field);
    } else if (key == "doffs") {
      calib.camera.doffs_px = parse_one_number(value, field);
      has_doffs = true;
    } else if (key == "baseline") {
      const double baseline_mm = parse_one_number(value, field);
      if (!(baseline_mm > 0.0)) throw InputError(field + ": baseline must be > 0 (mm)");
      calib.camera.baseline_m = baseline_mm / 1000.0;
      has_baseline = true;
    } else if (key == "width") {
      calib.width_px = parse_positive_int(value, field);
      calib.width_line = line_number;
    } else if (key == "height") {
      calib.height_px = parse_positive_int(value, field);
      calib.height_line = line_number;
    } else if (key == "ndisp") {
      calib.ndisp = parse_positive_int(value, field);
      ndisp_line = line_number;
    } else if (key == "vmin") {
      calib.vmin_px = parse_one_number(value, field);
      vmin_line = line_number;
    } else if (key == "vmax") {
      calib.vmax_px = parse_one_number(value, field);
      vmax_line = line_number;
    }
  }
  if (ndisp_line == 0) {
    throw InputError(file.string() +
                     ": no ndisp line (ndisp=N bounds the scene's disparities; Middlebury "
                     "2014/2021 calib.txt files have one)");
  }
  if ((vmin_line == 0) != (vmax_line == 0)) {
    throw InputError(
        file.string() + ": vmin and vmax go together (found only " +
        (vmin_line != 0 ? "vmin, line " + std::to_string(vmin_line) : "vmax, line " + std::to_string(vmax_line)) + ")");
  }
  if (vmin_line != 0) {
    if (calib.vmax_px < calib.vmin_px) {
      throw InputError(file.string() + " line " + std::to_string(vmax_line) +
                       ", vmax: " + std::to_string(calib.vmax_px) + " is below vmin " + std::to_string(calib.vmin_px));
    }
    calib.has_disparity_range = true;
  }
  if (!cam0.empty() && has_baseline) {
    StereoCalibration& c = calib.camera;
    c.focal_px = cam0[0];
    c.cx_px = cam0[2];
    c.cy_px = cam0[5];
    if (!(c.focal_px > 0.0)) throw InputError(file.string() + ", cam0: focal length must be > 0");
    if (!has_doffs && !cam1.empty()) c.doffs_px = cam1[2] - cam0[2];
    c.known = true;
  }
  return calib;
}

StereoCalibration read_kitti_calib(const fs::path& file, const std::string& left_key, const std::string& right_key) {
  std::ifstream in = open_text(file, "calibration file");
  std::map<std::string, std::vector<double>> found;
  std::map<std::string, int> found_line;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::string key = trim(line.substr(0, colon));
    if (key != left_key && key != right_key) continue;
    const std::string where = file.string() + " line " + std::to_string(line_number) + ", " + key;
    std::vector<double> p;
    if (!parse_numbers(line.substr(colon + 1), p)) {
      throw InputError(where + ": a value is not a number");
    }
    if (p.size() != 12) {
      throw InputError(where + ": expected 12 numbers (a 3x4 projection matrix), got " + std::to_string(p.size()));
    }
    found[key] = p;
    found_line[key] = line_number;
  }
  for (const std::string& key : {left_key, right_key}) {
    if (found.count(key) == 0) {
      throw InputError(file.string() + ": no " + key + " line (expected '" + key +
                       ": 12 numbers', the rectified projection matrix)");
    }
  }
  const std::vector<double>& pl = found[left_key];
  const std::vector<double>& pr = found[right_key];
  StereoCalibration c;
  c.source = file;
  c.focal_px = pl[0];
  c.cx_px = pl[2];
  c.cy_px = pl[6];
  const std::string left_where = file.string() + " line " + std::to_string(found_line[left_key]) + ", " + left_key;
  if (!(c.focal_px > 0.0)) throw InputError(left_where + ": focal length P[0] must be > 0");
  c.baseline_m = (pl[3] - pr[3]) / c.focal_px;
  if (!(c.baseline_m > 0.0)) {
    throw InputError(file.string() + " line " + std::to_string(found_line[right_key]) + ", " + right_key +
                     ": baseline (" + left_key + "[3] - " + right_key + "[3]) / f must be > 0, got " +
                     std::to_string(c.baseline_m) + " m");
  }
  c.doffs_px = pr[2] - pl[2];
  c.known = true;
  return c;
}

int read_middlebury_dmin(const fs::path& file) {
  std::ifstream in = open_text(file, "dmin file");
  std::ostringstream all;
  all << in.rdbuf();
  const std::string text = trim(all.str());
  std::vector<double> v;
  if (!parse_numbers(text, v) || v.size() != 1 || v[0] != std::floor(v[0]) || std::fabs(v[0]) > 1e6) {
    throw InputError(file.string() + ": expected one integer (the disparity offset dmin), got '" + text.substr(0, 40) +
                     "'");
  }
  return static_cast<int>(v[0]);
}

}  // namespace parallax::eval
