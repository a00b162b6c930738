// Rectification by remap tables through a line buffer (docs/algorithm.md §1): nearest
// neighbour on integer maps (as in the paper) or bilinear with F-bit fixed-point weights.
// One map entry is read per output pixel; input pixels are read in raster order up to
// A = R/2 rows ahead of the output row. Taps outside the buffered rows read 0 and are counted
// as window misses. C++14 synthesisable subset.
#pragma once

#include "parallax/kernels/common.hpp"
#include "parallax/kernels/resources.hpp"

namespace parallax {
namespace kern {

struct RectifyPlan {
  bool read_pixel;  // one input pixel
  bool write;       // reads one map entry and writes one output pixel
};

template <int MAX_W, int MAX_ROWS>
class Rectify {
 public:
  // One memory per buffered row; each row split into even and odd columns, so that a bilinear
  // tap pair (two adjacent columns of one row) and the incoming pixel meet at most one read and
  // one write per bank. A row is overwritten only after the outputs that read it (the plan), so
  // no dependence between iterations.
  Rectify() {
    PX_PRAGMA("HLS ARRAY_PARTITION variable=lb_ type=complete dim=1")
    PX_PRAGMA("HLS ARRAY_PARTITION variable=lb_ type=cyclic factor=2 dim=2")
    PX_PRAGMA("HLS DEPENDENCE variable=lb_ type=inter dependent=false")
  }
  void configure(const RectifyParams& p) {
    p_ = p;
    ahead_ = p.buffer_rows / 2;
    start_frame();
  }
  // Counters only (no division in the loop): the input's row, column and buffer slot, and the
  // oldest resident row of the output row's window with its slot.
  void start_frame() {
    in_row_ = 0;
    in_col_ = 0;
    in_slot_ = 0;
    x_ = 0;
    y_ = 0;
    done_ = false;
    window_misses_ = 0;
    base_row_ = ahead_ - p_.buffer_rows + 1;
    const int r = p_.buffer_rows;
    base_slot_ = ((base_row_ % r) + r) % r;  // once per frame, outside the pipelined loop
  }
  bool done() const { return done_; }

  // Resources of this configuration (resources.hpp): the R-row line buffer (bilinear reads two
  // adjacent columns of a row per cycle: true dual port), the window test of each tap, and for
  // bilinear the four weights (products of F+1-bit factors) and the four weighted taps.
  template <class R>
  void declare(R& r) const {
    declare_raster_control(r, p_.width_px, p_.height_px, 1);
    const bool bilinear = p_.mode == kRectifyBilinear;
    declare_storage(r, *this);
    r.registers("map_entry", 64, 1);
    r.op("tap_window_tests", kOpCompare, 16, bilinear ? 8 : 4);
    if (bilinear) {
      const int f = p_.frac_bits;
      r.op("weight_complements", kOpAdd, f + 1, 2);
      r.mul("weights", f + 1, f + 1, 4);
      r.mul("weighted_taps", 8, 2 * f + 2, 4);
      r.op("accumulate", kOpAdd, 2 * f + 10, 4);
      r.registers("taps", 8, 4);
    }
    r.registers("rectify_out", 8, 1);
  }
  int64_t window_misses() const { return window_misses_; }

  // Schedule of one firing (resources.hpp): a tap pair of two adjacent columns reads one even and
  // one odd bank of a row memory, the incoming pixel writes one bank: at most one read and one
  // write per bank. The counters are the recurrence.
  template <class S>
  void schedule(S& s) const {
    s.memory("rectify_line_buffer", 1, 1, 2);
    s.recurrence("raster_counters", 1);
    s.chain(kOpAdd, bits_for(uint64_t(p_.width_px)), 1);
    s.chain(kOpCompare, bits_for(uint64_t(p_.width_px)), 1);
    s.chain(kOpRegister, bits_for(uint64_t(p_.width_px)), 1);
  }

  RectifyPlan plan() const {
    RectifyPlan pl;
    const int last_row = min_int(y_ + ahead_, p_.height_px - 1);
    pl.write = !done_ && in_row_ > last_row;
    pl.read_pixel = in_row_ < p_.height_px && in_row_ <= y_ + ahead_;
    return pl;
  }

  template <class PixIn, class MapIn, class PixOut>
  void fire(const RectifyPlan& pl, PixIn& in, MapIn& map_in, PixOut& out) {
    if (pl.write) {
      const MapEntry m = map_in.read();
      out.write(p_.mode == kRectifyBilinear ? bilinear(m) : tap(m.x, m.y));
      if (++x_ == p_.width_px) {
        x_ = 0;
        ++base_row_;
        if (++base_slot_ == p_.buffer_rows) base_slot_ = 0;
        if (++y_ == p_.height_px) done_ = true;
      }
    }
    if (pl.read_pixel) {
      lb_[in_slot_][in_col_] = in.read();
      if (++in_col_ == p_.width_px) {
        in_col_ = 0;
        ++in_row_;
        if (++in_slot_ == p_.buffer_rows) in_slot_ = 0;
      }
    }
  }

 private:
  // Rows resident while producing output row y: [y + A - R + 1, y + A] within the image.
  uint8_t tap(int ix, int iy) {
    if (ix < 0 || ix >= p_.width_px || iy < 0 || iy >= p_.height_px) return 0;
    if (iy > y_ + ahead_ || iy < base_row_) {
      ++window_misses_;
      return 0;
    }
    // Slot of a resident row: base_slot + (iy - base_row), wrapped once (no division).
    int slot = base_slot_ + (iy - base_row_);
    if (slot >= p_.buffer_rows) slot -= p_.buffer_rows;
    return lb_[slot][ix];
  }

  uint8_t bilinear(const MapEntry& m) {
    const int f = p_.frac_bits;
    const int32_t one = int32_t(1) << f;
    const int ix = int(m.x >> f);
    const int iy = int(m.y >> f);
    const int32_t fx = m.x & (one - 1);
    const int32_t fy = m.y & (one - 1);
    const int32_t t00 = tap(ix, iy), t10 = tap(ix + 1, iy);
    const int32_t t01 = tap(ix, iy + 1), t11 = tap(ix + 1, iy + 1);
    const int32_t acc = t00 * (one - fx) * (one - fy) + t10 * fx * (one - fy) +
                        t01 * (one - fx) * fy + t11 * fx * fy;
    const int32_t round = f > 0 ? (int32_t(1) << (2 * f - 1)) : 0;
    return uint8_t((acc + round) >> (2 * f));
  }

  RectifyParams p_;
  int ahead_ = 0;
  int in_row_ = 0, in_col_ = 0, in_slot_ = 0;  // next input pixel: row, column, buffer slot
  int base_row_ = 0, base_slot_ = 0;           // oldest row of the output row's window, its slot
  int x_ = 0, y_ = 0;
  bool done_ = true;
  int64_t window_misses_ = 0;
  uint8_t lb_[MAX_ROWS][MAX_W];

 public:
  // Storage descriptor (resources.hpp) of lb_: one memory per buffered row, W deep (bilinear:
  // true dual port for the tap pair). Not yet described: the even/odd column banks of the
  // constructor's cyclic partitioning (docs/resources.md).
  template <class V>
  void storage(V& v) const {
    v.memory("rectify_line_buffer", lb_, p_.width_px, 8, p_.buffer_rows, p_.mode == kRectifyBilinear, 1);
  }
};

}  // namespace kern
}  // namespace parallax
