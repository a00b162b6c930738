// Winner-takes-all and left-right check (docs/algorithm.md §4) in one stage, because the right
// disparity is taken from the left aggregate volume: while the aggregates of pixel x stream in,
// every lane d is also a candidate for the right pixel x - d. A left pixel can be checked once
// the right pixel it points to has seen all its candidates, so with the LR check on, left
// disparities leave the stage D - 1 columns late (and are flushed at the end of each row).
// Everything the stage keeps between pixels is a shift register (as Vitis' own SGBM keeps its
// candidates): the right candidates still open, the finished right disparities and the delayed
// left results; every entry is a register with a fixed source, so a firing fits II = 1.
// In reverse mode (second pass of the 8-path variant) the stream runs right to left, bottom to
// top. With a uniqueness margin (uniqueness_pct > 0) the stage also tracks, across the chunks of
// a pixel, the smallest cost at least two disparities away from the running best (masked min
// trees over the lanes, three registers), and invalidates the pixel when that cost is within the
// margin of the best (docs/algorithm.md §4). With sub-pixel refinement (subpixel_bits f > 0) it
// keeps the aggregates beside the running best (the lane before it, or the previous chunk's last
// lane; the lane after it, or the next chunk's first) and refines the winner by a parabola in f
// fraction bits (subpixel_code below: f + 1 restoring division steps, no recurrence); the
// delayed left results carry the fraction, the LR check compares integer disparities.
// C++14 synthesisable subset.
#pragma once

#include "parallax/kernels/caps.hpp"
#include "parallax/kernels/common.hpp"
#include "parallax/kernels/pipeline.hpp"
#include "parallax/kernels/resources.hpp"
#include "parallax/kernels/shift_reg.hpp"

namespace parallax {
namespace kern {

// Sub-pixel refinement of the winner d (docs/algorithm.md §4): with a = S(d-1) - S(d) and
// b = S(d+1) - S(d) (both >= 0), the parabola's vertex lies (a - b) / (2 (a + b)) from d; the
// code is d * 2^f plus that offset in f fraction bits, rounded half up in magnitude:
// t = floor(|a - b| * 2^f / (a + b)) (0 when a + b = 0), r = (t + 1) >> 1 <= 2^(f-1), sign of
// a - b. At d = 0, d = D - 1 or f = 0 the code is d * 2^f. The division is restoring, one
// quotient bit per step (f + 1 steps; |a - b| <= a + b, so t <= 2^f).
inline int subpixel_offset(int d, int num_disp, int f, uint64_t s_left, uint64_t s_best, uint64_t s_right) {
  if (f <= 0 || d <= 0 || d + 1 >= num_disp) return 0;
  const uint64_t a = s_left - s_best;
  const uint64_t b = s_right - s_best;
  const uint64_t den = a + b;
  if (den == 0) return 0;
  const uint64_t num = a > b ? a - b : b - a;
  uint64_t rem = num;
  uint32_t t = 0;
subpixel_divide:
  for (int k = 0; k <= kMaxSubpixelBits; ++k) {
    if (k <= f) {
      const bool bit = rem >= den;
      rem = bit ? rem - den : rem;
      t = (t << 1) | (bit ? 1u : 0u);
      rem <<= 1;
    }
  }
  const int r = int((t + 1) >> 1);
  return a > b ? r : -r;
}
// The code of winner d: d * 2^f plus its offset.
inline uint32_t subpixel_code(int d, int num_disp, int f, uint64_t s_left, uint64_t s_best, uint64_t s_right) {
  return uint32_t(int(uint32_t(d) << f) + subpixel_offset(d, num_disp, f, s_left, s_best, s_right));
}

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
  // "No cost yet" of the uniqueness minima: above every aggregate (aggregate_bits <= 32).
  static constexpr uint64_t kNoneCost = uint64_t(1) << 32;

  // As the pipeline description configures the stage (pipeline.hpp: stage_setup("wta_lr", mask)).
  void configure(const StereoParams& p, const StageSetup& s) { configure(p, s.reverse); }
  StageSetup setup() const { return StageSetup{0u, false, false, reverse_}; }
  void configure(const StereoParams& p, bool reverse) {
    left_d_.name("left_disparities");
    left_frac_.name("left_fractions");
    right_cost_.name("right_candidate_costs");
    right_d_.name("right_candidate_disparities");
    finished_d_.name("right_disparities");
    p_ = p;
    reverse_ = reverse;
    d_ = Caps::disparities(p.disparities);
    lanes_ = Caps::parallel_units(p.parallel_units);
    m_ = Caps::min_disparity(p.min_disparity);
    f_ = p.subpixel_bits;
    chunks_ = d_ / lanes_;
    delay_ = p.lr_check ? d_ - 1 : 0;
    start_frame();
  }
  void start_frame() {
    x_ = 0;
    y_ = 0;
    chunk_ = 0;
    rot_ = 0;
    next_emit_ = 0;
    in_row_done_ = false;
    done_ = false;
  }
  bool done() const { return done_; }

