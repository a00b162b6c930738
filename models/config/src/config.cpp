#include "parallax/config/config.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "parallax/kernels/pipeline.hpp"

namespace parallax::config {
namespace {

const int kAngles[8] = {0, 45, 90, 135, 180, 225, 270, 315};

std::string trim(std::string s) {
  auto sp = [](unsigned char ch) { return std::isspace(ch) != 0; };
  while (!s.empty() && sp(s.back())) s.pop_back();
  std::size_t i = 0;
  while (i < s.size() && sp(s[i])) ++i;
  return s.substr(i);
}

int parse_int(const std::string& key, const std::string& v) {
  std::size_t used = 0;
  long x = 0;
  try {
    x = std::stol(v, &used);
  } catch (const std::exception&) {
    throw ConfigError("field '" + key + "': expected an integer, got '" + v + "'");
  }
  if (used != v.size() || x < -1000000000L || x > 1000000000L)
    throw ConfigError("field '" + key + "': expected an integer, got '" + v + "'");
  return int(x);
}

double parse_double(const std::string& key, const std::string& v) {
  std::size_t used = 0;
  double x = 0;
  try {
    x = std::stod(v, &used);
  } catch (const std::exception&) {
    throw ConfigError("field '" + key + "': expected a number, got '" + v + "'");
  }
  if (used != v.size() || !(x > -1e12 && x < 1e12))
    throw ConfigError("field '" + key + "': expected a number, got '" + v + "'");
  return x;
}

bool parse_bool(const std::string& key, const std::string& v) {
  std::string l = v;
  std::transform(l.begin(), l.end(), l.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  if (l == "true" || l == "on" || l == "yes" || l == "1") return true;
  if (l == "false" || l == "off" || l == "no" || l == "0") return false;
  throw ConfigError("field '" + key + "': expected true or false, got '" + v + "'");
}

// "5" -> 5x5, "5x3" -> 5 wide, 3 high.
void parse_size(const std::string& key, const std::string& v, int& w, int& h) {
  const auto xpos = v.find_first_of("xX");
  if (xpos == std::string::npos) {
    w = h = parse_int(key, v);
  } else {
    w = parse_int(key, trim(v.substr(0, xpos)));
    h = parse_int(key, trim(v.substr(xpos + 1)));
  }
}

}  // namespace

const std::vector<std::string>& field_names() {
  static const std::vector<std::string> names = {
      "name", "roi", "cost", "window", "disparities", "parallel_units", "paths", "p1", "p2",
      "lr_check", "lr_tolerance", "median", "clock_mhz", "rectify", "rectify_rows", "rectify_frac_bits",
      "rectify_maps_left", "rectify_maps_right", "input", "input_gbps", "camera_pixel_mhz", "camera_h_blank_px",
      "camera_v_blank_rows", "ddr_gbps", "ddr_latency_ns", "fifo_depth", "row_packing", "row_banks", "fifo_depth_<fifo>", "ii_<stage>",
      "latency_<stage>", "setup_<stage>", "host_copy_gbps", "host_latency_ms", "host_frame_ms"};
  return names;
}

unsigned parse_paths(const std::string& text) {
  const std::string t = trim(text);
  if (t.find(',') == std::string::npos && t.find('[') == std::string::npos) {
    const int n = parse_int("paths", t);
    switch (n) {
      case 1: return kern::kPath0;
      case 2: return kern::kPath0 | kern::kPath90;
      case 3: return kern::kPath0 | kern::kPath45 | kern::kPath90;
      case 4: return kern::kForwardPaths;
      case 8: return kern::kAllPaths;
      default:
        throw ConfigError("field 'paths': " + t +
                          " is not a path count (1, 2, 3, 4 or 8); give a list of angles such as 0,90 otherwise");
    }
  }
  std::string body = t;
  body.erase(std::remove(body.begin(), body.end(), '['), body.end());
  body.erase(std::remove(body.begin(), body.end(), ']'), body.end());
  unsigned mask = 0;
  std::stringstream ss(body);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const int a = parse_int("paths", trim(item));
    bool found = false;
    for (int i = 0; i < 8; ++i)
      if (kAngles[i] == a) {
        mask |= 1u << i;
        found = true;
      }
    if (!found) throw ConfigError("field 'paths': angle " + std::to_string(a) + " is not one of 0, 45, ..., 315");
  }
  return mask;
}

std::string paths_to_string(unsigned mask) {
  if (mask == kern::kForwardPaths) return "4";
  if (mask == kern::kAllPaths) return "8";
  std::string s;
  for (int i = 0; i < 8; ++i)
    if (mask & (1u << i)) s += (s.empty() ? "" : ",") + std::to_string(kAngles[i]);
  return "[" + s + "]";
}

void set_field(PipelineConfig& c, const std::string& key, const std::string& raw) {
  const std::string v = trim(raw);
  if (key == "name") c.name = v;
  else if (key == "roi") {
    if (v == "full") {
      c.roi_full = true;
    } else {
      c.roi_full = false;
      parse_size(key, v, c.roi_width_px, c.roi_height_px);
    }
  } else if (key == "cost") {
    if (v != "census" && v != "sad") throw ConfigError("field 'cost': expected census or sad, got '" + v + "'");
    c.cost = v;
  } else if (key == "window") parse_size(key, v, c.window_w, c.window_h);
  else if (key == "disparities") c.disparities = parse_int(key, v);
  else if (key == "parallel_units") c.parallel_units = parse_int(key, v);
  else if (key == "paths") c.path_mask = parse_paths(v);
  else if (key == "p1") c.p1 = parse_int(key, v);
  else if (key == "p2") c.p2 = parse_int(key, v);
  else if (key == "lr_check") c.lr_check = parse_bool(key, v);
  else if (key == "lr_tolerance") c.lr_tolerance = parse_int(key, v);
  else if (key == "median") c.median = (v == "off") ? 0 : parse_int(key, v);
  else if (key == "clock_mhz") c.clock_mhz = parse_int(key, v);
  else if (key == "rectify") {
    if (v != "none" && v != "nearest" && v != "bilinear")
      throw ConfigError("field 'rectify': expected none, nearest or bilinear, got '" + v + "'");
    c.rectify = v;
  } else if (key == "rectify_rows") c.rectify_rows = parse_int(key, v);
  else if (key == "rectify_frac_bits") c.rectify_frac_bits = parse_int(key, v);
  else if (key == "rectify_maps_left") c.rectify_maps_left = v;
  else if (key == "rectify_maps_right") c.rectify_maps_right = v;
  else if (key == "input") {
    if (v != "memory" && v != "camera") throw ConfigError("field 'input': expected memory or camera, got '" + v + "'");
    c.input = v;
  } else if (key == "input_gbps") c.input_gbps = parse_double(key, v);
  else if (key == "camera_pixel_mhz") c.camera_pixel_mhz = parse_double(key, v);
  else if (key == "camera_h_blank_px") c.camera_h_blank_px = parse_int(key, v);
  else if (key == "camera_v_blank_rows") c.camera_v_blank_rows = parse_int(key, v);
  else if (key == "ddr_gbps") c.ddr_gbps = parse_double(key, v);
  else if (key == "ddr_latency_ns") c.ddr_latency_ns = parse_int(key, v);
  else if (key == "fifo_depth") c.fifo_depth = parse_int(key, v);
  else if (key == "row_packing") c.row_packing = parse_int(key, v);
  else if (key == "row_banks") c.row_banks = parse_int(key, v);
  else if (key == "host_copy_gbps") c.host_copy_gbps = parse_double(key, v);
  else if (key == "host_latency_ms") c.host_latency_ms = parse_double(key, v);
  else if (key == "host_frame_ms") c.host_frame_ms = parse_double(key, v);
  else if (key.rfind("fifo_depth_", 0) == 0) c.fifo_depths[key.substr(11)] = parse_int(key, v);
  else if (key.rfind("ii_", 0) == 0) c.stage_ii[key.substr(3)] = parse_int(key, v);
  else if (key.rfind("latency_", 0) == 0) c.stage_latency[key.substr(8)] = parse_int(key, v);
  else if (key.rfind("setup_", 0) == 0) c.stage_setup[key.substr(6)] = parse_int(key, v);
  else {
    std::string known;
    for (const auto& n : field_names()) known += (known.empty() ? "" : ", ") + n;
    throw ConfigError("unknown field '" + key + "' (known fields: " + known + ")");
  }
}

std::vector<FieldError> validate(const PipelineConfig& c) {
  std::vector<FieldError> e;
  auto need = [&](bool ok, const char* field, const std::string& msg) {
    if (!ok) e.push_back({field, msg});
  };
  need(c.roi_full || (c.roi_width_px >= 1 && c.roi_width_px <= kern::kMaxWidthPx && c.roi_height_px >= 1 &&
                      c.roi_height_px <= kern::kMaxHeightPx),
       "roi", "each side must be in [1, 4096], or 'full'");
  need(c.window_w >= 1 && c.window_h >= 1 && c.window_w % 2 == 1 && c.window_h % 2 == 1 &&
           c.window_w <= kern::kMaxWindow && c.window_h <= kern::kMaxWindow,
       "window", "both sides odd, in [1, 9] (got " + std::to_string(c.window_w) + "x" + std::to_string(c.window_h) + ")");
  need(c.cost != "census" || c.window_w * c.window_h - 1 <= kern::kMaxCensusBits, "window",
       "census needs w*h - 1 <= 64 bits (9x7 is the largest 9-wide window)");
  need(c.disparities >= 1 && c.disparities <= kern::kMaxDisparities, "disparities",
       "must be in [1, 256] (got " + std::to_string(c.disparities) + ")");
  need(c.parallel_units >= 1 && c.disparities >= 1 && c.disparities % std::max(c.parallel_units, 1) == 0,
       "parallel_units", "must be >= 1 and divide disparities (" + std::to_string(c.parallel_units) + " does not divide " +
                             std::to_string(c.disparities) + ")");
  need(c.path_mask != 0 && (c.path_mask & ~kern::kAllPaths) == 0, "paths", "at least one path of 0..315");
  need(c.p1 >= 0, "p1", "must be >= 0 (got " + std::to_string(c.p1) + ")");
  need(c.p1 < c.p2, "p2", "must be greater than p1 (p1 = " + std::to_string(c.p1) + ", p2 = " + std::to_string(c.p2) + ")");
  need(c.p2 <= 65535, "p2", "must be <= 65535");
  need(c.lr_tolerance >= 0 && c.lr_tolerance < 256, "lr_tolerance", "must be in [0, 255]");
  need(c.median == 0 || c.median == 3 || c.median == 5 || c.median == 7, "median", "must be off (0), 3, 5 or 7");
  need(c.clock_mhz >= 1 && c.clock_mhz <= 1000, "clock_mhz", "must be in [1, 1000]");
  need(c.rectify_rows >= 1 && c.rectify_rows <= 256, "rectify_rows", "must be in [1, 256]");
  need(c.rectify_frac_bits >= 0 && c.rectify_frac_bits <= 10, "rectify_frac_bits", "must be in [0, 10]");
  need(c.rectify != "bilinear" || c.rectify_frac_bits >= 1, "rectify_frac_bits", "bilinear needs at least 1 fraction bit");
  need(c.rectify == "none" || !c.rectify_maps_left.empty(), "rectify_maps_left",
       "rectify: " + c.rectify + " needs the left camera's remap table");
  need(c.rectify == "none" || !c.rectify_maps_right.empty(), "rectify_maps_right",
       "rectify: " + c.rectify + " needs the right camera's remap table");
  need(c.input_gbps > 0, "input_gbps", "must be > 0");
  need(c.camera_pixel_mhz > 0, "camera_pixel_mhz", "must be > 0");
  need(c.camera_h_blank_px >= 0, "camera_h_blank_px", "must be >= 0");
  need(c.camera_v_blank_rows >= 0, "camera_v_blank_rows", "must be >= 0");
  need(c.ddr_gbps > 0, "ddr_gbps", "must be > 0");
  need(c.ddr_latency_ns >= 0, "ddr_latency_ns", "must be >= 0");
  need(c.fifo_depth >= 1, "fifo_depth", "must be >= 1");
  need(c.row_packing >= 1 && c.row_packing <= 256, "row_packing", "must be in [1, 256]");
  need(c.row_banks >= 0, "row_banks", "must be >= 0 (0 = one memory per word)");
  for (const auto& kv : c.fifo_depths) {
    const std::string field = "fifo_depth_" + kv.first;
    std::vector<std::string> names;  // each FIFO once (variants of the pipeline share names)
    for (const kern::PipelineFifo& f : kern::kPipelineFifos)
      if (std::find(names.begin(), names.end(), f.name) == names.end()) names.emplace_back(f.name);
    if (std::find(names.begin(), names.end(), kv.first) == names.end()) {
      std::string fifo_list;
      for (const auto& n : names) fifo_list += (fifo_list.empty() ? "" : ", ") + n;
      need(false, field.c_str(), "unknown FIFO '" + kv.first + "' (known: " + fifo_list + ")");
    }
    need(kv.second >= 1, field.c_str(), "must be >= 1");
  }
  // The pipeline's stage names (kernels/pipeline.hpp, the cycle model's stages).
  auto known_stage = [](const std::string& n) {
    for (const kern::PipelineStage& st : kern::kPipelineStages)
      if (n == st.name) return true;
    return false;
  };
  auto stage_list = [] {
    std::string l;
    for (const kern::PipelineStage& st : kern::kPipelineStages) l += (l.empty() ? "" : ", ") + std::string(st.name);
    return l;
  };
  for (const auto& kv : c.stage_ii) {
    const std::string field = "ii_" + kv.first;
    need(known_stage(kv.first), field.c_str(), "unknown stage '" + kv.first + "' (known: " + stage_list() + ")");
    need(kv.second >= 1, field.c_str(), "must be >= 1");
  }
  for (const auto& kv : c.stage_latency) {
    const std::string field = "latency_" + kv.first;
    need(known_stage(kv.first), field.c_str(), "unknown stage '" + kv.first + "' (known: " + stage_list() + ")");
    need(kv.second >= 0, field.c_str(), "must be >= 0");
  }
  for (const auto& kv : c.stage_setup) {
    const std::string field = "setup_" + kv.first;
    need(known_stage(kv.first), field.c_str(), "unknown stage '" + kv.first + "' (known: " + stage_list() + ")");
    need(kv.second >= 0, field.c_str(), "must be >= 0");
  }
  need(c.host_copy_gbps >= 0, "host_copy_gbps", "must be >= 0 (0 = no copies)");
  need(c.host_latency_ms >= 0, "host_latency_ms", "must be >= 0");
  need(c.host_frame_ms >= 0, "host_frame_ms", "must be >= 0");
  if (e.empty()) {
    const auto p = c.stereo_params(c.roi_full ? 640 : c.roi_width_px, c.roi_full ? 360 : c.roi_height_px);
    need(kern::aggregate_bits(p) <= 31, "p2", "aggregate would need more than 31 bits");
  }
  return e;
}

kern::StereoRegisters PipelineConfig::registers() const { return {p1, p2, lr_tolerance}; }

kern::StereoParams PipelineConfig::stereo_params(int width_px, int height_px) const {
  kern::StereoParams p{};
  p.width_px = width_px;
  p.height_px = height_px;
  p.cost = cost == "sad" ? kern::kCostSad : kern::kCostCensus;
  p.window_w = window_w;
  p.window_h = window_h;
  p.disparities = disparities;
  p.parallel_units = parallel_units;
  p.path_mask = path_mask;
  p.lr_check = lr_check;
  kern::set_registers(p, registers());
  p.median = median;
  return p;
}

kern::RectifyParams PipelineConfig::rectify_params(int width_px, int height_px) const {
  kern::RectifyParams r{};
  r.width_px = width_px;
  r.height_px = height_px;
  r.mode = rectify == "bilinear" ? kern::kRectifyBilinear : rectify == "nearest" ? kern::kRectifyNearest : kern::kRectifyNone;
  r.frac_bits = rectify == "bilinear" ? rectify_frac_bits : 0;
  r.buffer_rows = rectify_rows;
  return r;
}

PipelineConfig parse_config(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& ex) {
    throw ConfigError(source + ": not valid YAML: " + ex.what());
  }
  if (!root.IsMap()) throw ConfigError(source + ": expected a mapping of field: value");
  PipelineConfig c;
  std::vector<std::string> problems;
  for (const auto& kv : root) {
    if (!kv.first.IsScalar()) {
      problems.push_back("line " + std::to_string(kv.first.Mark().line + 1) + ": a key must be a field name, not a list or mapping");
      continue;
    }
    const std::string key = kv.first.Scalar();
    std::string value;
    if (kv.second.IsSequence()) {
      bool flat = true;
      for (const auto& item : kv.second) {
        if (!item.IsScalar()) {
          flat = false;
          break;
        }
        value += (value.empty() ? "" : ",") + item.Scalar();
      }
      if (!flat) {
        problems.push_back("field '" + key + "': a list of values, not of lists or mappings");
        continue;
      }
      value = "[" + value + "]";  // a list stays a list: paths [0] is an angle, not a count
    } else if (kv.second.IsScalar()) {
      value = kv.second.Scalar();
    } else {
      problems.push_back("field '" + key + "': expected a value or a list");
      continue;
    }
    try {
      set_field(c, key, value);
    } catch (const ConfigError& ex) {
      problems.push_back(ex.what());
    }
  }
  for (const auto& fe : validate(c)) problems.push_back("field '" + fe.field + "': " + fe.message);
  if (!problems.empty()) {
    std::string msg = source + ": invalid configuration:";
    for (const auto& p : problems) msg += "\n  - " + p;
    throw ConfigError(msg);
  }
  return c;
}

