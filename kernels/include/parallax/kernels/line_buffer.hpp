// A raster-order line buffer with clamped ("replicate") window access, the common memory of the
// window stages (census, SAD, median). It holds SLOTS rows of up to MAX_W pixels; input row yi
// lives in slot yi % rows. A window of k rows needs only k rows: the next input row overwrites
// the oldest row column by column, behind the window (see input_allowed()), as Vitis' line
// buffers do. C++14 synthesisable subset.
#pragma once

#include "parallax/kernels/access.hpp"
#include "parallax/kernels/common.hpp"
#include "parallax/kernels/resources.hpp"
#include "parallax/kernels/store.hpp"

namespace parallax {
namespace kern {

// The last pixel, clamped to the image, of the window a stage's next step needs: row
// min(y + ry, H - 1) and column min(x + prologue steps, W - 1), which is the window_ready()
// corner of both the prologue position (prime - rx) and the output x (where prime = rx). Kept as
// two saturating counters that step with the stage's own (issue 41, N3): the plan compares them
// with the line buffer's input position, no add, no clamp and no product on the loop's
// recurrence.
struct WindowCorner {
  int row = 0, col = 0;
  // The input gate of the next output (x_out, y_out) with a window of (gate_rx, ry) behind it
  // (LineBuffer::input_allowed): top = y_out - ry, first = max(0, top), left = x_out - gate_rx,
  // counted with the stage's own counters like the corner, so the plan compares counters only
  // (review S3: computed there, the subtractions and max sat on the plan's loop-carried path).
  int top = 0, first = 0, left = 0;
  // A frame's first row.
  void start(int ry, int height_px, int gate_rx) {
    row = min_int(ry, height_px - 1);
    col = 0;
    top = -ry;
    first = 0;
    left = -gate_rx;
  }
  // The next output column (the gate; prologue steps move the corner alone).
  void next_output_col() { ++left; }
  // The next prologue step or output column.
  void next_col(int width_px) { col = min_int(col + 1, width_px - 1); }
  // The next output row (its prologue starts at column 0).
  void next_row(int height_px, int gate_rx) {
    row = min_int(row + 1, height_px - 1);
    col = 0;
    first = top >= -1 ? top + 1 : 0;
    ++top;
    left = -gate_rx;
  }
  // The loop-carried chains a stage with a corner declares (its schedule(), resources.hpp): the
  // plan, the corner compared with the line buffer's input position (a compare of column
  // counters, its and/or with the row compare and the firing's enables), the counters'
  // next-value select and their register; the corner's column, a saturating increment under the
  // firing's enable; the input gate (input_allowed: three compares of counters in parallel, their
  // and/or with the input's end and the plan's other enables, the input counters' next-value
  // select and register); and the gate's column, an increment or the row's reset under the enable.
  template <class S>
  static void schedule(S& s, int width_px) {
    const int col_bits = bits_for(uint64_t(width_px));
    s.recurrence("plan_window_ready", 1);
    s.chain(kOpCompare, col_bits, 1);
    s.chain(kOpXor, 1, 2);
    s.chain(kOpMux, col_bits, 1);
    s.chain(kOpRegister, col_bits, 1);
    s.recurrence("window_corner", 1);
    s.chain(kOpAdd, col_bits, 1);
    s.chain(kOpCompare, col_bits, 1);
    s.chain(kOpMux, col_bits, 2);
    s.chain(kOpRegister, col_bits, 1);
    s.recurrence("plan_input_allowed", 1);
    s.chain(kOpCompare, col_bits, 1);
    s.chain(kOpXor, 1, 3);
    s.chain(kOpMux, col_bits, 1);
    s.chain(kOpRegister, col_bits, 1);
    s.recurrence("input_gate", 1);
    s.chain(kOpAdd, col_bits, 1);
    s.chain(kOpMux, col_bits, 2);
    s.chain(kOpRegister, col_bits, 1);
  }
  // Resources (resources.hpp) of the corner and gate counters and the plan's compares with the line
  // buffer's input position: the corner's row and column, the gate's top, first and left (one bit
  // more: they start below 0), the line buffer's oldest row; two saturating increments, the gate's
  // increments; the window-ready compares (row greater, row equal, column greater) and the input
  // gate's (oldest below first, oldest equal to top, column below left).
  template <class R>
  static void declare(R& r, int width_px, int height_px) {
    const int col_bits = bits_for(uint64_t(width_px)), row_bits = bits_for(uint64_t(height_px));
    r.registers("window_corner", row_bits + col_bits, 1);
    r.registers("input_gate", 2 * (row_bits + 1) + col_bits + 1 + row_bits + 1, 1);
    r.op("window_corner_steps", kOpAdd, col_bits, 2);
    r.op("input_gate_steps", kOpAdd, row_bits + 1, 3);
    r.op("plan_compares", kOpCompare, col_bits + 1, 6);
  }
  // From the counters (a scheduler that wrote them: resync()): the corner of output row y + ry after
  // x + steps window steps, the gate of output (x, y).
  void sync(int y, int ry, int x, int steps, int gate_rx, int width_px, int height_px) {
    row = min_int(y + ry, height_px - 1);
    col = min_int(x + steps, width_px - 1);
    top = y - ry;
    first = max_int(0, top);
    left = x - gate_rx;
  }
};

// T: the values pushed and read; S: the element type the memories store them in (store.hpp).
template <class T, int MAX_W, int SLOTS, bool COUNT = false, class S = T>
class LineBuffer {
 public:
  static constexpr int kSlots = SLOTS;
  static_assert(SLOTS <= 10 && kMaxHeightPx <= 4096, "slot(): the reciprocal is exact only up to 10 rows of 4096");
  // rows: slots in use (<= SLOTS), at least the window's height. Contract: the caller writes
  // only when input_allowed() says so.
  // One memory per row slot; a write of the incoming row never meets a read of the window's
  // rows in the same slot and column within a firing (input_allowed()). Between firings it can:
  // a stage waiting for input steps its window, at the next firing, onto the column the last
  // firing pushed (a read-after-write at distance 1). So the memories carry no DEPENDENCE
  // pragma: Vitis keeps that order, which costs no II (no recurrence runs through them: the
  // values come from the stream, the addresses from counters). Review S1, docs/hls-review.md.
  // The window reads every row memory once per step, at one column (column()), and selects its
  // rows from those values by slot: a read's memory never depends on run-time state, so each
  // memory sees one read and one write per firing (counted: issue 41).
  LineBuffer() {
    PX_PARTITION_COMPLETE(mem_, 1)
#ifdef PX_HLS_LINE_BUFFER_STORAGE
    PX_PRAGMA(PX_HLS_LINE_BUFFER_STORAGE)
#endif
    PX_COUNT_BIND(mem_, kStorageRamS2p)
  }
  // The name the access count reports the memories under (the stage's name for this buffer).
  void name(const char* n) {
    access_name(mem_, n);
  }
  void configure(int width_px, int height_px, int rows) {
    width_px_ = width_px;
    height_px_ = height_px;
    rows_ = rows;
    reciprocal_ = (65536u + uint32_t(rows) - 1u) / uint32_t(rows);
    reset();
  }
  void reset() {
    written_ = 0;
    in_row_ = 0;
    in_col_ = 0;
    in_slot_ = 0;
    oldest_ = -rows_;
  }

