// Internal: the periodic fast-forward of the cycle model's timing run (one-pass designs).
//
// Between the first and the last rows every stage runs the same plans row after row, so once
// the pipeline has settled, the whole timed state (every stage's next cycle and statistics,
// every FIFO's counters and the slot times future firings can read, every kernel's counters,
// the source and sink positions) advances by the same amount per output row: times by one
// period, counts by one row's worth. The evaluation is deterministic (which stage fires and
// what it plans depend on counts and counters only), so when three snapshots taken as the
// sink completes consecutive rows show the same differences twice, the next rows repeat them
// exactly, and K rows can be applied at once: state + K x difference. Conditions that keep it
// exact: the rows skipped stay clear of the frame's last rows (and the first rows are past);
// the source's arrivals either never set a firing's cycle and come no faster than one period
// per row, or repeat with exactly the period over the skipped rows (checked pixel by pixel;
// the skip ends before the first row that does not).
// The caller arms it only where that holds: the timing run of one-pass designs without
// rectification or VCD trace (engine.hpp). Tested against the coupled run, which never skips.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "parallax/sim/fifo.hpp"
#include "scheduler.hpp"

namespace parallax::sim::detail {

// Reads (out) or assigns (in) every field of the timed state, in visiting order.
struct StateIO {
  std::vector<int64_t>* out = nullptr;       // read mode: append every field
  const std::vector<int64_t>* in = nullptr;  // write mode: assign every field in order
  std::size_t pos = 0;
  template <class T>
  void operator()(T& field) {
    if (out)
      out->push_back(int64_t(field));
    else
      field = T((*in)[pos++]);
  }
};

// The figures of the run the fast-forward reads and advances; the run keeps them alive.
struct FastForwardRun {
  int64_t* next_src = nullptr;             // the source's next pixel
  int64_t* got = nullptr;                  // pixels the sink has taken
  int64_t* last_pixel_cycle = nullptr;     // the sink's last pixel (the period is read from it)
  int64_t* rows_fast_forwarded = nullptr;  // the report's count of rows applied at once
  int64_t source_total = 0;                // pixels the source delivers
  int64_t width = 0;                       // pixels per row
  int64_t settle_rows = 0;                 // rows the first rows' plans take
  double row_input_cycles = 0.0;           // cycles the input takes to deliver one row
};

// Host: the run that owns the kernels, with
//   template <class IO> void visit_kernels(IO& io);  // every kernel's timed counters, in a fixed order
//   void resync_kernels();                           // after the counters were assigned
//   int64_t input_arrival(int64_t pixel) const;      // cycle at which input pixel i arrives
template <bool kTimed>
class FastForward {
 public:
  // Arms the fast-forward for one run over the graph's nodes and FIFOs as they are now, or
  // disarms it.
  void start(bool enabled, Graph<kTimed>& graph, const FastForwardRun& run) {
    *this = FastForward{};
    enabled_ = enabled;
    if (!enabled_) return;
    graph_ = &graph;
    run_ = run;
    fifos_ = graph.fifo_list();
    for (const auto& n : graph.nodes())
      if (n->name() == "source") source_ = n.get();
  }
  bool enabled() const { return enabled_; }

