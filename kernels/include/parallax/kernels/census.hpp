// Census transform with Hamming distance (docs/algorithm.md §2) as a cost policy of CostStage.
// Window up to 9x9 with at most 64 code bits, clamped border; full (bit = tap < centre for every
// tap), sparse (every second tap in raster order) or centre-symmetric (tap < its mirror through
// the centre, first half of the taps); the first used tap in the most significant bit. C++14
// synthesisable subset.
#pragma once

#include "parallax/kernels/caps.hpp"
#include "parallax/kernels/common.hpp"
#include "parallax/kernels/cost_stage.hpp"
#include "parallax/kernels/line_buffer.hpp"
#include "parallax/kernels/shift_reg.hpp"

namespace parallax {
namespace kern {

template <class Caps>
class CensusMatcher {
 public:
  static constexpr int kMaxD = Caps::max_disparities;
  // Right codes kept: the D candidates and the min_disparity columns between them and x.
  static constexpr int kMaxSpan = Caps::max_disparities + Caps::max_min_disparity;
  static constexpr int kLanes = Caps::lanes;

  void configure(const StereoParams& p) {
    right_codes_.name("right_codes");
    w_ = p.window_w;
    h_ = p.window_h;
    kind_ = p.census;
    d_ = Caps::disparities(p.disparities);
    m_ = Caps::min_disparity(p.min_disparity);
    cost_max_ = uint16_t(cost_max(p));
  }

  // Computes the left code of pixel (x, y) and shifts the right code of column x into the shift
  // register of the last m + D right codes (entry k: column x - k; m = min_disparity). Contract:
  // called once per pixel, in raster order, before its costs().
  // Hardware (resources.hpp): a w x h window of registers per image, one comparison per code bit
  // and image (w*h - 1 for the full census), the m + D right codes in a shift register (complete
  // partitioning: one register each; lanes read entries m .. m + D - 1), and per lane an XOR and a
  // popcount adder tree; lane i of chunk c reads entry m + c*PU + i through a D/PU-input
  // multiplexer (none when PU = D).
  template <class R>
  void declare(R& r, const StereoParams& p) const {
    const int bits = code_bits();
    const int pu = p.parallel_units;
    DeclareStorage<R> st(r);
    storage(st, p);
    r.op("census_compares", kOpCompare, 8, 2 * bits);
    if (p.disparities > pu) r.mux("right_code_select", bits, p.disparities / pu, pu);
    r.op("hamming_xor", kOpXor, bits, pu);
    r.op("hamming_popcount", kOpPopcount, bits, pu);
  }

  // Registers only (windows, codes, the right codes' shift register): no memory port to count.
  template <class S>
  void schedule(S&, const StereoParams&) const {}

  // Columns left of the output column that costs() may still read from the line buffers (the
  // right image's codes are kept in the shift register, so only the window's own half width).
  int columns_behind() const { return w_ / 2; }

  // Pixel (x, y) starts: the codes of the windows prime() has just moved to (x, y).
  template <class LB>
  void begin_pixel(const LB&, const LB&, int, int) {
    left_code_ = code(left_win_);
    right_codes_.shift_in(code(right_win_), m_ + d_);
  }
  // Moves both windows one step to position x of row y (x < 0: the row's prologue).
  template <class LB>
  void prime(const LB& left, const LB& right, int x, int y) {
    left_win_.step_to(left, x, y, w_, h_, w_ / 2);
    right_win_.step_to(right, x, y, w_, h_, w_ / 2);
  }

  // The left pixel (x, y) of the last begin_pixel(): the window registers' centre.
  uint8_t centre_px() const { return left_win_.at(w_ / 2, h_ / 2); }

