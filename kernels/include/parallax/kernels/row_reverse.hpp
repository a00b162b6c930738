// Row reversal: the stream order of a one-pass design with the 180-degree path (docs/kernels.md,
// "The 180-degree path in one pass"). The 180-degree path runs right to left within a row, so
// it can start only when its row is complete, as in OpenCV's single-pass MODE_SGBM: the forward
// aggregation's costs and sums of a row go into a row memory, leave it with the row's pixels in
// reverse order (each pixel's chunks still ascending), and a second SgmAggregate with the pixel
// kind alone adds the 180-degree path on that stream. The WTA / left-right check runs in its
// reverse mode on it, the median on the mirrored rows (a k x k median with clamped borders
// commutes with mirroring), and a second reversal of the codes restores raster order for the
// output.
//
// One memory per stream, a row deep: a firing emits token t of row y and stores token t of row
// y + 1 at the same address (read before write, within the firing). Rows alternate their layout:
// an even row's pixel x lives in slot x, an odd row's in slot W - 1 - x, so reading row y
// backwards visits the slots in the order row y + 1 fills them. The first row is only read in,
// the last only emitted; in between, input and output advance in lock step, so a row leaves as
// the next one arrives (one row of latency).
//
// Dependences between firings: pixel x of a row is written at stream position x and read back,
// in the next row's emission, (2W - 1 - 2x) pixels later, i.e. (2W - 1 - 2x) x C firings (C =
// D/PU tokens per pixel). The last pixel (x = W - 1) would come back C firings after it was
// written, as little as one firing: it bypasses the memory through registers (its C tokens, the
// first the next emission reads). Every slot of the memory is then read at least 3C >= 3
// firings after its write, more than the firing's depth from read to write, so the memory
// carries no dependence between firings (DEPENDENCE inter false); the registers carry theirs as
// registers do. C++14 synthesisable subset.
#pragma once

#include "parallax/kernels/access.hpp"
#include "parallax/kernels/caps.hpp"
#include "parallax/kernels/common.hpp"
#include "parallax/kernels/resources.hpp"

namespace parallax {
namespace kern {

struct RowReversePlan {
  bool read;   // one token of the next row in
  bool write;  // one token of the buffered row out
  bool prime;  // always false
};

// The counters of a row reversal of rows of W pixels, `per_px` tokens per pixel.
class RowReverseControl {
 public:
  void configure(int width_px, int height_px, int per_px) {
    w_ = width_px;
    h_ = height_px;
    per_px_ = per_px;
    start_frame();
  }
  void start_frame() {
    in_x_ = in_c_ = in_row_ = 0;
    out_j_ = out_c_ = out_row_ = 0;
  }
  bool done() const { return out_row_ >= h_; }
  RowReversePlan plan() const {
    PX_PRAGMA("HLS INLINE")
    RowReversePlan pl;
    pl.prime = false;
    pl.read = in_row_ < h_;
    pl.write = out_row_ < in_row_;  // a whole row is buffered
    return pl;
  }
  // Slot of the next input token's pixel (image column in_x_ of row in_row_).
  int in_slot() const { return (in_row_ & 1) == 0 ? in_x_ : w_ - 1 - in_x_; }
  int in_chunk() const { return in_c_; }
  // Slot of the next output token's pixel: stream position out_j_ is image column W - 1 - out_j_.
  int out_slot() const { return (out_row_ & 1) == 0 ? w_ - 1 - out_j_ : out_j_; }
  int out_chunk() const { return out_c_; }
  // The input token is of a row's last pixel, the output token of a row's first stream pixel
  // (image column W - 1): the bypass registers' tokens.
  bool in_last() const { return in_x_ + 1 == w_; }
  bool out_first() const { return out_j_ == 0; }
  void advance(const RowReversePlan& pl) {
    if (pl.read) step(in_x_, in_c_, in_row_);
    if (pl.write) step(out_j_, out_c_, out_row_);
  }
  template <class V>
  void visit(V& v) {
    v(in_x_);
    v(in_c_);
    v(in_row_);
    v(out_j_);
    v(out_c_);
    v(out_row_);
  }
  // Control: input and output pixel, chunk and row counters with their end compares, the two
  // slot subtractions and their selects.
  template <class R>
  void declare(R& r) const {
    const int xb = bits_for(uint64_t(w_));
    declare_raster_control(r, w_, h_, per_px_);
    declare_raster_control(r, w_, h_, per_px_);
    r.op("row_reverse_slot", kOpAdd, xb, 2);
    r.op("row_reverse_slot_select", kOpMux, xb, 2);
    r.op("row_reverse_plan", kOpCompare, bits_for(uint64_t(h_)), 2);
    r.op("row_reverse_bypass_test", kOpCompare, xb, 2);
  }

