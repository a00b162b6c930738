// SGM aggregation over up to four streaming path kinds in one raster pass (docs/algorithm.md §3). For every pixel it
// consumes D/PU cost tokens and emits D/PU aggregate tokens S(p, d) = sum over the active paths of Lr(p, d) [+ F(p, d)
// from a previous pass]. C++14 synthesisable subset.
//
// Path kinds are relative to the stream order, so the same kernel serves the forward pass (kinds = paths 0/45/90/135)
// and, on a reversed stream, the backward pass of the eight-path variant (kinds = paths 180/225/270/315). Adding a path
// kind means adding an enumerator, its predecessor rule in predecessor(), and its memory (see docs/kernels.md).
//
// With MGM aggregation (docs/algorithm.md §3) every kind also steps from a second predecessor across its path, and the
// kinds pair up: the pixel and row-up kinds both step from the previous pixel and the previous row's same column, the
// row-left and row-right kinds both from the previous row's columns x - 1 and x + 1, so each pair is one recursion
// (mgm_kinds), computed once in the pixel or row-left kind's state and added once per path (aggregate_kind_mgm). The
// pixel kind gains a row memory; the row-left kind a window of registers over its row memory (read once per lane bank
// and firing, at x + 1; columns x and x - 1 are the two reads before it, and a row's column 0 is kept in head registers
// when written).
#pragma once

#include "parallax/kernels/caps.hpp"
#include "parallax/kernels/common.hpp"
#include "parallax/kernels/pipeline.hpp"
#include "parallax/kernels/resources.hpp"
#include "parallax/kernels/shift_reg.hpp"
#include "parallax/kernels/sgm_kinds.hpp"

namespace parallax {
namespace kern {

// The capacities of an aggregation stage with the pixel kind alone (the 180-degree path on reversed rows,
// row_reverse.hpp): no row memory, so one column of capacity.
template <class C>
using PixelPathCaps = Caps<1, C::max_disparities, C::lanes, C::window_rows, C::median_rows, 1u << kKindPixel, C::fixed,
                           C::max_min_disparity, C::count_accesses, typename C::store>;

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
  // The element type of the row memories (store.hpp): Word in software, path_bits wide in the export.
  typedef typename Caps::store::template path<Word>::type PathStore;
  // A member array (raw, or counted when Caps count accesses: access.hpp).
  template <class T, int... N>
  using Array = typename Caps::template array<T, N...>;
  static constexpr int kMaxW = Caps::max_width_px;
  static constexpr int kMaxD = Caps::max_disparities;
  static constexpr int kLanes = Caps::lanes;
  // One per row kind (kKindRowLeft .. kKindRowRight at kind - 1) and, for MGM, the pixel kind's (row_memory()).
  static constexpr int kRowMemories = 4;
  // Whether this instantiation has row kinds (else no row memory of any kind, intensities too).
  static constexpr bool kRowKinds = (Caps::kind_mask & ~(1u << kKindPixel)) != 0;
  // Whether rows may be as narrow as two pixels (then a row kind's next predecessor column can be the one being
  // written; see aggregate_kind): software, or a fixed width of 1 or 2.
  static constexpr bool kNarrowRows = !Caps::fixed || Caps::max_width_px <= 2;
  // The row memories' words (row_): a FIXED instantiation (the export) keeps each chunk's PU lanes as one word, [W x
  // D/PU][PU] reshaped in the last dimension, so the firing at column x, chunk c reads and writes the words x * D/PU +
  // c of its own and the next firing's, and lane i is bit field i of the word whatever the chunk; software
  // instantiations run any PU up to their lanes and keep a column's lanes flat, [W][D].
  static constexpr int kRowWords = Caps::fixed ? kMaxW * (kMaxD / kLanes) : kMaxW;
  static constexpr int kRowLanes = Caps::fixed ? kLanes : kMaxD;
  // Larger than any path cost (<= 2^path_bits - 1) and safe to add P1 to in 32 bits.
  static constexpr uint32_t kNone = sizeof(Word) == 2 ? 0xFFFFu : 0x7FFFFFFFu;