  // Called as the sink completes a row: takes a snapshot, and applies whole rows at once when
  // the last three snapshots show the same differences twice.
  template <class Host>
  void row_done(Host& host) {
    const int64_t w = run_.width;
    const int64_t rows_done = *run_.got / w;
    if (rows_done < run_.settle_rows) return;  // past the first rows' plans
    take_snapshot(host);
    if (history_.size() < 3) return;
    const Snapshot &a = history_[0], &b = history_[1], &c = history_[2];
    if (a.shape != b.shape || b.shape != c.shape || a.values.size() != c.values.size() ||
        a.slots.size() != c.slots.size())
      return;
    for (std::size_t i = 0; i < c.values.size(); ++i)
      if (c.values[i] - b.values[i] != b.values[i] - a.values[i]) return;
    const int64_t period = c.values.back() - b.values.back();
    if (period <= 0) return;
    for (std::size_t i = 0; i < c.slots.size(); ++i)
      if (c.slots[i] - b.slots[i] != period || b.slots[i] - a.slots[i] != period) return;
    const std::size_t next_at = c.values.size() - 3;  // visit_state's order: next_src, got, last pixel
    if (c.values[next_at] - b.values[next_at] != w) return;
    const int64_t rows = rows_to_skip(host, period);
    if (rows < 1) return;
    std::vector<int64_t> target(c.values.size());
    for (std::size_t i = 0; i < target.size(); ++i) target[i] = c.values[i] + rows * (c.values[i] - b.values[i]);
    StateIO writer;
    writer.in = &target;
    visit_state(host, writer);
    for (FifoBase* f : fifos_) f->shift_slot_times(rows * period);
    host.resync_kernels();
    *run_.rows_fast_forwarded += rows;
    history_.clear();
  }

 private:
  struct Snapshot {
    std::vector<int64_t> values, slots, shape;
    int64_t source_bound = 0;
  };

  template <class Host, class IO>
  void visit_state(Host& host, IO& io) {
    for (const auto& n : graph_->nodes()) n->visit(io);
    for (FifoBase* f : fifos_) f->visit(io);
    host.visit_kernels(io);
    io(*run_.next_src);
    io(*run_.got);
    io(*run_.last_pixel_cycle);  // last, the period is read from it
  }

  // Appends the state now to the history of the last three snapshots.
  template <class Host>
  void take_snapshot(Host& host) {
    Snapshot s;
    StateIO reader;
    reader.out = &s.values;
    visit_state(host, reader);
    for (FifoBase* f : fifos_) {
      const std::size_t before = s.slots.size();
      f->slot_times(s.slots);
      s.shape.push_back(int64_t(s.slots.size() - before));
    }
    for (const auto& n : graph_->nodes()) {
      const auto it = std::find(fifos_.begin(), fifos_.end(), n->blocked_fifo());
      s.shape.push_back(it == fifos_.end() ? -1 : int64_t(it - fifos_.begin()));
    }
    s.source_bound = source_->earliest_bound();
    history_.push_back(std::move(s));
    if (history_.size() > 3) history_.erase(history_.begin());
  }

  // The rows that can be applied at once with this period (< 1: none), as the input allows.
  template <class Host>
  int64_t rows_to_skip(const Host& host, int64_t period) const {
    const int64_t w = run_.width;
    const Snapshot &a = history_[0], &b = history_[1], &c = history_[2];
    const int64_t next = *run_.next_src;
    int64_t rows = (run_.source_total - next) / w - 3;  // stay clear of the last rows
    if (rows < 1) return rows;
    const bool arrival_bound = c.source_bound != b.source_bound || b.source_bound != a.source_bound;
    if (!arrival_bound) {
      // Never bound: it stays so if the input delivers a row in at most one period.
      if (host.input_arrival(next + w) - host.input_arrival(next) > period - 1 ||
          host.input_arrival(next + rows * w) - host.input_arrival(next) > rows * period - 1)
        return 0;
      if (run_.row_input_cycles > double(period) - 1.0) return 0;
      return rows;
    }
    // Skip the rows up to the first whose arrivals do not repeat with the period.
    for (int64_t j = next; j < next + rows * w; ++j)
      if (host.input_arrival(j) - host.input_arrival(j - w) != period) return (j - next) / w;
    return rows;
  }

  bool enabled_ = false;
  Graph<kTimed>* graph_ = nullptr;
  FastForwardRun run_;
  Node<kTimed>* source_ = nullptr;
  std::vector<FifoBase*> fifos_;
  std::vector<Snapshot> history_;  // the last three, oldest first
};

}  // namespace parallax::sim::detail
