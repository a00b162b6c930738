// The counting run (accesses.hpp).
#include "parallax/sim/accesses.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <mutex>
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

// A seeded texture (an LCG's high bits), the right image the left shifted by half the range.
GreyImage probe_image(int width_px, int height_px, int shift_px) {
  GreyImage g;
  g.width_px = width_px;
  g.height_px = height_px;
  g.px.resize(std::size_t(width_px) * std::size_t(height_px));
  uint32_t state = 0x2545F491u;
  std::vector<uint8_t> row(std::size_t(width_px) + std::size_t(shift_px));
  for (int y = 0; y < height_px; ++y) {
    for (auto& v : row) {
      state = state * 1664525u + 1013904223u;
      v = uint8_t(state >> 24);
    }
    for (int x = 0; x < width_px; ++x)
      g.px[std::size_t(y) * std::size_t(width_px) + std::size_t(x)] = row[std::size_t(x) + std::size_t(shift_px)];
  }
  return g;
}

std::string probe_key(const kern::StereoParams& p) {
  const int f[] = {p.width_px,
                   p.height_px,
                   p.cost,
                   p.window_w,
                   p.window_h,
                   p.disparities,
                   p.parallel_units,
                   int(p.path_mask),
                   p.p1,
                   p.p2,
                   int(p.lr_check),
                   p.lr_tolerance,
                   p.median,
                   p.uniqueness_pct,
                   p.census,
                   p.min_disparity,
                   p.p2_adaptive,
                   p.aggregation,
                   p.subpixel_bits};
  std::string k;
  for (int v : f) k += std::to_string(v) + ",";
  return k;
}

// The probe's parameters: the design's, with the penalties replaced by canonical ones of the
// same register widths (P2 all ones in its width, P1 a quarter of it). P1 and P2 are values the
// aggregation adds, never an index or a trip count: every RAM's banks and accesses per firing are
// the same whatever they are, and a sweep over penalties probes each structure once, whatever
// order its designs arrive in. Register files off the recurrences may count differently with the
// data (the LR check's right disparities); they force no II, and those on a recurrence bank alike
// (tests/sim/accesses_test.cpp, CountedII.PenaltiesChangeNoMemorysCounts).
kern::StereoParams probe_params(const kern::StereoParams& p) {
  kern::StereoParams q = p;
  q.p2 = int(kern::p2_register_max(p));
  q.p1 = q.p2 / 4;
  if (kern::aggregate_bits(q) != kern::aggregate_bits(p) || !func_param_errors(q).empty()) return p;
  return q;
}

std::vector<kern::MemoryAccesses> count_probe(const kern::StereoParams& p) {
  kern::StereoParams q = p;
  const int rows = std::max({p.window_h, p.median, 3});
  q.width_px = std::min(p.width_px, std::max(16, p.min_disparity + p.disparities + p.window_w + 8));
  q.height_px = std::min(p.height_px, 2 * rows + 2);
  if (!func_param_errors(q).empty()) q = p;  // a size the design rejects: the design's own
  const GreyImage left = probe_image(q.width_px, q.height_px, 0);
  const GreyImage right = probe_image(q.width_px, q.height_px, p.min_disparity + p.disparities / 2);
  kern::AccessRegistry::get().reset();
  if (kern::aggregate_bits(q) <= 16)
    run_counting<uint16_t>(left, right, q);
  else
    run_counting<uint32_t>(left, right, q);
  std::vector<kern::MemoryAccesses> out = kern::AccessRegistry::get().report();
  kern::AccessRegistry::get().reset();
  return out;
}

std::string op_text(const ChainOp& op) {
  static const char* const names[] = {"add", "compare", "mux", "popcount", "xor", "mul", "memory_read", "register"};
  const int k = int(op.kind);
  return std::string(k >= 0 && k < 8 ? names[k] : "?") + " " + std::to_string(op.width_bits) + " bits x " +
         std::to_string(op.count);
}

}  // namespace

std::vector<kern::MemoryAccesses> probe_memory_accesses(const kern::StereoParams& p) {
  const std::vector<std::string> errors = func_param_errors(p);
  if (!errors.empty()) detail::internal_error("probe_memory_accesses: " + errors.front());
  static std::mutex mutex;
  static std::map<std::string, std::vector<kern::MemoryAccesses>> memo;
  const kern::StereoParams q = probe_params(p);
  const std::string key = probe_key(q);
  {
    const std::lock_guard<std::mutex> lock(mutex);
    const auto it = memo.find(key);
    if (it != memo.end()) return it->second;
  }
  std::vector<kern::MemoryAccesses> counted = count_probe(q);
  const std::lock_guard<std::mutex> lock(mutex);
  return memo.emplace(key, std::move(counted)).first->second;
}

std::vector<kern::AccessStage> access_stages(const kern::StereoParams& p, const kern::RectifyParams& rectify,
                                             double clock_hz) {
  const std::vector<StageSchedule> schedules = stage_schedules(p, rectify, clock_hz);
  const double budget_ns = 1e9 / clock_hz * (1.0 - kClockUncertainty);
  std::vector<kern::AccessStage> stages;
  for (const StageSchedule& s : schedules) {
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
      ar.ii_forced = r.ii_at(budget_ns);
      a.recurrences.push_back(ar);
    }
    stages.push_back(a);
  }
  return stages;
}

std::string count_accesses_json(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                                const AccessRunOptions& opt) {
  const std::vector<std::string> errors = func_param_errors(p);
  if (!errors.empty()) detail::internal_error("count_accesses_json: " + errors.front());
  // The II each stage's pragma states (from the probe's counts and the declared recurrences),
  // before this frame's count: the probe uses the same registry.
  const std::vector<kern::AccessStage> stages = access_stages(p, opt.rectify, opt.clock_hz);
  kern::AccessRegistry::get().reset();
  if (kern::aggregate_bits(p) <= 16)
    run_counting<uint16_t>(left, right, p);
  else
    run_counting<uint32_t>(left, right, p);
  std::string json = kern::access_report_json(opt.design, stages);
  kern::AccessRegistry::get().reset();
  return json;
}

}  // namespace parallax::sim