  // Registers: everything but the row memories. Row memories: one per row kind, a word of PU lanes per chunk (row_word,
  // row_lane); a firing reads the next firing's word and writes its own, one read and one write per firing (simple dual
  // port). A row is read again only W firings after it was written, so no dependence between iterations on them.
  SgmAggregate() {
    PX_PRAGMA("HLS ARRAY_PARTITION variable=ahead_ type=complete dim=0")
    PX_PRAGMA("HLS ARRAY_PARTITION variable=mq_ type=complete dim=1")
    PX_PRAGMA("HLS ARRAY_PARTITION variable=run_min_ type=complete dim=1")
    PX_PARTITION_COMPLETE(pix_, 1)
    PX_PARTITION_COMPLETE(lag_, 1)
    PX_PARTITION_COMPLETE(row_, 1)
    PX_PARTITION_COMPLETE(row_min_, 1)
    PX_PRAGMA("HLS ARRAY_PARTITION variable=ahead2_ type=complete dim=0")
    PX_PRAGMA("HLS ARRAY_PARTITION variable=mq2_ type=complete dim=1")
    PX_PARTITION_COMPLETE(win_, 0)
    PX_PARTITION_COMPLETE(win_head_, 0)
    PX_PRAGMA("HLS ARRAY_PARTITION variable=win_min_ type=complete dim=1")
    // The row memories: a chunk's lanes are one word (software instantiations, whose PU is a run-time value, restate
    // the word per configuration when they count: count_row_layout), bound as the export's configuration header says
    // (PX_HLS_SGM_ROW_IMPL), else to any RAM.
    PX_RESHAPE_COMPLETE(row_, 3)
#ifdef PX_HLS_SGM_ROW_IMPL
    PX_BIND_RAM_S2P(row_, PX_HLS_SGM_ROW_IMPL)
#else
    PX_BIND_RAM_S2P_ANY(row_)
#endif
    PX_PRAGMA("HLS ARRAY_PARTITION variable=up_px_ type=complete dim=1")
    PX_PRAGMA("HLS ARRAY_PARTITION variable=head_px_ type=complete dim=1")
    PX_PRAGMA("HLS ARRAY_PARTITION variable=p2k_ type=complete dim=1")
    PX_BIND_RAM_S2P_ANY(row_px_)
    access_name(pix_, "pixel_path_previous");
    pix_q_.name("pixel_path_previous");
    pix_q_.clear();
    access_name(lag_, "row_left_delay");
    access_name(row_, "row_path");
    access_name(row_min_, "row_min");
    access_name(win_, "mgm_window");
    access_name(win_head_, "mgm_window_head");
    access_name(row_px_, "row_intensity");
    // Software instantiations read the don't-care lanes past PU (simd_trip): give them values once. (Nothing to do in
    // the export, where every lane is a design lane.)
    if (!Caps::fixed) {
    agg_clear_memories:
      for (int d = 0; d < kMaxD; ++d) {
        pix_[d] = 0;
        lag_[d] = 0;
        win_[0][d] = win_[1][d] = win_head_[d] = 0;
      }
      for (int x = 0; x < kMaxW; ++x) row_px_[x] = 0;
      for (int m = 0; m < kRowMemories; ++m)
        for (int x = 0; x < kMaxW; ++x) row_min_[m][x] = 0;
      for (int m = 0; m < kRowMemories; ++m)
        for (int w = 0; w < kRowWords; ++w)
          for (int l = 0; l < kRowLanes; ++l) row_[m][w][l] = 0;
    }
  }

