#include "parallax/eval/evaluate.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/persistence.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

namespace parallax::eval {
namespace fs = std::filesystem;

sim::GreyImage to_grey_image(const cv::Mat& m) {
  CV_Assert(m.type() == CV_8UC1);
  sim::GreyImage g;
  g.width_px = m.cols;
  g.height_px = m.rows;
  g.px.resize(std::size_t(m.cols) * std::size_t(m.rows));
  for (int y = 0; y < m.rows; ++y) std::copy_n(m.ptr<uint8_t>(y), m.cols, g.px.data() + std::size_t(y) * m.cols);
  return g;
}

DisparityMap to_disparity_map(const sim::DisparityCodes& codes) {
  DisparityMap out;
  out.disparity_px = cv::Mat(codes.height_px, codes.width_px, CV_32FC1);
  out.valid_mask = cv::Mat(codes.height_px, codes.width_px, CV_8UC1);
  const uint16_t invalid = uint16_t(codes.disparities << codes.subpixel_bits);  // docs/algorithm.md §5
  const float step_px = 1.0f / float(1 << codes.subpixel_bits);
  for (int y = 0; y < codes.height_px; ++y) {
    float* __restrict d = out.disparity_px.ptr<float>(y);
    uint8_t* __restrict v = out.valid_mask.ptr<uint8_t>(y);
    const uint16_t* __restrict c = codes.code.data() + std::size_t(y) * std::size_t(codes.width_px);
    for (int x = 0; x < codes.width_px; ++x) {
      const bool ok = c[x] != invalid;
      d[x] = ok ? float(codes.min_disparity) + float(c[x]) * step_px : 0.0f;
      v[x] = ok ? 255 : 0;
    }
  }
  return out;
}

RoiSize roi_for(const config::PipelineConfig& cfg) {
  RoiSize r;
  r.full = cfg.roi_full;
  r.width_px = cfg.roi_width_px;
  r.height_px = cfg.roi_height_px;
  return r;
}

DisparityMap run_design(const config::PipelineConfig& cfg, const cv::Mat& left, const cv::Mat& right,
                        sim::FuncPipeline& pipeline, const sim::FuncOptions& options) {
  CV_Assert(left.type() == CV_8UC1 && right.type() == CV_8UC1 && left.size() == right.size());
  const kern::StereoParams p = cfg.stereo_params(left.cols, left.rows);
  return to_disparity_map(pipeline.run(to_grey_image(left), to_grey_image(right), p, options));
}

Baseline parse_baseline(const std::string& name) {
  if (name == "opencv-hh4") return Baseline::opencv_hh4;
  if (name == "opencv-sgbm") return Baseline::opencv_sgbm;
  throw InputError("unknown baseline '" + name + "' (known: opencv-hh4, opencv-sgbm)");
}

std::string to_string(Baseline b) {
  return b == Baseline::opencv_hh4 ? "opencv-hh4" : "opencv-sgbm";
}

DisparityMap run_baseline(Baseline b, const BaselineParams& bp, const cv::Mat& left, const cv::Mat& right) {
  const int num_disp = ((std::max(bp.disparities, 16) + 15) / 16) * 16;
  auto sgbm = cv::StereoSGBM::create(0, num_disp, bp.block_size, bp.p1, bp.p2, bp.disp12_max_diff, 0, 0, 0, 0,
                                     b == Baseline::opencv_hh4 ? cv::StereoSGBM::MODE_HH4 : cv::StereoSGBM::MODE_SGBM);
  cv::Mat raw;
  sgbm->compute(left, right, raw);  // CV_16S, disparity * 16, invalid < 0
  DisparityMap out;
  raw.convertTo(out.disparity_px, CV_32F, 1.0 / 16.0);
  out.valid_mask = raw >= 0;
  out.disparity_px.setTo(0.0f, out.valid_mask == 0);
  return out;
}

EvalResult evaluate(const Dataset& dataset, const RoiSize& roi, const MatcherFactory& factory, const EvalOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<FrameRef> refs = list_frames(dataset, opt.gt_kind, opt.frames);
  if (refs.empty())
    throw InputError(dataset.root.string() + ": no frame with " + to_string(opt.gt_kind) + " ground truth" +
                     (opt.frames.empty() ? std::string() : " matches '" + opt.frames + "'"));
  if (!opt.save_dir.empty()) {
    std::error_code ec;
    fs::create_directories(opt.save_dir, ec);
    if (ec) throw InputError(opt.save_dir.string() + ": cannot create the folder: " + ec.message());
  }
  EvalResult result;
  result.frames.resize(refs.size());
  std::vector<std::vector<std::string>> notes(refs.size());
  std::vector<char> converted_flags(refs.size(), 0);
  std::vector<std::string> range_warnings(refs.size());
  std::vector<double> range_gt_max_px(refs.size(), 0.0);
  std::atomic<std::size_t> next{0};
  std::atomic<int> done{0};
  std::mutex mu;  // guards progress callback and the first error
  std::string first_error;
  auto worker = [&] {
    Matcher match;
    try {
      match = factory();
    } catch (const std::exception& e) {
      std::lock_guard<std::mutex> lock(mu);
      if (first_error.empty()) first_error = e.what();
      return;
    }
    for (std::size_t i = next++; i < refs.size(); i = next++) {
      try {
        Frame f = load_frame(refs[i]);
        if (opt.preprocess) opt.preprocess(f.left, f.right);
        const Roi r = resolve_roi(roi, f.left.cols, f.left.rows);
        DisparityMap d;
        if (opt.match_full_image) {
          const DisparityMap whole = match(f.left, f.right);
          d.disparity_px = crop_to_roi(whole.disparity_px, r);
          d.valid_mask = crop_to_roi(whole.valid_mask, r);
        } else {
          d = match(crop_to_roi(f.left, r), crop_to_roi(f.right, r));
        }
        const cv::Mat gt = crop_to_roi(f.gt_disparity_px, r), gt_mask = crop_to_roi(f.gt_mask, r);
        result.frames[i] = make_frame_row(f.id, count_frame(d.disparity_px, d.valid_mask, gt, gt_mask));
        notes[i] = f.notes;
        converted_flags[i] = f.converted_from_colour ? 1 : 0;
        if (opt.design_disparities > 0) {
          range_warnings[i] = disparity_range_warning(f, r, opt.design_disparities, opt.design_min_disparity);
          range_gt_max_px[i] = f.gt_max_disparity_px;
        }
        if (!opt.save_dir.empty()) {
          write_kitti_disparity(opt.save_dir / (f.id + "_10.png"), d.disparity_px, d.valid_mask);
          write_png(opt.save_dir / (f.id + "_colour.png"),
                    colourize_disparity(d.disparity_px, d.valid_mask, opt.colour_max_disparity_px));
        }
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(mu);
        if (first_error.empty()) first_error = "frame " + refs[i].id + ": " + e.what();
        next = refs.size();
        return;
      }
      const int n = ++done;
      if (opt.progress) {
        std::lock_guard<std::mutex> lock(mu);
        opt.progress(n, int(refs.size()), refs[i].id);
      }
    }
  };
  const int threads = std::max(1, std::min<int>(opt.threads, int(refs.size())));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& th : pool) th.join();
  if (!first_error.empty()) throw InputError(first_error);
  int converted = 0;
  for (std::size_t i = 0; i < refs.size(); ++i) {
    if (converted_flags[i]) ++converted;  // its colour note is summarised below, once
    for (const auto& s : notes[i]) {
      if (converted_flags[i] && s.find("colour images converted to grey") != std::string::npos) continue;
      if (std::find(result.notes.begin(), result.notes.end(), s) == result.notes.end()) result.notes.push_back(s);
    }
  }
  if (converted > 0)
    result.notes.push_back(
        std::to_string(converted) + " of " + std::to_string(refs.size()) +
        " frames had colour images, converted to grey with cv::cvtColor(COLOR_BGR2GRAY) as OpenCV does");
  // The design's D against the frames' disparities: one warning, naming the frame reaching
  // farthest.
  int uncovered = 0;
  std::size_t worst = refs.size();
  for (std::size_t i = 0; i < refs.size(); ++i) {
    if (range_warnings[i].empty()) continue;
    ++uncovered;
    if (worst == refs.size() || range_gt_max_px[i] > range_gt_max_px[worst]) worst = i;
  }
  if (uncovered > 0) {
    std::string w = "warning: ";
    if (uncovered > 1)
      w += "the design's D = " + std::to_string(opt.design_disparities) + " does not cover the disparities of " +
           std::to_string(uncovered) + " of " + std::to_string(refs.size()) + " frames; the farthest: ";
    result.notes.push_back(w + range_warnings[worst]);
  }
  result.pooled = pool_rows(result.frames);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

RectifyMaps maps_of_size(const RectifyMaps& maps, const config::PipelineConfig& cfg, int width_px, int height_px) {
  if (!maps.identity) return maps;
  const int frac = cfg.rectify == "bilinear" ? cfg.rectify_frac_bits : 0;
  RectifyMaps m;
  m.width_px = width_px;
  m.height_px = height_px;
  m.left.resize(std::size_t(width_px) * std::size_t(height_px));
  for (int y = 0; y < height_px; ++y)
    for (int x = 0; x < width_px; ++x)
      m.left[std::size_t(y) * std::size_t(width_px) + std::size_t(x)] =
          kern::MapEntry{int32_t(x) * (1 << frac), int32_t(y) * (1 << frac)};
  m.right = m.left;
  return m;
}

RectifyMaps load_rectify_maps(const config::PipelineConfig& cfg) {
  RectifyMaps maps;
  if (cfg.rectify_maps_left.empty() && cfg.rectify_maps_right.empty()) {
    maps.identity = true;
    return maps;
  }
  if (cfg.rectify_maps_left.empty() || cfg.rectify_maps_right.empty())
    throw InputError(std::string("rectify: ") + cfg.rectify + " needs both rectify_maps_left and rectify_maps_right " +
                     "(or neither: identity tables for images that are already rectified)");
  const int frac = cfg.rectify == "bilinear" ? cfg.rectify_frac_bits : 0;
  auto load = [&](const std::string& file, std::vector<kern::MapEntry>& out) {
    if (!fs::exists(file)) throw InputError(file + ": remap table not found");
    cv::Mat mx, my;
    try {
      cv::FileStorage fsr(file, cv::FileStorage::READ);
      if (!fsr.isOpened()) throw InputError(file + ": cannot open as an OpenCV FileStorage (YAML, XML or JSON)");
      fsr["map_x"] >> mx;
      fsr["map_y"] >> my;
    } catch (const cv::Exception& e) {
      throw InputError(file + ": cannot read the remap table: " + e.what());
    }
    if (mx.empty() || my.empty()) throw InputError(file + ": needs matrices 'map_x' and 'map_y'");
    if (mx.size() != my.size() || mx.channels() != 1 || my.channels() != 1)
      throw InputError(file + ": 'map_x' and 'map_y' must be single-channel matrices of one size");
    mx.convertTo(mx, CV_64F);
    my.convertTo(my, CV_64F);
    if (maps.width_px == 0) {
      maps.width_px = mx.cols;
      maps.height_px = mx.rows;
    } else if (mx.cols != maps.width_px || mx.rows != maps.height_px) {
      throw InputError(file + ": remap table is " + std::to_string(mx.cols) + "x" + std::to_string(mx.rows) +
                       ", the left camera's is " + std::to_string(maps.width_px) + "x" +
                       std::to_string(maps.height_px));
    }
    const double scale = double(1 << frac);
    out.resize(std::size_t(mx.total()));
    for (int y = 0; y < mx.rows; ++y)
      for (int x = 0; x < mx.cols; ++x) {
        const double sx = std::round(mx.at<double>(y, x) * scale), sy = std::round(my.at<double>(y, x) * scale);
        if (!(std::abs(sx) < 1e9 && std::abs(sy) < 1e9))
          throw InputError(file + ": map entry at (" + std::to_string(x) + ", " + std::to_string(y) +
                           ") is not finite");
        out[std::size_t(y) * mx.cols + x] = kern::MapEntry{int32_t(sx), int32_t(sy)};
      }
  };
  load(cfg.rectify_maps_left, maps.left);
  load(cfg.rectify_maps_right, maps.right);
  return maps;
}

void rectify_pair(const config::PipelineConfig& cfg, const RectifyMaps& loaded, cv::Mat& left, cv::Mat& right,
                  int64_t* window_misses) {
  const RectifyMaps maps = maps_of_size(loaded, cfg, left.cols, left.rows);
  if (left.cols != maps.width_px || left.rows != maps.height_px)
    throw InputError(cfg.rectify_maps_left + ": remap table is " + std::to_string(maps.width_px) + "x" +
                     std::to_string(maps.height_px) + " but the images are " + std::to_string(left.cols) + "x" +
                     std::to_string(left.rows));
  const kern::RectifyParams rp = cfg.rectify_params(left.cols, left.rows);
  auto one = [&](cv::Mat& img, const std::vector<kern::MapEntry>& map) {
    const sim::RectifyOutput r = sim::run_rectify_func(to_grey_image(img), map, rp);
    cv::Mat out(img.rows, img.cols, CV_8UC1);
    std::copy(r.image.px.begin(), r.image.px.end(), out.ptr<uint8_t>(0));
    img = out;
    if (window_misses) *window_misses += r.window_misses;
  };
  one(left, maps.left);
  one(right, maps.right);
}

EvalResult evaluate_design(const config::PipelineConfig& cfg, const Dataset& dataset, const EvalOptions& opt_in) {
  const RoiSize roi = opt_in.roi_from_config ? roi_for(cfg) : opt_in.roi;
  EvalOptions opt = opt_in;
  opt.design_disparities = cfg.disparities;
  opt.design_min_disparity = cfg.min_disparity;
  auto misses = std::make_shared<std::atomic<int64_t>>(0);
  if (cfg.rectify != "none") {
    auto maps = std::make_shared<RectifyMaps>(load_rectify_maps(cfg));
    opt.preprocess = [&cfg, maps, misses](cv::Mat& l, cv::Mat& r) {
      int64_t m = 0;
      rectify_pair(cfg, *maps, l, r, &m);
      *misses += m;
    };
  }
  EvalResult result = evaluate(
      dataset, roi,
      [&cfg]() -> Matcher {
        auto pipe = std::make_shared<sim::FuncPipeline>();
        return [&cfg, pipe](const cv::Mat& l, const cv::Mat& r) { return run_design(cfg, l, r, *pipe); };
      },
      opt);
  if (misses->load() > 0)
    result.notes.push_back("rectification: " + std::to_string(misses->load()) +
                           " map taps fell outside the line buffer's rows (read as 0); raise rectify_rows");
  return result;
}

EvalResult score_predictions(const fs::path& pred_dir, const Dataset& dataset, const RoiSize& roi,
                             const EvalOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!fs::is_directory(pred_dir)) throw InputError(pred_dir.string() + ": prediction folder not found");
  const std::vector<FrameRef> refs = list_frames(dataset, opt.gt_kind, opt.frames);
  if (refs.empty()) throw InputError(dataset.root.string() + ": no frame with ground truth to score");
  EvalResult result;
  for (const FrameRef& ref : refs) {
    // <id>_10.png as eval --save writes it (for KITTI that is the GT file's name), else the GT's
    // own name when it is a PNG (legacy pairs.tsv scenes).
    fs::path pred_file = pred_dir / (ref.id + "_10.png");
    if (!fs::exists(pred_file) && ref.gt_path.extension() == ".png" && fs::exists(pred_dir / ref.gt_path.filename()))
      pred_file = pred_dir / ref.gt_path.filename();
    if (!fs::exists(pred_file))
      throw InputError(pred_file.string() + ": missing prediction for frame " + ref.id +
                       " (named <frame id>_10.png, as eval --save writes it)");
    const Frame f = load_frame(ref);
    const Roi r = resolve_roi(roi, f.gt_disparity_px.cols, f.gt_disparity_px.rows);
    DisparityMap pred = read_kitti_disparity(pred_file);
    if (pred.disparity_px.size() == f.gt_disparity_px.size()) {
      pred.disparity_px = crop_to_roi(pred.disparity_px, r);
      pred.valid_mask = crop_to_roi(pred.valid_mask, r);
    } else if (pred.disparity_px.cols != r.width_px || pred.disparity_px.rows != r.height_px) {
      throw InputError(pred_file.string() + ": size " + std::to_string(pred.disparity_px.cols) + "x" +
                       std::to_string(pred.disparity_px.rows) + " is neither the image size " +
                       std::to_string(f.gt_disparity_px.cols) + "x" + std::to_string(f.gt_disparity_px.rows) +
                       " nor the ROI size " + std::to_string(r.width_px) + "x" + std::to_string(r.height_px));
    }
    const cv::Mat gt = crop_to_roi(f.gt_disparity_px, r), gt_mask = crop_to_roi(f.gt_mask, r);
    result.frames.push_back(make_frame_row(f.id, count_frame(pred.disparity_px, pred.valid_mask, gt, gt_mask)));
    if (opt.progress) opt.progress(int(result.frames.size()), int(refs.size()), f.id);
  }
  result.pooled = pool_rows(result.frames);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace parallax::eval
