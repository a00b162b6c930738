// II derived from the kernels' own schedule declarations (schedule.hpp).
#include "parallax/sim/schedule.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <sstream>

#include "parallax/kernels/access.hpp"
#include "parallax/kernels/caps.hpp"
#include "parallax/kernels/census.hpp"
#include "parallax/kernels/median.hpp"
#include "parallax/kernels/rectify.hpp"
#include "parallax/kernels/row_reverse.hpp"
#include "parallax/kernels/sad.hpp"
#include "parallax/kernels/sgm.hpp"
#include "parallax/kernels/wta_lr.hpp"
#include "parallax/sim/accesses.hpp"

namespace parallax::res::data {
extern const char* const operator_delays_csv;
}

namespace parallax::sim {
namespace {

[[noreturn]] void table_error(const std::string& what) {
  std::fprintf(stderr, "parallax: internal error: sim/data/operator_delays.csv: %s\n", what.c_str());
  std::abort();
}

// Fields of one CSV line; a field may be double-quoted (and then hold commas).
std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> f(1);
  bool quoted = false;
  for (char c : line) {
    if (c == '"')
      quoted = !quoted;
    else if (c == ',' && !quoted)
      f.emplace_back();
    else
      f.back() += c;
  }
  return f;
}

std::vector<OperatorDelay> parse_delays() {
  std::vector<OperatorDelay> rows;
  std::istringstream in(res::data::operator_delays_csv);
  std::string line;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      header = false;
      continue;
    }
    const auto f = csv_fields(line);
    if (f.size() != 5) table_error("a row has " + std::to_string(f.size()) + " fields, not 5: " + line);
    rows.push_back({f[0], std::atoi(f[1].c_str()), std::atoi(f[2].c_str()), std::atof(f[3].c_str()), f[4]});
  }
  if (rows.empty()) table_error("no rows");
  return rows;
}

const char* kind_key(kern::OpKind k) {
  switch (k) {
    case kern::kOpAdd:
      return "add";
    case kern::kOpCompare:
      return "compare";
    case kern::kOpMux:
      return "mux";
    case kern::kOpXor:
      return "xor";
    case kern::kOpMemRead:
      return "memory_read";
    case kern::kOpRegister:
      return "register";
    default:
      return "";
  }
}

// What a kernel's schedule() calls (resources.hpp).
struct Collector {
  StageSchedule* s;
  void memory(const char* name, int reads, int writes, int ports) {
    s->memories.push_back({name, reads, writes, ports});
  }
  void recurrence(const char* name, int distance) { s->recurrences.push_back({name, distance, {}, {}}); }
  void chain(kern::OpKind kind, int width_bits, int count) {
    if (s->recurrences.empty()) table_error("a chain operator before any recurrence");
    if (count > 0) s->recurrences.back().chain.push_back({kind, width_bits, count});
  }
  void via(const char* memory) {
    if (s->recurrences.empty()) table_error("a register file before any recurrence");
    s->recurrences.back().via.emplace_back(memory);
  }
};

// The counted memories of stage `name` (every array the counting run saw it access).
void add_counted(StageSchedule& s, const std::vector<kern::MemoryAccesses>& counted) {
  for (const kern::MemoryAccesses& m : counted) {
    if (m.stage != s.stage) continue;
    MemoryPorts mp;
    mp.name = m.name;
    mp.reads = m.max_reads_per_bank_per_firing;
    mp.writes = m.max_writes_per_bank_per_firing;
    mp.storage = kern::access_storage_kind(m.kind);
    mp.banks = m.banks;
    mp.runtime_banked_sites = m.runtime_banked_sites;
    mp.max_banks_per_site = m.max_banks_per_site;
    s.memories.push_back(mp);
  }
}

template <class Stage>
StageSchedule collect(const std::string& name, const Stage& stage, double clock_hz,
                      const std::vector<kern::MemoryAccesses>& counted) {
  StageSchedule s;
  s.stage = name;
  Collector c{&s};
  stage.schedule(c);
  add_counted(s, counted);
  add_banking_muxes(s);
  derive_ii(s, clock_hz);
  return s;
}

// schedule() reads only the configuration, never the memories: one column of capacity keeps the
// objects small (any D and PU fit).
using ScheduleCaps = kern::Caps<1, kern::kMaxDisparities, kern::kMaxDisparities>;

// Default-initialised (no zeroing of memories the declarations never read).
template <class T>
std::unique_ptr<T> make_stage() {
  return std::unique_ptr<T>(new T);
}

}  // namespace

const std::vector<OperatorDelay>& operator_delays() {
  static const std::vector<OperatorDelay> rows = parse_delays();
  return rows;
}

double operator_delay_ns(kern::OpKind kind, int width_bits) {
  const std::string key = kind_key(kind);
  for (const auto& r : operator_delays())
    if (r.kind == key && width_bits >= r.min_bits && width_bits <= r.max_bits) return r.delay_ns;
  table_error("no delay for " + (key.empty() ? std::string("this operator") : key) + " of " +
              std::to_string(width_bits) + " bits");
}

double Recurrence::delay_ns() const {
  double d = 0;
  for (const auto& op : chain) d += op.count * operator_delay_ns(op.kind, op.width_bits);
  return d;
}

int Recurrence::ii_at(double budget_ns) const {
  return std::max(1, int(std::ceil(delay_ns() / (budget_ns * distance) - 1e-9)));
}

int MemoryPorts::mii() const {
  if (storage >= 0) return kern::access_ii_forced(storage, reads, writes);
  return std::max(1, (reads + writes + ports - 1) / ports);
}