  // Costs of lanes d0 .. d0 + n - 1: Hamming distance to the right code at x - m - d, or cost_max
  // where x - m - d < 0. Contract: d0 is a multiple of PU and n = PU.
  template <class LB>
  void costs(const LB&, const LB&, int x, int, int d0, int n, uint16_t* PX_RESTRICT out) const {
    const uint64_t lc = from_store<uint64_t>(left_code_);
  census_hamming:
    for (int i = 0; i < Caps::trip(n, kLanes); ++i) {
      PX_PRAGMA("HLS UNROLL")
      if (i < n) {
        const int k = m_ + d0 + i;  // right column x - k
        out[i] =
            k <= x ? uint16_t(popcount_tree<kMaxCensusBits>(lc ^ from_store<uint64_t>(right_codes_.at(k)))) : cost_max_;
      }
    }
  }

 private:
  // Dispatches the common window shapes to code with constant sides; same bits as the generic form.
  typedef WindowRegs<uint8_t, kMaxWindow, Caps::window_rows, Caps::fixed> Window;
  uint64_t code(const Window& win) const {
    if (w_ == 5 && h_ == 5) return code_generic(win, 5, 5, kind_);
    if (w_ == 3 && h_ == 3) return code_generic(win, 3, 3, kind_);
    if (w_ == 7 && h_ == 5) return code_generic(win, 7, 5, kind_);
    if (w_ == 9 && h_ == 7) return code_generic(win, 9, 7, kind_);
    return code_generic(win, w_, h_, kind_);
  }

  // The code of the window registers: over the used taps in raster order, bit = tap < centre
  // (full, sparse) or tap < its mirror tap (symmetric); a comparator per code bit on fixed wiring
  // (the loops are bounded by the largest window and unrolled).
  static PX_INLINE uint64_t code_generic(const Window& win, const int w, const int h, const int kind) {
    const uint8_t centre = win.at(w / 2, h / 2);
    const int taps = w * h;
    const int bits = census_bits(kind, w, h);
    uint64_t c = 0;
  census_rows:
    for (int j = 0; j < Caps::trip(h, Caps::window_rows); ++j) {
      PX_PRAGMA("HLS UNROLL")
    census_cols:
      for (int i = 0; i < Caps::trip(w, kMaxWindow); ++i) {
        PX_PRAGMA("HLS UNROLL")
        // Used tap k (raster order) lands in bit bits - 1 - rank(k): the first used tap is the
        // most significant used bit.
        const int k = j * w + i;
        if (j < h && i < w && census_tap_used(kind, k, taps)) {
          const int bit = bits - 1 - census_tap_rank(kind, k, taps);
          const uint8_t other = kind == kCensusSymmetric ? win.at(w - 1 - i, h - 1 - j) : centre;
          c |= uint64_t(win.at(i, j) < other ? 1u : 0u) << bit;
        }
      }
    }
    return c;
  }

  int w_ = 5, h_ = 5, kind_ = kCensusFull, d_ = 1, m_ = 0;
  uint16_t cost_max_ = 24;
  // The left code and the right codes of columns x .. x - m - D + 1 (a shift register, one register per entry),
  // census_bits wide in the export (store.hpp).
  typedef typename Caps::store::census CodeStore;
  CodeStore left_code_ = 0;
  ShiftReg<CodeStore, kMaxSpan, Caps::fixed, Caps::count_accesses> right_codes_;
  Window left_win_, right_win_;  // the window registers of the two images
  int code_bits() const { return census_bits(kind_, w_, h_); }

 public:
  // Storage descriptor (resources.hpp) of the members above: the w x h window registers of each
  // image, the left code and the m + D right codes of census_bits() bits.
  template <class V>
  void storage(V& v, const StereoParams&) const {
    left_win_.storage(v, "census_left_window", w_, h_, 8);
    right_win_.storage(v, "census_right_window", w_, h_, 8);
    v.registers("census_left_code", left_code_, 1, code_bits());
    right_codes_.storage(v, "right_codes", m_ + d_, code_bits());
  }
};

template <class Caps>
using CensusCostStage = CostStage<Caps, CensusMatcher<Caps> >;

}  // namespace kern
}  // namespace parallax
