// Internal: the scheduler core both runs share, with no knowledge of the pipeline.
//
// A Graph owns the Nodes (stages) and knows the FIFOs between them (sim::Fifo, owned by the
// caller) with their producer and consumer. A pump is a std::function<bool()> that fires one
// stage while it can and returns whether it fired; Graph::schedule runs the pumps round-robin
// until `finished`. A round in which no pump fires while the run is unfinished is a deadlock
// (timed: diagnosed, naming every blocked stage and the FIFO it waits on) or an internal error
// (func). Node::attempt is the firing rule, kTimed = false for the func run (fire when the
// plan's inputs are non-empty and its outputs not full) and true for the cycle model (the same,
// at the earliest cycle II, token visibility, FIFO space and the caller's bound allow, with
// statistics and VCD events).
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "internal_error.hpp"
#include "parallax/sim/cycle.hpp"
#include "parallax/sim/fifo.hpp"
#include "vcd_trace.hpp"

namespace parallax::sim::detail {

// One FIFO a firing may touch, and whether the current plan uses it.
struct Port {
  FifoBase* fifo;
  bool used;
};

// One stage of the graph: timing, statistics and the firing rule.
template <bool kTimed>
class Node {
 public:
  Node(std::string name, StageTiming t, Trace* trace)
      : timing_(t), trace_(trace), tracing_(trace != nullptr && trace->active()), t_next_(t.setup_cycles) {
    report_.name = std::move(name);
    report_.ii_cycles = t.ii_cycles;
    report_.latency_cycles = t.latency_cycles;
    if (tracing_) {
      valid_sig_ = trace_->signal(report_.name + "_valid", 1);
      stall_sig_ = trace_->signal(report_.name + "_stall", 1);
    }
  }

  // Fires once if the plan's ports allow it (and, timed, no earlier than `earliest`): inputs
  // non-empty, outputs not full; timed: at max(t_next, visible inputs, free output slots).
  template <class Fire>
  [[gnu::always_inline]] bool attempt(std::initializer_list<Port> in, std::initializer_list<Port> out, Fire&& fire,
                                      int64_t earliest = 0) {
    if constexpr (!kTimed) {  // func run: only the plan's ports, no statistics
      for (const Port& p : in)
        if (p.used && p.fifo->empty()) return false;
      for (const Port& p : out)
        if (p.used && p.fifo->full()) return false;
      fire();
      return true;
    }
    for (const Port& p : in)
      if (p.used && p.fifo->empty()) return block(p.fifo, true);
    for (const Port& p : out)
      if (p.used && p.fifo->full()) return block(p.fifo, false);
    blocked_ = nullptr;
    if constexpr (kTimed) {
      const int64_t t_next = t_next_;
      int64_t t_in = t_next, t_out = t_next;
      for (const Port& p : in)
        if (p.used) t_in = std::max(t_in, p.fifo->head_visible());
      // Results enter the output FIFO at the end of the pipeline, L cycles after the firing.
      for (const Port& p : out)
        if (p.used) t_out = std::max(t_out, p.fifo->next_write_free() - timing_.latency_cycles);
      if (earliest > std::max(t_in, t_out)) ++earliest_bound_;  // the source's arrival set the cycle
      t_in = std::max(t_in, earliest);
      t_out = std::max(t_out, earliest);
      const int64_t t = std::max(t_in, t_out);
      {
        // Waiting before the first firing counts as input stall (the pipeline fills).
        const int64_t wait = t - t_next;
        const bool output_bound = t_out > t_in;
        report_.output_stall_cycles += output_bound ? wait : 0;
        report_.input_stall_cycles += output_bound ? 0 : wait;
      }
      for (const Port& p : in)
        if (p.used) p.fifo->stamp(t, 0);
      for (const Port& p : out)
        if (p.used) p.fifo->stamp(0, t + timing_.latency_cycles);
      if (tracing_) {
        if (t > t_next) {
          trace_->change(t_next, stall_sig_, 1, false);
          trace_->change(t, stall_sig_, 0, false);
        }
        trace_->change(t, valid_sig_, 1, false);
        trace_->change(t + 1, valid_sig_, 0, false);
        for (const Port& p : out)
          if (p.used) trace_->change(t + timing_.latency_cycles, trace_->fifo_signal(p.fifo), +1, true);
        for (const Port& p : in)
          if (p.used) trace_->change(t + 1, trace_->fifo_signal(p.fifo), -1, true);
      }
      fire();
      if (report_.fires == 0) report_.first_fire_cycle = t;
      report_.last_fire_cycle = t;
      t_next_ = t + timing_.ii_cycles;
    } else {
      fire();
    }
    ++report_.fires;
    return true;
  }

  bool block(const FifoBase* f, bool on_input) {
    blocked_ = f;
    blocked_on_input_ = on_input;
    blocked_at_ = on_input ? f->writes() : f->reads();
    return false;
  }
  // True while the FIFO that blocked the last attempt has not changed since: the plan (a
  // function of the stage's state) and so the same port would block again. Pumps return at
  // once then, which spares the scheduler a plan and an attempt per stage and round.
  [[gnu::always_inline]] bool still_blocked() const {
    return blocked_ && (blocked_on_input_ ? blocked_->writes() : blocked_->reads()) == blocked_at_;
  }

