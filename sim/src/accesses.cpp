// The counting run (accesses.hpp).
#include "parallax/sim/accesses.hpp"

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "engine.hpp"
#include "internal_error.hpp"
#include "parallax/kernels/access.hpp"
#include "parallax/sim/schedule.hpp"

namespace parallax::sim {
namespace {

// The counting instantiation: software capacities, lane loops run to PU exactly, counted arrays.
using CountCaps = kern::Caps<kern::kMaxWidthPx, kern::kMaxDisparities, kern::kMaxDisparities, kern::kMaxWindow,
                             kern::kMaxMedian, 0xFu, false, kern::kMaxMinDisparity, true>;

template <class Word>
void run_counting(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p) {
  auto engine = std::make_unique<detail::Engine<CountCaps, Word, false, true>>();
  DisparityCodes out;
  engine->run(left, right, p, detail::RunSetup{}, out, nullptr);
}

std::string op_text(const ChainOp& op) {
  static const char* const names[] = {"add", "compare", "mux", "popcount", "xor", "mul", "memory_read", "register"};
  const int k = int(op.kind);
  return std::string(k >= 0 && k < 8 ? names[k] : "?") + " " + std::to_string(op.width_bits) + " bits x " +
         std::to_string(op.count);
}

}  // namespace

std::string count_accesses_json(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                                const AccessRunOptions& opt) {
  const std::vector<std::string> errors = func_param_errors(p);
  if (!errors.empty()) detail::internal_error("count_accesses_json: " + errors.front());
  kern::AccessRegistry::get().reset();
  if (kern::aggregate_bits(p) <= 16)
    run_counting<uint16_t>(left, right, p);
  else
    run_counting<uint32_t>(left, right, p);
  const double budget_ns = 1e9 / opt.clock_hz * (1.0 - kClockUncertainty);
  std::vector<kern::AccessStage> stages;
  for (const StageSchedule& s : stage_schedules(p, opt.rectify, opt.clock_hz)) {
    kern::AccessStage a;
    a.name = s.stage;
    a.ii_declared = s.ii;
    for (const Recurrence& r : s.recurrences) {
      kern::AccessRecurrence ar;
      ar.name = r.name;
      for (const ChainOp& op : r.chain) ar.operators.push_back(op_text(op));
      ar.delay_ns = r.delay_ns();
      ar.budget_ns = budget_ns;
      ar.distance = r.distance;
      ar.ii_forced = std::max(1, int(std::ceil(ar.delay_ns / (budget_ns * r.distance) - 1e-9)));
      a.recurrences.push_back(ar);
    }
    stages.push_back(a);
  }
  std::string json = kern::access_report_json(opt.design, stages);
  kern::AccessRegistry::get().reset();
  return json;
}

}  // namespace parallax::sim