 private:
  void step(int& px, int& c, int& row) const {
    if (++c < per_px_) return;
    c = 0;
    if (++px < w_) return;
    px = 0;
    ++row;
  }
  int w_ = 1, h_ = 0, per_px_ = 1;
  int in_x_ = 0, in_c_ = 0, in_row_ = 0;
  int out_j_ = 0, out_c_ = 0, out_row_ = 0;
};

// What both reversals share: the control and its entry points (a stage's plan, step, visit).
class RowReverseStage {
 public:
  void start_frame() { ctl_.start_frame(); }
  bool done() const { return ctl_.done(); }
  RowReversePlan plan() const {
    PX_PRAGMA("HLS INLINE")
    return ctl_.plan();
  }
  void step(const RowReversePlan& pl) { ctl_.advance(pl); }
  template <class V>
  void visit(V& v) {
    ctl_.visit(v);
  }
  void resync() {}

 protected:
  RowReverseControl ctl_;
};

// The costs and forward sums of the aggregation, reversed row by row: two input and two output
// streams, one token of each per firing (the pair travels together). Memories cost_ and sum_: a
// FIXED instantiation keeps each chunk's PU lanes as one word, [W][D/PU][PU] reshaped in its
// last dimension (W x D/PU words of PU lanes); software instantiations run any PU up to their
// lanes and keep a row's lanes flat, [W][D][1]. One read and one write per firing on a simple
// dual-port RAM. The last pixel's tokens go through the bypass registers last_cost_ / last_sum_
// (D lanes) instead. A slot is always written by its row before the row reads it back, so
// nothing needs clearing.
template <class Caps, class Word>
class RowReverse : public RowReverseStage {
 public:
  typedef CostLanes<Caps::lanes> CostToken;
  typedef Lanes<Word, Caps::lanes> SumToken;
  // Element types of the memories and bypass registers (store.hpp): cost_bits and aggregate_bits wide in the export.
  typedef typename Caps::store::cost CostStore;
  typedef typename Caps::store::template sum<Word>::type SumStore;
  static constexpr int kMaxW = Caps::max_width_px;
  static constexpr int kMaxD = Caps::max_disparities;
  static constexpr int kLanes = Caps::lanes;
  // A word holds a chunk's PU lanes (the export) or, in software instantiations, the pixel's
  // whole column: either way the lanes of one firing are one word, one access (counted).
  static constexpr int kWords = Caps::fixed ? kMaxD / kLanes : 1;  // words per pixel
  static constexpr int kPerWord = Caps::fixed ? kLanes : kMaxD;    // lanes per word

  RowReverse() {
    PX_RESHAPE_COMPLETE(cost_, 3)
    PX_RESHAPE_COMPLETE(sum_, 3)
#ifdef PX_HLS_ROW_REVERSE_COST_STORAGE
    PX_PRAGMA(PX_HLS_ROW_REVERSE_COST_STORAGE)
    PX_PRAGMA(PX_HLS_ROW_REVERSE_SUM_STORAGE)
    PX_COUNT_BIND(cost_, kStorageRamS2p)
    PX_COUNT_BIND(sum_, kStorageRamS2p)
#else
    PX_BIND_RAM_S2P_ANY(cost_)
    PX_BIND_RAM_S2P_ANY(sum_)
#endif
    PX_BIND_RAM_S2P_ANY(px_)
    PX_PARTITION_COMPLETE(last_cost_, 1)
    PX_PARTITION_COMPLETE(last_sum_, 1)
    access_name(cost_, "row_reverse_cost");
    access_name(sum_, "row_reverse_sum");
    access_name(px_, "row_reverse_intensity");
    access_name(last_cost_, "row_reverse_last_cost");
    access_name(last_sum_, "row_reverse_last_sum");
  }