  // Appends the next input pixel in raster order.
  void push(T v) {
    mem_[in_slot_][in_col_] = v;
    skip_push();
  }
  // Counts the next input pixel without storing it (the control path alone; see step()).
  void skip_push() {
    ++written_;
    if (++in_col_ < width_px_) return;
    in_col_ = 0;
    ++in_row_;
    ++oldest_;
    if (++in_slot_ == rows_) in_slot_ = 0;
  }
  int64_t written() const {
    return written_;
  }

  // Control-state access for a scheduler that advances periodic rows at once (sim/, never
  // synthesised): visit(v) calls v(field) on every counter of the control path, by reference;
  // resync() recomputes the fields derived from them after a visitor wrote them.
  template <class V>
  void visit(V& v) {
    v(written_);
    v(in_row_);
    v(in_col_);
  }
  void resync() {
    in_slot_ = slot(in_row_);
    oldest_ = in_row_ - rows_;
  }

  // Hardware: one memory per row slot (the window reads all rows in one cycle), W words deep
  // (storage descriptor, resources.hpp: the slots in use of mem_).
  template <class V>
  void storage(V& v, const char* name, int value_bits) const {
    v.memory(name, mem_, width_px_, value_bits, rows_, false, 1);
  }
  template <class R>
  void declare(R& r, const char* name, int value_bits) const {
    DeclareStorage<R> s(r);
    storage(s, name, value_bits);
  }
  // The row selects of a window of `window_rows` rows over this buffer (WindowRegs::step_to): per
  // window row, slot() of its image row (a product by the reciprocal, the quotient times the rows
  // in use, a subtract; priced at the bits the values need: row < 2^bits(H), reciprocal <= 2^16)
  // and the rows:1 select of that slot's word among the memories' outputs.
  template <class R>
  void declare_row_selects(R& r, int window_rows, int value_bits) const {
    const int row_bits = bits_for(uint64_t(height_px_));
    r.mul("slot_by_reciprocal", row_bits, 17, window_rows);
    r.mul("slot_times_rows", row_bits, bits_for(uint64_t(rows_)), window_rows);
    r.op("slot_remainder", kOpAdd, row_bits, window_rows);
    r.mux("slot_select", value_bits, rows_, window_rows);
  }
  bool input_done() const {
    return in_row_ >= height_px_;
  }