  // As the pipeline description configures the stage (pipeline.hpp: stage_setup()); setup() is what
  // it was configured with (the kinds within Caps::kind_mask), which tests hold to the description.
  void configure(const StereoParams& p, const StageSetup& s) {
    configure(p, s.sgm_kinds, s.add_forward, s.tee_cost);
  }
  StageSetup setup() const {
    return StageSetup{kinds_, add_forward_, tee_cost_, false};
  }
  // kinds: StreamPathKind bits (their datapaths within Caps::kind_mask, datapath_kinds()); add_forward: add F from a
  // second input; tee_cost: copy the costs to a second output.
  void configure(const StereoParams& p, unsigned kinds, bool add_forward, bool tee_cost) {
    p_ = p;
    // MGM: a pair's datapath adds its Lr twice when both kinds of the pair are active.
    twice_straight_ = popcount_u32(kinds & ((1u << kKindPixel) | (1u << kKindRowUp))) == 2;
    twice_diagonal_ = popcount_u32(kinds & ((1u << kKindRowLeft) | (1u << kKindRowRight))) == 2;
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
  // A frame starts with the per-kind registers cleared (they are read, but not used, before the first firing writes
  // them: the first row and column have no predecessor).
  void start_frame() {
    x_ = 0;
    y_ = 0;
    chunk_ = 0;
    done_ = false;
    pix_min_ = 0;
    mlag_ = 0;
    win_min_[0] = win_min_[1] = win_head_min_ = 0;
  agg_reset_kinds:
    for (int k = 0; k < kKindCount; ++k) {
      PX_PRAGMA("HLS UNROLL")
      mq_[k] = 0;
      run_min_[k] = kNone;
    agg_reset_lanes:
      for (int i = 0; i < kLanes + 2; ++i) {
        PX_PRAGMA("HLS UNROLL")
        ahead_[k][i] = Word(kNone);
        if (k < 2) ahead2_[k][i] = Word(kNone);
      }
      if (k < 2) mq2_[k] = 0;
    }
  }
  bool done() const {
    return done_;
  }
  // The datapaths this stage computes (one per path kind; with MGM one per pair of kinds).
  int slots() const {
    return popcount_u32(datapaths());
  }
  // The path steps per pixel, each with its own adaptive P2 (MGM: two per datapath).
  int steps() const {
    return mgm() ? 2 * slots() : slots();
  }

  AggPlan plan() const {
    PX_PRAGMA("HLS INLINE")
    AggPlan pl;
    pl.read_cost = !done_;
    pl.read_forward = !done_ && add_forward_;
    pl.write_sum = !done_;
    pl.write_tee = !done_ && tee_cost_;
    return pl;
  }

  // One firing: the PU lanes [lo, lo + PU) of pixel (x, y) for every active path kind. Per kind, the predecessor's
  // lanes of this chunk arrived with the previous firing (ahead_), its lane lo - 1 is held from the chunk before
  // (ahead_[k][0]), and this firing fetches the predecessor's lanes of the next firing's chunk, whose first is lane lo
  // + PU. So every memory sees one read and one write per lane bank and firing (docs/kernels.md).
  template <class CostIn, class FwdIn, class SumOut, class TeeOut>
  void fire(const AggPlan& pl, CostIn& cost_in, FwdIn& fwd_in, SumOut& sum_out, TeeOut& tee_out) {
    PX_PRAGMA("HLS INLINE")
    PX_NO_DEPENDENCE(row_)
    PX_NO_DEPENDENCE(row_min_)
    PX_NO_DEPENDENCE(row_px_)
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
    // One datapath per path kind (kinds outside Caps::kind_mask have none); with MGM one per pair of kinds, its Lr
    // added once per active kind of the pair.
    const unsigned dk = datapaths();
    if (mgm()) {
      if ((Caps::kind_mask & (1u << kKindPixel)) != 0 && (dk & (1u << kKindPixel)) != 0)
        aggregate_kind_mgm<kKindPixel>(c, trip, twice_straight_, s);
      if ((Caps::kind_mask & (1u << kKindRowLeft)) != 0 && (dk & (1u << kKindRowLeft)) != 0)
        aggregate_kind_mgm<kKindRowLeft>(c, trip, twice_diagonal_, s);
    } else {
      if ((Caps::kind_mask & (1u << kKindPixel)) != 0 && (dk & (1u << kKindPixel)) != 0)
        aggregate_kind<kKindPixel>(c, trip, s);
      if ((Caps::kind_mask & (1u << kKindRowLeft)) != 0 && (dk & (1u << kKindRowLeft)) != 0)
        aggregate_kind<kKindRowLeft>(c, trip, s);
      if ((Caps::kind_mask & (1u << kKindRowUp)) != 0 && (dk & (1u << kKindRowUp)) != 0)
        aggregate_kind<kKindRowUp>(c, trip, s);
      if ((Caps::kind_mask & (1u << kKindRowRight)) != 0 && (dk & (1u << kKindRowRight)) != 0)
        aggregate_kind<kKindRowRight>(c, trip, s);
    }
    sum_out.write(s);
    if (tee_cost_) tee_out.write(c);
    if (p_.p2_adaptive > 0 && chunk_ + 1 == chunks_) keep_intensity();
    advance();
  }

  // The control path of fire(pl) alone (see CostStage::step): the chunk, column and row counters advance; no path cost
  // is read or written.
  void step(const AggPlan& pl) {
    (void)pl;
    advance();
  }

  // Control-state access for a scheduler that advances periodic rows at once (sim/, never synthesised): visit(v) calls
  // v(field) on every counter of the control path, by reference; resync() recomputes the fields derived from them after
  // a visitor wrote them.
  template <class V>
  void visit(V& v) {
    v(x_);
    v(y_);
    v(chunk_);
    v(done_);
  }
  void resync() {}

  // Resources and schedule of this configuration (sgm_resources.hpp).
  template <class S>
  void schedule(S& s) const {
    sgm_schedule(*this, s);
  }
  template <class R>
  void declare(R& r) const {
    sgm_declare(*this, r);
  }
  const StereoParams& params() const {
    return p_;
  }
  int lanes() const {
    return lanes_;
  }
  int disparity_count() const {
    return d_;
  }
  bool mgm() const {
    return p_.aggregation == kAggregationMgm;
  }
  unsigned datapaths() const {
    return datapath_kinds(kinds_, p_.aggregation);
  }
  // Whether a step reads the previous row's intensities (adaptive P2): a row kind, or MGM (whose pixel kind also steps
  // from the row above).
  bool row_intensities() const {
    return (kinds_ & ~(1u << kKindPixel)) != 0 || mgm();
  }

 private:
  // The row memory (row_, row_min_) of kind k: k - 1 for the row kinds, the last for the pixel kind (MGM only).
  static int row_memory(int k) {
    return k == kKindPixel ? kRowMemories - 1 : k - 1;
  }

  // MGM (docs/algorithm.md §3): Lr(p, d) = C(p, d) + floor((u_a(d) + u_b(d)) / 2) with u_q(d) = min(Lr(q, d), Lr(q,
  // d±1) + P1, M_q + P2_q) - M_q for the two predecessors (one when the other is outside the image, none at a path's
  // start), added into s once, or twice when both kinds of the pair are active (twice: a shift). K = kKindPixel: the
  // pair pixel / row-up, sides a = the previous pixel (pix_) and b = the previous row's column x (row memory at x). K =
  // kKindRowLeft: the pair row-left / row-right, sides a = the previous row's column x - 1 (window) and b = column x +
  // 1 (row memory at x + 1). The lanes' ahead registers follow SGM's protocol per side (ahead_ side a, ahead2_ side b):
  // this firing fetches the next firing's chunk of both.
  template <int K>
  PX_INLINE void aggregate_kind_mgm(const CostToken& c, int trip, bool twice, SumToken& s) {
    const int k = K;
    const bool straight = k == kKindPixel;
    const int n = lanes_;
    const int lo = chunk_ * n;
    const bool first = chunk_ == 0;
    const bool last = chunk_ + 1 == chunks_;
    const int nc = last ? 0 : chunk_ + 1;
    const int nlo = last ? 0 : lo + n;
    const int nx = last ? (x_ + 1 == p_.width_px ? 0 : x_ + 1) : x_;
    const int m = row_memory(k);
    const int xr = min_int(x_ + 1, p_.width_px - 1);
    const int nxr = min_int(nx + 1, p_.width_px - 1);

    const bool va = straight ? x_ > 0 : (y_ > 0 && x_ > 0);
    const bool vb = straight ? y_ > 0 : (y_ > 0 && x_ + 1 < p_.width_px);
    if (first) {  // both predecessors' minima, read once per pixel
      if (straight) {
        mq_[k] = pix_min_;
        mq2_[k] = from_store<Word>(row_min_[m][x_]);
      } else {
        const Word ahead_min = from_store<Word>(row_min_[m][xr]);
        mq_[k] = win_min_[1];
        win_min_[1] = x_ == 0 ? win_head_min_ : win_min_[0];
        win_min_[0] = ahead_min;
        mq2_[k] = ahead_min;
      }
    }

    Word next_a[kLanes], next_b[kLanes];
    Word* pa = ahead_[k];   // pa[i] is side a's Lr(q, lo - 1 + i), kNone outside [0, D)
    Word* pb = ahead2_[k];  // likewise side b
  agg_mgm_fetch:
    for (int i = 0; i < trip; ++i) {
      PX_PRAGMA("HLS UNROLL")
      const int d = nlo + i;
      if (straight) {
        next_a[i] = pix_read(d, i);
        next_b[i] = from_store<Word>(row_[m][row_word(nx, nc)][row_lane(nlo, i)]);
      } else {
        const Word ahead = from_store<Word>(row_[m][row_word(nxr, nc)][row_lane(nlo, i)]);
        next_a[i] = win_[1][d];
        win_[1][d] = nx == 0 ? win_head_[d] : win_[0][d];
        win_[0][d] = ahead;
        next_b[i] = ahead;
      }
    }
    if (!last) {
      pa[n + 1] = next_a[0];
      pb[n + 1] = next_b[0];
    }

    const Word wp1 = Word(p_.p1);
    const Word wma = mq_[k];
    const Word wmb = mq2_[k];
    const int ka = straight ? kKindPixel : kKindRowLeft;  // the adaptive P2 of each side's step
    const int kb = straight ? kKindRowUp : kKindRowRight;
    const uint32_t p2a = p_.p2_adaptive > 0 ? uint32_t(p2k_[ka]) : uint32_t(p_.p2);
    const uint32_t p2b = p_.p2_adaptive > 0 ? uint32_t(p2k_[kb]) : uint32_t(p_.p2);
    const Word wma_p2 = sat_add(wma, Word(p2a > kNone ? kNone : p2a));
    const Word wmb_p2 = sat_add(wmb, Word(p2b > kNone ? kNone : p2b));
    Word lmin = Word(kNone);
    Word lr[kLanes];
  agg_mgm_lanes:
    for (int i = 0; i < trip; ++i) {
      PX_PRAGMA("HLS UNROLL")
      const uint32_t ua = step_from(pa, i, wp1, wma, wma_p2);
      const uint32_t ub = step_from(pb, i, wp1, wmb, wmb_p2);
      const uint32_t u = va && vb ? (ua + ub) >> 1 : va ? ua : vb ? ub : 0u;
      const Word v = Word(c.v[i] + u);
      lr[i] = v;
      s.v[i] = Word(s.v[i] + (twice ? Word(v << 1) : v));
      const Word vm = Caps::fixed ? v : Word(v | pad_[i]);  // don't-care lanes past PU: no candidate
      lmin = vm < lmin ? vm : lmin;
    }
    const uint32_t prior = first ? kNone : run_min_[k];
    const uint32_t run_min = uint32_t(lmin) < prior ? uint32_t(lmin) : prior;
    run_min_[k] = run_min;

    // Store this chunk's Lr: the row memory at x, and the previous pixel (pixel kind) or a row's column 0 (row-left
    // kind's head). Rows of one or two pixels with one chunk per pixel: a column fetched above before this firing wrote
    // it takes this firing's Lr.
  agg_mgm_store:
    for (int i = 0; i < trip; ++i) {
      PX_PRAGMA("HLS UNROLL")
      row_[m][row_word(x_, chunk_)][row_lane(lo, i)] = lr[i];
      if (straight) {
        if (!kRotatingPix) pix_[lo + i] = lr[i];
        if (last && chunks_ == 1) next_a[i] = lr[i];  // the next pixel's predecessor is this one
        if (kNarrowRows && last && chunks_ == 1 && nx == x_) next_b[i] = lr[i];
      } else {
        if (x_ == 0) win_head_[lo + i] = lr[i];
        if (kNarrowRows && last && chunks_ == 1 && nxr == x_) {
          next_b[i] = lr[i];
          win_[0][lo + i] = lr[i];
        }
      }
    }
    if (straight) pix_push(lr);
    if (last) {
      row_min_[m][x_] = Word(run_min);
      if (straight) pix_min_ = Word(run_min);
      if (!straight && x_ == 0) win_head_min_ = Word(run_min);
    }
    pa[0] = last ? Word(kNone) : pa[n];
    pb[0] = last ? Word(kNone) : pb[n];
  agg_mgm_ahead:
    for (int i = 0; i < trip; ++i) {
      PX_PRAGMA("HLS UNROLL")
      pa[i + 1] = next_a[i];
      pb[i + 1] = next_b[i];
    }
    if (chunk_ + 2 >= chunks_) {
      pa[n + 1] = Word(kNone);
      pb[n + 1] = Word(kNone);
    }
  }

  // One predecessor's step into lane i (pred as ahead_): min(Lr(q, d), Lr(q, d±1) + P1, M + P2) - M, at most P2 (an
  // unsigned wrap where the predecessor is outside the image, never used).
  static uint32_t step_from(const Word* pred, int i, Word wp1, Word wm, Word wm_p2) {
    const Word a = pred[i + 1];
    const Word b = sat_add(pred[i], wp1);
    const Word e = sat_add(pred[i + 2], wp1);
    Word t = a < b ? a : b;
    t = t < e ? t : e;
    const Word mm = t < wm_p2 ? t : wm_p2;
    return uint32_t(Word(mm - wm));
  }

  // The pixel path's previous-pixel Lr (N2, issue 41). Software instantiations index pix_ by
  // disparity. The exported and counting ones keep the chunks written as a shift register, PU
  // entries per firing: a firing fetches the chunk written C - 1 firings before it (the previous
  // pixel's next chunk, or this pixel's chunk 0 at its last chunk), which is entry
  // (C - 1) PU - 1 - i for lane i before this firing's push, a constant per lane: no run-time
  // mux, and the scheduler sees no dependence from one firing's write to the next one's read.
  // With one chunk (C = 1) the fetch is this firing's own Lr, which the store supplies.
  static constexpr bool kRotatingPix = Caps::fixed || Caps::count_accesses;
  PX_INLINE Word pix_read(int d, int i) const {
    if (!kRotatingPix) return pix_[d];
    const int pu = Caps::parallel_units(lanes_);
    const int c = Caps::disparities(d_) / pu;
    return c > 1 ? from_store<Word>(pix_q_.at((c - 1) * pu - 1 - i)) : Word(0);
  }
  PX_INLINE void pix_push(const Word* lr) {
    if (!kRotatingPix) return;
    const int pu = Caps::parallel_units(lanes_);
    const int d = Caps::disparities(d_);
  agg_pix_push:
    for (int i = 0; i < kLanes; ++i) {
      PX_PRAGMA("HLS UNROLL")
      if (i < pu) pix_q_.shift_in(lr[i], d);
    }
  }

  // Lr(p, d) = C(p, d) + min(Lr(q, d), Lr(q, d±1) + P1, M + P2) - M over the lanes of this firing for path kind k,
  // added into s; at the start of a path (predecessor outside the image) Lr(p, d) = C(p, d). Memory contract:
  // row_[m][x] holds the previous row's Lr of column x until this row's firing at x overwrites it; lag_ holds the
  // previous row's Lr of column x - 1 (row-left); pix_ holds the previous pixel's Lr until this pixel overwrites it.
  template <int K>
  PX_INLINE void aggregate_kind(const CostToken& c, int trip, SumToken& s) {
    const int k = K;
    const int n = lanes_;
    const int lo = chunk_ * n;
    const bool first = chunk_ == 0;
    const bool last = chunk_ + 1 == chunks_;
    // The next firing's position: the next chunk, or chunk 0 of the next pixel (the next row's first at the end of a
    // row).
    const int nc = last ? 0 : chunk_ + 1;
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
        mlag_ = from_store<Word>(row_min_[m][x_]);
      } else {
        mq_[k] = from_store<Word>(row_min_[m][k == kKindRowUp ? x_ : xr]);
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
        next[i] = pix_read(d, i);
      } else if (k == kKindRowUp) {
        next[i] = from_store<Word>(row_[m][row_word(nx, nc)][row_lane(nlo, i)]);
      } else if (k == kKindRowLeft) {
        next[i] = from_store<Word>(lag_[d]);
        lag_[d] = from_store<Word>(row_[m][row_word(nx, nc)][row_lane(nlo, i)]);
      } else {
        next[i] = from_store<Word>(row_[m][row_word(nxr, nc)][row_lane(nlo, i)]);
      }
    }