  void configure(const StereoParams& p) {
    p_ = p;
    d_ = Caps::disparities(p.disparities);
    lanes_ = Caps::parallel_units(p.parallel_units);
    ctl_.configure(p.width_px, p.height_px, d_ / lanes_);
  }

  // One firing: the buffered row's next token out (read first), then the next row's token in,
  // at the same address when both happen (or the same bypass registers, when W = 1).
  template <class CostIn, class SumIn, class CostOut, class SumOut>
  void fire(const RowReversePlan& pl, CostIn& cost_in, SumIn& sum_in, CostOut& cost_out, SumOut& sum_out) {
    PX_PRAGMA("HLS INLINE")
    PX_NO_DEPENDENCE(cost_)
    PX_NO_DEPENDENCE(sum_)
    PX_NO_DEPENDENCE(px_)
    const int trip = Caps::trip(lanes_, kLanes);
    if (pl.write) {
      const int xs = ctl_.out_slot();
      const int c = ctl_.out_chunk();
      const bool bypass = ctl_.out_first();
      CostToken ct;
      SumToken st;
      // The pixel's intensity: read with its first token (before this firing's input may
      // overwrite the slot at its last one), held for the others.
      if (c == 0) out_px_ = bypass ? last_px_ : px_[xs];
      ct.px = out_px_;
    row_reverse_out:
      for (int i = 0; i < trip; ++i) {
        PX_PRAGMA("HLS UNROLL")
        const int w = Caps::fixed ? c : 0, l = Caps::fixed ? i : c * lanes_ + i;
        ct.v[i] = bypass ? from_store<uint16_t>(last_cost_[c * lanes_ + i]) : from_store<uint16_t>(cost_[xs][w][l]);
        st.v[i] = bypass ? from_store<Word>(last_sum_[c * lanes_ + i]) : from_store<Word>(sum_[xs][w][l]);
      }
      cost_out.write(ct);
      sum_out.write(st);
    }
    if (pl.read) {
      const CostToken ct = cost_in.read();
      const SumToken st = sum_in.read();
      const int xs = ctl_.in_slot();
      const int c = ctl_.in_chunk();
      const bool bypass = ctl_.in_last();
      if (c + 1 == d_ / lanes_) {  // the intensity, with the pixel's last token
        if (bypass)
          last_px_ = ct.px;
        else
          px_[xs] = ct.px;
      }
    row_reverse_in:
      for (int i = 0; i < trip; ++i) {
        PX_PRAGMA("HLS UNROLL")
        const int w = Caps::fixed ? c : 0, l = Caps::fixed ? i : c * lanes_ + i;
        if (bypass) {
          last_cost_[c * lanes_ + i] = ct.v[i];
          last_sum_[c * lanes_ + i] = st.v[i];
        } else {
          cost_[xs][w][l] = ct.v[i];
          sum_[xs][w][l] = st.v[i];
        }
      }
    }
    ctl_.advance(pl);
  }

