// SGM aggregation over up to four streaming path kinds in one raster pass (docs/algorithm.md §3).
// For every pixel it consumes D/PU cost tokens and emits D/PU aggregate tokens
// S(p, d) = sum over the active paths of Lr(p, d) [+ F(p, d) from a previous pass].
// C++14 synthesisable subset.
//
// Path kinds are relative to the stream order, so the same kernel serves the forward pass
// (kinds = paths 0/45/90/135) and, on a reversed stream, the backward pass of the eight-path
// variant (kinds = paths 180/225/270/315). Adding a path kind means adding an enumerator, its
// predecessor rule in predecessor(), and its memory (see docs/kernels.md).
#pragma once

#include "parallax/kernels/caps.hpp"
#include "parallax/kernels/common.hpp"
#include "parallax/kernels/resources.hpp"

namespace parallax {
namespace kern {

enum StreamPathKind : int {
  kKindPixel = 0,     // predecessor (x-1, y): previous pixel of the stream
  kKindRowLeft = 1,   // predecessor (x-1, y-1): previous row, one column back
  kKindRowUp = 2,     // predecessor (x, y-1): previous row, same column
  kKindRowRight = 3,  // predecessor (x+1, y-1): previous row, one column ahead
  kKindCount = 4
};

// The stream kinds of one pass for an image-direction path mask. forward: 0/45/90/135 map to
// pixel/row-left/row-up/row-right; backward (reversed stream): 180/225/270/315 likewise.
inline unsigned stream_kinds(unsigned path_mask, bool backward) {
  const unsigned m = backward ? (path_mask >> 4) : path_mask;
  return m & 0xFu;
}

struct AggPlan {
  bool read_cost;     // one cost token
  bool read_forward;  // one token of the forward sum F (second pass of the 8-path variant)
  bool write_sum;     // one aggregate token
  bool write_tee;     // the cost token again, for the frame buffer (first pass of 8 paths)
};

template <class Caps, class Word>
class SgmAggregate {
 public:
  typedef Lanes<uint16_t, Caps::lanes> CostToken;
  typedef Lanes<Word, Caps::lanes> SumToken;
  static constexpr int kMaxW = Caps::max_width_px;
  static constexpr int kMaxD = Caps::max_disparities;
  // Larger than any path cost (<= 2^path_bits - 1) and safe to add P1 to in 32 bits.
  static constexpr uint32_t kNone = sizeof(Word) == 2 ? 0xFFFFu : 0x7FFFFFFFu;

  // kinds: StreamPathKind bits; add_forward: add F from a second input; tee_cost: copy the
  // costs to a second output.
  void configure(const StereoParams& p, unsigned kinds, bool add_forward, bool tee_cost) {
#ifdef PX_HLS_SGM_ROW_PARTITION
    PX_PRAGMA(PX_HLS_SGM_ROW_PARTITION)
#endif
#ifdef PX_HLS_SGM_ROW_STORAGE
    PX_PRAGMA(PX_HLS_SGM_ROW_STORAGE)
#endif
#ifdef PX_HLS_SGM_HOLD_PARTITION
    PX_PRAGMA(PX_HLS_SGM_HOLD_PARTITION)
#endif
    p_ = p;
    add_forward_ = add_forward;
    tee_cost_ = tee_cost;
    n_slots_ = 0;
  agg_config_kinds:
    int row_memories = 0;
    for (int k = 0; k < kKindCount; ++k)
      if (kinds & (1u << k)) {
        row_slot_[n_slots_] = k == kKindPixel ? 0 : row_memories++;  // contract: <= Caps::row_kinds
        kind_[n_slots_++] = k;
      }
    lanes_ = p.parallel_units;
    chunks_ = p.disparities / p.parallel_units;
  agg_config_pad:
    for (int s = 0; s < kKindCount; ++s)
      for (int b = 0; b < 2; ++b) {
        hold_[s][b][0] = Word(kNone);
        hold_[s][b][p.disparities + 1] = Word(kNone);
      }
    start_frame();
  }
  void start_frame() {
    x_ = 0;
    y_ = 0;
    chunk_ = 0;
    parity_ = 0;
    done_ = false;
  }
  bool done() const { return done_; }
  int slots() const { return n_slots_; }

