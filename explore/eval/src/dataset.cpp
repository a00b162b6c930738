// Stereo datasets: layout detection, frame lists and filters, frame loading, ROI, cropping.
// Readers of the layouts as downloaded: KITTI 2015, KITTI 2012 (grey or colour), Middlebury
// 2014/2021 and 2005/2006 scene folders, and the legacy Middlebury index pairs.tsv.
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/text_util.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>
#include <system_error>

#include "parallax/eval/disparity_io.hpp"

namespace parallax::explore {
using detail::trim;
namespace fs = std::filesystem;

namespace {

std::string size_text(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }
std::string size_text(const cv::Mat& m) { return size_text(m.cols, m.rows); }

bool is_dir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}


std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, sep)) parts.push_back(part);
  if (!s.empty() && s.back() == sep) parts.emplace_back();
  return parts;
}

bool all_digits(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c)) != 0;
  });
}

// "000001_10.png" -> "000001"; anything else -> "".
std::string kitti_id_of(const std::string& file_name) {
  const std::string suffix = "_10.png";
  if (file_name.size() != 6 + suffix.size()) return "";
  if (file_name.compare(6, suffix.size(), suffix) != 0) return "";
  const std::string id = file_name.substr(0, 6);
  return all_digits(id) ? id : "";
}

std::string kitti_file(const std::string& id) { return id + "_10.png"; }

// Folder names of a KITTI layout.
struct KittiDirs {
  const char* left;
  const char* right;
  const char* noc;
  const char* occ;
};

// The default folders of a layout (KITTI 2012: the grey images).
KittiDirs kitti_dirs(DatasetLayout layout) {
  if (layout == DatasetLayout::kitti2012) return {"image_0", "image_1", "disp_noc", "disp_occ"};
  return {"image_2", "image_3", "disp_noc_0", "disp_occ_0"};
}

// The folders an opened KITTI dataset reads (KITTI 2012 may use colored_0/1).
KittiDirs kitti_dirs(const Dataset& dataset) {
  KittiDirs dirs = kitti_dirs(dataset.layout);
  if (!dataset.kitti_left_dir.empty()) {
    dirs.left = dataset.kitti_left_dir.c_str();
    dirs.right = dataset.kitti_right_dir.c_str();
  }
  return dirs;
}

const char* gt_dir_name(DatasetLayout layout, GtKind kind) {
  const KittiDirs dirs = kitti_dirs(layout);
  return kind == GtKind::noc ? dirs.noc : dirs.occ;
}

bool path_exists(const fs::path& p) {
  std::error_code ec;
  return fs::exists(p, ec);
}

// Middlebury scene folders, recognised by any of their images or GT files (a calib.txt or
// dmin.txt alone does not make a scene).
enum class MiddleburyScene { none, y2014, y2006 };

constexpr const char* kMiddlebury2014Files[] = {"im0.png", "im1.png", "disp0GT.pfm", "disp0.pfm"};
constexpr const char* kMiddlebury2006Files[] = {"view1.png", "view5.png", "disp1.png"};

MiddleburyScene middlebury_scene_kind(const fs::path& dir) {
  for (const char* name : kMiddlebury2014Files)
    if (path_exists(dir / name)) return MiddleburyScene::y2014;
  for (const char* name : kMiddlebury2006Files)
    if (path_exists(dir / name)) return MiddleburyScene::y2006;
  return MiddleburyScene::none;
}

// Sub-folders of dir, sorted by name (hidden ones skipped).
std::vector<fs::path> sub_folders(const fs::path& dir) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!name.empty() && name[0] != '.' && is_dir(it->path())) out.push_back(it->path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<fs::path> middlebury_scene_folders(const fs::path& dir) {
  std::vector<fs::path> scenes;
  for (const fs::path& sub : sub_folders(dir))
    if (middlebury_scene_kind(sub) != MiddleburyScene::none) scenes.push_back(sub);
  return scenes;
}

// Detects a layout in dir. KITTI 2012 reads image_0/1 when present, else colored_0/1.
bool detect_layout(const fs::path& dir, Dataset& dataset) {
  dataset.kitti_left_dir.clear();
  dataset.kitti_right_dir.clear();
  if (is_dir(dir / "image_2") && is_dir(dir / "image_3")) {
    dataset.layout = DatasetLayout::kitti2015;
    return true;
  }
  if (is_dir(dir / "image_0") && is_dir(dir / "image_1")) {
    dataset.layout = DatasetLayout::kitti2012;
    dataset.kitti_left_dir = "image_0";
    dataset.kitti_right_dir = "image_1";
    return true;
  }
  if (is_dir(dir / "colored_0") && is_dir(dir / "colored_1")) {
    dataset.layout = DatasetLayout::kitti2012;
    dataset.kitti_left_dir = "colored_0";
    dataset.kitti_right_dir = "colored_1";
    return true;
  }
  dataset.layout = DatasetLayout::middlebury;
  if (is_file(dir / "pairs.tsv")) {
    dataset.middlebury_source = "pairs.tsv";
    return true;
  }
  if (middlebury_scene_kind(dir) != MiddleburyScene::none) {
    dataset.middlebury_source = "scene folder";
    return true;
  }
  if (!middlebury_scene_folders(dir).empty()) {
    dataset.middlebury_source = "scene folders";
    return true;
  }
  return false;
}

int parse_int(const std::string& text, const std::string& where) {
  try {
    std::size_t used = 0;
    const int value = std::stoi(text, &used);
    if (used == text.size()) return value;
  } catch (const std::exception&) {
  }
  throw InputError(where + ": '" + text + "' is not an integer");
}

double parse_double(const std::string& text, const std::string& where) {
  try {
    std::size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size()) return value;
  } catch (const std::exception&) {
  }
  throw InputError(where + ": '" + text + "' is not a number");
}

