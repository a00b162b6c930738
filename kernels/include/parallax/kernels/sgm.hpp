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

// The capacities of an aggregation stage with the pixel kind alone (the 180-degree path on
// reversed rows, row_reverse.hpp): no row memory, so one column of capacity.
template <class C>
using PixelPathCaps = Caps<1, C::max_disparities, C::lanes, C::window_rows, C::median_rows, 1u << kKindPixel, C::fixed,
                           C::max_min_disparity>;

struct AggPlan {
  bool read_cost;     // one cost token
  bool read_forward;  // one token of the forward sum F (second pass of the 8-path variant)
  bool write_sum;     // one aggregate token
  bool write_tee;     // the cost token again, for the frame buffer (first pass of 8 paths)
};

template <class Caps, class Word>
class SgmAggregate {
 public:
  typedef CostLanes<Caps::lanes> CostToken;
  typedef Lanes<Word, Caps::lanes> SumToken;
  static constexpr int kMaxW = Caps::max_width_px;
  static constexpr int kMaxD = Caps::max_disparities;
  static constexpr int kLanes = Caps::lanes;
  static constexpr int kRowMemories = 3;  // one per row kind (kKindRowLeft .. kKindRowRight)
  // Whether this instantiation has row kinds (else no row memory of any kind, intensities too).
  static constexpr bool kRowKinds = (Caps::kind_mask & ~(1u << kKindPixel)) != 0;
  // Whether rows may be as narrow as two pixels (then a row kind's next predecessor column can
  // be the one being written; see aggregate_kind): software, or a fixed width of 1 or 2.
  static constexpr bool kNarrowRows = !Caps::fixed || Caps::max_width_px <= 2;
  // Larger than any path cost (<= 2^path_bits - 1) and safe to add P1 to in 32 bits.
  static constexpr uint32_t kNone = sizeof(Word) == 2 ? 0xFFFFu : 0x7FFFFFFFu;

  // Registers: everything but the row memories. Row memories: one per row kind, each split into
  // banks as the export's mapping says (by default PU lane banks: lane i of every chunk in bank
  // i); one read and one write per bank and firing (simple dual port). A row is read again only
  // W firings after it was written, so no dependence between iterations on them.
  SgmAggregate() {
    PX_PRAGMA("HLS ARRAY_PARTITION variable=ahead_ type=complete dim=0")
    PX_PRAGMA("HLS ARRAY_PARTITION variable=mq_ type=complete dim=1")
    PX_PRAGMA("HLS ARRAY_PARTITION variable=run_min_ type=complete dim=1")
    PX_PRAGMA("HLS ARRAY_PARTITION variable=pix_ type=complete dim=1")
    PX_PRAGMA("HLS ARRAY_PARTITION variable=lag_ type=complete dim=1")
    PX_PRAGMA("HLS ARRAY_PARTITION variable=row_ type=complete dim=1")
    PX_PRAGMA("HLS ARRAY_PARTITION variable=row_min_ type=complete dim=1")
#ifdef PX_HLS_SGM_ROW_RESHAPE
    PX_PRAGMA(PX_HLS_SGM_ROW_RESHAPE)
#endif
#ifdef PX_HLS_SGM_ROW_PARTITION
    PX_PRAGMA(PX_HLS_SGM_ROW_PARTITION)
#else
    PX_PRAGMA("HLS ARRAY_PARTITION variable=row_ type=cyclic factor=kLanes dim=3")
#endif
#ifdef PX_HLS_SGM_ROW_STORAGE
    PX_PRAGMA(PX_HLS_SGM_ROW_STORAGE)
#endif
    PX_PRAGMA("HLS DEPENDENCE variable=row_ type=inter dependent=false")
    PX_PRAGMA("HLS DEPENDENCE variable=row_min_ type=inter dependent=false")
    PX_PRAGMA("HLS ARRAY_PARTITION variable=up_px_ type=complete dim=1")
    PX_PRAGMA("HLS ARRAY_PARTITION variable=head_px_ type=complete dim=1")
    PX_PRAGMA("HLS ARRAY_PARTITION variable=p2k_ type=complete dim=1")
    PX_PRAGMA("HLS BIND_STORAGE variable=row_px_ type=ram_s2p")
    PX_PRAGMA("HLS DEPENDENCE variable=row_px_ type=inter dependent=false")
    // Software instantiations read the don't-care lanes past PU (simd_trip): give them values
    // once. (Nothing to do in the export, where every lane is a design lane.)
    if (!Caps::fixed) {
    agg_clear_memories:
      for (int d = 0; d < kMaxD; ++d) pix_[d] = lag_[d] = 0;
      for (int x = 0; x < kMaxW; ++x) row_px_[x] = 0;
      for (int m = 0; m < kRowMemories; ++m)
        for (int x = 0; x < kMaxW; ++x) {
          row_min_[m][x] = 0;
          for (int d = 0; d < kMaxD; ++d) row_[m][x][d] = 0;
        }
    }
  }

