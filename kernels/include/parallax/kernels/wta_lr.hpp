// Winner-takes-all and left-right check (docs/algorithm.md §4) in one stage, because the right
// disparity is taken from the left aggregate volume: while the aggregates of pixel x stream in,
// every lane d is also a candidate for the right pixel x - d. A left pixel can be checked once
// the right pixel it points to has seen all its candidates, so with the LR check on, left
// disparities leave the stage D - 1 columns late (and are flushed at the end of each row).
// In reverse mode (second pass of the 8-path variant) the stream runs right to left, bottom to
// top. C++14 synthesisable subset.
#pragma once

#include "parallax/kernels/caps.hpp"
#include "parallax/kernels/common.hpp"
#include "parallax/kernels/resources.hpp"

namespace parallax {
namespace kern {

struct WtaPlan {
  bool read;   // one aggregate token
  bool write;  // one disparity code
};

template <class Caps, class Word>
class WtaLr {
 public:
  typedef Lanes<Word, Caps::lanes> SumToken;
  static constexpr int kRingMask = Caps::column_ring - 1;

  void configure(const StereoParams& p, bool reverse) {
    p_ = p;
    reverse_ = reverse;
    lanes_ = p.parallel_units;
    chunks_ = p.disparities / p.parallel_units;
    delay_ = p.lr_check ? p.disparities - 1 : 0;
    start_frame();
  }
  void start_frame() {
    x_ = 0;
    y_ = 0;
    chunk_ = 0;
    next_emit_ = 0;
    in_row_done_ = false;
    done_ = false;
  }
  bool done() const { return done_; }

  WtaPlan plan() const {
    WtaPlan pl;
    if (done_) {
      pl.read = pl.write = false;
      return pl;
    }
    if (in_row_done_) {  // flushing the delayed left pixels of this row
      pl.read = false;
      pl.write = true;
      return pl;
    }
    pl.read = true;
    // The last token of pixel x releases left pixel x - delay.
    pl.write = chunk_ + 1 == chunks_ && x_ - delay_ >= 0;
    return pl;
  }

  template <class InS, class OutS>
  void fire(const WtaPlan& pl, InS& in, OutS& out) {
    if (pl.read) consume(in.read());
    if (pl.write) out.write(emit());
    finish(pl);
  }

  // The control path of fire(pl) alone (see CostStage::step): emit() advances next_emit_ and
  // nothing else of the control state.
  void step(const WtaPlan& pl) {
    if (pl.write) ++next_emit_;
    finish(pl);
  }

  // Control-state access for a scheduler that advances periodic rows at once (sim/, never
  // synthesised): visit(v) calls v(field) on every counter of the control path, by reference;
  // resync() recomputes the fields derived from them after a visitor wrote them.
  template <class V>
  void visit(V& v) {
    v(x_);
    v(y_);
    v(chunk_);
    v(next_emit_);
    v(in_row_done_);
    v(done_);
  }
  void resync() {}

  // Resources of this configuration (resources.hpp): the min tree and first-lane encoder over
  // PU lanes, the left results delayed by D - 1 columns for the check (delay_ + 1 entries), and
  // with the LR check the right candidates of the last 2D - 1 columns in PU banks with a
  // compare-select per lane.
  template <class R>
  void declare(R& r) const {
    const int ab = aggregate_bits(p_);
    const int db = disparity_bits(p_);
    const int pu = lanes_;
    declare_raster_control(r, p_.width_px, p_.height_px, chunks_);
    if (pu > 1) {
      r.op("wta_min_tree", kOpCompare, ab, pu - 1);
      r.op("wta_min_select", kOpMux, ab, pu - 1);
    }
    r.op("wta_first_lane", kOpCompare, ab, pu);
    r.op("wta_best", kOpCompare, ab, 1);
    r.registers("wta_best", ab + db, 1);
    r.memory("left_disparities", delay_ + 1, db, 1, false);
    r.op("emit_counter", kOpAdd, bits_for(uint64_t(p_.width_px)), 1);
    if (p_.lr_check) {
      const int entries = 2 * p_.disparities - 1;
      r.memory("right_candidates", (entries + pu - 1) / pu, ab + db, pu, false);
      r.op("right_compare", kOpCompare, ab, pu);
      r.op("right_select", kOpMux, ab + db, pu);
      r.op("lr_difference", kOpAdd, db, 2);
      r.op("lr_tolerance", kOpCompare, db, 1);
    }
  }