  // Pixel (x, y) with both coordinates clamped to the image; it must be resident. One read of
  // each row memory in use (a window of one row: one memory).
  T at_clamped(int x, int y) const {
    T col[SLOTS];
    PX_PRAGMA("HLS ARRAY_PARTITION variable=col type=complete dim=1")
    column(clamp_int(x, 0, width_px_ - 1), col);
    return col[slot_clamped(y)];
  }

  // Column x of every row memory in use (x not clamped): one read per memory, whatever rows the
  // caller then selects (slot_clamped()).
  void column(int x, T out[SLOTS]) const {
  line_buffer_column:
    for (int s = 0; s < SLOTS; ++s) {
      PX_PRAGMA("HLS UNROLL")
      out[s] = s < rows_ ? from_store<T>(mem_[s][x]) : T(0);
    }
  }
  // The slot of image row clamp(y).
  int slot_clamped(int y) const {
    return slot(clamp_int(y, 0, height_px_ - 1));
  }
  // row % rows by a multiply: exact for row < 4096 and rows <= 10 (error < 4096 * 10 / 2^16).
  int slot(int row) const {
    return row - int((uint32_t(row) * reciprocal_) >> 16) * rows_;
  }
  int clamp_x(int x) const {
    return clamp_int(x, 0, width_px_ - 1);
  }

  // True when the window whose last pixel is `corner` (a WindowCorner the stage keeps) is
  // resident: window_ready() with the corner counted instead of computed (issue 41, N3), so the
  // stage's plan is two compares of counters.
  template <class C>
  bool corner_resident(const C& corner) const {
    return in_row_ > corner.row || (in_row_ == corner.row && in_col_ > corner.col);
  }
  // True when every pixel of the clamped window of radius (rx, ry) around (x, y) is resident: the
  // next input position (in_row_, in_col_) lies beyond the window's last pixel in raster order.
  // Row and column compared separately (issue 41, N3): the same answer as comparing the pixels
  // written with last_row * W + last_col, without a 64-bit product on the plan's path.
  bool window_ready(int x, int y, int rx, int ry) const {
    const int last_row = min_int(y + ry, height_px_ - 1);
    const int last_col = min_int(x + rx, width_px_ - 1);
    return in_row_ > last_row || (in_row_ == last_row && in_col_ > last_col);
  }
  // True when the next input pixel may be written without overwriting a pixel that the window
  // of radius (rx, ry) around the next output (x_out, y_out), or a later output, still needs.
  // It overwrites row in_row - rows at column in_col: free when that row lies above every
  // window still to come, or when it is the top row of output row y_out's windows (and of no
  // later row's) and the column lies left of the window at x_out. Rows near the top are shared
  // by several output rows through clamping (y_out < ry), so they are not overwritten early.
  // The window's rows and columns come from the stage's counted gate (WindowCorner: first =
  // max(0, y_out - ry), top = y_out - ry, left = x_out - rx) and the row written over from a
  // counter (oldest_ = in_row - rows), so the plan compares counters only.
  template <class C>
  bool input_allowed(const C& gate) const {
    return !input_done() && (oldest_ < gate.first || (oldest_ == gate.top && in_col_ < gate.left));
  }