  // kinds: StreamPathKind bits (within Caps::kind_mask); add_forward: add F from a second input;
  // tee_cost: copy the costs to a second output.
  void configure(const StereoParams& p, unsigned kinds, bool add_forward, bool tee_cost) {
    p_ = p;
    kinds_ = kinds & Caps::kind_mask;
    add_forward_ = add_forward;
    tee_cost_ = tee_cost;
    d_ = Caps::disparities(p.disparities);
    lanes_ = Caps::parallel_units(p.parallel_units);
    chunks_ = d_ / lanes_;
    if (!Caps::fixed) {
    agg_pad:
      for (int i = 0; i < kLanes; ++i) pad_[i] = i < lanes_ ? Word(0) : Word(~Word(0));
    }
    start_frame();
  }
  // A frame starts with the per-kind registers cleared (they are read, but not used, before the
  // first firing writes them: the first row and column have no predecessor).
  void start_frame() {
    x_ = 0;
    y_ = 0;
    chunk_ = 0;
    done_ = false;
    pix_min_ = 0;
    mlag_ = 0;
  agg_reset_kinds:
    for (int k = 0; k < kKindCount; ++k) {
      PX_PRAGMA("HLS UNROLL")
      mq_[k] = 0;
      run_min_[k] = kNone;
    agg_reset_lanes:
      for (int i = 0; i < kLanes + 2; ++i) {
        PX_PRAGMA("HLS UNROLL")
        ahead_[k][i] = Word(kNone);
      }
    }
  }
  bool done() const {
    return done_;
  }
  int slots() const {
    return popcount_u32(kinds_);
  }

  AggPlan plan() const {
    AggPlan pl;
    pl.read_cost = !done_;
    pl.read_forward = !done_ && add_forward_;
    pl.write_sum = !done_;
    pl.write_tee = !done_ && tee_cost_;
    return pl;
  }

