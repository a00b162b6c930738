// Sum of absolute differences over a w x h window (docs/algorithm.md §2) as a cost policy of
// CostStage. Clamped border on both images. C++14 synthesisable subset.
#pragma once

#include "parallax/kernels/access.hpp"
#include "parallax/kernels/caps.hpp"
#include "parallax/kernels/common.hpp"
#include "parallax/kernels/cost_stage.hpp"

namespace parallax {
namespace kern {

template <class Caps>
class SadMatcher {
 public:
  static constexpr int kLanes = Caps::lanes;
  static_assert(kMaxWindow * kMaxWindow * 255 <= 0xFFFF, "a window's sum of differences fits a 16-bit cost");
  // The previous pixel's sums: PU lanes read and written per firing, lane i in bank i.
  SadMatcher() { PX_PARTITION_CYCLIC(last_, kLanes, 1) }
  void configure(const StereoParams& p) {
    // The count's statement of the layout at the design's PU (kLanes in the export, where the two
    // are equal; a software instantiation's kLanes is its capacity).
    access_partition(last_, "sad_last_sums", kPartitionCyclic, p.parallel_units, 1);
    w_ = p.window_w;
    h_ = p.window_h;
    width_px_ = p.width_px;
    disparities_ = p.disparities;
    m_ = Caps::min_disparity(p.min_disparity);
    cost_max_ = uint16_t(cost_max(p));
  }

  // Hardware (resources.hpp): the left window and m + D + w right columns of h pixels in registers;
  // per lane w*h absolute differences (subtract, negate, select) and an adder tree.
  template <class R>
  void declare(R& r, const StereoParams& p) const {
    const int taps = w_ * h_;
    const int pu = p.parallel_units;
    DeclareStorage<R> st(r);
    storage(st, p);
    r.op("sad_differences", kOpAdd, 9, 2 * taps * pu);
    r.op("sad_abs_select", kOpMux, 8, taps * pu);
    r.op("sad_adder_tree", kOpAdd, cost_bits(p), (taps - 1) * pu);
  }

  // No recurrence of its own (the previous pixel's sums, PU lane banks, are counted).
  template <class S>
  void schedule(S&, const StereoParams&) const {}

  // Columns left of the output column that costs() may still read from the line buffers: the
  // right window at x - d reaches x - D + 1 - w/2, and the slide's trailing column one more.
  // (The registers below hold them; this keeps the line buffers' overwrite rule, and so the
  // schedule, as it was.)
  int columns_behind() const { return w_ / 2 + disparities_; }

  // Moves the registers to pixel (x, y): the left image's w + 1 columns x - 1 - w/2 .. x + w/2
  // and the right image's m + D + w columns x + w/2 - (m + D + w - 1) .. x + w/2 (m =
  // min_disparity), each clamped to the
  // image, over the window's h rows. The next pixel of a row shifts them one column and reads
  // one new pixel per row memory and image; any other move reloads them whole.
  // Contract: once per pixel, in raster order, after prime() moved the registers to (x, y) and
  // before costs() is called for every d in [0, D); the registers hold all it needs.
  template <class LB>
  void begin_pixel(const LB&, const LB&, int, int) {}
  // Moves both registers one step to position x of row y (x < 0: the row's prologue).
  template <class LB>
  void prime(const LB& left, const LB& right, int x, int y) {
    const int rw = w_ / 2;
    left_.step_to(left, x, y, w_ + 1, h_, rw);          // columns x - 1 - rw .. x + rw
    right_.step_to(right, x, y, right_span(), h_, rw);  // columns x + rw - (m + D + w - 1) .. x + rw
  }

  // The left pixel (x, y) of the last begin_pixel(): the left window's column x (index 1 + w/2),
  // centre row.
  uint8_t centre_px() const { return left_.at(1 + w_ / 2, h_ / 2); }

