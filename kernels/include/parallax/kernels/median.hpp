// k x k median of disparity codes (docs/algorithm.md §5): clamped border, output = element of
// rank (k*k - 1) / 2 of the sorted window, invalid code D sorting above every valid code.
// Reads and writes one code per firing in steady state (II = 1); the last k/2 rows are emitted
// after the input has ended. k = 0 or 1 passes codes through. C++14 synthesisable subset.
#pragma once

#include "parallax/kernels/caps.hpp"
#include "parallax/kernels/common.hpp"
#include "parallax/kernels/line_buffer.hpp"

namespace parallax {
namespace kern {

struct MedianPlan {
  bool read;   // one input code
  bool write;  // one output code
  bool prime;  // a prologue step of the window registers (the start of a row), no output
};

// Keys wider than 16 bits (codes with sub-pixel fractions, disparity_bits + 6 > 16): the export
// defines it for its design (a compile-time choice there); software instantiations decide at
// run time.
#ifndef PX_MEDIAN_WIDE_KEYS
#define PX_MEDIAN_WIDE_KEYS 0
#endif

template <class Caps>
class Median {
 public:
  static constexpr int kRows = Caps::median_rows;  // line-buffer slots: the window's k rows

  void configure(const StereoParams& p) {
    k_ = p.median >= 3 ? p.median : 1;
    wide_ = disparity_bits(p) + kKeyIndexBits > 16;
    r_ = k_ / 2;
    width_px_ = p.width_px;
    height_px_ = p.height_px;
    lb_.name("median_line_buffer");
    lb_.configure(p.width_px, p.height_px, k_);
    start_frame();
  }
  void start_frame() {
    lb_.reset();
    x_ = 0;
    y_ = 0;
    prime_ = 0;
    corner_.start(r_, height_px_, r_);
    done_ = false;
  }
  bool done() const { return done_; }

  MedianPlan plan() const {
    PX_PRAGMA("HLS INLINE")
    MedianPlan pl;
    // A row starts with r prologue steps of the window registers (positions -r .. -1).
    const bool priming = !done_ && x_ == 0 && prime_ < r_;
    // The window's last pixel is counted (corner_: window_ready(prime_ - r_ or x_, y_, r_, r_)).
    pl.prime = priming && lb_.corner_resident(corner_);
    pl.write = !priming && !done_ && lb_.corner_resident(corner_);
    pl.read = !pl.prime && lb_.input_allowed(corner_);  // as CostStage::plan()
    return pl;
  }

  template <class InS, class OutS>
  void fire(const MedianPlan& pl, InS& in, OutS& out) {
    PX_PRAGMA("HLS INLINE")
    // One window step per firing (one read per row memory): a prologue position or an output.
    if (pl.prime || (pl.write && k_ > 1)) win_.step_to(lb_, pl.prime ? prime_ - r_ : x_, y_, k_, k_, r_);
    if (pl.prime) prime_step();
    if (pl.write) {
      // Only the sizes the window registers hold are instantiated (kRows = k of the export).
      out.write(k_ == 1                     ? lb_.at_clamped(x_, y_)
                : k_ == 3                   ? window_median < kRows < 3 ? 1 : 3 > ()
                                  : k_ == 5 ? window_median < kRows < 5 ? 1 : 5 > ()
                                  : window_median < kRows < 7 ? 1
                                            : 7 > ());
      advance();
    }
    if (pl.read) lb_.push(in.read());
  }

  // The control path of fire(pl) alone (see CostStage::step).
  void step(const MedianPlan& pl) {
    if (pl.prime) prime_step();
    if (pl.write) advance();
    if (pl.read) lb_.skip_push();
  }

  // Control-state access for a scheduler that advances periodic rows at once (sim/, never
  // synthesised): visit(v) calls v(field) on every counter of the control path, by reference;
  // resync() recomputes the fields derived from them after a visitor wrote them.
  template <class V>
  void visit(V& v) {
    v(x_);
    v(y_);
    v(prime_);
    v(done_);
    lb_.visit(v);
  }
  void resync() {
    lb_.resync();
    corner_.sync(y_, r_, x_, prime_, r_, width_px_, height_px_);
  }