  // One firing: the PU lanes [lo, lo + PU) of pixel (x, y) for every active path kind.
  // Per kind, the predecessor's lanes of this chunk arrived with the previous firing (ahead_),
  // its lane lo - 1 is held from the chunk before (ahead_[k][0]), and this firing fetches the
  // predecessor's lanes of the next firing's chunk, whose first is lane lo + PU. So every memory
  // sees one read and one write per lane bank and firing (docs/kernels.md).
  template <class CostIn, class FwdIn, class SumOut, class TeeOut>
  void fire(const AggPlan& pl, CostIn& cost_in, FwdIn& fwd_in, SumOut& sum_out, TeeOut& tee_out) {
    (void)pl;
    const CostToken c = cost_in.read();
    const int trip = lane_trip();  // the lanes every loop of this firing runs
    if (p_.p2_adaptive > 0 && chunk_ == 0) adapt_p2(c.px);
    SumToken s;
    if (add_forward_) {
      const SumToken f = fwd_in.read();
    agg_add_forward:
      for (int i = 0; i < trip; ++i) {
        PX_PRAGMA("HLS UNROLL")
        s.v[i] = f.v[i];
      }
    } else {
    agg_clear:
      for (int i = 0; i < trip; ++i) {
        PX_PRAGMA("HLS UNROLL")
        s.v[i] = 0;
      }
    }
    // One datapath per path kind (kinds outside Caps::kind_mask have none).
    if ((Caps::kind_mask & (1u << kKindPixel)) != 0 && (kinds_ & (1u << kKindPixel)) != 0)
      aggregate_kind<kKindPixel>(c, trip, s);
    if ((Caps::kind_mask & (1u << kKindRowLeft)) != 0 && (kinds_ & (1u << kKindRowLeft)) != 0)
      aggregate_kind<kKindRowLeft>(c, trip, s);
    if ((Caps::kind_mask & (1u << kKindRowUp)) != 0 && (kinds_ & (1u << kKindRowUp)) != 0)
      aggregate_kind<kKindRowUp>(c, trip, s);
    if ((Caps::kind_mask & (1u << kKindRowRight)) != 0 && (kinds_ & (1u << kKindRowRight)) != 0)
      aggregate_kind<kKindRowRight>(c, trip, s);
    sum_out.write(s);
    if (tee_cost_) tee_out.write(c);
    if (p_.p2_adaptive > 0 && chunk_ + 1 == chunks_) keep_intensity();
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
  void resync() {}

  // Resources of this configuration (resources.hpp). Row paths keep the previous row's Lr in
  // memories: `packing` disparities per word, the words of a column spread over `banks`
  // memories (0: one memory per word, complete partitioning), and the previous row's minimum
  // per column; the pixel path keeps the previous pixel's Lr and minimum in registers; the
  // row-left path delays the previous row's column by one pixel in registers. Every path holds
  // the predecessor's lanes of the next chunk and lane lo - 1. Per lane and path: two +P1 adds,
  // the min of four, + C - M, and the running minimum; per lane the sum over paths.
  // Schedule of one firing (resources.hpp). Each row memory's bank sees one read (the next
  // chunk's lanes) and one write (this chunk's); each row-minimum memory one read (chunk 0) and
  // one write (the last chunk). The pixel path's minimum M is written by a pixel's last firing
  // and used by the next firing; the lanes' minimum is taken off that path (see
  // aggregate_kind), so the chain from M to M is the subtraction, the min with C + P2, the
  // running minimum and its register. The running minimum itself recurs every firing.
  template <class S>
  void schedule(S& s) const {
    const int pb = path_bits(p_);
  agg_schedule_kinds:
    for (int k = 1; k < kKindCount; ++k) {
      if (((kinds_ >> k) & 1u) == 0) continue;
      s.memory(k == kKindRowLeft ? "row_path_left" : k == kKindRowUp ? "row_path_up" : "row_path_right", 1, 1, 2);
      s.memory(k == kKindRowLeft ? "row_min_left" : k == kKindRowUp ? "row_min_up" : "row_min_right", 1, 1, 2);
    }
    if ((kinds_ & (1u << kKindPixel)) != 0) {
      s.recurrence("pixel_path_minimum", 1);
      s.chain(kOpAdd, pb + 1, 1);      // min_d (C_d + t_d) - M
      s.chain(kOpCompare, pb + 1, 1);  // min with min_d C_d + P2
      s.chain(kOpMux, pb + 1, 1);
      s.chain(kOpCompare, pb, 1);  // running minimum over the chunks
      s.chain(kOpMux, pb, 1);
      s.chain(kOpRegister, pb, 1);
    }
    s.recurrence("running_minimum", 1);
    s.chain(kOpCompare, pb, 1);
    s.chain(kOpMux, pb, 1);
    s.chain(kOpRegister, pb, 1);
    // Adaptive P2: the previous row's intensities, one read and one write per pixel.
    if (p_.p2_adaptive > 0 && (kinds_ & ~(1u << kKindPixel)) != 0) s.memory("row_intensity", 1, 1, 2);
  }

  template <class R>
  void declare(R& r, int packing, int banks) const {
    const int pb = path_bits(p_);
    const int ab = aggregate_bits(p_);
    const int d = d_;
    const int pu = lanes_;
    declare_raster_control(r, p_.width_px, p_.height_px, d / pu);
    DeclareStorage<R> st(r);
    storage(st, packing, banks);
  agg_declare_paths:
    for (int k = 0; k < kKindCount; ++k) {
      if (((kinds_ >> k) & 1u) == 0) continue;
      if (d > pu) r.op("path_predecessor_select", kOpMux, pb, pu * (d / pu - 1));
      r.op("path_p1_adds", kOpAdd, pb + 1, 2 * pu);
      r.op("path_p2_add", kOpAdd, pb + 1, 1);
      r.op("path_min_of_four", kOpCompare, pb + 1, 3 * pu);
      r.op("path_min_select", kOpMux, pb + 1, 3 * pu);
      r.op("path_cost_minus_min", kOpAdd, pb + 1, 2 * pu);
      r.op("path_running_min", kOpCompare, pb, pu);
      r.op("path_running_min_select", kOpMux, pb, pu);
    }
    if (p_.p2_adaptive > 0) {
      // Per active kind: |I(p) - I(q)| (a subtraction and a negation's select), the product by
      // the register (8 x 8 bits), P2 minus it with the floor P1 + 1 (a subtraction, a compare
      // and a select), and the selects of the window's shift.
      const int pen = penalty_bits(p_);
      r.op("p2_adaptive_step", kOpAdd, 9, 2 * slots());
      r.op("p2_adaptive_abs", kOpMux, 8, slots());
      r.mul("p2_adaptive_product", 8, kP2AdaptiveBits, slots());
      r.op("p2_adaptive_lower", kOpAdd, pen + 1, slots());
      r.op("p2_adaptive_floor", kOpCompare, pen + 1, slots());
      r.op("p2_adaptive_floor_select", kOpMux, pen, slots());
    }
    r.op("sum_over_paths", kOpAdd, ab, pu * slots());
    r.registers("cost_in", pu * cost_bits(p_), 1);
    r.registers("sum_token", pu * ab, 1);
  }

 private:
  // Lr(p, d) = C(p, d) + min(Lr(q, d), Lr(q, d±1) + P1, M + P2) - M over the lanes of this
  // firing for path kind k, added into s; at the start of a path (predecessor outside the
  // image) Lr(p, d) = C(p, d). Memory contract: row_[m][x] holds the previous row's Lr of column
  // x until this row's firing at x overwrites it; lag_ holds the previous row's Lr of column
  // x - 1 (row-left); pix_ holds the previous pixel's Lr until this pixel overwrites it.
  template <int K>
  PX_INLINE void aggregate_kind(const CostToken& c, int trip, SumToken& s) {
    const int k = K;
    const int n = lanes_;
    const int lo = chunk_ * n;
    const bool first = chunk_ == 0;
    const bool last = chunk_ + 1 == chunks_;
    // The next firing's position: the next chunk, or chunk 0 of the next pixel (the next row's
    // first at the end of a row).
    const int nlo = last ? 0 : lo + n;
    const int nx = last ? (x_ + 1 == p_.width_px ? 0 : x_ + 1) : x_;
    const int m = k - 1;  // row memory of a row kind
    const int xr = min_int(x_ + 1, p_.width_px - 1);
    const int nxr = min_int(nx + 1, p_.width_px - 1);

    // The predecessor's minimum M (read once per pixel) and whether the predecessor exists.
    bool valid;
    if (k == kKindPixel) {
      valid = x_ > 0;
    } else if (k == kKindRowUp) {
      valid = y_ > 0;
    } else if (k == kKindRowLeft) {
      valid = y_ > 0 && x_ > 0;
    } else {
      valid = y_ > 0 && x_ + 1 < p_.width_px;
    }
    if (first) {
      if (k == kKindPixel) {
        mq_[k] = pix_min_;
      } else if (k == kKindRowLeft) {
        mq_[k] = mlag_;
        mlag_ = row_min_[m][x_];
      } else {
        mq_[k] = row_min_[m][k == kKindRowUp ? x_ : xr];
      }
    }

    // Fetch the predecessor's lanes of the next firing's chunk (trip: lane_trip()).
    Word next[kLanes];
    Word* pred = ahead_[k];  // pred[i] is Lr(q, lo - 1 + i), kNone outside [0, D)
  agg_fetch:
    for (int i = 0; i < trip; ++i) {
      PX_PRAGMA("HLS UNROLL")
      const int d = nlo + i;
      if (k == kKindPixel) {
        next[i] = pix_[d];
      } else if (k == kKindRowUp) {
        next[i] = row_[m][nx][d];
      } else if (k == kKindRowLeft) {
        next[i] = lag_[d];
        lag_[d] = row_[m][nx][d];
      } else {
        next[i] = row_[m][nxr][d];
      }
    }

    // Lane lo + PU is the next chunk's first (kNone past D, set by the firing before).
    if (!last) pred[n + 1] = next[0];

    const uint32_t m_prev = mq_[k];
    const Word wp1 = Word(p_.p1);
    const Word wm = Word(m_prev);
    const uint32_t p2 = p_.p2_adaptive > 0 ? uint32_t(p2k_[k]) : uint32_t(p_.p2);
    const Word wm_p2 = sat_add(wm, Word(p2 > kNone ? kNone : p2));
    // The lanes' minimum, kept off the recurrence through M: with t_d = min(Lr(q,d),
    // Lr(q,d±1) + P1), Lr(p,d) = C_d + min(t_d - M, P2), so min_d Lr(p,d) =
    // min(min_d (C_d + t_d) - M, min_d C_d + P2): both inner minima are independent of M, and
    // the chain from M to the next M is a subtraction and two compare-selects (docs/kernels.md).
    // Software instantiations take min_d Lr(p,d) directly, the same value by that identity
    // (kernels_common_test runs both forms on whole frames): one 16-bit reduction, no widening.
    uint32_t ct_min = 0xFFFFFFFFu;  // min_d (C_d + t_d)
    uint32_t c_min = 0xFFFFFFFFu;   // min_d C_d
    Word lmin = Word(kNone);
    Word lr[kLanes];
  agg_lanes:
    for (int i = 0; i < trip; ++i) {
      PX_PRAGMA("HLS UNROLL")
      const Word a = pred[i + 1];
      const Word b = sat_add(pred[i], wp1);
      const Word e = sat_add(pred[i + 2], wp1);
      Word t = a < b ? a : b;
      t = t < e ? t : e;
      const Word mm = t < wm_p2 ? t : wm_p2;
      const uint32_t cost = c.v[i];
      // At the start of a path (no predecessor) Lr = C.
      const Word v = valid ? Word(Word(cost) + Word(mm - wm)) : Word(cost);
      lr[i] = v;
      s.v[i] = Word(s.v[i] + v);
      if (Caps::fixed) {
        const uint32_t ct = cost + uint32_t(t);
        ct_min = ct < ct_min ? ct : ct_min;
        c_min = cost < c_min ? cost : c_min;
      } else {
        const Word vm = Word(v | pad_[i]);  // a don't-care lane past PU is no candidate (all ones)
        lmin = vm < lmin ? vm : lmin;
      }
    }
    uint32_t lane_min;
    if (Caps::fixed) {
      const uint32_t cp2 = c_min + p2;
      const uint32_t ct_m = ct_min - m_prev;
      lane_min = !valid ? c_min : (ct_m < cp2 ? ct_m : cp2);
    } else {
      lane_min = lmin;
    }
    const uint32_t prior = first ? kNone : run_min_[k];
    const uint32_t run_min = lane_min < prior ? lane_min : prior;
    run_min_[k] = run_min;

    // Store this chunk's Lr where the next row (row kinds) or the next pixel (pixel kind) reads it.
  agg_store:
    for (int i = 0; i < trip; ++i) {
      PX_PRAGMA("HLS UNROLL")
      if (k == kKindPixel) {
        pix_[lo + i] = lr[i];
        if (last && chunks_ == 1) next[i] = lr[i];  // the next pixel's predecessor is this one
      } else {
        row_[m][x_][lo + i] = lr[i];
        // Rows of one or two pixels with one chunk per pixel (software instantiations and
        // exports that narrow): the next firing's predecessor column is the one this firing
        // writes, fetched above before the write; it takes this firing's Lr instead.
        if (kNarrowRows && last && chunks_ == 1) {
          if (k == kKindRowUp && nx == x_) next[i] = lr[i];
          if (k == kKindRowRight && nxr == x_) next[i] = lr[i];
          if (k == kKindRowLeft && nx == x_) lag_[lo + i] = lr[i];
        }
      }
    }
    if (last) {
      if (k == kKindPixel)
        pix_min_ = Word(run_min);
      else
        row_min_[m][x_] = Word(run_min);
    }
    // The next firing's predecessor lanes: its lane lo - 1 is this chunk's last (none before
    // lane 0), its lanes are the ones fetched, and past the last chunk there is no lane.
    pred[0] = last ? Word(kNone) : pred[n];
  agg_ahead:
    for (int i = 0; i < trip; ++i) {
      PX_PRAGMA("HLS UNROLL")
      pred[i + 1] = next[i];
    }
    if (chunk_ + 2 >= chunks_) pred[n + 1] = Word(kNone);
  }

  // Adaptive P2 (docs/algorithm.md §3), at a pixel's first firing: each kind's P2 from the
  // intensity step between this pixel and that kind's predecessor. The previous row's
  // intensities of columns x - 1, x, x + 1 are a window of registers (up_px_): it shifts by one
  // column per pixel, taking column x + 1 fetched by the previous pixel's last firing; a row
  // starts from the previous row's first two columns (head_px_), so the row memory sees one read
  // and one write per pixel (keep_intensity).
  void adapt_p2(uint8_t px) {
    cur_px_ = px;
    if (x_ == 0) {
      up_px_[1] = head_px_[0];
      up_px_[2] = head_px_[1];
    } else {
      up_px_[0] = up_px_[1];
      up_px_[1] = up_px_[2];
      up_px_[2] = fetched_px_;
    }
    const int a = p_.p2_adaptive;
    p2k_[kKindPixel] = Word(adaptive_p2(p_.p1, p_.p2, a, px, prev_px_));
    p2k_[kKindRowLeft] = Word(adaptive_p2(p_.p1, p_.p2, a, px, up_px_[0]));
    p2k_[kKindRowUp] = Word(adaptive_p2(p_.p1, p_.p2, a, px, up_px_[1]));
    p2k_[kKindRowRight] = Word(adaptive_p2(p_.p1, p_.p2, a, px, up_px_[2]));
  }
  // At a pixel's last firing: its intensity becomes the next pixel's predecessor and the next
  // row's (row memory at x, and the row's first two columns in head_px_); the row memory gives
  // column x + 2 of the previous row, the next pixel's x + 1.
  void keep_intensity() {
    prev_px_ = cur_px_;
    if (!kRowKinds) return;
    fetched_px_ = row_px_[min_int(x_ + 2, p_.width_px - 1)];
    row_px_[x_] = cur_px_;
    if (x_ < 2) head_px_[x_] = cur_px_;
  }

  // Lane loops run to PU: the compile-time LANES in the export, where PU = LANES. A software
  // instantiation whose pixel is one chunk (PU = D) runs whole SIMD vectors instead: the lanes
  // past PU are don't-care (written to the unused rest of a column, masked out of the minimum,
  // never read as sums).
  int lane_trip() const {
    return chunks_ == 1 ? Caps::simd_trip(lanes_, kLanes < kMaxD ? kLanes : kMaxD) : Caps::trip(lanes_, kLanes);
  }

  // a + b, saturating at kNone (the largest value Lr arithmetic needs). Sums that could exceed
  // Word saturate, which cannot change a minimum because Lr(q, d) <= 2^path_bits - 1 is always
  // a candidate and fits.
  static Word sat_add(Word a, Word b) {
    const Word r = Word(a + b);
    return (r < a || r > Word(kNone)) ? Word(kNone) : r;
  }

  void advance() {
    if (++chunk_ < chunks_) return;
    chunk_ = 0;
    if (++x_ < p_.width_px) return;
    x_ = 0;
    if (++y_ < p_.height_px) return;
    done_ = true;
  }

  StereoParams p_;
  unsigned kinds_ = 0;
  bool add_forward_ = false, tee_cost_ = false;
  int d_ = 1, lanes_ = 1, chunks_ = 1;
  int x_ = 0, y_ = 0, chunk_ = 0;
  bool done_ = true;
  // Per path kind: the predecessor's lanes of this chunk, its lane lo - 1, its minimum M and
  // the running minimum of this pixel's Lr.
  Word ahead_[kKindCount][kLanes + 2];  // [0]: lane lo - 1; [1, PU]: lanes lo..; [PU + 1]: lane lo + PU
  Word mq_[kKindCount];
  uint32_t run_min_[kKindCount];
  Word pix_[kMaxD];   // pixel path: the previous pixel's Lr (this pixel's, lanes already done)
  Word pix_min_ = 0;  // pixel path: the previous pixel's minimum
  Word lag_[kMaxD];   // row-left path: the previous row's Lr of column x - 1 (x, lanes already read)
  Word mlag_ = 0;     // row-left path: the previous row's minimum of column x - 1
  Word row_[kRowMemories][kMaxW][kMaxD];  // row kinds: previous-row Lr per column
  Word row_min_[kRowMemories][kMaxW];     // row kinds: previous-row min_d Lr per column
  Word pad_[kLanes];                      // software only: all ones in the don't-care lanes past PU (lane_trip)
  // Adaptive P2 (adapt_p2): this pixel's intensity, the previous pixel's, the previous row's
  // (memory, its columns x - 1 .. x + 1 in registers, its first two columns), and each kind's P2.
  uint8_t cur_px_ = 0, prev_px_ = 0, fetched_px_ = 0;
  uint8_t row_px_[kMaxW];
  uint8_t up_px_[3] = {0, 0, 0};
  uint8_t head_px_[2] = {0, 0};
  Word p2k_[kKindCount];

 public:
  // Storage descriptor (resources.hpp) of the members above, per active path kind, with the
  // path-cost width: the pixel path's pix_ (D) and pix_min_; a row kind's row memory
  // row_[kind - 1] (`packing` disparities per word, the ceil(D / packing) words of a column in
  // `banks` memories, 0: one memory per word, W deep each) and its row minima row_min_[kind - 1]
  // (one memory, W deep); the row-left kind's lag_ (D) and mlag_; every kind's ahead_ (PU),
  // edge_, mq_ and run_min_.
  template <class V>
  void storage(V& v, int packing, int banks) const {
    const int pb = path_bits(p_);
    const int q = packing < 1 ? 1 : (packing > d_ ? d_ : packing);
    const int words = (d_ + q - 1) / q;
    const int memories = banks <= 0 || banks > words ? words : banks;
    const int words_per_memory = (words + memories - 1) / memories;
    v.unused("software_lane_pad", pad_);  // read only where !Caps::fixed
  agg_storage_kinds:
    for (int k = 0; k < kKindCount; ++k) {
      if (((kinds_ >> k) & 1u) == 0) {  // an inactive kind's state is never written: no hardware
        if (k == kKindPixel) v.unused("pixel_path_previous", pix_);
        if (k == kKindRowLeft) v.unused("row_left_delay", lag_);
        if (k != kKindPixel) v.unused("row_path", row_[k - 1]);
        if (k != kKindPixel) v.unused("row_min", row_min_[k - 1]);
        v.unused("path_predecessor_lanes", ahead_[k]);
        continue;
      }
      if (k == kKindPixel) {
        v.registers("pixel_path_previous", pix_, d_, pb);
        v.registers("pixel_path_min", pix_min_, 1, pb);
      } else {
        const int m = k - 1;
        v.memory(k == kKindRowLeft ? "row_path_left"
                 : k == kKindRowUp ? "row_path_up"
                                   : "row_path_right",
                 row_[m], int64_t(p_.width_px) * words_per_memory, q * pb, memories, false, q);
        v.memory(k == kKindRowLeft ? "row_min_left"
                 : k == kKindRowUp ? "row_min_up"
                                   : "row_min_right",
                 row_min_[m], p_.width_px, pb, 1, false, 1);
        if (k == kKindRowLeft) {
          v.registers("row_left_delay", lag_, d_, pb);
          v.registers("row_left_delay_min", mlag_, 1, pb);
        }
      }
      v.registers_part("path_predecessor_lanes", ahead_[k], lanes_ + 1, pb);
      v.registers("path_min_previous", mq_[k], 1, pb);
      v.registers("path_min_running", run_min_[k], 1, pb);
    }
    intensity_storage(v);
  }

 private:
  // The adaptive P2's state (adapt_p2): no hardware without it; the row intensities only with a
  // row kind active.
  template <class V>
  void intensity_storage(V& v) const {
    const bool on = p_.p2_adaptive > 0;
    const bool rows = on && (kinds_ & ~(1u << kKindPixel)) != 0;
    if (on) {
      v.registers("intensity_current", cur_px_, 1, 8);
      v.registers("intensity_previous_pixel", prev_px_, 1, 8);
      v.registers_part("p2_adaptive_per_kind", p2k_, slots(), penalty_bits(p_));
    } else {
      v.unused("intensity_current", cur_px_);
      v.unused("intensity_previous_pixel", prev_px_);
      v.unused("p2_adaptive_per_kind", p2k_);
    }
    if (rows) {
      v.memory("row_intensity", row_px_, p_.width_px, 8, 1, false, 1);
      v.registers("intensity_row_window", up_px_, 3, 8);
      v.registers("intensity_row_head", head_px_, 2, 8);
      v.registers("intensity_row_fetched", fetched_px_, 1, 8);
    } else {
      v.unused("row_intensity", row_px_);
      v.unused("intensity_row_window", up_px_);
      v.unused("intensity_row_head", head_px_);
      v.unused("intensity_row_fetched", fetched_px_);
    }
  }
};

}  // namespace kern
}  // namespace parallax
