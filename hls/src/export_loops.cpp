// The loops of the exported top that run until their stage is done: LOOP_TRIPCOUNT and PIPELINE
// II, and the testbench's table of declared II and recurrences (export_loops.hpp).
#include "export_loops.hpp"

#include <algorithm>
#include <cstdio>

#include "export_parts.hpp"
#include "parallax/kernels/sgm.hpp"

namespace parallax::hlsx::detail {
namespace {

// The stages whose loops in the top run until the stage is done (`while (!stage.done())`), by the
// placeholder of their LOOP_TRIPCOUNT: each loop fires its kernel once per iteration, so its trip
// count is the cycle model's firings of the stage (several stages: the instances of one loop).
struct TripLoop {
  const char* key;
  std::vector<std::string> stages;
};
std::vector<TripLoop> trip_loops(const config::PipelineConfig& c) {
  std::vector<TripLoop> loops = {{"TRIPCOUNT_COST", {"cost"}},
                                 {"TRIPCOUNT_AGGREGATE", {"aggregate"}},
                                 {"TRIPCOUNT_WTA_LR", {"wta_lr"}},
                                 {"TRIPCOUNT_MEDIAN", {"median"}}};
  if (kern::two_pass_paths(c.path_mask)) loops.push_back({"TRIPCOUNT_AGGREGATE_BACK", {"aggregate_back"}});
  if (kern::row_reverse_paths(c.path_mask)) {
    loops.push_back({"TRIPCOUNT_ROW_REVERSE", {"row_reverse"}});
    loops.push_back({"TRIPCOUNT_AGGREGATE_ROW", {"aggregate_row"}});
    loops.push_back({"TRIPCOUNT_ROW_UNREVERSE", {"row_unreverse"}});
  }
  if (c.rectify != "none") loops.push_back({"TRIPCOUNT_RECTIFY", {"rectify_left", "rectify_right"}});
  return loops;
}

// min, max and mean of the firings of `stages` in `fires`; ExportError naming a missing stage.
std::string tripcount_pragma(const std::map<std::string, int64_t>& fires, const std::vector<std::string>& stages,
                             const std::string& frame) {
  int64_t lo = 0, hi = 0, sum = 0;
  for (std::size_t i = 0; i < stages.size(); ++i) {
    const auto it = fires.find(stages[i]);
    if (it == fires.end() || it->second < 1)
      throw ExportError("export: the cycle model's firings of stage '" + stages[i] + "' on the " + frame +
                        " frame are missing");
    lo = i == 0 ? it->second : std::min(lo, it->second);
    hi = i == 0 ? it->second : std::max(hi, it->second);
    sum += it->second;
  }
  const int64_t avg = (sum + int64_t(stages.size()) / 2) / int64_t(stages.size());
  return fragment("loop_tripcount",
                  {{"MIN", std::to_string(lo)}, {"MAX", std::to_string(hi)}, {"AVG", std::to_string(avg)}});
}

// A C string literal of a simulator or model identifier (no character needs escaping).
std::string quoted(const std::string& t) {
  return "\"" + t + "\"";
}

// The testbench's table of the kernel stages' declared II and recurrences (access_stages), to
// which its C simulation adds the counted memories (csim_accesses.json). Names and operator
// texts are the simulator's identifiers: no character needs escaping in a C string.
std::string access_stage_table(const ExportRequest& r) {
  auto number = [](double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3f", x);
    return std::string(buf);
  };
  std::string o;
  for (const kern::AccessStage& s : r.access_stages) {
    o += fragment("tb_access_stage", {{"NAME", s.name}, {"II", std::to_string(s.ii_declared)}});
    for (const kern::AccessRecurrence& rec : s.recurrences) {
      std::string ops;
      for (const std::string& op : rec.operators) ops += (ops.empty() ? "" : ", ") + quoted(op);
      o += fragment("tb_access_recurrence", {{"NAME", rec.name},
                                             {"OPERATORS", ops},
                                             {"DELAY_NS", number(rec.delay_ns)},
                                             {"BUDGET_NS", number(rec.budget_ns)},
                                             {"DISTANCE", std::to_string(rec.distance)},
                                             {"II_FORCED", std::to_string(rec.ii_forced)}});
    }
  }
  return o;
}

// LOOP_TRIPCOUNT and PIPELINE II of the loops that run until their stage is done.
}  // namespace

void loop_values(const ExportRequest& r, std::map<std::string, std::string>& v) {
  const config::PipelineConfig& c = r.config;
  // LOOP_TRIPCOUNT of the loops that run until their stage is done: the cycle model's firings per
  // frame, of the full frame and of the reduced one.
  std::string trip_table;
  for (const char* key :
       {"TRIPCOUNT_COST", "TRIPCOUNT_AGGREGATE", "TRIPCOUNT_WTA_LR", "TRIPCOUNT_MEDIAN", "TRIPCOUNT_AGGREGATE_BACK",
        "TRIPCOUNT_RECTIFY", "TRIPCOUNT_ROW_REVERSE", "TRIPCOUNT_AGGREGATE_ROW", "TRIPCOUNT_ROW_UNREVERSE"})
    v[key] = "";
  for (const TripLoop& l : trip_loops(c)) {
    v[l.key] = fragment("by_frame", {{"FULL_FRAME", tripcount_pragma(r.stage_fires, l.stages, "full")},
                                     {"REDUCED_FRAME", tripcount_pragma(r.reduced_stage_fires, l.stages, "reduced")}});
    for (const std::string& st : l.stages)
      trip_table += std::string(trip_table.empty() ? "" : ", ") + st + " " + std::to_string(r.stage_fires.at(st));
  }
  v["TRIPCOUNT_TABLE"] = trip_table;
  // PIPELINE II of each stage's loop: the cycle model's (derived from the kernels' schedule
  // declarations at this clock); the rectify loop serves both cameras.
  auto ii_of = [&](std::initializer_list<const char*> stages) {
    int ii = 1;
    for (const auto& t : r.stage_timing)
      for (const char* st : stages)
        if (t.name == st) ii = std::max(ii, t.ii_cycles);
    return std::to_string(ii);
  };
  v["II_COST"] = ii_of({"cost"});
  v["II_AGGREGATE"] = ii_of({"aggregate"});
  v["II_AGGREGATE_BACK"] = ii_of({"aggregate_back"});
  v["II_WTA_LR"] = ii_of({"wta_lr"});
  v["II_MEDIAN"] = ii_of({"median"});
  v["II_RECTIFY"] = ii_of({"rectify_left", "rectify_right"});
  v["II_ROW_REVERSE"] = ii_of({"row_reverse"});
  v["II_AGGREGATE_ROW"] = ii_of({"aggregate_row"});
  v["II_ROW_UNREVERSE"] = ii_of({"row_unreverse"});
  v["ACCESS_STAGES"] = access_stage_table(r);
}

void priced_width_values(const res::Inventory& inv, std::map<std::string, std::string>& v) {
  std::string o;
  auto row = [&](const std::string& stage, const std::string& name, bool memory, int bits) {
    o += fragment(
        "tb_priced_width",
        {{"STAGE", stage}, {"NAME", name}, {"MEMORY", memory ? "true" : "false"}, {"BITS", std::to_string(bits)}});
  };
  for (const res::MemoryItem& m : inv.memories)
    if (m.kind == res::MemoryKind::array) row(m.stage, m.name, true, m.width_bits);
  for (const res::RegisterItem& g : inv.registers) row(g.stage, g.name, false, g.width_bits);
  v["PRICED_WIDTHS"] = o;
}

}  // namespace parallax::hlsx::detail
