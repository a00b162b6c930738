#include "parallax/explore/evaluate.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

namespace parallax::explore {
namespace fs = std::filesystem;

namespace {

sim::GreyImage to_grey_image(const cv::Mat& m) {
  sim::GreyImage g;
  g.width_px = m.cols;
  g.height_px = m.rows;
  g.px.resize(std::size_t(m.cols) * std::size_t(m.rows));
  for (int y = 0; y < m.rows; ++y) std::copy_n(m.ptr<uint8_t>(y), m.cols, g.px.data() + std::size_t(y) * m.cols);
  return g;
}

}  // namespace

RoiSize roi_for(const config::PipelineConfig& cfg) {
  RoiSize r;
  r.full = cfg.roi_full;
  r.width_px = cfg.roi_width_px;
  r.height_px = cfg.roi_height_px;
  return r;
}

DisparityMap run_design(const config::PipelineConfig& cfg, const cv::Mat& left, const cv::Mat& right,
                        sim::FuncPipeline& pipeline) {
  CV_Assert(left.type() == CV_8UC1 && right.type() == CV_8UC1 && left.size() == right.size());
  const kern::StereoParams p = cfg.stereo_params(left.cols, left.rows);
  const sim::DisparityCodes codes = pipeline.run(to_grey_image(left), to_grey_image(right), p);
  DisparityMap out;
  out.disparity_px = cv::Mat(left.rows, left.cols, CV_32FC1);
  out.valid_mask = cv::Mat(left.rows, left.cols, CV_8UC1);
  const uint16_t invalid = uint16_t(kern::invalid_code(p));
  for (int y = 0; y < left.rows; ++y) {
    float* d = out.disparity_px.ptr<float>(y);
    uint8_t* v = out.valid_mask.ptr<uint8_t>(y);
    const uint16_t* c = codes.code.data() + std::size_t(y) * left.cols;
    for (int x = 0; x < left.cols; ++x) {
      const bool ok = c[x] != invalid;
      d[x] = ok ? float(c[x]) : 0.0f;
      v[x] = ok ? 255 : 0;
    }
  }
  return out;
}

Baseline parse_baseline(const std::string& name) {
  if (name == "opencv-hh4") return Baseline::opencv_hh4;
  if (name == "opencv-sgbm") return Baseline::opencv_sgbm;
  throw InputError("unknown baseline '" + name + "' (known: opencv-hh4, opencv-sgbm)");
}

std::string to_string(Baseline b) { return b == Baseline::opencv_hh4 ? "opencv-hh4" : "opencv-sgbm"; }

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
  if (!opt.save_dir.empty()) fs::create_directories(opt.save_dir);
  EvalResult result;
  result.frames.resize(refs.size());
  std::vector<std::vector<std::string>> notes(refs.size());
  std::vector<char> converted_flags(refs.size(), 0);
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
        const Frame f = load_frame(refs[i]);
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
        if (!opt.save_dir.empty()) {
          write_kitti_disparity(opt.save_dir / (f.id + "_10.png"), d.disparity_px, d.valid_mask);
          write_png(opt.save_dir / (f.id + "_colour.png"), colourize_disparity(d.disparity_px, d.valid_mask, opt.colour_max_disparity_px));
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
    if (converted_flags[i]) {
      ++converted;
      continue;  // summarised below, once
    }
    for (const auto& s : notes[i])
      if (std::find(result.notes.begin(), result.notes.end(), s) == result.notes.end()) result.notes.push_back(s);
  }
  if (converted > 0)
    result.notes.push_back(std::to_string(converted) + " of " + std::to_string(refs.size()) +
                           " frames had colour images, converted to grey with cv::cvtColor(COLOR_BGR2GRAY) as OpenCV does");
  result.pooled = pool_rows(result.frames);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

EvalResult evaluate_design(const config::PipelineConfig& cfg, const Dataset& dataset, const EvalOptions& opt) {
  const RoiSize roi = opt.roi_from_config ? roi_for(cfg) : opt.roi;
  return evaluate(dataset, roi,
                  [&cfg]() -> Matcher {
                    auto pipe = std::make_shared<sim::FuncPipeline>();
                    return [&cfg, pipe](const cv::Mat& l, const cv::Mat& r) { return run_design(cfg, l, r, *pipe); };
                  },
                  opt);
}

EvalResult score_predictions(const fs::path& pred_dir, const Dataset& dataset, const RoiSize& roi,
                             const EvalOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!fs::is_directory(pred_dir)) throw InputError(pred_dir.string() + ": prediction folder not found");
  const std::vector<FrameRef> refs = list_frames(dataset, opt.gt_kind, opt.frames);
  if (refs.empty()) throw InputError(dataset.root.string() + ": no frame with ground truth to score");
  EvalResult result;
  for (const FrameRef& ref : refs) {
    const fs::path pred_file = pred_dir / ref.gt_path.filename();
    if (!fs::exists(pred_file))
      throw InputError(pred_file.string() + ": missing prediction for frame " + ref.id + " (named like the GT file)");
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

}  // namespace parallax::explore