  // Schedule of one firing: no recurrence (the bypass registers are written by the last pixel and
  // read by the first, never a chain within one firing); the memories' accesses are counted.
  template <class S>
  void schedule(S&) const {}
  template <class R>
  void declare(R& r) const {
    const int cb = cost_bits(p_), ab = aggregate_bits(p_);
    ctl_.declare(r);
    declare_storage(r, *this);
    r.registers("row_reverse_tokens", lanes_ * (cb + ab), 1);
    // Per lane: the bypass registers' D/PU-input read and the choice between them and the memory.
    const int chunks = d_ / lanes_;
    if (chunks > 1) r.op("row_reverse_bypass_read", kOpMux, cb + ab, lanes_ * (chunks - 1));
    r.op("row_reverse_bypass_select", kOpMux, cb + ab, lanes_);
  }
  // Storage descriptor: the two row memories (W x D / PU words of PU lanes each) and the bypass
  // registers of the last pixel (D lanes).
  template <class V>
  void storage(V& v) const {
    const int64_t words = int64_t(p_.width_px) * (d_ / lanes_);
    v.memory("row_reverse_cost", cost_, words, lanes_ * cost_bits(p_), 1, false, lanes_);
    v.memory("row_reverse_sum", sum_, words, lanes_ * aggregate_bits(p_), 1, false, lanes_);
    v.registers_part("row_reverse_last_cost", last_cost_, d_, cost_bits(p_));
    v.registers_part("row_reverse_last_sum", last_sum_, d_, aggregate_bits(p_));
    if (p_.p2_adaptive > 0) {  // the intensities the 180-degree path's adaptive P2 reads
      v.memory("row_reverse_intensity", px_, p_.width_px, 8, 1, false, 1);
      v.registers("row_reverse_last_intensity", last_px_, 1, 8);
      v.registers("row_reverse_out_intensity", out_px_, 1, 8);
    } else {
      v.unused("row_reverse_intensity", px_);
      v.unused("row_reverse_last_intensity", last_px_);
      v.unused("row_reverse_out_intensity", out_px_);
    }
  }

 private:
  StereoParams p_;
  int d_ = 1, lanes_ = 1;
  template <class T, int... N>
  using Array = typename ArrayOf<Caps::count_accesses, T, N...>::type;
  Array<CostStore, kMaxW, kWords, kPerWord> cost_;
  Array<SumStore, kMaxW, kWords, kPerWord> sum_;
  Array<CostStore, kMaxD> last_cost_;
  Array<SumStore, kMaxD> last_sum_;
  Array<uint8_t, kMaxW> px_;  // the buffered row's left intensities, one per pixel slot
  uint8_t last_px_ = 0, out_px_ = 0;
};

// The disparity codes reversed row by row (raster order again after a row-reversed back end):
// one code in and one out per firing, one memory of W codes; the last pixel's code bypasses it
// through a register (C = 1 above: the memory's slots come back at least 3 firings later).
template <class Caps>
class RowReverseCodes : public RowReverseStage {
 public:
  static constexpr int kMaxW = Caps::max_width_px;

  RowReverseCodes() {
#ifdef PX_HLS_ROW_REVERSE_CODES_STORAGE
    PX_PRAGMA(PX_HLS_ROW_REVERSE_CODES_STORAGE)
    PX_COUNT_BIND(codes_, kStorageRamS2p)
#else
    PX_BIND_RAM_S2P_ANY(codes_)
#endif
    access_name(codes_, "row_reverse_codes");
  }

  void configure(const StereoParams& p) {
    p_ = p;
    ctl_.configure(p.width_px, p.height_px, 1);
  }

  template <class In, class Out>
  void fire(const RowReversePlan& pl, In& in, Out& out) {
    PX_PRAGMA("HLS INLINE")
    PX_NO_DEPENDENCE(codes_)
    if (pl.write) out.write(ctl_.out_first() ? last_ : from_store<DispCode>(codes_[ctl_.out_slot()]));
    if (pl.read) {
      const DispCode c = in.read();
      if (ctl_.in_last())
        last_ = c;
      else
        codes_[ctl_.in_slot()] = c;
    }
    ctl_.advance(pl);
  }

  // No recurrence; the memory's accesses are counted.
  template <class S>
  void schedule(S&) const {}
  template <class R>
  void declare(R& r) const {
    ctl_.declare(r);
    declare_storage(r, *this);
    r.op("row_reverse_bypass_select", kOpMux, disparity_bits(p_), 1);
  }
  template <class V>
  void storage(V& v) const {
    v.memory("row_reverse_codes", codes_, p_.width_px, disparity_bits(p_), 1, false, 1);
    v.registers("row_reverse_last_code", last_, 1, disparity_bits(p_));
  }

 private:
  StereoParams p_;
  typename ArrayOf<Caps::count_accesses, typename Caps::store::code, kMaxW>::type codes_;  // disparity_bits wide
  DispCode last_ = 0;
};

}  // namespace kern
}  // namespace parallax