 private:
  void consume(const SumToken& t) {
    const int lo = chunk_ * lanes_;
    if (chunk_ == 0) {
      best_cost_ = 0xFFFFFFFFu;
      best_d_ = 0;
    }
    const int n = lanes_;
    // Min tree, then a priority encoder for the smallest lane holding the minimum.
    uint32_t chunk_min = 0xFFFFFFFFu;
  wta_min:
    for (int i = 0; i < n; ++i) {
      PX_PRAGMA("HLS UNROLL")
      const uint32_t s = t.v[i];
      chunk_min = s < chunk_min ? s : chunk_min;
    }
    int first = n;
  wta_first:
    for (int i = 0; i < n; ++i) {
      PX_PRAGMA("HLS UNROLL")
      const int hit = uint32_t(t.v[i]) == chunk_min ? i : n;
      first = hit < first ? hit : first;
    }
    if (chunk_min < best_cost_) {  // strict: an earlier chunk (smaller d) wins ties
      best_cost_ = chunk_min;
      best_d_ = lo + first;
    }
    if (p_.lr_check) right_candidates(t, lo);
    if (chunk_ + 1 == chunks_) left_d_[x_ & kRingMask] = DispCode(best_d_);
  }

  // Lane d is a candidate for the right pixel x_img - d (when it exists), held at its stream
  // column. A right pixel's first candidate (forward: d = 0; reverse: d = D - 1, or the first
  // column of the row) meets an entry reset to "none"; candidates arrive in ascending d
  // (forward) or descending d (reverse), so the smallest d wins ties with < or <= respectively.
  void right_candidates(const SumToken& t, int lo) {
    const int x_img = reverse_ ? p_.width_px - 1 - x_ : x_;
    if (chunk_ == 0) {
      if (!reverse_) {
        reset_right(x_);
      } else if (x_ == 0) {
      wta_reset_row:
        for (int d = 0; d < p_.disparities; ++d) reset_right(d);
      } else {
        reset_right(x_ + p_.disparities - 1);
      }
    }
    const int valid = min_int(lanes_, x_img - lo + 1);  // lanes with x_img - d >= 0
    // Lane i's slot is base + i (mod ring): contiguous, so split once at the ring's end.
    const int base = reverse_ ? slot_of(x_ + lo) : slot_of(x_ - lo);
    const int first_run = min_int(valid, Caps::column_ring - base);
    update_right(t, lo, 0, first_run, base);
    update_right(t, lo, first_run, valid, base - Caps::column_ring);
  }

  void update_right(const SumToken& t, int lo, int i0, int i1, int offset) {
    const bool rev = reverse_;
  wta_right_lanes:
    for (int i = i0; i < i1; ++i) {
      PX_PRAGMA("HLS UNROLL")
      const int slot = offset + i;
      const uint32_t s = t.v[i];
      const uint32_t c = right_cost_[slot];
      const bool better = s < c || (rev && s == c);
      right_cost_[slot] = better ? s : c;
      right_d_[slot] = better ? lo + i : right_d_[slot];
    }
  }

  // Ring slot of a right pixel by stream column: mirrored in forward mode so that the lanes of
  // one token always occupy ascending slots.
  int slot_of(int stream_col) const { return (reverse_ ? stream_col : -stream_col) & kRingMask; }

  void reset_right(int stream_col) {
    right_cost_[slot_of(stream_col)] = 0xFFFFFFFFu;
    right_d_[slot_of(stream_col)] = 0;
  }

  DispCode emit() {
    const int xs = next_emit_++;
    const int d = left_d_[xs & kRingMask];
    const int x_img = reverse_ ? p_.width_px - 1 - xs : xs;
    const DispCode invalid = DispCode(p_.disparities);
    if (d > x_img) return invalid;
    if (p_.lr_check) {
      const int xr_stream = reverse_ ? xs + d : xs - d;
      const int dr = right_d_[slot_of(xr_stream)];
      const int diff = d > dr ? d - dr : dr - d;
      if (diff > p_.lr_tolerance) return invalid;
    }
    return DispCode(d);
  }

  void finish(const WtaPlan& pl) {
    if (pl.read) advance_input();
    else if (next_emit_ >= p_.width_px) next_row();
  }

  void advance_input() {
    if (++chunk_ < chunks_) return;
    chunk_ = 0;
    if (++x_ < p_.width_px) return;
    if (next_emit_ < p_.width_px)
      in_row_done_ = true;
    else
      next_row();
  }

  void next_row() {
    in_row_done_ = false;
    x_ = 0;
    next_emit_ = 0;
    if (++y_ >= p_.height_px) done_ = true;
  }

  StereoParams p_;
  bool reverse_ = false;
  int lanes_ = 1, chunks_ = 1, delay_ = 0;
  int x_ = 0, y_ = 0, chunk_ = 0, next_emit_ = 0;
  bool in_row_done_ = false, done_ = true;
  uint32_t best_cost_ = 0;
  int best_d_ = 0;
  DispCode left_d_[Caps::column_ring];     // left WTA results awaiting the check, by stream column
  uint32_t right_cost_[Caps::column_ring]; // right WTA running minimum, by stream column
  int right_d_[Caps::column_ring];
};

}  // namespace kern
}  // namespace parallax
