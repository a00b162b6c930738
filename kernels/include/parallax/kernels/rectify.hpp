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

// FIXED: the exported instantiation (MAX_ROWS = R): every row memory is read at fixed
// addresses by an unrolled loop over the rows (below); software instantiations read the one row
// a tap needs.
template <int MAX_W, int MAX_ROWS, bool FIXED = false>
class Rectify {
 public:
  // One memory per buffered row (W deep). A firing either takes an input pixel (one write) or
  // produces an output pixel (reads), never both (plan()), and fire() keeps the two in exclusive
  // branches: per firing a row memory sees one write, or the reads of the one tap row it may
  // hold: its columns ix (and ix + 1 for bilinear, the second port). A row is overwritten only
  // after the outputs that read it (the plan), but an output may read the pixel the previous
  // firing wrote (a read-after-write at distance 1), so the memories carry no DEPENDENCE pragma:
  // Vitis keeps that order at no II (no recurrence runs through them).
  Rectify() {
    PX_PRAGMA("HLS ARRAY_PARTITION variable=lb_ type=complete dim=1")
#ifdef PX_HLS_RECTIFY_STORAGE
    PX_PRAGMA(PX_HLS_RECTIFY_STORAGE)
#endif
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
  bool done() const {
    return done_;
  }

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
  int64_t window_misses() const {
    return window_misses_;
  }

  // Schedule of one firing (resources.hpp): per row memory either the write of the input pixel
  // or the reads of one tap row (two adjacent columns for bilinear, on a true dual-port RAM; one
  // column for nearest, on a simple dual-port RAM), in exclusive branches: the busier branch
  // counts. The counters are the recurrence.
  template <class S>
  void schedule(S& s) const {
    s.memory("rectify_line_buffer", p_.mode == kRectifyBilinear ? 2 : 1, 0, 2);
    s.recurrence("raster_counters", 1);
    s.chain(kOpAdd, bits_for(uint64_t(p_.width_px)), 1);
    s.chain(kOpCompare, bits_for(uint64_t(p_.width_px)), 1);
    s.chain(kOpRegister, bits_for(uint64_t(p_.width_px)), 1);
  }

  RectifyPlan plan() const {
    PX_PRAGMA("HLS INLINE")
    RectifyPlan pl;
    const int last_row = min_int(y_ + ahead_, p_.height_px - 1);
    pl.write = !done_ && in_row_ > last_row;
    pl.read_pixel = in_row_ < p_.height_px && in_row_ <= y_ + ahead_;
    return pl;
  }

  template <class PixIn, class MapIn, class PixOut>
  void fire(const RectifyPlan& pl, PixIn& in, MapIn& map_in, PixOut& out) {
    PX_PRAGMA("HLS INLINE")
    if (pl.write) {
      const MapEntry m = map_in.read();
      out.write(p_.mode == kRectifyBilinear ? bilinear(m) : nearest(m));
      if (++x_ == p_.width_px) {
        x_ = 0;
        ++base_row_;
        if (++base_slot_ == p_.buffer_rows) base_slot_ = 0;
        if (++y_ == p_.height_px) done_ = true;
      }
    } else if (pl.read_pixel) {  // exclusive with a write (plan()): the row memories' ports
      lb_[in_slot_][in_col_] = in.read();
      if (++in_col_ == p_.width_px) {
        in_col_ = 0;
        ++in_row_;
        if (++in_slot_ == p_.buffer_rows) in_slot_ = 0;
      }
    }
  }

 private:
  // Whether tap (ix, iy) reads the buffer: inside the image and resident while producing output
  // row y ([y + A - R + 1, y + A]); a tap in the image but not resident is a window miss. Taps
  // that do not read are 0.
  bool tap_ok(int ix, int iy) {
    if (ix < 0 || ix >= p_.width_px || iy < 0 || iy >= p_.height_px) return false;
    if (iy > y_ + ahead_ || iy < base_row_) {
      ++window_misses_;
      return false;
    }
    return true;
  }
  // Slot of a resident row: base_slot + (iy - base_row), wrapped once (no division).
  int slot_of(int iy) const {
    const int slot = base_slot_ + (iy - base_row_);
    return slot >= p_.buffer_rows ? slot - p_.buffer_rows : slot;
  }
  // Exported, every row memory is read at fixed addresses by an unrolled loop over the rows
  // and the slots select (one column per memory for nearest, two for bilinear: its two ports);
  // software reads the rows a tap needs, only where the tap reads (ok).
  // Column c of the row in slot s, 0 unless ok.
  int32_t read_one(int s, int c, bool ok) const {
    if (!FIXED) return ok ? int32_t(lb_[s][c]) : 0;
    int32_t v = 0;
  rectify_rows_read_one:
    for (int r = 0; r < MAX_ROWS; ++r) {
      PX_PRAGMA("HLS UNROLL")
      const int32_t u = lb_[r][c];
      if (r == s) v = u;
    }
    return ok ? v : 0;
  }
  // Columns c0, c1 of the rows in slots s0, s1 (the four bilinear taps), each 0 unless its ok.
  void read_pair(int s0, int s1, int c0, int c1, const bool ok[4], int32_t t[4]) const {
    if (!FIXED) {
      t[0] = ok[0] ? int32_t(lb_[s0][c0]) : 0;
      t[1] = ok[1] ? int32_t(lb_[s0][c1]) : 0;
      t[2] = ok[2] ? int32_t(lb_[s1][c0]) : 0;
      t[3] = ok[3] ? int32_t(lb_[s1][c1]) : 0;
      return;
    }
    int32_t a0 = 0, b0 = 0, a1 = 0, b1 = 0;
  rectify_rows_read_pair:
    for (int r = 0; r < MAX_ROWS; ++r) {
      PX_PRAGMA("HLS UNROLL")
      const int32_t u = lb_[r][c0];
      const int32_t w = lb_[r][c1];
      if (r == s0) {
        a0 = u;
        b0 = w;
      }
      if (r == s1) {
        a1 = u;
        b1 = w;
      }
    }
    t[0] = ok[0] ? a0 : 0;
    t[1] = ok[1] ? b0 : 0;
    t[2] = ok[2] ? a1 : 0;
    t[3] = ok[3] ? b1 : 0;
  }
  static int clamp_col(int c, int w) {
    return c < 0 ? 0 : (c >= w ? w - 1 : c);
  }
  static int clamp_slot(int s, int r) {
    return s < 0 || s >= r ? 0 : s;
  }

  uint8_t nearest(const MapEntry& m) {
    const int ix = int(m.x), iy = int(m.y);
    const bool ok = tap_ok(ix, iy);
    return uint8_t(read_one(clamp_slot(slot_of(iy), p_.buffer_rows), clamp_col(ix, p_.width_px), ok));
  }

  uint8_t bilinear(const MapEntry& m) {
    const int f = p_.frac_bits;
    const int32_t one = int32_t(1) << f;
    const int ix = int(m.x >> f);
    const int iy = int(m.y >> f);
    const int32_t fx = m.x & (one - 1);
    const int32_t fy = m.y & (one - 1);
    // Taps (ix, iy), (ix + 1, iy), (ix, iy + 1), (ix + 1, iy + 1).
    bool ok[4];
    ok[0] = tap_ok(ix, iy);
    ok[1] = tap_ok(ix + 1, iy);
    ok[2] = tap_ok(ix, iy + 1);
    ok[3] = tap_ok(ix + 1, iy + 1);
    int32_t t[4];
    read_pair(clamp_slot(slot_of(iy), p_.buffer_rows), clamp_slot(slot_of(iy + 1), p_.buffer_rows),
              clamp_col(ix, p_.width_px), clamp_col(ix + 1, p_.width_px), ok, t);
    const int32_t t00 = t[0], t10 = t[1], t01 = t[2], t11 = t[3];
    const int32_t acc = t00 * (one - fx) * (one - fy) + t10 * fx * (one - fy) + t01 * (one - fx) * fy + t11 * fx * fy;
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
  // true dual port for the tap pair, read at two columns in one firing).
  template <class V>
  void storage(V& v) const {
    v.memory("rectify_line_buffer", lb_, p_.width_px, 8, p_.buffer_rows, p_.mode == kRectifyBilinear, 1);
  }
};

}  // namespace kern
}  // namespace parallax
