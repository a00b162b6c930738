// Winner-takes-all and left-right check (docs/algorithm.md §4) in one stage, because the right
// disparity is taken from the left aggregate volume: while the aggregates of pixel x stream in,
// every lane d is also a candidate for the right pixel x - d. A left pixel can be checked once
// the right pixel it points to has seen all its candidates, so with the LR check on, left
// disparities leave the stage D - 1 columns late (and are flushed at the end of each row).
// Everything the stage keeps between pixels is a shift register (as Vitis' own SGBM keeps its
// candidates): the right candidates still open, the finished right disparities and the delayed
// left results; every entry is a register with a fixed source, so a firing fits II = 1.
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
  bool prime;  // always false (no window registers)
};

template <class Caps, class Word>
class WtaLr {
 public:
  typedef Lanes<Word, Caps::lanes> SumToken;
  static constexpr int kMaxD = Caps::max_disparities;
  static constexpr int kLanes = Caps::lanes;
  static constexpr uint32_t kNoCost = 0xFFFFFFFFu;

  void configure(const StereoParams& p, bool reverse) {
    p_ = p;
    reverse_ = reverse;
    d_ = Caps::disparities(p.disparities);
    lanes_ = Caps::parallel_units(p.parallel_units);
    chunks_ = d_ / lanes_;
    delay_ = p.lr_check ? d_ - 1 : 0;
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
    pl.prime = false;
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
    if (pl.read) {
      consume(in.read());
    } else {  // a flushing firing: one more column passes with no candidates
      ++time_;
      shift_column();
      shift_left(0);
    }
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
  // PU lanes, the left results delayed by D - 1 columns for the check (a shift register), and
  // with the LR check the right candidates of the D open columns and the D - 1 finished right
  // disparities in shift registers, a compare-select per lane (lane i of chunk c reaches entry
  // c*PU + i through a D/PU-input multiplexer) and the D-input read of the right disparity.
  // Schedule of one firing (resources.hpp): registers only; the recurrences are the best cost of
  // the pixel across its chunks and each open right candidate's running minimum (a compare and
  // a select into a register, behind the shift's select).
  template <class S>
  void schedule(S& s) const {
    const int ab = aggregate_bits(p_);
    s.recurrence("best_cost", 1);
    s.chain(kOpCompare, ab, 1);
    s.chain(kOpMux, ab, 1);
    s.chain(kOpRegister, ab, 1);
    if (p_.lr_check) {
      s.recurrence("right_candidates", 1);
      s.chain(kOpMux, ab, 1);
      s.chain(kOpCompare, ab, 1);
      s.chain(kOpMux, ab, 1);
      s.chain(kOpRegister, ab, 1);
    }
  }

  template <class R>
  void declare(R& r) const {
    const int ab = aggregate_bits(p_);
    const int db = disparity_bits(p_);
    const int d = p_.disparities;
    const int pu = p_.parallel_units;
    declare_raster_control(r, p_.width_px, p_.height_px, d / pu);
    if (pu > 1) {
      r.op("wta_min_tree", kOpCompare, ab, pu - 1);
      r.op("wta_min_select", kOpMux, ab, pu - 1);
    }
    r.op("wta_first_lane", kOpCompare, ab, pu);
    r.op("wta_best", kOpCompare, ab, 1);
    declare_storage(r, *this);
    r.op("emit_counter", kOpAdd, bits_for(uint64_t(p_.width_px)), 1);
    if (p_.lr_check) {
      if (d > pu) r.op("right_candidate_select", kOpMux, ab + db, pu * (d / pu - 1));
      r.op("right_compare", kOpCompare, ab, pu);
      r.op("right_select", kOpMux, ab + db, pu);
      r.op("right_disparity_read", kOpMux, db, d - 1);
      r.op("lr_difference", kOpAdd, db, 2);
      r.op("lr_tolerance", kOpCompare, db, 1);
    }
  }

 private:
  void consume(const SumToken& t) {
    const int lo = chunk_ * lanes_;
    if (chunk_ == 0) {
      best_cost_ = kNoCost;
      best_d_ = 0;
      time_ = x_;
      shift_column();
    }
    const int n = lanes_;
    // Min tree, then a priority encoder for the smallest lane holding the minimum.
    uint32_t chunk_min = kNoCost;
  wta_min:
    for (int i = 0; i < Caps::trip(n, kLanes); ++i) {
      PX_PRAGMA("HLS UNROLL")
      const uint32_t s = i < n ? uint32_t(t.v[i]) : kNoCost;
      chunk_min = s < chunk_min ? s : chunk_min;
    }
    int first = n;
  wta_first:
    for (int i = 0; i < Caps::trip(n, kLanes); ++i) {
      PX_PRAGMA("HLS UNROLL")
      const int hit = i < n && uint32_t(t.v[i]) == chunk_min ? i : n;
      first = hit < first ? hit : first;
    }
    if (chunk_min < best_cost_) {  // strict: an earlier chunk (smaller d) wins ties
      best_cost_ = chunk_min;
      best_d_ = lo + first;
    }
    if (p_.lr_check) right_candidates(t, lo);
    if (chunk_ + 1 == chunks_) shift_left(DispCode(best_d_));
  }

  // The left results' delay line moves one column: entry k holds the result k columns back.
  void shift_left(DispCode newest) { left_d_.shift_in(newest, delay_ + 1); }

  // One column passes (the first token of a pixel, or a flushing firing after the row's input):
  // the open right candidates move one entry along the stream, the one leaving the open window
  // is finished and joins the finished right disparities. At the start of a row all are reset.
  // Forward: open entry k is the right pixel x - k (the stream column's candidates for lane d
  // land in entry d); reverse: open entry k is stream column x + k.
  void shift_column() {
    if (!p_.lr_check) return;
    const bool row_start = x_ == 0 && !in_row_done_;
    finished_d_.shift_in(reverse_ ? right_d_.at(0) : right_d_.at(d_ - 1), d_ - 1);
    if (row_start) {
    wta_open_reset:
      for (int k = 0; k < Caps::trip(d_, kMaxD); ++k) {
        PX_PRAGMA("HLS UNROLL")
        if (k < d_) {
          right_cost_.set(k, uint32_t(kNoCost));
          right_d_.set(k, 0);
        }
      }
    } else if (!reverse_) {  // entry k takes entry k - 1; entry 0 is new
      right_cost_.shift_in(uint32_t(kNoCost), d_);
      right_d_.shift_in(0, d_);
    } else {  // entry k takes entry k + 1; entry D - 1 is new
      right_cost_.shift_back(uint32_t(kNoCost), d_);
      right_d_.shift_back(0, d_);
    }
  }

  // Lane d of this token is a candidate for the right pixel x_img - d (when it exists), held in
  // open entry d. Candidates of one right pixel arrive in ascending d (forward) or descending d
  // (reverse), so the smallest d wins ties with < or <= respectively.
  void right_candidates(const SumToken& t, int lo) {
    const int x_img = reverse_ ? p_.width_px - 1 - x_ : x_;
    const bool rev = reverse_;
    const int n = min_int(lanes_, x_img - lo + 1);  // lanes with a right pixel x_img - d >= 0
  wta_right_lanes:
    for (int i = 0; i < Caps::trip(n, kLanes); ++i) {
      PX_PRAGMA("HLS UNROLL")
      const int d = lo + i;
      const uint32_t s = t.v[i];
      const uint32_t c = right_cost_.at(d);
      const bool better = i < n && (s < c || (rev && s == c));
      right_cost_.set(d, better ? s : c);
      right_d_.set(d, better ? DispCode(d) : right_d_.at(d));
    }
  }

  // The oldest left pixel not yet emitted, checked against the right pixel it points to. After
  // the shift of stream column t (real, or a flushing firing's), the left pixel xs is left
  // entry t - xs (delay_, except while flushing a row narrower than D); the right pixel of left
  // disparity d is, forward, t - xs + d columns old: open entry t - xs + d while younger than
  // D, else finished entry t - xs + d - D; reverse, stream column xs + d: open entry
  // xs + d - t when not behind t, else finished entry t - 1 - xs - d.
  DispCode emit() {
    const int xs = next_emit_++;
    const int lag = in_row_done_ ? time_ - xs : delay_;
    const int d = left_d_.at(lag);
    const int x_img = reverse_ ? p_.width_px - 1 - xs : xs;
    const DispCode invalid = DispCode(d_);
    if (d > x_img) return invalid;
    if (p_.lr_check) {
      int dr;
      if (!reverse_) {
        const int age = lag + d;
        dr = age < d_ ? right_d_.at(age) : finished_d_.at(age - d_);
      } else {
        const int ahead = d - lag;
        dr = ahead >= 0 ? right_d_.at(ahead) : finished_d_.at(-ahead - 1);
      }
      const int diff = d > dr ? d - dr : dr - d;
      if (diff > p_.lr_tolerance) return invalid;
    }
    return DispCode(d);
  }

  void finish(const WtaPlan& pl) {
    if (pl.read)
      advance_input();
    else if (next_emit_ >= p_.width_px)
      next_row();
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
  int d_ = 1, lanes_ = 1, chunks_ = 1, delay_ = 0;
  int x_ = 0, y_ = 0, chunk_ = 0, next_emit_ = 0;
  int time_ = 0;  // stream column of the last column shift (flushing firings count on past W - 1)
  bool in_row_done_ = false, done_ = true;
  uint32_t best_cost_ = 0;
  int best_d_ = 0;
  // Shift registers (common.hpp): the left WTA results of the last D columns (entry k: k columns
  // back), the open right candidates' running minimum and its disparity, the finished right
  // disparities (D - 1 used).
  ShiftReg<DispCode, kMaxD, Caps::fixed> left_d_;
  ShiftReg<uint32_t, kMaxD, Caps::fixed> right_cost_;
  ShiftReg<DispCode, kMaxD, Caps::fixed> right_d_;
  ShiftReg<DispCode, kMaxD, Caps::fixed> finished_d_;

 public:
  // Storage descriptor (resources.hpp) of the members above: the best cost and disparity of the
  // pixel; the left results' delay line (delay_ + 1 entries: D with the LR check, 1 without);
  // with the LR check the D open right candidates (cost and disparity) and the D - 1 finished
  // right disparities (the shift lengths shift_left() and shift_column() use).
  template <class V>
  void storage(V& v) const {
    const int ab = aggregate_bits(p_);
    const int db = disparity_bits(p_);
    v.registers("wta_best_cost", best_cost_, 1, ab);
    v.registers("wta_best_disparity", best_d_, 1, db);
    left_d_.storage(v, "left_disparities", delay_ + 1, db);
    const int lr = p_.lr_check ? 1 : 0;  // without the check: never written (no hardware)
    right_cost_.storage(v, "right_candidate_costs", lr * d_, ab);
    right_d_.storage(v, "right_candidate_disparities", lr * d_, db);
    finished_d_.storage(v, "right_disparities", lr * (d_ - 1), db);
  }
};

}  // namespace kern
}  // namespace parallax