  // Costs of lanes d0 .. d0 + n - 1. Away from the borders the window sum slides:
  // S(x, d) = S(x-1, d) + column(x + rw) - column(x - 1 - rw), columns of absolute differences
  // over the h rows; near a border (where a clamp would apply) it is summed over the whole
  // window. Both give the same integer. Right pixel (x - m - d + c) is
  // right_.at(span - 1 - rw - m - d + c, j); left pixel (x + c) is left_.at(1 + rw + c, j).
  template <class LB>
  void costs(const LB&, const LB&, int x, int, int d0, int n, uint16_t* out) {
    const int rw = w_ / 2, span = right_span();
    // Lanes are a prefix that slides (m + d <= x - 1 - rw, right edge clear), then lanes summed
    // directly (m + d <= x), then lanes without a right pixel (m + d > x).
    // Every loop runs to its capacity in the export (lanes, window rows and columns), its body
    // guarded; software instantiations run the runtime counts.
    const int n_slide = x + rw <= width_px_ - 1 ? clamp_int(x - rw - m_ - d0, 0, n) : 0;
    const int n_valid = clamp_int(x - m_ - d0 + 1, 0, n);
    if (n_slide > 0) slide(d0, n_slide, out);
  sad_lanes:
    for (int i = 0; i < Caps::trip(n, kLanes); ++i) {
      PX_PRAGMA("HLS UNROLL")
      if (i >= n_slide && i < n_valid) {
        const int d = d0 + i;
        uint32_t sum = 0;
      sad_rows:
        for (int j = 0; j < Caps::trip(h_, Caps::window_rows); ++j) {
          PX_PRAGMA("HLS UNROLL")
        sad_cols:
          for (int c = 0; c < Caps::trip(w_, kMaxWindow); ++c) {
            PX_PRAGMA("HLS UNROLL")
            if (j < h_ && c < w_) {
              const int diff = int(left_.at(1 + c, j)) - int(right_.at(span - 1 - 2 * rw - m_ - d + c, j));
              sum += uint32_t(diff < 0 ? -diff : diff);
            }
          }
        }
        out[i] = uint16_t(sum);
      } else if (i >= n_valid && i < n) {
        out[i] = cost_max_;  // no right pixel
      }
    }
    // The sums the next pixel slides from: one store per lane, whichever way its sum was made
    // (one write per lane bank and firing; a sum fits 16 bits: see kMaxWindow).
  sad_keep:
    for (int i = 0; i < Caps::trip(n, kLanes); ++i) {
      PX_PRAGMA("HLS UNROLL")
      if (i < n_valid) last_[d0 + i] = out[i];
    }
  }

  // S(x, d) = S(x - 1, d) + column(x + rw, d) - column(x - 1 - rw, d) for lanes [0, n), n <= PU
  // (loops to the capacities in the export, bodies guarded, as in costs()).
  void slide(int d0, int n, uint16_t* out) {
    const int span = right_span() - m_;  // the offsets below count from column x + rw - m
    int32_t acc[Caps::lanes];
    PX_PRAGMA("HLS ARRAY_PARTITION variable=acc type=complete dim=1")
  sad_slide_init:
    for (int i = 0; i < Caps::trip(n, kLanes); ++i) {
      PX_PRAGMA("HLS UNROLL")
      acc[i] = i < n ? from_store<int32_t>(last_[d0 + i]) : 0;
    }
  sad_slide_rows:
    for (int j = 0; j < Caps::trip(h_, Caps::window_rows); ++j) {
      PX_PRAGMA("HLS UNROLL")
      if (j < h_) {
        const int lead = left_.at(w_, j);                                           // column x + rw
        const int trail = left_.at(0, j);                                           // column x - 1 - rw
        const uint8_t* PX_RESTRICT r_lead = right_.row(j) + (span - 1 - d0);        // column x + rw - m - d0
        const uint8_t* PX_RESTRICT r_trail = right_.row(j) + (span - 1 - w_ - d0);  // column x - 1 - rw - m - d0
      sad_slide_lanes:
        for (int i = 0; i < Caps::trip(n, kLanes); ++i) {
          PX_PRAGMA("HLS UNROLL")
          const int a = lead - int(r_lead[-i]);
          const int b = trail - int(r_trail[-i]);
          if (i < n) acc[i] += (a < 0 ? -a : a) - (b < 0 ? -b : b);
        }
      }
    }
  sad_slide_out:
    for (int i = 0; i < Caps::trip(n, kLanes); ++i) {
      PX_PRAGMA("HLS UNROLL")
      if (i < n) out[i] = uint16_t(acc[i]);
    }
  }

 private:
  int right_span() const { return m_ + disparities_ + w_; }  // right columns held
  int w_ = 5, h_ = 5, width_px_ = 1, disparities_ = 1, m_ = 0;
  uint16_t cost_max_ = 0;
  // The left window's w + 1 columns and the right image's m + D + w columns, over the h rows.
  WindowRegs<uint8_t, kMaxWindow + 1, Caps::window_rows, Caps::fixed> left_;
  WindowRegs<uint8_t, Caps::max_min_disparity + Caps::max_disparities + kMaxWindow, Caps::window_rows, Caps::fixed>
      right_;
  typename ArrayOf<Caps::count_accesses, typename Caps::store::cost, Caps::max_disparities>::type
      last_;  // S(x - 1, d) of this row, where it was a real sum (cost_bits wide in the export, store.hpp)

 public:
  // Storage descriptor (resources.hpp) of the members above: the left window's w + 1 columns and
  // the right image's m + D + w columns over h rows; the previous sums in PU lane banks (cyclic
  // partitioning by LANES: PU memories of D/PU words of the cost width).
  template <class V>
  void storage(V& v, const StereoParams& p) const {
    left_.storage(v, "sad_left_window", w_ + 1, h_, 8);
    right_.storage(v, "sad_right_columns", right_span(), h_, 8);
    const int pu = Caps::parallel_units(p.parallel_units);
    v.memory("sad_last_sums", last_, (disparities_ + pu - 1) / pu, cost_bits(p), pu, false, 1);
  }
};

template <class Caps>
using SadCostStage = CostStage<Caps, SadMatcher<Caps> >;

}  // namespace kern
}  // namespace parallax