  // Timed-state access for the periodic fast-forward (see FifoBase::visit).
  template <class V>
  void visit(V& v) {
    v(t_next_);
    v(report_.fires);
    v(report_.input_stall_cycles);
    v(report_.output_stall_cycles);
    v(report_.first_fire_cycle);
    v(report_.last_fire_cycle);
    v(blocked_on_input_);
    v(blocked_at_);
    v(earliest_bound_);
  }
  // Firings whose cycle the `earliest` bound (a source's arrival) set, above every other bound.
  int64_t earliest_bound() const { return earliest_bound_; }

  // busy = fires x II.
  const StageReport& report() const {
    report_.busy_cycles = report_.fires * timing_.ii_cycles;
    return report_;
  }
  const FifoBase* blocked_fifo() const { return blocked_; }
  bool blocked_on_input() const { return blocked_on_input_; }
  int64_t t_next() const { return t_next_; }
  void set_t_next(int64_t t) { t_next_ = t; }
  const std::string& name() const { return report_.name; }

 private:
  StageTiming timing_;
  Trace* trace_;
  bool tracing_;
  mutable StageReport report_;  // busy_cycles is derived in report()
  int64_t t_next_;
  const FifoBase* blocked_ = nullptr;
  bool blocked_on_input_ = false;
  int64_t blocked_at_ = 0;  // the blocking FIFO's writes (input) or reads (output) at the block
  int64_t earliest_bound_ = 0;
  int valid_sig_ = -1, stall_sig_ = -1;
};

// The stages and FIFOs of one run, their scheduling and deadlock diagnosis. Stages are pumps:
// each fires its kernel while it can and says whether it fired; a round in which no pump fires
// while the run is unfinished is a deadlock (timed) or an internal error (func).
template <bool kTimed>
class Graph {
 public:
  using NodeT = Node<kTimed>;
  explicit Graph(Trace* trace) : trace_(trace) {}

  NodeT& add_node(const std::string& name, StageTiming t) {
    nodes_.push_back(std::make_unique<NodeT>(name, t, trace_));
    return *nodes_.back();
  }
  void add_fifo(FifoBase* f, const std::string& producer, const std::string& consumer) {
    fifos_.push_back({f, producer, consumer});
  }
  void mark_done(const std::string& name) {
    if (!is_done(name)) done_.push_back(name);
  }
  bool is_done(const std::string& name) const { return std::find(done_.begin(), done_.end(), name) != done_.end(); }

  // Runs the pumps round-robin until `finished`. Returns false on deadlock (timed), with the
  // diagnosis in deadlock_message() / deadlock_cycle().
  bool schedule(const std::vector<std::function<bool()>>& pumps, const std::function<bool()>& finished) {
    while (!finished()) {
      bool progress = false;
      for (const auto& pump : pumps) progress |= pump();
      if (!progress) {
        if (!kTimed) internal_error("func scheduler made no progress");
        diagnose();
        return false;
      }
    }
    return true;
  }

  const std::string& deadlock_message() const { return message_; }
  int64_t deadlock_cycle() const { return cycle_; }
  const std::vector<std::unique_ptr<NodeT>>& nodes() const { return nodes_; }
  std::string producer_of(const FifoBase* f) const {
    for (const auto& fi : fifos_)
      if (fi.fifo == f) return fi.producer;
    return "";
  }
  std::string consumer_of(const FifoBase* f) const {
    for (const auto& fi : fifos_)
      if (fi.fifo == f) return fi.consumer;
    return "";
  }
  void clear_fifos() { fifos_.clear(); }
  std::vector<FifoBase*> fifo_list() const {
    std::vector<FifoBase*> list;
    for (const auto& fi : fifos_) list.push_back(fi.fifo);
    return list;
  }

 private:
  struct FifoInfo {
    FifoBase* fifo;
    std::string producer, consumer;
  };

  // Names every blocked stage with the FIFO it waits on; a full FIFO whose consumer waits
  // elsewhere is the undersized one.
  void diagnose() {
    int64_t cycle = 0;
    std::string msg;
    for (const auto& n : nodes_) {
      const FifoBase* f = n->blocked_fifo();
      if (!f) continue;
      cycle = std::max(cycle, n->t_next());
      if (!msg.empty()) msg += "; ";
      if (n->blocked_on_input()) {
        const std::string prod = producer_of(f);
        msg += "stage '" + n->name() + "' waits for a token on FIFO '" + f->name() + "' (empty, producer '" + prod +
               "'" + (is_done(prod) ? " has finished" : "") + ")";
      } else {
        msg += "stage '" + n->name() + "' waits for space in FIFO '" + f->name() + "' (full at depth " +
               std::to_string(f->depth()) + ", consumer '" + consumer_of(f) + "'): FIFO '" + f->name() +
               "' is too shallow";
      }
    }
    cycle_ = cycle;
    message_ = "deadlock at cycle " + std::to_string(cycle) + ": " + msg;
  }

  Trace* trace_;
  std::vector<std::unique_ptr<NodeT>> nodes_;
  std::vector<FifoInfo> fifos_;
  std::vector<std::string> done_;
  std::string message_;
  int64_t cycle_ = -1;
};

}  // namespace parallax::sim::detail