// Reads pairs.tsv: a header row naming the columns (scene, left, right, gt_left, a column whose
// name contains "divisor", invalid; optional width, height), then one tab-separated row per
// scene. Paths are relative to the file's folder. Empty lines and lines starting with '#' are
// skipped.
std::vector<FrameRef> read_pairs_tsv(const fs::path& tsv) {
  std::ifstream in(tsv);
  if (!in) throw InputError(tsv.string() + ": cannot be read");
  std::string line;
  std::vector<std::string> header;
  int line_number = 0;
  while (header.empty() && std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trim(line).empty() || line[0] == '#') continue;
    header = split(line, '\t');
  }
  if (header.empty()) throw InputError(tsv.string() + ": empty file, expected a header row");
  auto column = [&](const std::string& name, bool required) -> int {
    for (std::size_t i = 0; i < header.size(); ++i) {
      const std::string h = trim(header[i]);
      const bool match = name == "divisor" ? h.find("divisor") != std::string::npos : h == name;
      if (match) return static_cast<int>(i);
    }
    if (required) {
      throw InputError(tsv.string() + ": header has no '" + name + "' column");
    }
    return -1;
  };
  const int c_scene = column("scene", true);
  const int c_left = column("left", true);
  const int c_right = column("right", true);
  const int c_gt = column("gt_left", true);
  const int c_divisor = column("divisor", true);
  const int c_invalid = column("invalid", true);
  const int c_width = column("width", false);
  const int c_height = column("height", false);
  const int c_format = column("gt_format", false);
  const int needed = std::max({c_scene, c_left, c_right, c_gt, c_divisor, c_invalid, c_width,
                               c_height, c_format}) +
                     1;

  const fs::path base = tsv.parent_path();
  std::vector<FrameRef> pairs;
  std::vector<std::string> scenes;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trim(line).empty() || line[0] == '#') continue;
    const std::string where = tsv.string() + " line " + std::to_string(line_number);
    std::vector<std::string> f = split(line, '\t');
    if (static_cast<int>(f.size()) < needed) {
      throw InputError(where + ": " + std::to_string(f.size()) + " tab-separated fields, " +
                       "expected at least " + std::to_string(needed));
    }
    for (std::string& s : f) s = trim(s);
    FrameRef ref;
    const std::string scene = f[c_scene];
    ref.id = fs::path(scene).filename().string();
    ref.layout = DatasetLayout::middlebury;
    ref.left_path = base / f[c_left];
    ref.right_path = base / f[c_right];
    ref.gt_path = base / f[c_gt];
    ref.scene_kind = "Middlebury (pairs.tsv)";
    ref.gt_divisor = parse_double(f[c_divisor], where + ", divisor");
    if (!(ref.gt_divisor > 0.0)) throw InputError(where + ": divisor must be > 0");
    // A PFM GT (gt_format "pfm", or gt_left ending in .pfm) marks unknown pixels with inf.
    std::string gt_ext = ref.gt_path.extension().string();
    for (char& c : gt_ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    std::string invalid = f[c_invalid];
    for (char& c : invalid) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const bool pfm = gt_ext == ".pfm" || (c_format >= 0 && f[c_format] == "pfm");
    if (pfm) {
      ref.gt_format = GtFormat::pfm;
      if (invalid != "inf" && invalid != "+inf") {
        throw InputError(where + ", invalid: '" + f[c_invalid] + "': a PFM ground truth (" +
                         f[c_gt] + ") marks unknown pixels with inf; write 'inf'");
      }
    } else if (invalid == "inf" || invalid == "+inf") {
      throw InputError(where + ", invalid: 'inf' marks unknown pixels of PFM ground truth only; " +
                       f[c_gt] + " is an integer image: give the value meaning no GT (e.g. 0)");
    } else {
      ref.gt_invalid_value = parse_int(f[c_invalid], where + ", invalid");
    }
    if (c_width >= 0) ref.expected_width_px = parse_int(f[c_width], where + ", width");
    if (c_height >= 0) ref.expected_height_px = parse_int(f[c_height], where + ", height");
    if (c_width >= 0 || c_height >= 0) ref.expected_size_source = tsv.string() + " line " +
                                                                  std::to_string(line_number);
    pairs.push_back(ref);
    scenes.push_back(scene);
  }
  if (pairs.empty()) throw InputError(tsv.string() + ": no scene rows");
  // Ids are the scene folder names; when two scenes share one, use the whole scene path.
  std::map<std::string, int> uses;
  for (const FrameRef& p : pairs) ++uses[p.id];
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (uses[pairs[i].id] > 1) {
      std::string id = scenes[i];
      std::replace(id.begin(), id.end(), '/', '_');
      pairs[i].id = id;
    }
  }
  return pairs;
}

// The scene string of a Middlebury frame (for filter matching): "2003/teddy".
std::string middlebury_scene(const Dataset& dataset, const FrameRef& ref) {
  const fs::path rel = ref.left_path.parent_path().lexically_relative(dataset.frames_dir);
  return rel.generic_string();
}

