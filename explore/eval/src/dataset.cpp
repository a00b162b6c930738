// Stereo datasets, the common part: the helpers the dataset sources share, the frame filter,
// layout detection, open_dataset and list_frames. The layouts are read in kitti.cpp and
// middlebury.cpp, frames loaded in frame.cpp, the ROI in roi.cpp and the cropper is crop.cpp;
// their shared declarations are in dataset_internal.hpp.
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/text_util.hpp"

#include <algorithm>
#include <cctype>
#include <set>
#include <sstream>
#include <system_error>

#include "dataset_internal.hpp"

namespace parallax::eval {
using detail::trim;
namespace fs = std::filesystem;

namespace dataset_detail {

std::string size_text(int w, int h) {
  return std::to_string(w) + "x" + std::to_string(h);
}
std::string size_text(const cv::Mat& m) {
  return size_text(m.cols, m.rows);
}

bool is_dir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

bool path_exists(const fs::path& p) {
  std::error_code ec;
  return fs::exists(p, ec);
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
  return !s.empty() &&
         std::all_of(s.begin(), s.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
}

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

std::vector<std::size_t> select_frames(const std::vector<std::string>& ids, const std::vector<std::string>& aliases,
                                       bool numeric, const std::string& filter, const std::string& what) {
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

}  // namespace dataset_detail

using dataset_detail::gt_dir_name;
using dataset_detail::is_dir;
using dataset_detail::is_file;
using dataset_detail::is_middlebury_scene;
using dataset_detail::kitti_frame_ref;
using dataset_detail::kitti_gt_ids;
using dataset_detail::middlebury_scene;
using dataset_detail::middlebury_scene_folders;
using dataset_detail::read_middlebury_scenes;
using dataset_detail::select_frames;
using dataset_detail::sub_folders;

namespace {

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
  if (is_middlebury_scene(dir)) {
    dataset.middlebury_source = "scene folder";
    return true;
  }
  if (!middlebury_scene_folders(dir).empty()) {
    dataset.middlebury_source = "scene folders";
    return true;
  }
  return false;
}

}  // namespace

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

std::string to_string(GtKind kind) {
  return kind == GtKind::noc ? "noc" : "occ";
}

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
        dir.string() +
        ": unknown dataset layout (expected KITTI 2015 image_2/ + image_3/, KITTI "
        "2012 image_0/ + image_1/ or colored_0/ + colored_1/, a Middlebury scene "
        "folder (im0.png, im1.png, disp0.pfm, calib.txt; or view1.png, view5.png, "
        "disp1.png, dmin.txt), a folder of such scenes, or a pairs.tsv, in the "
        "folder or its training/ subfolder)" +
        (nested.empty() ? std::string() : "; its sub-folders " + nested + " hold Middlebury scenes: give one"));
  }
  if (dataset.layout == DatasetLayout::middlebury) {
    dataset.middlebury_scenes = read_middlebury_scenes(dataset);
  }
  return dataset;
}

std::vector<FrameRef> list_frames(const Dataset& dataset, GtKind gt_kind, const std::string& frame_filter) {
  const std::string what =
      to_string(dataset.layout) + " dataset " + dataset.frames_dir.string() + " (" + to_string(gt_kind) + " GT)";
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

}  // namespace parallax::eval