std::string read_text_file(const std::string& path, const std::string& what, std::size_t max_bytes) {
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(st)) throw ConfigError(path + ": " + what + " not found");
  if (std::filesystem::is_directory(st)) throw ConfigError(path + ": is a folder, not a " + what);
  if (!std::filesystem::is_regular_file(st)) throw ConfigError(path + ": not a regular file (a " + what + " is a text file)");
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw ConfigError(path + ": cannot read the " + what + ": " + ec.message());
  if (size > max_bytes)
    throw ConfigError(path + ": " + std::to_string(size) + " bytes; a " + what + " may have at most " +
                      std::to_string(max_bytes) + " bytes");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path + ": cannot open the " + what);
  std::string text(std::size_t(size), '\0');
  in.read(&text[0], std::streamsize(size));
  if (std::size_t(in.gcount()) != size) throw ConfigError(path + ": cannot read the " + what + " (short read)");
  return text;
}

PipelineConfig load_config(const std::string& path) {
  PipelineConfig c = parse_config(read_text_file(path, "configuration file"), path);
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  for (std::string* maps : {&c.rectify_maps_left, &c.rectify_maps_right})
    if (!maps->empty() && std::filesystem::path(*maps).is_relative()) *maps = (dir / *maps).string();
  return c;
}

std::string to_yaml(const PipelineConfig& c) {
  std::ostringstream o;
  o.precision(12);
  o << "name: " << c.name << "\n";
  o << "roi: " << (c.roi_full ? std::string("full") : std::to_string(c.roi_width_px) + "x" + std::to_string(c.roi_height_px)) << "\n";
  o << "cost: " << c.cost << "\n";
  o << "window: " << c.window_w << "x" << c.window_h << "\n";
  o << "disparities: " << c.disparities << "\n";
  o << "parallel_units: " << c.parallel_units << "\n";
  o << "paths: " << paths_to_string(c.path_mask) << "\n";
  o << "p1: " << c.p1 << "\n";
  o << "p2: " << c.p2 << "\n";
  o << "lr_check: " << (c.lr_check ? "true" : "false") << "\n";
  o << "lr_tolerance: " << c.lr_tolerance << "\n";
  o << "median: " << c.median << "\n";
  o << "clock_mhz: " << c.clock_mhz << "\n";
  o << "rectify: " << c.rectify << "\n";
  o << "rectify_rows: " << c.rectify_rows << "\n";
  o << "rectify_frac_bits: " << c.rectify_frac_bits << "\n";
  if (!c.rectify_maps_left.empty()) o << "rectify_maps_left: " << c.rectify_maps_left << "\n";
  if (!c.rectify_maps_right.empty()) o << "rectify_maps_right: " << c.rectify_maps_right << "\n";
  o << "input: " << c.input << "\n";
  o << "input_gbps: " << c.input_gbps << "\n";
  o << "camera_pixel_mhz: " << c.camera_pixel_mhz << "\n";
  o << "camera_h_blank_px: " << c.camera_h_blank_px << "\n";
  o << "camera_v_blank_rows: " << c.camera_v_blank_rows << "\n";
  o << "ddr_gbps: " << c.ddr_gbps << "\n";
  o << "ddr_latency_ns: " << c.ddr_latency_ns << "\n";
  o << "fifo_depth: " << c.fifo_depth << "\n";
  o << "row_packing: " << c.row_packing << "\n";
  o << "row_banks: " << c.row_banks << "\n";
  for (const auto& kv : c.fifo_depths) o << "fifo_depth_" << kv.first << ": " << kv.second << "\n";
  for (const auto& kv : c.stage_ii) o << "ii_" << kv.first << ": " << kv.second << "\n";
  for (const auto& kv : c.stage_latency) o << "latency_" << kv.first << ": " << kv.second << "\n";
  for (const auto& kv : c.stage_setup) o << "setup_" << kv.first << ": " << kv.second << "\n";
  o << "host_copy_gbps: " << c.host_copy_gbps << "\n";
  o << "host_latency_ms: " << c.host_latency_ms << "\n";
  o << "host_frame_ms: " << c.host_frame_ms << "\n";
  return o.str();
}

}  // namespace parallax::config
