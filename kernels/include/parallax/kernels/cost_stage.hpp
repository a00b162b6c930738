// Matching-cost stage: streams the left and right pixels (raster order) into line buffers and
// emits, for every left pixel in raster order, D matching costs in D/PU firings of PU lanes.
// The cost function is a policy (census.hpp, sad.hpp). C++14 synthesisable subset.
#pragma once

#include "parallax/kernels/caps.hpp"
#include "parallax/kernels/common.hpp"
#include "parallax/kernels/line_buffer.hpp"

namespace parallax {
namespace kern {

// What the next firing of a cost stage does. Contract: plan() is const and cheap; fire() does
// exactly what the plan said, and a plan with neither flag set never occurs before done().
struct CostPlan {
  bool read;   // reads one pixel from each of the left and right input streams
  bool write;  // writes one token of PU costs
  bool prime;  // a prologue step of the window registers (the start of a row), no output
};

template <class Caps, class Matcher>
class CostStage {
 public:
  typedef CostLanes<Caps::lanes> Token;
  static constexpr int kRows = Caps::window_rows;  // line-buffer slots: the window's rows

  void configure(const StereoParams& p) {
    p_ = p;
    rx_ = p.window_w / 2;
    ry_ = p.window_h / 2;
    lanes_ = p.parallel_units;
    chunks_ = p.disparities / p.parallel_units;
    left_.name("left_line_buffer");
    right_.name("right_line_buffer");
    left_.configure(p.width_px, p.height_px, p.window_h);
    right_.configure(p.width_px, p.height_px, p.window_h);
    matcher_.configure(p);
    start_frame();
  }
  void start_frame() {
    left_.reset();
    right_.reset();
    x_ = 0;
    y_ = 0;
    chunk_ = 0;
    prime_ = 0;
    corner_.start(ry_, p_.height_px, matcher_.columns_behind());
    out_done_ = false;
  }
  bool done() const { return out_done_; }

  CostPlan plan() const {
    PX_PRAGMA("HLS INLINE")
    CostPlan pl;
    pl.prime = false;
    if (chunk_ != 0) {  // the rest of a pixel's chunks: its window was ready at chunk 0
      pl.write = true;
      pl.read = false;
      return pl;
    }
    // A row starts with rx prologue steps of the window registers (positions -rx .. -1), each
    // once its column is resident; then the outputs.
    if (!out_done_ && x_ == 0 && prime_ < rx_) {
      pl.prime = left_.corner_resident(corner_);  // window_ready(prime_ - rx_, y_, rx_, ry_)
      pl.write = false;
    } else {
      pl.write = !out_done_ && left_.corner_resident(corner_);  // window_ready(x_, y_, rx_, ry_)
    }
    // A prologue step reads no input: a row then takes as many input pixels as it has outputs, so
    // the input does not drift ahead row after row (the schedule stays periodic).
    pl.read = !pl.prime && left_.input_allowed(corner_) && (chunk_ == 0 || !pl.write);
    return pl;
  }

  template <class InS, class OutS>
  void fire(const CostPlan& pl, InS& left_in, InS& right_in, OutS& out) {
    PX_PRAGMA("HLS INLINE")
    // One window step per firing (one read per row memory): a prologue position or the pixel's
    // first chunk, never both (plan()).
    const bool pixel = pl.write && chunk_ == 0;
    if (pl.prime || pixel) matcher_.prime(left_, right_, pixel ? x_ : prime_ - rx_, y_);
    if (pl.prime) prime_step();
    if (pl.write) {
      if (pixel) matcher_.begin_pixel(left_, right_, x_, y_);
      Token t;
      const int d0 = chunk_ * lanes_;
      matcher_.costs(left_, right_, x_, y_, d0, lanes_, t.v);
      t.px = matcher_.centre_px();
      out.write(t);
      advance();
    }
    if (pl.read) {
      left_.push(left_in.read());
      right_.push(right_in.read());
    }
  }