// Selects among candidate frames (ids in dataset order; aliases: other accepted names of each
// frame, may be empty) by a filter. Returns indices into ids, in dataset order. `numeric` =
// KITTI rules (numbers, ranges), else exact names. `what` describes the candidates for errors.
std::vector<std::size_t> select_frames(const std::vector<std::string>& ids,
                                       const std::vector<std::string>& aliases, bool numeric,
                                       const std::string& filter, const std::string& what) {
  std::vector<std::size_t> all(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) all[i] = i;
  const std::string f = trim(filter);
  if (f.empty() || f == "all") return all;

  std::set<std::size_t> chosen;
  auto find_id = [&](const std::string& name) -> int {
    for (std::size_t i = 0; i < ids.size(); ++i) {
      if (ids[i] == name || (!aliases.empty() && aliases[i] == name)) return static_cast<int>(i);
    }
    return -1;
  };
  auto pad6 = [](long long n) {
    std::string s = std::to_string(n);
    return std::string(s.size() < 6 ? 6 - s.size() : 0, '0') + s;
  };
  for (const std::string& raw : split(f, ',')) {
    const std::string item = trim(raw);
    const std::string where = "frame filter '" + filter + "', item '" + item + "'";
    if (item.empty()) throw InputError(where + ": empty item");
    if (!numeric) {
      const int i = find_id(item);
      if (i < 0) throw InputError(where + ": no such frame in " + what);
      chosen.insert(static_cast<std::size_t>(i));
      continue;
    }
    const std::size_t dash = item.find('-');
    if (dash != std::string::npos) {
      const std::string a = trim(item.substr(0, dash));
      const std::string b = trim(item.substr(dash + 1));
      if (!all_digits(a) || !all_digits(b) || a.size() > 6 || b.size() > 6) {
        throw InputError(where + ": a range is two frame numbers, e.g. 1-5");
      }
      const long long lo = std::stoll(a);
      const long long hi = std::stoll(b);
      if (lo > hi) throw InputError(where + ": empty range (first > last)");
      bool any = false;
      for (std::size_t i = 0; i < ids.size(); ++i) {
        const long long n = std::stoll(ids[i]);
        if (n >= lo && n <= hi) {
          chosen.insert(i);
          any = true;
        }
      }
      if (!any) throw InputError(where + ": the range covers no frame of " + what);
      continue;
    }
    if (!all_digits(item) || item.size() > 6) {
      throw InputError(where + ": expected a frame number, a 6-digit id or a range a-b");
    }
    const std::string id = pad6(std::stoll(item));
    const int i = find_id(id);
    if (i < 0) throw InputError(where + ": frame " + id + " does not exist in " + what);
    chosen.insert(static_cast<std::size_t>(i));
  }
  return std::vector<std::size_t>(chosen.begin(), chosen.end());
}

// Ids of the frames of a KITTI dataset that have GT of a kind, sorted; empty if the GT folder
// is missing.
std::vector<std::string> kitti_gt_ids(const Dataset& dataset, GtKind kind) {
  const fs::path dir = dataset.frames_dir / gt_dir_name(dataset.layout, kind);
  std::vector<std::string> ids;
  if (!is_dir(dir)) return ids;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    const std::string id = kitti_id_of(e.path().filename().string());
    if (!id.empty() && e.is_regular_file()) ids.push_back(id);
  }
  std::sort(ids.begin(), ids.end());
  return ids;
}

// The calibration file of a KITTI frame: KITTI 2015 calib_cam_to_cam/NNNNNN.txt, KITTI 2012
// calib/NNNNNN.txt.
fs::path kitti_calib_file(const Dataset& dataset, const std::string& id) {
  const char* dir = dataset.layout == DatasetLayout::kitti2012 ? "calib" : "calib_cam_to_cam";
  return dataset.frames_dir / dir / (id + ".txt");
}

FrameRef kitti_frame_ref(const Dataset& dataset, const std::string& id, GtKind kind) {
  const KittiDirs dirs = kitti_dirs(dataset);
  FrameRef ref;
  ref.id = id;
  ref.layout = dataset.layout;
  ref.scene_kind = dataset.layout == DatasetLayout::kitti2012 ? "KITTI 2012" : "KITTI 2015";
  ref.left_path = dataset.frames_dir / dirs.left / kitti_file(id);
  ref.right_path = dataset.frames_dir / dirs.right / kitti_file(id);
  ref.gt_path = dataset.frames_dir / gt_dir_name(dataset.layout, kind) / kitti_file(id);
  ref.gt_kind = kind;
  ref.gt_format = GtFormat::png;
  ref.gt_divisor = 256.0;
  ref.gt_invalid_value = 0;
  const fs::path calib = kitti_calib_file(dataset, id);
  if (path_exists(calib)) ref.kitti_calib_path = calib;
  return ref;
}

void require_file(const fs::path& file, const char* role) {
  if (is_dir(file)) {
    throw InputError(file.string() + ": " + role + " path is a folder, expected a file");
  }
  if (!is_file(file)) throw InputError(file.string() + ": " + role + " file not found");
}

// ---------------------------------------------------------------------------------------------
// Middlebury scene folders

// A file a Middlebury scene needs: InputError naming it when missing or a folder.
void require_scene_file(const fs::path& file, const char* role, const char* layout_hint) {
  if (is_dir(file)) {
    throw InputError(file.string() + ": " + role + " path is a folder, expected a file");
  }
  if (!is_file(file)) {
    throw InputError(file.string() + ": " + role + " file not found (" + layout_hint + ")");
  }
}

// The first of the names present in dir (a folder in its place is an error), else empty.
fs::path optional_scene_file(const fs::path& dir, std::initializer_list<const char*> names,
                             const char* role) {
  for (const char* name : names) {
    const fs::path file = dir / name;
    if (!path_exists(file)) continue;
    if (is_dir(file)) {
      throw InputError(file.string() + ": " + role + " path is a folder, expected a file");
    }
    return file;
  }
  return {};
}