  AggPlan plan() const {
    AggPlan pl;
    pl.read_cost = !done_;
    pl.read_forward = !done_ && add_forward_;
    pl.write_sum = !done_;
    pl.write_tee = !done_ && tee_cost_;
    return pl;
  }

  template <class CostIn, class FwdIn, class SumOut, class TeeOut>
  void fire(const AggPlan& pl, CostIn& cost_in, FwdIn& fwd_in, SumOut& sum_out, TeeOut& tee_out) {
    (void)pl;
    const CostToken c = cost_in.read();
    SumToken s;
    if (add_forward_) {
      const SumToken f = fwd_in.read();
    agg_add_forward:
      for (int i = 0; i < lanes_; ++i) s.v[i] = f.v[i];
    } else {
    agg_clear:
      for (int i = 0; i < lanes_; ++i) s.v[i] = 0;
    }
    const int n = lanes_;  // a local bound: stores through dest must not hide the trip count
    const int lo = chunk_ * n;
    const uint32_t p1 = uint32_t(p_.p1);
    const uint32_t p2 = uint32_t(p_.p2);
  agg_paths:
    for (int slot = 0; slot < n_slots_; ++slot) {
      Word pred_local[Caps::lanes + 2];
      const Word* pred = 0;  // pred[i] is Lr(q, lo - 1 + i)
      uint32_t m_prev = 0;
      Word* dest = 0;
      const bool valid = predecessor(slot, lo, pred_local, &pred, &m_prev, &dest);
      if (chunk_ == 0) min_[slot] = kNone;
      uint32_t run_min = min_[slot];
      if (valid) {
        run_min = update_lanes(pred, c.v, dest, s.v, n, p1, p2, m_prev, run_min);
      } else {
      agg_lanes_start:
        for (int i = 0; i < n; ++i) {
          PX_PRAGMA("HLS UNROLL")
          const uint32_t lr = c.v[i];
          dest[i] = Word(lr);
          s.v[i] = Word(s.v[i] + lr);
          run_min = lr < run_min ? lr : run_min;
        }
      }
      min_[slot] = run_min;
      if (chunk_ + 1 == chunks_) finish_pixel(slot);
    }
    sum_out.write(s);
    if (tee_cost_) tee_out.write(c);
    advance();
  }

  // The control path of fire(pl) alone (see CostStage::step): the chunk, column and row
  // counters advance; no path cost is read or written.
  void step(const AggPlan& pl) {
    (void)pl;
    advance();
  }

  // Control-state access for a scheduler that advances periodic rows at once (sim/, never
  // synthesised): visit(v) calls v(field) on every counter of the control path, by reference;
  // resync() recomputes the fields derived from them after a visitor wrote them.
  template <class V>
  void visit(V& v) {
    v(x_);
    v(y_);
    v(chunk_);
    v(done_);
  }
  void resync() { parity_ = (y_ * p_.width_px + x_) & 1; }  // parity toggles once per pixel

