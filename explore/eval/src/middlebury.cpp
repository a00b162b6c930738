// The Middlebury layouts: 2014/2021 scene folders (im0.png, im1.png, disp0GT.pfm or disp0.pfm,
// calib.txt, mask0nocc.png), 2005/2006 scene folders (view1.png, view5.png, disp1.png and its
// scale by image size, dmin.txt), folders of such scenes, and the legacy index pairs.tsv.
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/text_util.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <map>

#include "dataset_internal.hpp"

namespace parallax::eval::dataset_detail {
using detail::trim;
namespace fs = std::filesystem;

namespace {

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

}  // namespace

bool is_middlebury_scene(const fs::path& dir) {
  return middlebury_scene_kind(dir) != MiddleburyScene::none;
}

std::vector<fs::path> middlebury_scene_folders(const fs::path& dir) {
  std::vector<fs::path> scenes;
  for (const fs::path& sub : sub_folders(dir))
    if (middlebury_scene_kind(sub) != MiddleburyScene::none) scenes.push_back(sub);
  return scenes;
}

// ---------------------------------------------------------------------------------------------
// pairs.tsv

namespace {

// The value of the whole of text by parse (std::stoi, std::stod: value from text, characters
// used); InputError "where: 'text' is not <what>" when it fails or leaves characters over.
template <class Parse>
auto parse_whole(const std::string& text, const std::string& where, const char* what, Parse parse) {
  try {
    std::size_t used = 0;
    const auto value = parse(text, &used);
    if (used == text.size()) return value;
  } catch (const std::exception&) {
  }
  throw InputError(where + ": '" + text + "' is not " + what);
}

int parse_int(const std::string& text, const std::string& where) {
  return parse_whole(text, where, "an integer",
                     [](const std::string& t, std::size_t* used) { return std::stoi(t, used); });
}

double parse_double(const std::string& text, const std::string& where) {
  return parse_whole(text, where, "a number",
                     [](const std::string& t, std::size_t* used) { return std::stod(t, used); });
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
  const int needed = std::max({c_scene, c_left, c_right, c_gt, c_divisor, c_invalid, c_width, c_height, c_format}) + 1;

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
      throw InputError(where + ": " + std::to_string(f.size()) + " tab-separated fields, " + "expected at least " +
                       std::to_string(needed));
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
        throw InputError(where + ", invalid: '" + f[c_invalid] + "': a PFM ground truth (" + f[c_gt] +
                         ") marks unknown pixels with inf; write 'inf'");
      }
    } else if (invalid == "inf" || invalid == "+inf") {
      throw InputError(where + ", invalid: 'inf' marks unknown pixels of PFM ground truth only; " + f[c_gt] +
                       " is an integer image: give the value meaning no GT (e.g. 0)");
    } else {
      ref.gt_invalid_value = parse_int(f[c_invalid], where + ", invalid");
    }
    if (c_width >= 0) ref.expected_width_px = parse_int(f[c_width], where + ", width");
    if (c_height >= 0) ref.expected_height_px = parse_int(f[c_height], where + ", height");
    if (c_width >= 0 || c_height >= 0) ref.expected_size_source = tsv.string() + " line " + std::to_string(line_number);
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
fs::path optional_scene_file(const fs::path& dir, std::initializer_list<const char*> names, const char* role) {
  for (const char* name : names) {
    fs::path file = dir / name;
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
constexpr const char* kHint2006 = "a Middlebury 2005/2006 scene holds view1.png, view5.png, disp1.png, dmin.txt";

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
        ref.expected_size_source = calib_file.string() + " lines " + std::to_string(calib.width_line) + "-" +
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

}  // namespace

std::vector<FrameRef> read_middlebury_scenes(const Dataset& dataset) {
  std::vector<FrameRef> scenes;
  if (dataset.middlebury_source == "pairs.tsv") {
    scenes = read_pairs_tsv(dataset.frames_dir / "pairs.tsv");
  } else if (dataset.middlebury_source == "scene folder") {
    scenes.push_back(middlebury_scene_ref(dataset.frames_dir));
  } else {
    for (const fs::path& scene : middlebury_scene_folders(dataset.frames_dir)) {
      scenes.push_back(middlebury_scene_ref(scene));
    }
  }
  return scenes;
}

// The scene string of a Middlebury frame (for filter matching): "2003/teddy".
std::string middlebury_scene(const Dataset& dataset, const FrameRef& ref) {
  const fs::path rel = ref.left_path.parent_path().lexically_relative(dataset.frames_dir);
  return rel.generic_string();
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

}  // namespace parallax::eval::dataset_detail
