// Census transform with Hamming distance (docs/algorithm.md §2) as a cost policy of CostStage.
// Window up to 9x7 (w*h - 1 <= 64 bits), clamped border, bit = neighbour < centre, first tap in
// the most significant used bit. C++14 synthesisable subset.
#pragma once

#include "parallax/kernels/caps.hpp"
#include "parallax/kernels/common.hpp"
#include "parallax/kernels/cost_stage.hpp"
#include "parallax/kernels/line_buffer.hpp"

namespace parallax {
namespace kern {

template <class Caps>
class CensusMatcher {
 public:
  void configure(const StereoParams& p) {
#ifdef PX_HLS_CENSUS_CODES_PARTITION
    PX_PRAGMA(PX_HLS_CENSUS_CODES_PARTITION)
#endif
    w_ = p.window_w;
    h_ = p.window_h;
    cost_max_ = uint16_t(cost_max(p));
  }

  // Computes the left and right codes of pixel (x, y); the right code joins the ring of the last
  // D right codes of this row. Contract: called once per pixel, in raster order, before cost().
  // Hardware (resources.hpp): a w x h window of registers per image, w*h - 1 comparisons per
  // image, the right codes of the last D columns in PU banks, and PU XOR + popcount lanes.
  template <class R>
  void declare(R& r, const StereoParams& p) const {
    const int taps = w_ * h_;
    const int bits = taps - 1;
    const int pu = p.parallel_units;
    r.registers("census_windows", 8, 2 * taps);
    r.op("census_compares", kOpCompare, 8, 2 * bits);
    r.registers("census_codes", bits, 2);
    r.memory("right_codes", (p.disparities + pu - 1) / pu, bits, pu, false);
    r.op("hamming_xor", kOpXor, bits, pu);
    r.op("hamming_popcount", kOpPopcount, bits, pu);
  }

  // Columns left of the output column that costs() may still read from the line buffers (the
  // right image's codes are kept in a ring, so only the window's own half width).
  int columns_behind() const { return w_ / 2; }

  template <class LB>
  void begin_pixel(const LB& left, const LB& right, int x, int y) {
    left_win_.move_to(left, x, y, w_, h_);
    right_win_.move_to(right, x, y, w_, h_);
    left_code_ = code(left_win_);
    right_codes_[slot_of(x)] = code(right_win_);
  }

  // Costs of lanes d0 .. d0 + n - 1: Hamming distance to the right code at x - d, or cost_max
  // where x - d < 0. The ring is mirrored (slot of column c is -c mod ring) so that the lanes
  // read ascending slots.
  template <class LB>
  void costs(const LB&, const LB&, int x, int, int d0, int n, uint16_t* out) const {
    const int valid = clamp_int(x - d0 + 1, 0, n);  // lanes with x - d >= 0
    const int base = slot_of(x - d0);
    const int first_run = min_int(valid, Caps::column_ring - base);
    hamming_run(out, 0, first_run, base);
    hamming_run(out, first_run, valid, base - Caps::column_ring);
  census_none:
    for (int i = valid; i < n; ++i) out[i] = cost_max_;
  }

 private:
  static int slot_of(int column) { return (-column) & (Caps::column_ring - 1); }

  void hamming_run(uint16_t* PX_RESTRICT out, int i0, int i1, int offset) const {
    const uint64_t lc = left_code_;
    const uint64_t* PX_RESTRICT ring = right_codes_;
  census_hamming:
    for (int i = i0; i < i1; ++i) out[i] = uint16_t(popcount64(lc ^ ring[offset + i]));
  }

  // Dispatches the common window shapes to fully unrolled code; same bits as the generic form.
  typedef WindowRegs<uint8_t, kMaxWindow, Caps::window_rows> Window;
  uint64_t code(const Window& win) const {
    if (w_ == 5 && h_ == 5) return code_generic(win, 5, 5);
    if (w_ == 3 && h_ == 3) return code_generic(win, 3, 3);
    if (w_ == 7 && h_ == 5) return code_generic(win, 7, 5);
    if (w_ == 9 && h_ == 7) return code_generic(win, 9, 7);
    return code_generic(win, w_, h_);
  }

  // The code of the window registers: bit = tap < centre, over the taps in raster order.
  static PX_INLINE uint64_t code_generic(const Window& win, const int w, const int h) {
    const uint8_t centre = win.at(w / 2, h / 2);
    const int taps = w * h;
    const int centre_tap = taps / 2;
    uint64_t c = 0;
  census_rows:
    for (int j = 0; j < h; ++j) {
    census_cols:
      for (int i = 0; i < w; ++i) {
        // Tap k (raster order, centre skipped) lands in bit taps - 2 - k': the first tap is the
        // most significant used bit.
        const int k = j * w + i;
        if (k == centre_tap) continue;
        const int bit = taps - 2 - (k < centre_tap ? k : k - 1);
        c |= uint64_t(win.at(i, j) < centre ? 1u : 0u) << bit;
      }
    }
    return c;
  }

  int w_ = 5, h_ = 5;
  uint16_t cost_max_ = 24;
  uint64_t left_code_ = 0;
  uint64_t right_codes_[Caps::column_ring];
  Window left_win_, right_win_;  // the window registers of the two images
};

template <class Caps>
using CensusCostStage = CostStage<Caps, CensusMatcher<Caps> >;

}  // namespace kern
}  // namespace parallax