  // Schedule of one firing (resources.hpp): the raster counters (the line buffer's accesses are
  // counted: accesses.hpp).
  template <class S>
  void schedule(S& s) const {
    s.recurrence("raster_counters", 1);
    s.chain(kOpAdd, bits_for(uint64_t(width_px_)), 1);
    s.chain(kOpCompare, bits_for(uint64_t(width_px_)), 1);
    s.chain(kOpRegister, bits_for(uint64_t(width_px_)), 1);
    WindowCorner::schedule(s, width_px_);  // the plan and the corner (issue 41, N3)
  }

  // Resources of this configuration (resources.hpp) for values of value_bits: the k-row line
  // buffer, the k x k window, and the rank network over n = k*k keys (the value and the window
  // index): one comparator per pair of keys, n(n-1)/2, since the keys are distinct and a < b is
  // !(b < a); per key a popcount of the n - 1 comparisons that rank it; n equality tests against
  // the median rank and a select.
  template <class R>
  void declare(R& r, int value_bits) const {
    declare_raster_control(r, width_px_, height_px_, 1);
    WindowCorner::declare(r, width_px_, height_px_);
    declare_storage(r, *this, value_bits);
    if (k_ > 1) lb_.declare_row_selects(r, k_, value_bits);
    const RankNetwork net = rank_network();
    if (net.keys > 1) {
      // Keys: the value and the window index (bits_for(n - 1) of the kKeyIndexBits the key
      // reserves); a rank counts the comparisons its key takes part in.
      r.op("rank_compares", kOpCompare, value_bits + bits_for(uint64_t(net.keys - 1)), net.pairs);
      r.op("rank_counts", kOpPopcount, net.max_per_key, net.keys);
      r.op("rank_pick", kOpCompare, bits_for(uint64_t(net.keys)), net.keys);
      r.mux("rank_select", value_bits, net.keys, 1);  // the key whose rank is the median's, one-hot
    }
    r.registers("median_out", value_bits, 1);
  }

  // Storage descriptor (resources.hpp) of the members: the k-row line buffer (one memory per
  // row) and the k x k window registers.
  template <class V>
  void storage(V& v, int value_bits) const {
    lb_.storage(v, "median_line_buffer", value_bits);
    win_.storage(v, "median_window", k_, k_, value_bits);
  }

  // The rank network the instantiation builds for its k (the dispatch of fire()): the
  // comparators rank_pairs<n>() visits (n(n-1)/2), the keys and the most comparisons one key
  // takes part in; none for k = 1 (pass-through).
  struct RankNetwork {
    int keys, pairs, max_per_key;
  };
  RankNetwork rank_network() const {
    PairCount c;
    if (k_ == 3)
      rank_pairs<fitted(3) * fitted(3)>(c);
    else if (k_ == 5)
      rank_pairs<fitted(5) * fitted(5)>(c);
    else if (k_ > 1)
      rank_pairs<fitted(7) * fitted(7)>(c);
    RankNetwork n;
    n.keys = c.keys;
    n.pairs = c.pairs;
    n.max_per_key = 0;
    for (int a = 0; a < c.keys; ++a) n.max_per_key = c.per_key[a] > n.max_per_key ? c.per_key[a] : n.max_per_key;
    return n;
  }
  // Bits of a key below the code: the window index (code << kKeyIndexBits | index).
  static constexpr int kKeyIndexBits = 6;