constexpr const char* kHint2014 =
    "a Middlebury 2014/2021 scene holds im0.png, im1.png, disp0GT.pfm or disp0.pfm, calib.txt";
constexpr const char* kHint2006 =
    "a Middlebury 2005/2006 scene holds view1.png, view5.png, disp1.png, dmin.txt";

FrameRef middlebury_scene_ref(const fs::path& dir) {
  FrameRef ref;
  ref.id = dir.filename().string();
  ref.layout = DatasetLayout::middlebury;
  ref.gt_kind = GtKind::noc;
  if (middlebury_scene_kind(dir) == MiddleburyScene::y2014) {
    ref.scene_kind = "Middlebury 2014/2021";
    ref.left_path = dir / "im0.png";
    ref.right_path = dir / "im1.png";
    require_scene_file(ref.left_path, "left image", kHint2014);
    require_scene_file(ref.right_path, "right image", kHint2014);
    ref.gt_path = optional_scene_file(dir, {"disp0GT.pfm", "disp0.pfm"}, "ground-truth");
    ref.gt_format = GtFormat::pfm;
    ref.gt_divisor = 1.0;
    ref.noc_mask_path = optional_scene_file(dir, {"mask0nocc.png"}, "non-occlusion mask");
    const fs::path calib_file = optional_scene_file(dir, {"calib.txt"}, "calibration");
    if (!calib_file.empty()) {
      const MiddleburyCalib calib = read_middlebury_calib(calib_file);
      ref.ndisp = calib.ndisp;
      ref.calibration = calib.camera;
      if (calib.width_px > 0 && calib.height_px > 0) {
        ref.expected_width_px = calib.width_px;
        ref.expected_height_px = calib.height_px;
        ref.expected_size_source = calib_file.string() + " lines " +
                                   std::to_string(calib.width_line) + "-" +
                                   std::to_string(calib.height_line) + " (width, height)";
      }
    }
  } else {
    ref.scene_kind = "Middlebury 2005/2006";
    ref.left_path = dir / "view1.png";
    ref.right_path = dir / "view5.png";
    require_scene_file(ref.left_path, "left image", kHint2006);
    require_scene_file(ref.right_path, "right image", kHint2006);
    ref.gt_path = optional_scene_file(dir, {"disp1.png"}, "ground-truth");
    ref.gt_format = GtFormat::png_by_size;
    ref.gt_invalid_value = 0;
    const fs::path dmin_file = optional_scene_file(dir, {"dmin.txt"}, "dmin");
    if (!dmin_file.empty()) ref.dmin_px = read_middlebury_dmin(dmin_file);
  }
  return ref;
}

// Middlebury 2005/2006 disp1.png scale by image height. The 2005 and 2006 sets come in full
// (1110 rows), half (555) and third (370) size, and their 8-bit disparity maps store the
// disparity in pixels of that size times 1, 2 or 3 (so a map holds the full-size disparity
// whatever the size), 0 meaning unknown: the convention of the dataset pages
// vision.middlebury.edu/stereo/data/scenes2005/ and scenes2006/. Checked through the search
// tool (the pages themselves were not reachable): the Middlebury SDK's disp2pfm.cpp, quoted in
// github.com/NVlabs/FoundationStereo/issues/149, divides "by dispfact (use 2 for half-size,
// etc.)", and public loaders divide third-size maps by 3 and half-size ones by 2.
// Returns 0 for any other height.
int middlebury_2006_scale(int image_height_px) {
  constexpr int kFullHeightPx = 1110;
  for (int scale = 1; scale <= 3; ++scale) {
    const int height = (kFullHeightPx + scale / 2) / scale;  // 1110, 555, 370
    if (std::abs(image_height_px - height) <= 1) return scale;
  }
  return 0;
}

// Reads an image as stored (depth and channels unchanged).
cv::Mat read_raw(const fs::path& file, const char* role) {
  require_file(file, role);
  cv::Mat image = decode_image_file(file, role);
  if (image.empty()) {
    throw InputError(file.string() + ": " + role + " file cannot be decoded as an image");
  }
  return image;
}

