// Sum of absolute differences over a w x h window (docs/algorithm.md §2) as a cost policy of
// CostStage. Clamped border on both images. C++14 synthesisable subset.
#pragma once

#include "parallax/kernels/caps.hpp"
#include "parallax/kernels/common.hpp"
#include "parallax/kernels/cost_stage.hpp"

namespace parallax {
namespace kern {

template <class Caps>
class SadMatcher {
 public:
  void configure(const StereoParams& p) {
    w_ = p.window_w;
    h_ = p.window_h;
    cost_max_ = uint16_t(cost_max(p));
  }

  // Latches the left window of pixel (x, y). Contract: once per pixel, before cost().
  template <class LB>
  void begin_pixel(const LB& left, const LB&, int x, int y) {
    int k = 0;
  sad_latch_rows:
    for (int j = -(h_ / 2); j <= h_ / 2; ++j) {
    sad_latch_cols:
      for (int i = -(w_ / 2); i <= w_ / 2; ++i) window_[k++] = left.at_clamped(x + i, y + j);
    }
  }

  template <class LB>
  uint16_t cost(const LB&, const LB& right, int x, int y, int d) const {
    if (x - d < 0) return cost_max_;
    int sum = 0;
    int k = 0;
  sad_rows:
    for (int j = -(h_ / 2); j <= h_ / 2; ++j) {
    sad_cols:
      for (int i = -(w_ / 2); i <= w_ / 2; ++i) {
        const int diff = int(window_[k++]) - int(right.at_clamped(x - d + i, y + j));
        sum += diff < 0 ? -diff : diff;
      }
    }
    return uint16_t(sum);
  }

 private:
  int w_ = 5, h_ = 5;
  uint16_t cost_max_ = 0;
  uint8_t window_[kMaxWindow * kMaxWindow];
};

template <class Caps>
using SadCostStage = CostStage<Caps, SadMatcher<Caps> >;

}  // namespace kern
}  // namespace parallax
