// Internal: the frames of one sweep, decoded and cropped once for all its cost groups.
//
// A sweep evaluates its designs in groups that share the cost stage (sweep.cpp), and every group
// reads every frame of the dataset; decoding a KITTI frame (two colour PNGs and a 16-bit GT PNG)
// takes longer than the fast engine's whole frame. The cache keeps each frame's cropped images
// (compact copies, not views of the decoded frame) under a byte budget shared by the threads; a
// frame that finds the budget spent is decoded for its use and not kept. Entries are immutable
// once inserted, so readers hold them without a lock.
#pragma once

#include <cstddef>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include "parallax/eval/dataset.hpp"

namespace parallax::search::detail {

// One frame as a cost group reads it: the ROI's grey pair and ground truth.
struct CroppedFrame {
  std::string id;
  eval::Roi roi;
  cv::Mat left, right;      // CV_8UC1, the ROI
  cv::Mat gt_disparity_px;  // CV_32FC1, the ROI
  cv::Mat gt_mask;          // CV_8UC1, the ROI
  std::size_t bytes() const {
    return left.total() * left.elemSize() + right.total() * right.elemSize() +
           gt_disparity_px.total() * gt_disparity_px.elemSize() + gt_mask.total() * gt_mask.elemSize();
  }
};

class FrameCache {
 public:
  explicit FrameCache(std::size_t budget_bytes) : budget_bytes_(budget_bytes) {}

  // The frame `ref` cropped to `roi_size`, decoded now unless an earlier call kept it; a thread
  // asking for a frame another thread is decoding waits for that one. Throws what
  // eval::load_frame throws (the file named).
  std::shared_ptr<const CroppedFrame> get(const eval::FrameRef& ref, const eval::RoiSize& roi_size) {
    const std::string key = ref.left_path.string() + "|" + ref.right_path.string() + "|" + ref.gt_path.string() + "|" +
                            eval::to_string(roi_size);
    std::unique_lock<std::mutex> lock(mu_);
    const auto it = entries_.find(key);
    if (it != entries_.end()) {
      const std::shared_future<Entry> pending = it->second;
      lock.unlock();
      return pending.get();  // kept, or being decoded by another thread
    }
    std::promise<Entry> promise;
    entries_.emplace(key, promise.get_future().share());
    lock.unlock();
    Entry made;
    try {
      made = decode(ref, roi_size);
    } catch (...) {
      promise.set_exception(std::current_exception());
      lock.lock();
      entries_.erase(key);  // a later call tries again
      throw;
    }
    promise.set_value(made);
    lock.lock();
    if (used_bytes_ + made->bytes() <= budget_bytes_)
      used_bytes_ += made->bytes();
    else
      entries_.erase(key);  // over the budget: decoded for this use (and its waiters) only
    return made;
  }

  std::size_t kept_frames() const {
    const std::lock_guard<std::mutex> lock(mu_);
    return entries_.size();
  }

 private:
  using Entry = std::shared_ptr<const CroppedFrame>;

  static Entry decode(const eval::FrameRef& ref, const eval::RoiSize& roi_size) {
    auto made = std::make_shared<CroppedFrame>();
    const eval::Frame f = eval::load_frame(ref);
    made->id = f.id;
    made->roi = eval::resolve_roi(roi_size, f.left.cols, f.left.rows);
    made->left = eval::crop_to_roi(f.left, made->roi).clone();
    made->right = eval::crop_to_roi(f.right, made->roi).clone();
    made->gt_disparity_px = eval::crop_to_roi(f.gt_disparity_px, made->roi).clone();
    made->gt_mask = eval::crop_to_roi(f.gt_mask, made->roi).clone();
    return made;
  }

  const std::size_t budget_bytes_;
  mutable std::mutex mu_;
  // Kept frames and frames being decoded (their waiters share the future).
  std::map<std::string, std::shared_future<Entry>> entries_;
  std::size_t used_bytes_ = 0;
};

}  // namespace parallax::search::detail