// Reads an 8-bit image as grey; sets `converted` when it had colour.
cv::Mat read_grey(const fs::path& file, const char* role, bool& converted) {
  cv::Mat image = read_raw(file, role);
  if (image.depth() != CV_8U) {
    throw InputError(file.string() + ": " + role + " image has " +
                     std::to_string(8 * image.elemSize1()) + "-bit samples, expected 8-bit");
  }
  if (image.channels() == 1) return image;
  cv::Mat grey;
  if (image.channels() == 3) {
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  } else if (image.channels() == 4) {
    cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
  } else {
    throw InputError(file.string() + ": " + role + " image has " +
                     std::to_string(image.channels()) + " channels, expected 1, 3 or 4");
  }
  converted = true;
  return grey;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// ROI

Roi centred_roi(int image_w, int image_h, int roi_w, int roi_h) {
  if (roi_w <= 0 || roi_h <= 0) {
    throw InputError("ROI " + size_text(roi_w, roi_h) + ": width and height must be > 0");
  }
  if (roi_w > image_w || roi_h > image_h) {
    throw InputError("ROI " + size_text(roi_w, roi_h) + " is larger than the image (" +
                     size_text(image_w, image_h) + "); use --roi full, or --set roi=WxH with a smaller size");
  }
  return Roi{(image_w - roi_w) / 2, (image_h - roi_h) / 2, roi_w, roi_h};
}

Roi full_roi(int image_w, int image_h) { return Roi{0, 0, image_w, image_h}; }

RoiSize parse_roi_size(const std::string& text) {
  const std::string t = trim(text);
  if (t == "full") return RoiSize{};
  const std::size_t x = t.find_first_of("xX");
  if (x != std::string::npos) {
    const std::string w = t.substr(0, x);
    const std::string h = t.substr(x + 1);
    if (all_digits(w) && all_digits(h) && w.size() <= 6 && h.size() <= 6) {
      const int width_px = std::stoi(w);
      const int height_px = std::stoi(h);
      if (width_px > 0 && height_px > 0) return RoiSize{false, width_px, height_px};
    }
  }
  throw InputError("ROI '" + text + "': expected 'full' or WIDTHxHEIGHT, e.g. 640x360");
}

std::string to_string(const RoiSize& size) {
  return size.full ? "full" : size_text(size.width_px, size.height_px);
}

Roi resolve_roi(const RoiSize& size, int image_w, int image_h) {
  if (size.full) return full_roi(image_w, image_h);
  return centred_roi(image_w, image_h, size.width_px, size.height_px);
}

cv::Mat crop_to_roi(const cv::Mat& image, const Roi& roi) {
  if (roi.x0 < 0 || roi.y0 < 0 || roi.width_px <= 0 || roi.height_px <= 0 ||
      roi.x0 + roi.width_px > image.cols || roi.y0 + roi.height_px > image.rows) {
    throw std::invalid_argument("crop_to_roi: ROI " + size_text(roi.width_px, roi.height_px) +
                                " at (" + std::to_string(roi.x0) + ", " + std::to_string(roi.y0) +
                                ") does not fit in a " + size_text(image) + " image");
  }
  return image(cv::Rect(roi.x0, roi.y0, roi.width_px, roi.height_px));
}

// ---------------------------------------------------------------------------------------------
// Datasets

std::string to_string(DatasetLayout layout) {
  switch (layout) {
    case DatasetLayout::kitti2015:
      return "kitti2015";
    case DatasetLayout::kitti2012:
      return "kitti2012";
    case DatasetLayout::middlebury:
      return "middlebury";
  }
  return "unknown";
}

std::string to_string(GtKind kind) { return kind == GtKind::noc ? "noc" : "occ"; }

GtKind parse_gt_kind(const std::string& text) {
  const std::string t = trim(text);
  if (t == "noc") return GtKind::noc;
  if (t == "occ") return GtKind::occ;
  throw InputError("ground-truth kind '" + text + "': expected 'noc' or 'occ'");
}

RoiSize default_roi_size(DatasetLayout layout) {
  if (layout == DatasetLayout::middlebury) return RoiSize{};
  return RoiSize{false, kKittiRoiWidthPx, kKittiRoiHeightPx};
}

Dataset open_dataset(const fs::path& dir) {
  if (is_file(dir)) {
    throw InputError(dir.string() + ": is a file; give the dataset folder (or one scene's folder)");
  }
  if (!is_dir(dir)) throw InputError(dir.string() + ": dataset folder not found");
  fs::path given = dir.lexically_normal();
  if (!given.has_filename()) given = given.parent_path();  // "a/b/" -> "a/b"

  Dataset dataset;
  if (detect_layout(given, dataset)) {
    dataset.frames_dir = given;
    dataset.root = given.filename() == "training" ? given.parent_path() : given;
    if (dataset.root.empty()) dataset.root = ".";
  } else if (detect_layout(given / "training", dataset)) {
    dataset.frames_dir = given / "training";
    dataset.root = given;
  } else {
    // A folder of folders of scenes (e.g. MiddEval3/ holding trainingQ/, trainingH/, ...).
    std::string nested;
    for (const fs::path& sub : sub_folders(given)) {
      if (!middlebury_scene_folders(sub).empty()) {
        nested += (nested.empty() ? "" : ", ") + sub.filename().string();
      }
    }
    throw InputError(
        dir.string() + ": unknown dataset layout (expected KITTI 2015 image_2/ + image_3/, KITTI "
                       "2012 image_0/ + image_1/ or colored_0/ + colored_1/, a Middlebury scene "
                       "folder (im0.png, im1.png, disp0.pfm, calib.txt; or view1.png, view5.png, "
                       "disp1.png, dmin.txt), a folder of such scenes, or a pairs.tsv, in the "
                       "folder or its training/ subfolder)" +
        (nested.empty() ? std::string()
                        : "; its sub-folders " + nested + " hold Middlebury scenes: give one"));
  }
  if (dataset.layout == DatasetLayout::middlebury) {
    if (dataset.middlebury_source == "pairs.tsv") {
      dataset.middlebury_scenes = read_pairs_tsv(dataset.frames_dir / "pairs.tsv");
    } else if (dataset.middlebury_source == "scene folder") {
      dataset.middlebury_scenes.push_back(middlebury_scene_ref(dataset.frames_dir));
    } else {
      for (const fs::path& scene : middlebury_scene_folders(dataset.frames_dir)) {
        dataset.middlebury_scenes.push_back(middlebury_scene_ref(scene));
      }
    }
  }
  return dataset;
}

std::vector<FrameRef> list_frames(const Dataset& dataset, GtKind gt_kind,
                                  const std::string& frame_filter) {
  const std::string what = to_string(dataset.layout) + " dataset " + dataset.frames_dir.string() +
                           " (" + to_string(gt_kind) + " GT)";
  std::vector<FrameRef> candidates;
  std::vector<std::string> ids;
  std::vector<std::string> aliases;
  if (dataset.layout == DatasetLayout::middlebury) {
    for (FrameRef ref : dataset.middlebury_scenes) {
      if (ref.gt_path.empty()) continue;  // a scene without GT (e.g. a test scene)
      ref.gt_kind = gt_kind;
      ids.push_back(ref.id);
      aliases.push_back(middlebury_scene(dataset, ref));
      candidates.push_back(ref);
    }
    if (ids.empty()) {
      throw InputError(dataset.frames_dir.string() +
                       ": no Middlebury scene with ground truth (disp0GT.pfm or disp0.pfm for "
                       "2014/2021 scenes, disp1.png for 2005/2006 scenes)");
    }
  } else {
    ids = kitti_gt_ids(dataset, gt_kind);
    if (ids.empty()) {
      throw InputError((dataset.frames_dir / gt_dir_name(dataset.layout, gt_kind)).string() +
                       ": no ground truth of kind " + to_string(gt_kind) +
                       " (folder missing or without NNNNNN_10.png files)");
    }
    for (const std::string& id : ids) candidates.push_back(kitti_frame_ref(dataset, id, gt_kind));
  }
  const bool numeric = dataset.layout != DatasetLayout::middlebury;
  std::vector<FrameRef> frames;
  for (std::size_t i : select_frames(ids, aliases, numeric, frame_filter, what)) {
    frames.push_back(candidates[i]);
  }
  return frames;
}

namespace {

// Ground truth of an integer image (KITTI, pairs.tsv, Middlebury 2005/2006) into the frame.
void decode_integer_gt(const FrameRef& ref, Frame& frame, std::ostringstream& note) {
  const cv::Mat gt = read_raw(ref.gt_path, "ground-truth");
  const bool kitti = ref.layout != DatasetLayout::middlebury;
  if (kitti && gt.type() != CV_16UC1) {
    throw InputError(ref.gt_path.string() + ": ground truth is a " +
                     std::to_string(gt.channels()) + "-channel " +
                     std::to_string(8 * gt.elemSize1()) +
                     "-bit image, but KITTI disparity PNGs are 16-bit single-channel "
                     "(disparity = value / 256, 0 = no GT)");
  }
  if (gt.channels() != 1 || (gt.depth() != CV_8U && gt.depth() != CV_16U)) {
    throw InputError(ref.gt_path.string() +
                     ": ground truth must be a single-channel 8- or "
                     "16-bit image, got " +
                     std::to_string(gt.channels()) + " channel(s) of " +
                     std::to_string(8 * gt.elemSize1()) + " bits");
  }
  if (gt.size() != frame.left.size()) {
    throw InputError(ref.gt_path.string() + ": ground truth is " + size_text(gt) +
                     " but the left image " + ref.left_path.string() + " is " +
                     size_text(frame.left));
  }
  double divisor = ref.gt_divisor;
  if (ref.gt_format == GtFormat::png_by_size) {
    if (gt.depth() != CV_8U) {
      throw InputError(ref.gt_path.string() +
                       ": a Middlebury 2005/2006 disparity map is 8-bit, this one is 16-bit");
    }
    const int scale = middlebury_2006_scale(frame.left.rows);
    if (scale == 0) {
      throw InputError(ref.left_path.string() + ": image height " +
                       std::to_string(frame.left.rows) +
                       " px is none of the Middlebury 2005/2006 sizes (full 1110, half 555, "
                       "third 370 rows), so the scale of " +
                       ref.gt_path.filename().string() + " is unknown");
    }
    divisor = scale;
    static const char* const kSizes[] = {"", "full", "half", "third"};
    note << ref.scene_kind << " ground truth " << ref.gt_path.filename().string() << " at "
         << kSizes[scale] << " size: disparity = value / " << scale
         << ", 0 = no GT; it serves both noc and occ (dmin.txt, the offset by which the pair "
            "was cropped, is not added: the GT is relative to the images as given)";
  }
  cv::Mat values;
  gt.convertTo(values, CV_32S);
  frame.gt_disparity_px = cv::Mat(gt.size(), CV_32FC1);
  frame.gt_mask = cv::Mat(gt.size(), CV_8UC1);
  for (int y = 0; y < gt.rows; ++y) {
    const std::int32_t* v = values.ptr<std::int32_t>(y);
    float* d = frame.gt_disparity_px.ptr<float>(y);
    std::uint8_t* ok = frame.gt_mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < gt.cols; ++x) {
      const bool has_gt = v[x] != ref.gt_invalid_value;
      ok[x] = has_gt ? 255 : 0;
      d[x] = has_gt ? static_cast<float>(static_cast<double>(v[x]) / divisor) : 0.0f;
    }
  }
  if (ref.gt_format == GtFormat::png && ref.layout == DatasetLayout::middlebury) {
    note << "frame " << ref.id << ": Middlebury GT " << ref.gt_path.filename().string()
         << " (disparity = value / " << ref.gt_divisor << ", value " << ref.gt_invalid_value
         << " = no GT) serves both noc and occ";
  }
}

// Ground truth of a PFM file (Middlebury 2014/2021, pairs.tsv rows with a .pfm GT).
void decode_pfm_gt(const FrameRef& ref, Frame& frame, std::ostringstream& note) {
  DisparityMap gt = read_pfm_disparity(ref.gt_path);
  if (gt.disparity_px.size() != frame.left.size()) {
    throw InputError(ref.gt_path.string() + ": ground truth is " + size_text(gt.disparity_px) +
                     " but the left image " + ref.left_path.string() + " is " +
                     size_text(frame.left));
  }
  if (ref.gt_divisor != 1.0) gt.disparity_px /= ref.gt_divisor;
  frame.gt_disparity_px = gt.disparity_px;
  frame.gt_mask = gt.valid_mask;
  note << (ref.scene_kind.empty() ? "Middlebury" : ref.scene_kind) << " ground truth "
       << ref.gt_path.filename().string() << " (float PFM, inf = no GT)";
  if (ref.gt_divisor != 1.0) note << " divided by " << ref.gt_divisor;
  if (!ref.noc_mask_path.empty()) {
    note << ": occ uses every pixel with GT, noc only those that " << ref.noc_mask_path.filename().string()
         << " marks non-occluded (255)";
  } else {
    note << " serves both noc and occ";
  }
}

// MiddEval3's mask0nocc.png: 255 = non-occluded, 128 = occluded, 0 = no GT.
void apply_noc_mask(const FrameRef& ref, Frame& frame) {
  const cv::Mat mask = read_raw(ref.noc_mask_path, "non-occlusion mask");
  if (mask.type() != CV_8UC1) {
    throw InputError(ref.noc_mask_path.string() +
                     ": non-occlusion mask must be an 8-bit single-channel image");
  }
  if (mask.size() != frame.left.size()) {
    throw InputError(ref.noc_mask_path.string() + ": non-occlusion mask is " + size_text(mask) +
                     " but the left image " + ref.left_path.string() + " is " +
                     size_text(frame.left));
  }
  for (int y = 0; y < mask.rows; ++y) {
    const std::uint8_t* m = mask.ptr<std::uint8_t>(y);
    std::uint8_t* ok = frame.gt_mask.ptr<std::uint8_t>(y);
    float* d = frame.gt_disparity_px.ptr<float>(y);
    for (int x = 0; x < mask.cols; ++x) {
      if (m[x] != 255) {
        ok[x] = 0;
        d[x] = 0.0f;
      }
    }
  }
}

}  // namespace