 private:
  typename ArrayOf<COUNT, S, SLOTS, MAX_W>::type mem_;
  int width_px_ = 0;
  int height_px_ = 0;
  int rows_ = 1;
  int64_t written_ = 0;
  int in_row_ = 0, in_col_ = 0, in_slot_ = 0;  // position of the next input pixel: row, column, slot
  int oldest_ = 0;                             // the row the next input pixel writes over: in_row_ - rows_
  uint32_t reciprocal_ = 65536u;               // ceil(2^16 / rows)
};

}  // namespace kern
}  // namespace parallax

namespace parallax {
namespace kern {

// The window registers of a window stage: the clamped pixels (x + reach - (w - 1) + i,
// y + j - h/2), i < w, j < h, of the current position (x, y). reach is how far the window
// extends right of x: w/2 for a centred window (Census, median), w/2 of the matching window for
// SAD's wider left and right registers. The window moves one step per firing and reads one pixel
// per row memory, what keeps a hardware window stage at II = 1: a row starts at x = -reach,
// where every column is the row's first pixel (clamped: one read, broadcast), and each later step
// shifts the window one column and reads column x + reach (clamped). The stages spend `reach`
// prologue firings per row on the positions -reach .. -1 (CostStage, Median). Contract: the
// pixels read are resident in the line buffer.
// LITERAL (the exported, FIXED instantiations): registers that shift along fixed wires. Software
// instantiations keep each row as a mirrored ring with a moving base (as ShiftReg, common.hpp),
// so a shift costs one write per row instead of w moves; the pixels held are the same.
template <class T, int MAX_W, int MAX_H, bool LITERAL = true>
class WindowRegs {
 public:
  WindowRegs() { PX_PRAGMA("HLS ARRAY_PARTITION variable=v_ type=complete dim=0") }
  // Moves to (x, y): x = -reach starts row y, any other x follows x - 1 of the same row.
  template <class LB>
  void step_to(const LB& lb, int x, int y, int w, int h, int reach) {
    const int ry = h / 2;
    const bool start = x == -reach;
    const int col = start ? 0 : lb.clamp_x(x + reach);
    if (!start && !LITERAL) base_ = (base_ + 1) & (kRing - 1);
    T column[LB::kSlots];  // the column of every row memory: one read each
    PX_PRAGMA("HLS ARRAY_PARTITION variable=column type=complete dim=1")
    lb.column(col, column);
  window_rows:
    for (int j = 0; j < MAX_H; ++j) {
      PX_PRAGMA("HLS UNROLL")
      if (j < h) {
        const T pixel = column[lb.slot_clamped(y + j - ry)];
      window_cols:
        for (int i = 0; i < (LITERAL ? MAX_W : 1); ++i) {
          PX_PRAGMA("HLS UNROLL")
          if (LITERAL && i < w) v_[j][i] = start || i + 1 == w ? pixel : v_[j][i + 1 < MAX_W ? i + 1 : i];
        }
        if (!LITERAL) {
          if (start) {
          window_fill:
            for (int i = 0; i < w; ++i) put(j, i, pixel);
          } else {
            put(j, w - 1, pixel);
          }
        }
      }
    }
  }
  // Pixel (x + reach - (w - 1) + i, y + j - h/2), clamped to the image.
  T at(int i, int j) const { return v_[j][LITERAL ? i : base_ + i]; }
  // Storage descriptor (resources.hpp): w x h of the registers hold pixels (the rest, sized for
  // the largest window, are never written in the literal form).
  template <class V>
  void storage(V& v, const char* name, int w, int h, int width_bits) const {
    v.window(name, v_, w, h, width_bits);
  }
  // Row j of the registers (for lane-parallel reads): entries 0 .. w - 1 are contiguous.
  const T* row(int j) const { return v_[j] + (LITERAL ? 0 : base_); }

 private:
  static constexpr int ring_size() {
    int r = 1;
    while (r < MAX_W) r *= 2;
    return r;
  }
  static constexpr int kRing = LITERAL ? MAX_W : ring_size();
  void put(int j, int i, T v) {
    const int p = base_ + i;
    v_[j][p] = v;
    v_[j][p < kRing ? p + kRing : p - kRing] = v;
  }
  T v_[MAX_H][LITERAL ? MAX_W : 2 * kRing];
  int base_ = 0;  // ring base (software instantiations only)
};

}  // namespace kern
}  // namespace parallax