 private:
  // Rank selection by counting on distinct keys (code * 64 + window index): the keys are a
  // permutation-free total order, so exactly one has (k*k - 1) / 2 smaller keys, and its code
  // is the median; no data-dependent control flow. The exported (FIXED) instantiation builds the
  // network synthesis should see: one comparator per pair of keys, n(n-1)/2, each counting for
  // both keys (a < b is !(b < a) for distinct keys), as the resource model declares. Software
  // instantiations count the same ranks with all n x n comparisons over 32-lane vectors (twice
  // the comparisons, a tenth of the time on a CPU); the equivalence tests run the software form
  // and the exported C simulation the pair form, both against one golden model.
  template <int K>
  DispCode window_median() const {
    const bool wide = Caps::fixed ? PX_MEDIAN_WIDE_KEYS != 0 : wide_;  // a constant in the export
    return wide ? rank_median<K, uint32_t>() : rank_median<K, uint16_t>();
  }
  template <int K, class Key>
  DispCode rank_median() const {
    static_assert(K <= kRows, "the window registers hold k x k codes");
    const int kN = K * K;
    const int kPad = (kN + 31) / 32 * 32;  // lanes padded with keys above every real key
    Key key[kPad];
    uint16_t smaller[kPad];
  median_gather:
    for (int a = 0; a < kPad; ++a) {
      PX_PRAGMA("HLS UNROLL")
      key[a] = a < kN ? Key((Key(win_.at(a % K, a / K)) << kKeyIndexBits) | Key(a)) : Key(~Key(0));
      smaller[a] = 0;
    }
    if (Caps::fixed) {
      RankPair<kPad, Key> pair(key, smaller);
      rank_pairs<kN>(pair);
    } else {
    median_count:
      for (int b = 0; b < kN; ++b) {
        const Key kb = key[b];
      median_count_lanes:
        for (int a = 0; a < kPad; ++a) smaller[a] = uint16_t(smaller[a] + (kb < key[a] ? 1 : 0));
      }
    }
    const int want = (kN - 1) / 2;
    DispCode result = 0;
  median_pick:
    for (int a = 0; a < kN; ++a) {
      PX_PRAGMA("HLS UNROLL")
      if (smaller[a] == want) result = DispCode(key[a] >> kKeyIndexBits);
    }
    return result;
  }

  // The pair network of n keys: one comparator per pair a < b, visited by the loops the exported
  // (FIXED) instantiation unrolls; declare() counts the comparators with the same loops.
  template <int N, class F>
  static PX_INLINE void rank_pairs(F& f) {
  median_pairs:
    for (int a = 0; a < N; ++a) {
      PX_PRAGMA("HLS UNROLL")
    median_pairs_inner:
      for (int b = 0; b < N; ++b) {
        PX_PRAGMA("HLS UNROLL")
        if (b > a) f(a, b);
      }
    }
  }
  // A comparator of the network: each comparison counts for both keys (a < b is !(b < a) for
  // distinct keys).
  template <int P, class Key>
  struct RankPair {
    const Key (&key)[P];
    uint16_t (&smaller)[P];
    RankPair(const Key (&k)[P], uint16_t (&s)[P]) : key(k), smaller(s) {}
    PX_INLINE void operator()(int a, int b) {
      const int a_smaller = key[a] < key[b] ? 1 : 0;
      smaller[b] = uint16_t(smaller[b] + a_smaller);
      smaller[a] = uint16_t(smaller[a] + 1 - a_smaller);
    }
  };
  // Counts the comparators of the network (declarations only).
  struct PairCount {
    int keys = 0, pairs = 0;
    int per_key[kMaxMedian * kMaxMedian] = {};
    void operator()(int a, int b) {
      ++pairs;
      ++per_key[a];
      ++per_key[b];
      keys = b + 1 > keys ? b + 1 : keys;
    }
  };
  // The window size the registers hold for a median of k (fire(): only those are instantiated).
  static constexpr int fitted(int k) { return kRows < k ? 1 : k; }

  void prime_step() {
    ++prime_;
    corner_.next_col(width_px_);
  }
  void advance() {
    if (++x_ == width_px_) {
      x_ = 0;
      prime_ = 0;
      corner_.next_row(height_px_, r_);
      if (++y_ == height_px_) done_ = true;
    } else {
      corner_.next_col(width_px_);
      corner_.next_output_col();
    }
  }

  int k_ = 1, r_ = 0, width_px_ = 0, height_px_ = 0;
  bool wide_ = false;  // rank keys of 32 bits (PX_MEDIAN_WIDE_KEYS)
  int x_ = 0, y_ = 0;
  int prime_ = 0;        // prologue steps of this row's window registers done (of r)
  WindowCorner corner_;  // the last pixel the next window step needs
  bool done_ = true;
  LineBuffer<DispCode, Caps::max_width_px, kRows, Caps::count_accesses, typename Caps::store::code> lb_;
  WindowRegs<DispCode, kRows, kRows, Caps::fixed> win_;  // the k x k window registers of the output position
};

}  // namespace kern
}  // namespace parallax