Frame load_frame(const FrameRef& ref) {
  Frame frame;
  frame.id = ref.id;
  bool left_colour = false;
  bool right_colour = false;
  frame.left = read_grey(ref.left_path, "left image", left_colour);
  frame.right = read_grey(ref.right_path, "right image", right_colour);
  if (frame.right.size() != frame.left.size()) {
    throw InputError(ref.right_path.string() + ": right image is " + size_text(frame.right) +
                     " but the left image " + ref.left_path.string() + " is " +
                     size_text(frame.left));
  }
  if (ref.expected_width_px > 0 && ref.expected_height_px > 0 &&
      (frame.left.cols != ref.expected_width_px || frame.left.rows != ref.expected_height_px)) {
    throw InputError(ref.left_path.string() + ": left image is " + size_text(frame.left) +
                     " but " +
                     (ref.expected_size_source.empty() ? std::string("the dataset")
                                                       : ref.expected_size_source) +
                     " declares " + size_text(ref.expected_width_px, ref.expected_height_px));
  }
  if (left_colour || right_colour) {
    frame.converted_from_colour = true;
    frame.notes.push_back("frame " + ref.id +
                          ": colour images converted to grey with cv::cvtColor(COLOR_BGR2GRAY)");
  }
  if (ref.layout == DatasetLayout::kitti2012 &&
      ref.left_path.parent_path().filename() == "colored_0") {
    frame.notes.push_back(
        "KITTI 2012: no image_0/ + image_1/, so the colour pairs colored_0/ + colored_1/ are "
        "read (the same cameras)");
  }

  std::ostringstream note;
  if (ref.gt_format == GtFormat::pfm) {
    decode_pfm_gt(ref, frame, note);
  } else {
    decode_integer_gt(ref, frame, note);
  }
  if (ref.gt_kind == GtKind::noc && !ref.noc_mask_path.empty()) apply_noc_mask(ref, frame);
  if (!note.str().empty()) frame.notes.push_back(note.str());

  if (cv::countNonZero(frame.gt_mask) == 0) {
    throw InputError(ref.gt_path.string() + ": ground truth has no valid pixel (" +
                     (ref.gt_format == GtFormat::pfm
                          ? std::string("every value is inf")
                          : "every value is " + std::to_string(ref.gt_invalid_value)) +
                     " = no GT" +
                     (ref.gt_kind == GtKind::noc && !ref.noc_mask_path.empty()
                          ? std::string(" after the non-occlusion mask")
                          : std::string()) +
                     "): nothing to score frame " + ref.id + " against");
  }
  cv::minMaxLoc(frame.gt_disparity_px, nullptr, &frame.gt_max_disparity_px, nullptr, nullptr,
                frame.gt_mask);

  frame.ndisp = ref.ndisp;
  frame.calibration = ref.calibration;
  frame.dmin_px = ref.dmin_px;
  if (!ref.kitti_calib_path.empty()) {
    frame.calibration = ref.layout == DatasetLayout::kitti2012
                            ? read_kitti_calib(ref.kitti_calib_path, "P0", "P1")
                            : read_kitti_calib(ref.kitti_calib_path, "P_rect_02", "P_rect_03");
  }
  return frame;
}

