// Internal: the periodic fast-forward of the cycle model's timing run, for a one-pass design and
// for each pass of the two-pass (8-path) design.
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
// every rate a node waits for (the source's arrivals; the frame buffer's write rate for pass 1's
// sink) either never sets a firing's cycle and allows one row in less than a period, or repeats
// with exactly the period over the skipped rows (checked unit by unit; the skip ends before the
// first row that does not). A pass's sink is the stage whose completed rows are counted: the
// disparity sink (one pass), the frame-buffer writer (pass 1, rows of words), the map writer
// (pass 2); its source the input (one pass, pass 1) or the frame-buffer reader (pass 2). The
// FIFOs of an earlier pass are idle and left out.
// The caller arms it only where that holds: the timing run without rectification or VCD trace
// (engine.hpp). Tested against the every-firing and the coupled runs, which never skip.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
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

// A node whose firings wait for a rate (the input's arrivals, the frame buffer's words): its
// next unit, units per sink row, the units of the frame and when unit i is available.
struct RateBound {
  const char* node = nullptr;          // the node's name (null: none)
  int64_t* next = nullptr;             // its next unit (a counter the state visits)
  int64_t per_row = 0;                 // units per row of the sink
  int64_t total = 0;                   // units in the frame
  double row_cycles = 0.0;             // cycles the rate takes for one row's units
  std::function<int64_t(int64_t)> at;  // the cycle unit i is available
};

// The figures of the run the fast-forward reads and advances; the run keeps them alive.
struct FastForwardRun {
  int64_t* got = nullptr;                  // units the sink has completed
  int64_t sink_per_row = 0;                // sink units per row
  int64_t* last_cycle = nullptr;           // the sink's last firing (the period is read from it)
  int64_t* rows_fast_forwarded = nullptr;  // the report's count of rows applied at once
  std::vector<int64_t*> counters;          // further counters the pass's pumps keep
  int64_t settle_rows = 0;                 // sink rows the first rows' plans take
  std::size_t first_fifo = 0;              // the graph's FIFOs before it belong to an earlier pass
  RateBound source;                        // the pass's source: its end bounds the skip
  RateBound sink_rate;                     // a rate the sink waits for (node null: none)
};

// Host: the run that owns the kernels, with
//   template <class IO> void visit_kernels(IO& io);  // every kernel's timed counters, in a fixed order
//   void resync_kernels();                           // after the counters were assigned
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
    const std::vector<FifoBase*> all = graph.fifo_list();
    fifos_.assign(all.begin() + std::ptrdiff_t(std::min(run.first_fifo, all.size())), all.end());
    for (const auto& n : graph.nodes()) {
      if (run.source.node != nullptr && n->name() == run.source.node) source_ = n.get();
      if (run.sink_rate.node != nullptr && n->name() == run.sink_rate.node) sink_node_ = n.get();
    }
    if (source_ == nullptr) enabled_ = false;  // not a graph this knows: never skip
  }
  bool enabled() const { return enabled_; }

  // Called as the sink completes a row: takes a snapshot, and applies whole rows at once when
  // the last three snapshots show the same differences twice.
  template <class Host>
  void row_done(Host& host) {
    const int64_t rows_done = *run_.got / run_.sink_per_row;
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
    const std::size_t next_at = c.values.size() - 3;  // visit_state's order: source's next, got, last cycle
    if (c.values[next_at] - b.values[next_at] != run_.source.per_row) return;
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
    int64_t source_bound = 0, sink_bound = 0;
  };

  template <class Host, class IO>
  void visit_state(Host& host, IO& io) {
    for (const auto& n : graph_->nodes()) n->visit(io);
    for (FifoBase* f : fifos_) f->visit(io);
    host.visit_kernels(io);
    for (int64_t* c : run_.counters) io(*c);
    io(*run_.source.next);
    io(*run_.got);
    io(*run_.last_cycle);  // last, the period is read from it
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
    s.sink_bound = sink_node_ != nullptr ? sink_node_->earliest_bound() : 0;
    history_.push_back(std::move(s));
    if (history_.size() > 3) history_.erase(history_.begin());
  }

  // The rows that can be applied at once with this period (< 1: none), as the rates allow.
  template <class Host>
  int64_t rows_to_skip(const Host&, int64_t period) const {
    const Snapshot &a = history_[0], &b = history_[1], &c = history_[2];
    const RateBound& src = run_.source;
    int64_t rows = (src.total - *src.next) / src.per_row - 3;  // stay clear of the last rows
    if (rows < 1) return rows;
    rows = rate_rows(src, c.source_bound != b.source_bound || b.source_bound != a.source_bound, period, rows);
    if (rows >= 1 && sink_node_ != nullptr)
      rows = rate_rows(run_.sink_rate, c.sink_bound != b.sink_bound || b.sink_bound != a.sink_bound, period, rows);
    return rows;
  }
  // At most `rows` rows over which the rate keeps to the schedule: never bound, it stays so if it
  // allows a row in less than one period; bound, up to the first row whose units do not repeat
  // with exactly the period.
  static int64_t rate_rows(const RateBound& r, bool bound, int64_t period, int64_t rows) {
    const int64_t next = *r.next, u = r.per_row;
    if (!bound) {
      if (r.at(next + u) - r.at(next) > period - 1 || r.at(next + rows * u) - r.at(next) > rows * period - 1) return 0;
      if (r.row_cycles > double(period) - 1.0) return 0;
      return rows;
    }
    for (int64_t j = next; j < next + rows * u; ++j)
      if (j < u || r.at(j) - r.at(j - u) != period) return (j - next) / u;
    return rows;
  }

  bool enabled_ = false;
  Graph<kTimed>* graph_ = nullptr;
  FastForwardRun run_;
  Node<kTimed>* source_ = nullptr;
  Node<kTimed>* sink_node_ = nullptr;
  std::vector<FifoBase*> fifos_;
  std::vector<Snapshot> history_;  // the last three, oldest first
};

}  // namespace parallax::sim::detail
