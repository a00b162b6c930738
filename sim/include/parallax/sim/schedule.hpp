// The initiation interval of each stage, derived from what its kernel declares (issue 14):
// II = max(1, ResMII, RecMII), ResMII from the accesses per firing of each memory over its ports,
// RecMII from the operator chain of each loop-carried recurrence against the clock (operator
// delays: sim/data/operator_delays.csv, with their sources; the budget per cycle is the period
// less Vitis' default 27 % clock uncertainty).
#pragma once

#include <string>
#include <vector>

#include "parallax/kernels/params.hpp"
#include "parallax/kernels/pipeline.hpp"
#include "parallax/kernels/resources.hpp"

namespace parallax::sim {

// Vitis HLS's default clock uncertainty: 27 % of the period (UG1702, HLS General Options).
constexpr double kClockUncertainty = 0.27;

struct OperatorDelay {
  std::string kind;  // add, compare, mux, xor, memory_read, register
  int min_bits = 1, max_bits = 64;
  double delay_ns = 0;
  std::string source;
};

// The table of sim/data/operator_delays.csv (compiled in).
const std::vector<OperatorDelay>& operator_delays();
// Delay of one operator of this kind and width (the row whose width range holds it).
double operator_delay_ns(kern::OpKind kind, int width_bits);

// One memory of a stage and its accesses per firing. Counted (storage >= 0): the largest reads and
// writes any bank received in one firing of the counting run (accesses.hpp), on the ports its
// binding gives a bank. Declared (storage < 0): what the kernel's schedule() states, over `ports`
// ports shared by reads and writes (the rectify stages, which the counting run does not fire).
struct MemoryPorts {
  std::string name;
  int reads = 0, writes = 0, ports = 2;
  int storage = -1;              // kern::StorageType of a counted memory; -1: declared
  int banks = 1;                 // banks the count reached
  int runtime_banked_sites = 0;  // sites whose bank is chosen at run time (counted on every bank they reach)
  int max_banks_per_site = 1;    // the widest such site's fan-in: its read mux or write decoder
  int mii() const;               // the smallest II the accesses fit the ports at
  std::string describe() const;  // "memory NAME (ram_s2p, counted): R reads + W writes per bank and firing"
};

struct ChainOp {
  kern::OpKind kind;
  int width_bits = 1;
  int count = 1;
};

struct Recurrence {
  std::string name;
  int distance = 1;
  std::vector<ChainOp> chain;
  // Counted register files the chain passes through (the kernel's schedule() names them): when
  // the count shows a site choosing among B > 1 of their registers at run time, the chain gains
  // the read mux (one LUT level per 4 inputs) and the write decoder (a compare of the index).
  std::vector<std::string> via;
  double delay_ns() const;
  // The smallest II at which the chain fits `distance` firings of budget_ns each.
  int ii_at(double budget_ns) const;
};

// A stage's declarations and what follows from them at one clock.
struct StageSchedule {
  std::string stage;
  std::vector<MemoryPorts> memories;
  std::vector<Recurrence> recurrences;
  int res_mii = 1;
  int rec_mii = 1;
  int ii = 1;
  kern::StageSetup setup = {0u, false, false, false};  // what the stage's kernel was configured with
  std::string
      limit;  // what sets II: "memory NAME: R reads + W writes on P ports" or "recurrence NAME: X ns over D firings"
};

// II of one stage from its declarations at clock_hz.
void derive_ii(StageSchedule& s, double clock_hz);
// Adds to each recurrence that passes through a register file the count shows banked at run
// time its read mux and write decoder, and sets its distance to 1 (the scheduler's view).
void add_banking_muxes(StageSchedule& s);

// The schedules of the design's kernel stages (cost, aggregate, aggregate_back for two passes,
// wta_lr, median, rectify_left/right when rectifying), derived at clock_hz: the memories as the
// counting run of the kernels counts them on a probe frame (probe_memory_accesses(), accesses.hpp),
// the recurrences as the kernels' schedule() declares their operator chains. Stages without a
// declaration (source, sink, maps, DDR) fire at II = 1.
std::vector<StageSchedule> stage_schedules(const kern::StereoParams& p, const kern::RectifyParams& rectify,
                                           double clock_hz);

}  // namespace parallax::sim