    // Lane lo + PU is the next chunk's first (kNone past D, set by the firing before).
    if (!last) pred[n + 1] = next[0];

    const uint32_t m_prev = mq_[k];
    const Word wp1 = Word(p_.p1);
    const Word wm = Word(m_prev);
    const uint32_t p2 = p_.p2_adaptive > 0 ? uint32_t(p2k_[k]) : uint32_t(p_.p2);
    const Word wm_p2 = sat_add(wm, Word(p2 > kNone ? kNone : p2));
    // The lanes' minimum, kept off the recurrence through M: with t_d = min(Lr(q,d), Lr(q,d±1) + P1), Lr(p,d) = C_d +
    // min(t_d - M, P2), so min_d Lr(p,d) = min(min_d (C_d + t_d) - M, min_d C_d + P2): both inner minima are
    // independent of M, and the chain from M to the next M is a subtraction and two compare-selects (docs/kernels.md).
    // Software instantiations take min_d Lr(p,d) directly, the same value by that identity (kernels_common_test runs
    // both forms on whole frames): one 16-bit reduction, no widening.
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
        if (!kRotatingPix) pix_[lo + i] = lr[i];
        if (last && chunks_ == 1) next[i] = lr[i];  // the next pixel's predecessor is this one
      } else {
        row_[m][row_word(x_, chunk_)][row_lane(lo, i)] = lr[i];
        // Rows of one or two pixels with one chunk per pixel (software instantiations and exports that narrow): the
        // next firing's predecessor column is the one this firing writes, fetched above before the write; it takes this
        // firing's Lr instead.
        if (kNarrowRows && last && chunks_ == 1) {
          if (k == kKindRowUp && nx == x_) next[i] = lr[i];
          if (k == kKindRowRight && nxr == x_) next[i] = lr[i];
          if (k == kKindRowLeft && nx == x_) lag_[lo + i] = lr[i];
        }
      }
    }
    if (k == kKindPixel) pix_push(lr);
    if (last) {
      if (k == kKindPixel)
        pix_min_ = Word(run_min);
      else
        row_min_[m][x_] = Word(run_min);
    }
    // The next firing's predecessor lanes: its lane lo - 1 is this chunk's last (none before lane 0), its lanes are the
    // ones fetched, and past the last chunk there is no lane.
    pred[0] = last ? Word(kNone) : pred[n];
  agg_ahead:
    for (int i = 0; i < trip; ++i) {
      PX_PRAGMA("HLS UNROLL")
      pred[i + 1] = next[i];
    }
    if (chunk_ + 2 >= chunks_) pred[n + 1] = Word(kNone);
  }

  // Adaptive P2 (docs/algorithm.md §3), at a pixel's first firing: each kind's P2 from the intensity step between this
  // pixel and that kind's predecessor. The previous row's intensities of columns x - 1, x, x + 1 are a window of
  // registers (up_px_): it shifts by one column per pixel, taking column x + 1 fetched by the previous pixel's last
  // firing; a row starts from the previous row's first two columns (head_px_), so the row memory sees one read and one
  // write per pixel (keep_intensity).
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
  // At a pixel's last firing: its intensity becomes the next pixel's predecessor and the next row's (row memory at x,
  // and the row's first two columns in head_px_); the row memory gives column x + 2 of the previous row, the next
  // pixel's x + 1.
  void keep_intensity() {
    prev_px_ = cur_px_;
    if (!kRowKinds && !mgm()) return;
    fetched_px_ = row_px_[min_int(x_ + 2, p_.width_px - 1)];
    row_px_[x_] = cur_px_;
    if (x_ < 2) head_px_[x_] = cur_px_;
  }

  // Lane loops run to PU: the compile-time LANES in the export, where PU = LANES. A software instantiation whose pixel
  // is one chunk (PU = D) runs whole SIMD vectors instead: the lanes past PU are don't-care (written to the unused rest
  // of a column, masked out of the minimum, never read as sums).
  int lane_trip() const {
    return chunks_ == 1 ? Caps::simd_trip(lanes_, kLanes < kMaxD ? kLanes : kMaxD) : Caps::trip(lanes_, kLanes);
  }

  // The row memories' word of column x, chunk c, and the element of lane i of a chunk starting at disparity lo.
  static int row_word(int x, int c) {
    return Caps::fixed ? x * (kMaxD / kLanes) + c : x;
  }
  static int row_lane(int lo, int i) {
    return Caps::fixed ? i : lo + i;
  }

  // a + b, saturating at kNone (the largest value Lr arithmetic needs). Sums that could exceed Word saturate, which
  // cannot change a minimum because Lr(q, d) <= 2^path_bits - 1 is always a candidate and fits.
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
  bool twice_straight_ = false, twice_diagonal_ = false;
  bool add_forward_ = false, tee_cost_ = false;
  int d_ = 1, lanes_ = 1, chunks_ = 1;
  int x_ = 0, y_ = 0, chunk_ = 0;
  bool done_ = true;
  // Per path kind: the predecessor's lanes of this chunk, its lane lo - 1, its minimum M and the running minimum of
  // this pixel's Lr.
  Word ahead_[kKindCount][kLanes + 2];  // [0]: lane lo - 1; [1, PU]: lanes lo..; [PU + 1]: lane lo + PU
  Word mq_[kKindCount];
  uint32_t run_min_[kKindCount];
  Array<Word, kMaxD> pix_;  // pixel path: the previous pixel's Lr (this pixel's, lanes already done)
  // The same in the exported and counting instantiations (kRotatingPix): a shift register of the
  // chunks written, PU entries pushed per firing (pix_push), so lane i reads a fixed entry (PathStore: store.hpp).
  ShiftReg<PathStore, kMaxD, Caps::fixed, Caps::count_accesses> pix_q_;
  Word pix_min_ = 0;             // pixel path: the previous pixel's minimum
  Array<PathStore, kMaxD> lag_;  // row-left path: the previous row's Lr of column x - 1 (x, lanes already read)
  Word mlag_ = 0;                // row-left path: the previous row's minimum of column x - 1
  // Row kinds (and MGM's pixel kind): the previous row's Lr and min_d Lr per column, path_bits wide in the export.
  Array<PathStore, kRowMemories, kRowWords, kRowLanes> row_;
  Array<PathStore, kRowMemories, kMaxW> row_min_;
  // MGM (aggregate_kind_mgm): each datapath's second predecessor lanes and minimum; the row-left datapath's window over
  // its previous row ([0] column x, [1] column x - 1 of the next firing's pixel; lanes of chunks not yet fetched one
  // pixel behind), the row's column 0, and the same for the minima (at the current pixel).
  Word ahead2_[2][kLanes + 2];
  Word mq2_[2];
  Array<Word, 2, kMaxD> win_;
  Array<Word, kMaxD> win_head_;
  Word win_min_[2];
  Word win_head_min_ = 0;
  Word pad_[kLanes];  // software only: all ones in the don't-care lanes past PU (lane_trip)
  // Adaptive P2 (adapt_p2): this pixel's intensity, the previous pixel's, the previous row's (memory, its columns x - 1
  // .. x + 1 in registers, its first two columns), and each kind's P2.
  uint8_t cur_px_ = 0, prev_px_ = 0, fetched_px_ = 0;
  Array<uint8_t, kMaxW> row_px_;
  uint8_t up_px_[3] = {0, 0, 0};
  uint8_t head_px_[2] = {0, 0};
  Word p2k_[kKindCount];

 public:
  // Counting instantiations (access.hpp) of software capacities: the export's row words at this configuration's PU
  // (a column's D lanes in D/PU words of PU), stated at run time after configure().
  void count_row_layout() {
    access_reshape(row_, "row_path", Caps::fixed ? 0 : lanes_, 3);
    access_bind(row_, "row_path", kStorageRamS2p);
  }
  // Storage descriptor (resources.hpp) of the members above, per active path kind, with the path-cost width: the pixel
  // path's pix_ (D) and pix_min_; a row kind's row memory row_[kind - 1] (a word of PU lanes per chunk, W x D/PU deep)
  // and its row minima row_min_[kind - 1] (W deep); the row-left kind's lag_ (D) and mlag_; every kind's ahead_ (PU),
  // edge_, mq_ and run_min_.
  template <class V>
  void storage(V& v) const;  // defined in sgm_resources.hpp

 private:
  // MGM's state (aggregate_kind_mgm), no hardware with SGM: per datapath the second predecessor's lanes and minimum;
  // the pixel datapath's row memory (mapped as the row kinds'); the row-left datapath's window, head column and their
  // minima.
  template <class V>
  void mgm_storage(V& v, int64_t words) const {
    const int pb = path_bits(p_);
    const bool on = mgm();
    const unsigned dk = datapaths();
    const int pixel = row_memory(kKindPixel);
    if (on && (dk & (1u << kKindPixel)) != 0) {
      v.memory("row_path_pixel", row_[pixel], words, lanes_ * pb, 1, false, lanes_);
      v.memory("row_min_pixel", row_min_[pixel], p_.width_px, pb, 1, false, 1);
    } else {
      v.unused("row_path", row_[pixel]);
      v.unused("row_min", row_min_[pixel]);
    }
  agg_mgm_storage_kinds:
    for (int k = 0; k < 2; ++k) {  // the datapaths: kKindPixel, kKindRowLeft
      if (on && ((dk >> k) & 1u) != 0) {
        v.registers_part("mgm_second_lanes", ahead2_[k], lanes_ + 1, pb);
        v.registers("mgm_second_min", mq2_[k], 1, pb);
      } else {
        v.unused("mgm_second_lanes", ahead2_[k]);
        v.unused("mgm_second_min", mq2_[k]);
      }
    }
    if (on && (dk & (1u << kKindRowLeft)) != 0) {
      v.registers("mgm_row_window", win_, 2 * d_, pb);
      v.registers("mgm_row_head", win_head_, d_, pb);
      v.registers("mgm_row_window_min", win_min_, 2, pb);
      v.registers("mgm_row_head_min", win_head_min_, 1, pb);
    } else {
      v.unused("mgm_row_window", win_);
      v.unused("mgm_row_head", win_head_);
      v.unused("mgm_row_window_min", win_min_);
      v.unused("mgm_row_head_min", win_head_min_);
    }
  }

  // The adaptive P2's state (adapt_p2): no hardware without it; the row intensities only with a row kind active.
  template <class V>
  void intensity_storage(V& v) const;  // sgm_resources.hpp
};

}  // namespace kern
}  // namespace parallax

#include "parallax/kernels/sgm_resources.hpp"
