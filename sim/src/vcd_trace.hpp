// Internal: the cycle model's VCD trace. Signals (a stage's valid and stall bits, a FIFO's
// occupancy) are registered by name and width; the scheduler reports level changes (absolute
// values) and occupancy changes (deltas) at cycles, in any order. Only the window [from, to)
// is kept: changes at or before `from` fold into the levels at the window's start, changes from
// `to` on are dropped, so memory stays proportional to the window. write() emits the window as
// VCD, one time unit per cycle. A trace with to <= from is inactive and records nothing.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "parallax/sim/fifo.hpp"

namespace parallax::sim::detail {

// VCD events inside a window of cycles.
class Trace {
 public:
  Trace(int64_t from, int64_t to) : from_(from), to_(to) {}
  bool active() const { return to_ > from_; }
  int signal(const std::string& name, int width) {
    names_.push_back(name);
    widths_.push_back(width);
    return int(names_.size()) - 1;
  }
  // The occupancy signal of a FIFO (registered on first use).
  int fifo_signal(const FifoBase* f) {
    for (std::size_t i = 0; i < fifo_keys_.size(); ++i)
      if (fifo_keys_[i] == f) return fifo_sigs_[i];
    int width = 1;
    while (width < 31 && (int64_t(1) << width) <= int64_t(f->depth() == 0 ? 1 << 20 : f->depth())) ++width;
    const int sig = signal("fifo_" + f->name(), width);
    fifo_keys_.push_back(f);
    fifo_sigs_.push_back(sig);
    return sig;
  }
  // Events after the window are dropped; events up to its start are folded into the levels at
  // the start, so memory stays proportional to the window.
  void change(int64_t cycle, int sig, int64_t delta_or_value, bool is_delta) {
    if (!active() || cycle >= to_) return;
    if (cycle <= from_) {
      if (pre_level_.size() < names_.size()) {
        pre_level_.resize(names_.size(), 0);
        pre_cycle_.resize(names_.size(), -1);
      }
      if (is_delta) {
        pre_level_[std::size_t(sig)] += delta_or_value;
      } else if (cycle >= pre_cycle_[std::size_t(sig)]) {
        pre_level_[std::size_t(sig)] = delta_or_value;
        pre_cycle_[std::size_t(sig)] = cycle;
      }
      return;
    }
    events_.push_back({cycle, sig, delta_or_value, is_delta});
  }
  // Writes the window as VCD (one timestep = one cycle), levels reconstructed from the events.
  void write(const std::string& path, const std::string& scope) const;

 private:
  struct Event {
    int64_t cycle;
    int sig;
    int64_t v;
    bool delta;
  };
  int64_t from_, to_;
  std::vector<std::string> names_;
  std::vector<int> widths_;
  std::vector<Event> events_;
  std::vector<const FifoBase*> fifo_keys_;
  std::vector<int> fifo_sigs_;
  std::vector<int64_t> pre_level_;  // levels at the window's start
  std::vector<int64_t> pre_cycle_;  // cycle of the last absolute value folded in, per signal
};

}  // namespace parallax::sim::detail