  // The control path of fire(pl) alone: the counters advance exactly as fire(pl) advances them,
  // no pixel is stored and no cost computed. plan() after step(pl) equals plan() after fire(pl),
  // so a scheduler can time the stage without its datapath (the cycle model's timing run).
  void step(const CostPlan& pl) {
    if (pl.prime) prime_step();
    if (pl.write) advance();
    if (pl.read) {
      left_.skip_push();
      right_.skip_push();
    }
  }

  const StereoParams& params() const { return p_; }

  // Control-state access for a scheduler that advances periodic rows at once (sim/, never
  // synthesised): visit(v) calls v(field) on every counter of the control path, by reference;
  // resync() recomputes the fields derived from them after a visitor wrote them.
  template <class V>
  void visit(V& v) {
    v(x_);
    v(y_);
    v(chunk_);
    v(prime_);
    v(out_done_);
    left_.visit(v);
    right_.visit(v);
  }
  void resync() {
    left_.resync();
    right_.resync();
    corner_.sync(y_, ry_, x_, prime_, matcher_.columns_behind(), p_.width_px, p_.height_px);
  }

  // Resources of this configuration (resources.hpp): raster control, the two line buffers of
  // the window's rows, the matcher's datapath, the output token.
  template <class R>
  void declare(R& r) const {
    declare_raster_control(r, p_.width_px, p_.height_px, chunks_);
    WindowCorner::declare(r, p_.width_px, p_.height_px);
    left_.declare(r, "left_line_buffer", 8);
    right_.declare(r, "right_line_buffer", 8);
    left_.declare_row_selects(r, 2 * ry_ + 1, 8);
    right_.declare_row_selects(r, 2 * ry_ + 1, 8);
    matcher_.declare(r, p_);
    r.registers("cost_token", lanes_ * cost_bits(p_), 1);
  }

  // Schedule of one firing (resources.hpp): the raster counters are the only recurrence (the
  // line buffers' accesses are counted: accesses.hpp).
  template <class S>
  void schedule(S& s) const {
    matcher_.schedule(s, p_);
    s.recurrence("raster_counters", 1);
    s.chain(kOpAdd, bits_for(uint64_t(chunks_)), 1);
    s.chain(kOpCompare, bits_for(uint64_t(chunks_)), 1);
    s.chain(kOpRegister, bits_for(uint64_t(chunks_)), 1);
    WindowCorner::schedule(s, p_.width_px);  // the plan and the corner (issue 41, N3)
  }

 private:
  void prime_step() {
    ++prime_;
    corner_.next_col(p_.width_px);
  }
  void advance() {
    if (++chunk_ < chunks_) return;
    chunk_ = 0;
    if (++x_ < p_.width_px) {
      corner_.next_col(p_.width_px);
      corner_.next_output_col();
      return;
    }
    x_ = 0;
    prime_ = 0;
    corner_.next_row(p_.height_px, matcher_.columns_behind());
    if (++y_ < p_.height_px) return;
    out_done_ = true;
  }

  StereoParams p_;
  int rx_ = 0, ry_ = 0, lanes_ = 1, chunks_ = 1;
  int x_ = 0, y_ = 0, chunk_ = 0;
  int prime_ = 0;        // prologue steps of this row's window registers done (of rx)
  WindowCorner corner_;  // the last pixel the next window step needs
  bool out_done_ = true;
  LineBuffer<uint8_t, Caps::max_width_px, kRows, Caps::count_accesses> left_;
  LineBuffer<uint8_t, Caps::max_width_px, kRows, Caps::count_accesses> right_;
  Matcher matcher_;  // mutable state: cost() may keep running sums

 public:
  // Storage descriptor (resources.hpp) of the members above: the two line buffers (the window's
  // rows, one memory per row) and the matcher's registers and memories; declare() declares
  // exactly these (the line buffers here, the matcher's in its own declare()).
  template <class V>
  void storage(V& v) const {
    left_.storage(v, "left_line_buffer", 8);
    right_.storage(v, "right_line_buffer", 8);
    matcher_.storage(v, p_);
  }
};

}  // namespace kern
}  // namespace parallax