  WtaPlan plan() const {
    PX_PRAGMA("HLS INLINE")
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
    PX_PRAGMA("HLS INLINE")
    if (pl.read) {
      consume(in.read());
    } else {  // a flushing firing: one more column passes with no candidates
      ++time_;
      shift_column();
      shift_left(0, 0);
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
  void resync() { rot_ = kRotatingRight ? chunk_ * lanes_ : 0; }

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
    if (p_.uniqueness_pct > 0) {  // the far minimum: masked min tree, then the merge into it
      s.recurrence("uniqueness_far_min", 1);
      s.chain(kOpCompare, ab + 1, 1);
      s.chain(kOpMux, ab + 1, 2);
      s.chain(kOpRegister, ab + 1, 1);
    }
    if (p_.lr_check) {
      // An open candidate updated at chunk c of pixel x is next updated, one entry further
      // after the pixel's shift, at chunk c (c - 1 for lane 0 in reverse) of pixel x + 1: C - 1
      // firings later at the least (1 when PU = D). The chain: the shift's select, the read of
      // the entry (the count adds its mux when lanes reach entries at run time), the compare,
      // the select and the write (the count adds its decoder).
      s.recurrence("right_candidates", max_int(1, chunks_ - 1));
      s.via("right_candidate_costs");
      s.chain(kOpMux, ab, 1);
      s.chain(kOpCompare, ab, 1);
      s.chain(kOpMux, ab, 1);
      s.chain(kOpRegister, ab, 1);
    }
  }

  template <class R>
  void declare(R& r) const {
    const int ab = aggregate_bits(p_);
    const int db = disparity_int_bits(p_);
    const int d = p_.disparities;
    const int pu = p_.parallel_units;
    declare_raster_control(r, p_.width_px, p_.height_px, d / pu);
    if (p_.subpixel_bits > 0) {
      // The neighbours' selects over the lanes (before the best, after it, the last lane) and
      // their registers' selects; a = S(d-1) - S(d), b = S(d+1) - S(d), a + b, |a - b|; the
      // restoring division (f + 1 compare-subtract steps); the rounding and the signed offset.
      const int f = p_.subpixel_bits;
      if (pu > 1) r.op("subpixel_neighbour_select", kOpMux, ab, 3 * (pu - 1));
      r.op("subpixel_neighbour_update", kOpMux, ab, 3);
      r.op("subpixel_differences", kOpAdd, ab + 1, 4);
      r.op("subpixel_magnitude", kOpMux, ab + 1, 1);
      r.op("subpixel_divide_steps", kOpAdd, ab + 2, f + 1);
      r.op("subpixel_divide_select", kOpMux, ab + 2, f + 1);
      r.op("subpixel_round", kOpAdd, f + 1, 1);
      r.op("subpixel_offset", kOpAdd, disparity_bits(p_), 1);
      r.op("subpixel_edges", kOpCompare, db, 2);
    }
    if (pu > 1) {
      r.op("wta_min_tree", kOpCompare, ab, pu - 1);
      r.op("wta_min_select", kOpMux, ab, pu - 1);
    }
    r.op("wta_first_lane", kOpCompare, ab, pu);
    r.op("wta_best", kOpCompare, ab, 1);
    declare_storage(r, *this);
    r.op("emit_counter", kOpAdd, bits_for(uint64_t(p_.width_px)), 1);
    if (p_.uniqueness_pct > 0) {
      // Per lane: its position against the chunk's first minimum (two index compares) and four
      // masked copies; four min trees (below the best - 1, above the best + 1, all but the last
      // lane, all but lane 0), the merges into the three minima, and the final test
      // 100 * far < (100 + u) * best: a constant product, a product by the register, a compare.
      const int ib = bits_for(uint64_t(pu));
      r.op("uniqueness_lane_position", kOpCompare, ib, 2 * pu);
      r.op("uniqueness_lane_mask", kOpMux, ab + 1, 4 * pu);
      if (pu > 1) {
        r.op("uniqueness_min_trees", kOpCompare, ab + 1, 4 * (pu - 1));
        r.op("uniqueness_min_select", kOpMux, ab + 1, 4 * (pu - 1));
      }
      r.op("uniqueness_merge", kOpCompare, ab + 1, 3);
      r.op("uniqueness_merge_select", kOpMux, ab + 1, 5);
      r.op("uniqueness_far", kOpCompare, ab + 1, 1);
      r.op("uniqueness_times_100", kOpAdd, ab + 8, 2);
      r.mul("uniqueness_margin", ab, kUniquenessBits + 1, 1);
      r.op("uniqueness_test", kOpCompare, ab + 9, 1);
    }
    if (p_.lr_check) {
      // The lanes update registers 0 .. PU - 1 (rotating, right_entry): no read select; each
      // register takes its update, its rotated neighbour or holds (a 2:1 mux after the update's).
      if (d > pu) r.op("right_candidate_rotate", kOpMux, ab + 1 + db, d);
      r.op("right_compare", kOpCompare, ab, pu);
      r.op("right_select", kOpMux, ab + db, pu);
      r.mux("right_disparity_read", db, d, 1);  // emit(): the entry the left disparity points to
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
    if (p_.uniqueness_pct > 0) track_uniqueness(t, lo, n, chunk_min, first);
    if (f_ > 0) track_neighbours(t, n, chunk_min, first);
    if (chunk_min < best_cost_) {  // strict: an earlier chunk (smaller d) wins ties
      best_cost_ = chunk_min;
      best_d_ = lo + first;
    }
    if (p_.lr_check) right_candidates(t, lo);
    if (chunk_ + 1 == chunks_) {
      // The fraction travels beside the integer winner, biased by 2^(f-1) into [0, 2^f].
      const int offset = f_ > 0 ? subpixel_offset(best_d_, d_, f_, sp_left_, best_cost_, sp_right_) : 0;
      shift_left(unique() ? DispCode(best_d_) : DispCode(d_), DispCode(offset + ((1 << f_) >> 1)));
    }
  }

  // Sub-pixel neighbours of the running best (called before the best is updated, chunks in
  // ascending d): when this chunk takes the best at lane `first`, S at first - 1 (the previous
  // chunk's last lane when first = 0) and at first + 1 (pending when first is the last lane: the
  // next chunk's lane 0 fills it). Two PU-input selects and three registers.
  void track_neighbours(const SumToken& t, int n, uint32_t chunk_min, int first) {
    uint32_t before = kNoCost, after = kNoCost, last_lane = kNoCost;
  wta_subpixel_lanes:
    for (int i = 0; i < Caps::trip(n, kLanes); ++i) {
      PX_PRAGMA("HLS UNROLL")
      const uint32_t c = uint32_t(t.v[i]);
      before = i + 1 == first ? c : before;
      after = i < n && i == first + 1 ? c : after;
      last_lane = i + 1 == n ? c : last_lane;
    }
    if (chunk_min < best_cost_) {
      sp_left_ = first == 0 ? sp_prev_last_ : before;
      sp_right_ = after;
      sp_pending_ = first + 1 >= n;
    } else if (sp_pending_) {
      sp_right_ = uint32_t(t.v[0]);
      sp_pending_ = false;
    }
    sp_prev_last_ = last_lane;
  }

  // Uniqueness state of the pixel, the lanes of a chunk holding d = lo .. lo + n - 1 in
  // ascending order and chunks arriving in ascending d; called before the best is updated, so
  // best_cost_ is the minimum of every cost before this chunk (kNoCost at its first). Keeps
  // below_last_ = the minimum of all costs so far but the last one, left_min_ = the minimum over
  // d <= best - 2 and right_min_ = the minimum over d >= best + 2 (kNoneCost when empty).
  void track_uniqueness(const SumToken& t, int lo, int n, uint32_t chunk_min, int first) {
    if (chunk_ == 0) below_last_ = left_min_ = right_min_ = kNoneCost;
    const uint64_t before = chunk_ == 0 ? kNoneCost : uint64_t(best_cost_);
    // Masked minima over the lanes: below the chunk minimum's left neighbour, above its right
    // neighbour, all lanes but the last, all lanes but lane 0.
    uint64_t below = kNoneCost, above = kNoneCost, head = kNoneCost, tail = kNoneCost;
  wta_unique_lanes:
    for (int i = 0; i < Caps::trip(n, kLanes); ++i) {
      PX_PRAGMA("HLS UNROLL")
      const uint64_t c = i < n ? uint64_t(uint32_t(t.v[i])) : kNoneCost;
      below = i + 2 <= first && c < below ? c : below;
      above = i >= first + 2 && c < above ? c : above;
      head = i + 1 < n && c < head ? c : head;
      tail = i >= 1 && c < tail ? c : tail;
    }
    if (chunk_min < best_cost_) {  // the best moves to d = lo + first
      left_min_ = first == 0 ? below_last_ : (before < below ? before : below);
      right_min_ = above;
    } else {  // the best stays at best_d_ < lo: lanes from best + 2 join the far side
      const uint64_t far = best_d_ + 1 == lo ? tail : uint64_t(chunk_min);
      right_min_ = far < right_min_ ? far : right_min_;
    }
    below_last_ = before < head ? before : head;
  }

  // The pixel's best passes the uniqueness test: no cost at least two disparities away from it
  // is below (100 + u) / 100 times the best (always true with u = 0).
  bool unique() const {
    if (p_.uniqueness_pct <= 0) return true;
    const uint64_t far = left_min_ < right_min_ ? left_min_ : right_min_;
    if (far == kNoneCost) return true;
    return far * 100u >= uint64_t(best_cost_) * uint64_t(100 + p_.uniqueness_pct);
  }

  // The left results' delay line moves one column: entry k holds the result k columns back.
  void shift_left(DispCode newest, DispCode fraction) {
    left_d_.shift_in(newest, delay_ + 1);
    if (f_ > 0) left_frac_.shift_in(fraction, delay_ + 1);
  }

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

  // Lane d of this token is a candidate for the right pixel x_img - m - d (when it exists), held
  // in open entry d. Candidates of one right pixel arrive in ascending d (forward) or descending d
  // (reverse), so the smallest d wins ties with < or <= respectively. (The offset m moves every
  // right pixel by the same columns, so the entries' ages are those of m = 0.)
  void right_candidates(const SumToken& t, int lo) {
    const int x_img = reverse_ ? p_.width_px - 1 - x_ : x_;
    const bool rev = reverse_;
    const int n = min_int(lanes_, x_img - m_ - lo + 1);  // lanes with a right pixel x_img - m - d >= 0
  wta_right_lanes:
    for (int i = 0; i < Caps::trip(n, kLanes); ++i) {
      PX_PRAGMA("HLS UNROLL")
      const int d = lo + i;
      const int e = kRotatingRight ? i : d;  // the register of open entry d (see right_entry)
      const uint32_t s = t.v[i];
      const uint32_t c = from_store<uint32_t>(right_cost_.at(e));
      const bool better = i < n && (s < c || (rev && s == c));
      right_cost_.set(e, better ? s : c);
      right_d_.set(e, better ? DispCode(d) : from_store<DispCode>(right_d_.at(e)));
    }
    if (kRotatingRight) {  // the next chunk's entries to registers 0 .. PU - 1
      right_cost_.rotate(lanes_, d_);
      right_d_.rotate(lanes_, d_);
      rot_ += lanes_;
      if (rot_ >= d_) rot_ -= d_;
    }
  }

  // Open right entries (N2, issue 41). Software instantiations keep open entry e in register e.
  // The exported and counting ones rotate the registers by PU after each chunk, so chunk c's
  // lanes always update registers 0 .. PU - 1 (fixed wiring, no run-time mux): open entry e is
  // in register (e - rot_) mod D, rot_ = c PU between chunks, 0 at a pixel's start, where the
  // column shift runs.
  static constexpr bool kRotatingRight = Caps::fixed || Caps::count_accesses;
  int right_entry(int e) const {
    if (!kRotatingRight) return e;
    const int r = e - rot_;
    return r < 0 ? r + d_ : r;
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
    const int d = from_store<int>(left_d_.at(lag));
    const int x_img = reverse_ ? p_.width_px - 1 - xs : xs;
    const DispCode invalid = DispCode(d_ << f_);
    // The code with the fraction (biased by 2^(f-1) in left_frac_).
    const DispCode code = f_ > 0 ? DispCode((d << f_) + int(left_frac_.at(lag)) - ((1 << f_) >> 1)) : DispCode(d);
    if (d >= d_ || m_ + d > x_img) return invalid;  // not unique, or the match is outside the image
    if (p_.lr_check) {
      int dr;
      if (!reverse_) {
        const int age = lag + d;
        dr = from_store<int>(age < d_ ? right_d_.at(right_entry(age)) : finished_d_.at(age - d_));
      } else {
        const int ahead = d - lag;
        dr = from_store<int>(ahead >= 0 ? right_d_.at(right_entry(ahead)) : finished_d_.at(-ahead - 1));
      }
      const int diff = d > dr ? d - dr : dr - d;
      if (diff > p_.lr_tolerance) return invalid;
    }
    return code;
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
  int d_ = 1, lanes_ = 1, chunks_ = 1, delay_ = 0, m_ = 0, f_ = 0;
  int rot_ = 0;  // open right entries: the rotation of their registers (right_entry)
  int x_ = 0, y_ = 0, chunk_ = 0, next_emit_ = 0;
  int time_ = 0;  // stream column of the last column shift (flushing firings count on past W - 1)
  bool in_row_done_ = false, done_ = true;
  uint32_t best_cost_ = 0;
  int best_d_ = 0;
  uint64_t below_last_ = 0, left_min_ = 0, right_min_ = 0;  // uniqueness minima (track_uniqueness)
  uint32_t sp_left_ = 0, sp_right_ = 0, sp_prev_last_ = 0;  // sub-pixel neighbours (track_neighbours)
  bool sp_pending_ = false;
  // Shift registers (common.hpp): the left WTA results of the last D columns (entry k: k columns
  // back), the open right candidates' running minimum and its disparity, the finished right
  // disparities (D - 1 used).
  // Integer disparities and open right costs, stored at disparity_int_bits and aggregate_bits + 1 in the export
  // (store.hpp; a right cost's all-ones value is the mark of none, above every cost).
  typedef typename Caps::store::disparity DispStore;
  typedef typename Caps::store::sum_or_none CostOrNone;
  ShiftReg<DispStore, kMaxD, Caps::fixed, Caps::count_accesses> left_d_;
  ShiftReg<DispCode, kMaxD, Caps::fixed, Caps::count_accesses>
      left_frac_;  // sub-pixel: each left result's biased offset
  ShiftReg<CostOrNone, kMaxD, Caps::fixed, Caps::count_accesses> right_cost_;
  ShiftReg<DispStore, kMaxD, Caps::fixed, Caps::count_accesses> right_d_;
  ShiftReg<DispStore, kMaxD, Caps::fixed, Caps::count_accesses> finished_d_;

 public:
  // Storage descriptor (resources.hpp) of the members above: the best cost and disparity of the
  // pixel; the left results' delay line (delay_ + 1 entries: D with the LR check, 1 without);
  // with the LR check the D open right candidates (cost and disparity) and the D - 1 finished
  // right disparities (the shift lengths shift_left() and shift_column() use).
  template <class V>
  void storage(V& v) const {
    const int ab = aggregate_bits(p_);
    const int db = disparity_int_bits(p_);
    v.registers("wta_best_cost", best_cost_, 1, ab);
    v.registers("wta_best_disparity", best_d_, 1, db);
    if (p_.uniqueness_pct > 0) {
      v.registers("uniqueness_below_last", below_last_, 1, ab + 1);
      v.registers("uniqueness_left_min", left_min_, 1, ab + 1);
      v.registers("uniqueness_right_min", right_min_, 1, ab + 1);
    } else {
      v.unused("uniqueness_below_last", below_last_);
      v.unused("uniqueness_left_min", left_min_);
      v.unused("uniqueness_right_min", right_min_);
    }
    if (p_.subpixel_bits > 0) {
      v.registers("subpixel_before_best", sp_left_, 1, ab);
      v.registers("subpixel_after_best", sp_right_, 1, ab);
      v.registers("subpixel_previous_last_lane", sp_prev_last_, 1, ab);
      v.registers("subpixel_pending", sp_pending_, 1, 1);
    } else {
      v.unused("subpixel_before_best", sp_left_);
      v.unused("subpixel_after_best", sp_right_);
      v.unused("subpixel_previous_last_lane", sp_prev_last_);
      v.unused("subpixel_pending", sp_pending_);
    }
    left_d_.storage(v, "left_disparities", delay_ + 1, db);
    left_frac_.storage(v, "left_fractions", f_ > 0 ? delay_ + 1 : 0, f_ + 1);
    const int lr = p_.lr_check ? 1 : 0;                                // without the check: never written (no hardware)
    right_cost_.storage(v, "right_candidate_costs", lr * d_, ab + 1);  // + the mark of none
    right_d_.storage(v, "right_candidate_disparities", lr * d_, db);
    finished_d_.storage(v, "right_disparities", lr * (d_ - 1), db);
  }
};

}  // namespace kern
}  // namespace parallax