  // Resources of this configuration (resources.hpp). Row paths keep the previous row's Lr in
  // memories: `packing` disparities per word, the words of a column spread over `banks`
  // memories (0: one memory per word, complete partitioning); the pixel path keeps the previous
  // pixel's Lr in registers (hold_). Per lane and path: two +P1 adds, the min of four, + C - M,
  // and the running minimum; per lane the sum over paths.
  template <class R>
  void declare(R& r, int packing, int banks) const {
    const int pb = path_bits(p_);
    const int ab = aggregate_bits(p_);
    const int d = p_.disparities;
    const int pu = lanes_;
    declare_raster_control(r, p_.width_px, p_.height_px, chunks_);
    const int q = packing < 1 ? 1 : (packing > d ? d : packing);
    const int words = (d + q - 1) / q;
    const int memories = banks <= 0 || banks > words ? words : banks;
    const int words_per_memory = (words + memories - 1) / memories;
  agg_declare_paths:
    for (int s = 0; s < n_slots_; ++s) {
      const int k = kind_[s];
      if (k == kKindPixel) {
        r.registers("pixel_path_previous", pb, 2 * d);
        r.registers("pixel_path_min", pb, 2);
      } else {
        const char* row = k == kKindRowLeft ? "row_path_left" : k == kKindRowUp ? "row_path_up" : "row_path_right";
        const char* mins = k == kKindRowLeft ? "row_min_left" : k == kKindRowUp ? "row_min_up" : "row_min_right";
        r.memory(row, int64_t(p_.width_px) * words_per_memory, q * pb, memories, false);
        r.memory(mins, p_.width_px, pb, 1, false);
      }
      r.op("path_p1_adds", kOpAdd, pb + 1, 2 * pu);
      r.op("path_p2_add", kOpAdd, pb + 1, 1);
      r.op("path_min_of_four", kOpCompare, pb + 1, 3 * pu);
      r.op("path_min_select", kOpMux, pb + 1, 3 * pu);
      r.op("path_cost_minus_min", kOpAdd, pb + 1, 2 * pu);
      r.op("path_running_min", kOpCompare, pb, pu);
      r.op("path_running_min_select", kOpMux, pb, pu);
      r.registers("path_min", pb, 1);
    }
    r.op("sum_over_paths", kOpAdd, ab, pu * n_slots_);
    r.registers("cost_in", pu * cost_bits(p_), 1);
    r.registers("sum_token", pu * ab, 1);
  }

 private:
  // Fetches the predecessor lanes [lo - 1, lo + PU] of slot's path, its minimum M and where the
  // new Lr lanes go. Returns false at the start of the path (predecessor outside the image).
  // Memory contract: row_[s][x] holds the previous row's Lr until this pixel overwrites it;
  // hold_[s][parity] receives the old row values of this pixel (read before the write).
  PX_INLINE bool predecessor(int slot, int lo, Word* local, const Word** pred, uint32_t* m_prev, Word** dest) {
    const int d_count = p_.disparities;
    const int kind = kind_[slot];
    const int par = parity_;
    Word* row_here = &row_[row_slot_[slot]][x_ * d_count];  // rows packed at the runtime D
    if (kind == kKindPixel) {
      *pred = &hold_[slot][par ^ 1][lo];
      *m_prev = hold_min_[slot][par ^ 1];
      *dest = &hold_[slot][par][1 + lo];
      return x_ > 0;
    }
    *dest = row_here + lo;
    if (kind == kKindRowUp || kind == kKindRowLeft) {
      // Read the old (previous-row) lanes of this column before they are overwritten; row-up
      // also needs lane lo + PU, which the next chunk has not written yet.
      const int hi = kind == kKindRowUp ? min_int(lo + lanes_, d_count - 1) : lo + lanes_ - 1;
      copy_lanes(&hold_[slot][par][1 + lo], row_here + lo, hi - lo + 1);
      if (chunk_ == 0) hold_min_[slot][par] = row_min_[row_slot_[slot]][x_];
      if (kind == kKindRowUp) {
        *pred = &hold_[slot][par][lo];
        *m_prev = hold_min_[slot][par];
        return y_ > 0;
      }
      *pred = &hold_[slot][par ^ 1][lo];
      *m_prev = hold_min_[slot][par ^ 1];
      return y_ > 0 && x_ > 0;
    }
    // Row-right: column x + 1 still holds the previous row.
    const bool valid = y_ > 0 && x_ + 1 < p_.width_px;
    if (!valid) return false;
    const Word* row_next = &row_[row_slot_[slot]][(x_ + 1) * d_count];
    const int hi = lo + lanes_ - 1;
    local[0] = lo == 0 ? Word(kNone) : row_next[lo - 1];
    copy_lanes(local + 1, row_next + lo, lanes_);
    local[lanes_ + 1] = hi + 1 >= d_count ? Word(kNone) : row_next[hi + 1];
    *pred = local;
    *m_prev = row_min_[row_slot_[slot]][x_ + 1];
    return true;
  }