std::string disparity_range_warning(const Frame& frame, const Roi& roi, int disparities) {
  if (disparities <= 0) return "";
  const cv::Mat gt = crop_to_roi(frame.gt_disparity_px, roi);
  const cv::Mat mask = crop_to_roi(frame.gt_mask, roi);
  std::int64_t gt_pixels = 0;
  std::int64_t beyond = 0;
  double max_px = 0.0;
  for (int y = 0; y < gt.rows; ++y) {
    const float* d = gt.ptr<float>(y);
    const std::uint8_t* ok = mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < gt.cols; ++x) {
      if (ok[x] == 0) continue;
      ++gt_pixels;
      max_px = std::max(max_px, static_cast<double>(d[x]));
      if (d[x] >= static_cast<float>(disparities)) ++beyond;
    }
  }
  const bool ndisp_beyond = frame.ndisp > disparities;
  if (beyond == 0 && !ndisp_beyond) return "";
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(1);
  out << "frame " << frame.id << ": the design's D = " << disparities << " searches 0-"
      << disparities - 1 << " px, but ";
  if (frame.ndisp > 0) out << "the scene's ndisp is " << frame.ndisp << " (calib.txt) and ";
  out << "its ground truth inside the ROI reaches " << max_px << " px: ";
  if (beyond > 0) {
    out << 100.0 * static_cast<double>(beyond) /
               static_cast<double>(std::max<std::int64_t>(gt_pixels, 1))
        << " % of the ground-truth pixels (" << beyond << " of " << gt_pixels
        << ") are out of its reach";
  } else {
    out << "no ground-truth pixel is out of its reach, but the scene's bound is";
  }
  return out.str();
}