std::string MemoryPorts::describe() const {
  if (storage < 0)
    return "memory " + name + ": " + std::to_string(reads) + " reads + " + std::to_string(writes) + " writes on " +
           std::to_string(ports) + " ports";
  std::string d = "memory " + name + " (" + kern::access_storage_name(storage) +
                  ", counted): " + std::to_string(reads) + " reads + " + std::to_string(writes) +
                  " writes per bank and firing";
  if (runtime_banked_sites > 0)
    d += ", " + std::to_string(runtime_banked_sites) + " site(s) banked at run time over " + std::to_string(banks) +
         " banks";
  return d;
}

// What the counted banking implies for the recurrences that pass through a register file
// (Recurrence::via). B registers reached by one site at run time are a B:1 read mux, ceil(log4 B)
// levels of LUT6 (a LUT6 selects among 4), and a write decoder comparing the index
// (ceil(log2 B) bits), both at the chain's width. And the scheduler cannot tell which register a
// run-time index reaches: a write in one firing may be the register the next firing reads, so
// the chain's distance is 1 whatever the kernel's own (a pixel's chunks apart, say). A kernel
// earns its distance back by indexing the registers with constants (a rotating register file).
void add_banking_muxes(StageSchedule& s) {
  for (Recurrence& r : s.recurrences)
    for (const std::string& name : r.via)
      for (const MemoryPorts& m : s.memories) {
        if (m.name != name || m.max_banks_per_site < 2) continue;
        int select_bits = 0;
        while ((1 << select_bits) < m.max_banks_per_site) ++select_bits;
        const int width = r.chain.empty() ? 1 : r.chain.front().width_bits;
        r.chain.push_back({kern::kOpMux, width, (select_bits + 1) / 2});
        r.chain.push_back({kern::kOpCompare, select_bits, 1});
        r.distance = 1;
      }
}

void derive_ii(StageSchedule& s, double clock_hz) {
  const double budget_ns = 1e9 / clock_hz * (1.0 - kClockUncertainty);
  s.res_mii = 1;
  s.rec_mii = 1;
  s.limit = "";
  for (const auto& m : s.memories)
    if (m.mii() > s.res_mii) {
      s.res_mii = m.mii();
      s.limit = m.describe();
    }
  // The recurrence that sets RecMII: the largest II, then the longest delay per firing of its
  // distance (the tightest chain).
  std::string rec_limit;
  double tightest = -1;
  for (const auto& r : s.recurrences) {
    const double d = r.delay_ns();
    const int mii = r.ii_at(budget_ns);
    const double per_firing = d / r.distance;
    if (mii > s.rec_mii || (mii == s.rec_mii && per_firing > tightest)) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "recurrence %s: %.2f ns over %d firing(s) of %.2f ns", r.name.c_str(), d,
                    r.distance, budget_ns);
      rec_limit = buf;
      tightest = per_firing;
      s.rec_mii = mii;
    }
  }
  s.ii = std::max({1, s.res_mii, s.rec_mii});
  if (s.rec_mii > s.res_mii || s.limit.empty()) s.limit = rec_limit;
  if (s.limit.empty()) s.limit = "no loop-carried dependence; every memory access within its ports";
}

std::vector<StageSchedule> stage_schedules(const kern::StereoParams& p, const kern::RectifyParams& rectify,
                                           double clock_hz) {
  std::vector<StageSchedule> out;
  const std::vector<kern::MemoryAccesses> counted = probe_memory_accesses(p);
  if (p.cost == kern::kCostCensus) {
    auto cost = make_stage<kern::CensusCostStage<ScheduleCaps>>();
    cost->configure(p);
    out.push_back(collect("cost", *cost, clock_hz, counted));
  } else {
    auto cost = make_stage<kern::SadCostStage<ScheduleCaps>>();
    cost->configure(p);
    out.push_back(collect("cost", *cost, clock_hz, counted));
  }
  {
    // The SGM and WTA stages with the configure() arguments of the pipeline description.
    auto agg = make_stage<kern::SgmAggregate<ScheduleCaps, uint32_t>>();
    auto add_sgm = [&](const char* stage) {
      agg->configure(p, kern::stage_setup(stage, p.path_mask));
      out.push_back(collect(stage, *agg, clock_hz, counted));
      out.back().setup = agg->setup();
    };
    add_sgm("aggregate");
    if (kern::two_pass_paths(p.path_mask)) add_sgm("aggregate_back");
    if (kern::row_reverse_paths(p.path_mask)) {
      auto rev = make_stage<kern::RowReverse<ScheduleCaps, uint32_t>>();
      rev->configure(p);
      out.push_back(collect("row_reverse", *rev, clock_hz, counted));
      add_sgm("aggregate_row");
      auto codes = make_stage<kern::RowReverseCodes<ScheduleCaps>>();
      codes->configure(p);
      out.push_back(collect("row_unreverse", *codes, clock_hz, counted));
    }
  }
  {
    auto wta = make_stage<kern::WtaLr<ScheduleCaps, uint32_t>>();
    wta->configure(p, kern::stage_setup("wta_lr", p.path_mask));
    out.push_back(collect("wta_lr", *wta, clock_hz, counted));
    out.back().setup = wta->setup();
  }
  {
    auto median = make_stage<kern::Median<ScheduleCaps>>();
    median->configure(p);
    out.push_back(collect("median", *median, clock_hz, counted));
  }
  if (rectify.mode != kern::kRectifyNone) {
    auto rect = make_stage<kern::Rectify<1, 1>>();
    rect->configure(rectify);
    out.push_back(collect("rectify_left", *rect, clock_hz, {}));
    out.push_back(collect("rectify_right", *rect, clock_hz, {}));
  }
  return out;
}

}  // namespace parallax::sim