  // GCC 12 cannot see that a token read from a FIFO is initialised in every lane it uses when
  // the token type is narrow (8 lanes) and n is a runtime value; the lanes read are < n <= LANES.
#if defined(__GNUC__) && !defined(__clang__) && !defined(__SYNTHESIS__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
  // Lr(p, d) = C(p, d) + min(Lr(q, d), Lr(q, d±1) + P1, M + P2) - M for n lanes, added into
  // sum; returns the running minimum. pred[i] is Lr(q, lo - 1 + i), with kNone outside [0, D).
  // In Word arithmetic: sums that could exceed Word saturate, which cannot change a minimum
  // because Lr(q, d) <= 2^path_bits - 1 is always a candidate and fits.
  static uint32_t update_lanes(const Word* pred, const uint16_t* cost, Word* dest, Word* sum, int n,
                               uint32_t p1, uint32_t p2, uint32_t m_prev, uint32_t run_min) {
    const Word wp1 = Word(p1);
    const Word wm = Word(m_prev);
    const Word wm_p2 = sat_add(wm, Word(p2 > kNone ? kNone : p2));
    Word lane_min = Word(kNone);
  agg_lanes:
    for (int i = 0; i < n; ++i) {
      PX_PRAGMA("HLS UNROLL")
      const Word a = pred[i + 1];
      const Word b = sat_add(pred[i], wp1);
      const Word e = sat_add(pred[i + 2], wp1);
      Word m = a < b ? a : b;
      m = m < e ? m : e;
      m = m < wm_p2 ? m : wm_p2;
      const Word lr = Word(Word(cost[i]) + Word(m - wm));
      dest[i] = lr;
      sum[i] = Word(sum[i] + lr);
      lane_min = lr < lane_min ? lr : lane_min;
    }
    return uint32_t(lane_min) < run_min ? uint32_t(lane_min) : run_min;
  }

#if defined(__GNUC__) && !defined(__clang__) && !defined(__SYNTHESIS__)
#pragma GCC diagnostic pop
#endif

  // a + b, saturating at kNone (the largest value Lr arithmetic needs).
  static Word sat_add(Word a, Word b) {
    const Word r = Word(a + b);
    return (r < a || r > Word(kNone)) ? Word(kNone) : r;
  }

  void finish_pixel(int slot) {
    if (kind_[slot] == kKindPixel)
      hold_min_[slot][parity_] = Word(min_[slot]);
    else
      row_min_[row_slot_[slot]][x_] = Word(min_[slot]);
  }

  void advance() {
    if (++chunk_ < chunks_) return;
    chunk_ = 0;
    parity_ ^= 1;
    if (++x_ < p_.width_px) return;
    x_ = 0;
    if (++y_ < p_.height_px) return;
    done_ = true;
  }

  StereoParams p_;
  bool add_forward_ = false, tee_cost_ = false;
  int kind_[kKindCount];
  int row_slot_[kKindCount];  // slot -> row memory (row kinds only; the pixel kind keeps registers)
  int n_slots_ = 0;
  int lanes_ = 1, chunks_ = 1;
  int x_ = 0, y_ = 0, chunk_ = 0, parity_ = 0;
  bool done_ = true;
  uint32_t min_[kKindCount];                  // running min of this pixel's Lr, per slot
  Word hold_[kKindCount][2][kMaxD + 2];       // ping-pong per pixel parity, sentinel-padded
  Word hold_min_[kKindCount][2];
  Word row_[Caps::row_kinds][kMaxW * kMaxD];  // previous-row Lr per column, one memory per row kind
  Word row_min_[Caps::row_kinds][kMaxW];      // previous-row min_k Lr per column
};

}  // namespace kern
}  // namespace parallax