// ---------------------------------------------------------------------------------------------
// Cropping

CropSummary crop_dataset(const fs::path& src_dir, const std::string& frame_filter,
                         const std::vector<GtKind>& gt_kinds, int roi_w, int roi_h,
                         const fs::path& out_dir) {
  const Dataset dataset = open_dataset(src_dir);
  if (dataset.layout == DatasetLayout::middlebury) {
    throw InputError(src_dir.string() + ": crop_dataset supports KITTI datasets only");
  }
  if (gt_kinds.empty()) throw InputError("crop_dataset: no ground-truth kind given");

  // Frames with at least one of the requested GT kinds, then the filter.
  std::set<GtKind> kinds(gt_kinds.begin(), gt_kinds.end());
  std::map<GtKind, std::set<std::string>> has_gt;
  std::set<std::string> union_ids;
  for (GtKind kind : kinds) {
    for (const std::string& id : kitti_gt_ids(dataset, kind)) {
      has_gt[kind].insert(id);
      union_ids.insert(id);
    }
  }
  const std::vector<std::string> ids(union_ids.begin(), union_ids.end());
  if (ids.empty()) throw InputError(src_dir.string() + ": no frame with the requested GT");
  const std::string what = to_string(dataset.layout) + " dataset " + dataset.frames_dir.string();
  const std::vector<std::size_t> chosen = select_frames(ids, {}, true, frame_filter, what);

  const KittiDirs src = kitti_dirs(dataset);
  const KittiDirs dst = kitti_dirs(DatasetLayout::kitti2015);
  const fs::path out_frames = out_dir / "training";
  std::error_code ec;
  for (const char* sub : {dst.left, dst.right}) {
    fs::create_directories(out_frames / sub, ec);
    if (ec) throw std::runtime_error((out_frames / sub).string() + ": " + ec.message());
  }
  for (GtKind kind : kinds) {
    fs::create_directories(out_frames / gt_dir_name(DatasetLayout::kitti2015, kind), ec);
    if (ec) throw std::runtime_error(out_frames.string() + ": " + ec.message());
  }

  CropSummary summary;
  for (std::size_t index : chosen) {
    const std::string& id = ids[index];
    const std::string name = kitti_file(id);
    const fs::path left_path = dataset.frames_dir / src.left / name;
    const fs::path right_path = dataset.frames_dir / src.right / name;
    const cv::Mat left = read_raw(left_path, "left image");
    const cv::Mat right = read_raw(right_path, "right image");
    if (right.size() != left.size()) {
      throw InputError(right_path.string() + ": right image is " + size_text(right) +
                       " but the left image " + left_path.string() + " is " + size_text(left));
    }
    const Roi roi = centred_roi(left.cols, left.rows, roi_w, roi_h);
    struct Output {
      cv::Mat image;
      fs::path file;
    };
    std::vector<Output> outputs = {
        {crop_to_roi(left, roi).clone(), out_frames / dst.left / name},
        {crop_to_roi(right, roi).clone(), out_frames / dst.right / name}};
    for (GtKind kind : kinds) {
      if (has_gt[kind].count(id) == 0) continue;
      const fs::path gt_path = dataset.frames_dir / gt_dir_name(dataset.layout, kind) / name;
      const cv::Mat gt = read_raw(gt_path, "ground-truth");
      if (gt.type() != CV_16UC1) {
        throw InputError(gt_path.string() + ": ground truth must be a 16-bit single-channel PNG");
      }
      if (gt.size() != left.size()) {
        throw InputError(gt_path.string() + ": ground truth is " + size_text(gt) +
                         " but the left image " + left_path.string() + " is " + size_text(left));
      }
      // Raw uint16 values are copied unchanged: the crop's GT is bit-identical to the source.
      outputs.push_back({crop_to_roi(gt, roi).clone(),
                         out_frames / gt_dir_name(DatasetLayout::kitti2015, kind) / name});
    }
    for (const Output& o : outputs) {
      write_png(o.file, o.image);
      summary.files_written.push_back(o.file);
    }
    summary.frame_ids.push_back(id);
  }

  const fs::path licence = dataset.root / "LICENSE.txt";
  if (is_file(licence)) {
    // Copied by content (not fs::copy_file) so that the copy gets ordinary permissions and
    // a later run can overwrite it even when the source is read-only.
    const fs::path target = out_dir / "LICENSE.txt";
    std::ifstream in(licence, std::ios::binary);
    if (!in) throw InputError(licence.string() + ": cannot be read");
    fs::remove(target, ec);
    std::ofstream out(target, std::ios::binary);
    out << in.rdbuf();
    out.close();
    if (!out)
      throw std::runtime_error(target.string() + ": cannot write a copy of " + licence.string());
    summary.files_written.push_back(target);
  }
  return summary;
}

}  // namespace parallax::explore
