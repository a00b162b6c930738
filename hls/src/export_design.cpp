// The export's design constants (export_parts.hpp): name, clock, sizes, structure, bit widths,
// register values and the storage directives the resource model maps.
#include <cmath>
#include <string>

#include "export_parts.hpp"
#include "parallax/kernels/sgm_kinds.hpp"

namespace parallax::hlsx::detail {

// The design's name, clock, sizes, structure constants, bit widths and register values.
void design_values(const ExportRequest& r, const kern::StereoParams& p, Values& v) {
  const config::PipelineConfig& c = r.config;
  v["NAME"] = c.name;
  v["NAME_ID"] = identifier(c.name);
  v["ORIGIN"] = r.origin;
  v["PART"] = r.part;
  v["CLOCK_MHZ"] = fixed(r.clock_mhz, r.clock_mhz == std::floor(r.clock_mhz) ? 0 : 3);
  v["PERIOD_NS"] = clock_period_ns(r.clock_mhz);
  v["WIDTH"] = std::to_string(r.width_px);
  v["HEIGHT"] = std::to_string(r.height_px);
  v["REDUCED_HEIGHT"] = std::to_string(r.reduced_height_px);
  const bool census = p.cost == kern::kCostCensus;
  v["COST_ENUM"] = census ? "kCostCensus" : "kCostSad";
  v["COST_HEADER"] = census ? "census.hpp" : "sad.hpp";
  v["COST_STAGE"] = census ? "CensusCostStage" : "SadCostStage";
  v["COST_NAME"] = !census                              ? "SAD"
                   : p.census == kern::kCensusSparse    ? "sparse Census"
                   : p.census == kern::kCensusSymmetric ? "centre-symmetric Census"
                                                        : "Census";
  const char* census_enums[] = {"kCensusFull", "kCensusSparse", "kCensusSymmetric"};
  v["CENSUS_ENUM"] = census_enums[p.census == kern::kCensusSparse ? 1 : p.census == kern::kCensusSymmetric ? 2 : 0];
  v["WINDOW_W"] = std::to_string(p.window_w);
  v["WINDOW_H"] = std::to_string(p.window_h);
  v["DISPARITIES"] = std::to_string(p.disparities);
  v["DISPARITIES_MINUS_1"] = std::to_string(p.disparities - 1);
  v["MIN_DISPARITY"] = std::to_string(p.min_disparity);
  v["P2_ADAPTIVE"] = std::to_string(p.p2_adaptive);
  v["P2_ADAPTIVE_01"] = p.p2_adaptive > 0 ? "1" : "0";
  v["SUBPIXEL_BITS"] = std::to_string(p.subpixel_bits);
  v["MEDIAN_WIDE_KEYS"] = kern::disparity_bits(p) + 6 > 16 ? "1" : "0";  // 6: median.hpp kKeyIndexBits
  v["AGGREGATION_ENUM"] = p.aggregation == kern::kAggregationMgm ? "kAggregationMgm" : "kAggregationSgm";
  v["STRUCTURE_KNOBS_TEXT"] = std::string(p.aggregation == kern::kAggregationMgm ? ", MGM aggregation" : "") +
                              (p.p2_adaptive > 0 ? ", adaptive P2 (a = " + std::to_string(p.p2_adaptive) + ")" : "");
  v["MIN_DISPARITY_TEXT"] =
      p.min_disparity == 0 ? "" : " from m = " + std::to_string(p.min_disparity) + " (code d is the disparity m + d)";
  v["PARALLEL_UNITS"] = std::to_string(p.parallel_units);
  v["PATH_MASK"] = std::to_string(p.path_mask);
  v["PATHS"] = config::paths_to_string(p.path_mask);
  v["LR_CHECK"] = p.lr_check ? "true" : "false";
  v["LR_CHECK_TEXT"] = p.lr_check ? "on" : "off";
  v["MEDIAN"] = std::to_string(p.median >= 3 ? p.median : 0);
  v["MEDIAN_ROWS"] = std::to_string(p.median >= 3 ? p.median : 1);
  // Stream path kinds of the forward and, for two passes, the backward pass (one kernel type serves both).
  v["KIND_MASK"] = std::to_string(kern::datapath_kinds(kern::stream_kinds(p.path_mask, false), p.aggregation) |
                                  kern::datapath_kinds(kern::stream_kinds(p.path_mask, true), p.aggregation));
  v["MEDIAN_TEXT"] = p.median >= 3 ? std::to_string(p.median) + "x" + std::to_string(p.median) : "off";
  v["COST_MAX"] = std::to_string(kern::cost_max(p));
  v["COST_BITS"] = std::to_string(kern::cost_bits(p));
  v["PENALTY_BITS"] = std::to_string(kern::penalty_bits(p));
  v["PATH_BITS"] = std::to_string(kern::path_bits(p));
  v["CENSUS_BITS"] =
      std::to_string(p.cost == kern::kCostCensus ? kern::census_bits(p.census, p.window_w, p.window_h) : 1);
  v["AGGREGATE_BITS"] = std::to_string(kern::aggregate_bits(p));
  v["DISPARITY_BITS"] = std::to_string(kern::disparity_bits(p));
  v["OUT_BITS"] = std::to_string(((kern::disparity_bits(p) + 7) / 8) * 8);
  v["AGG_WORD"] = kern::aggregate_bits(p) <= 16 ? "uint16_t" : "uint32_t";
  // The runtime registers: AXI4-Lite ports of the top; these values are the testbench's.
  const kern::StereoRegisters regs = c.registers();
  v["P1"] = std::to_string(regs.p1);
  v["P2"] = std::to_string(regs.p2);
  v["LR_TOLERANCE"] = std::to_string(regs.lr_tolerance);
  v["UNIQUENESS_PCT"] = std::to_string(regs.uniqueness_pct);
  v["UNIQUENESS_BITS"] = std::to_string(kern::kUniquenessBits);
  v["UNIQUENESS"] = regs.uniqueness_pct > 0 ? "true" : "false";
  v["UNIQUENESS_TEXT"] =
      regs.uniqueness_pct > 0 ? "built with the check; 0 turns it off" : "built without the check: ignored";
  v["FRAMES"] = std::to_string(kTestbenchFrames);
  // structure_params(): every field but the size (the frame's, full or reduced) from the table.
  std::string fields;
  kern::for_each_param(p, [&](const kern::ParamField& f) {
    const std::string name = f.name;
    if (name == "width_px" || name == "height_px") return;
    fields += fragment(f.is_register ? "register_param" : "structure_param",
                       {{"FIELD", name}, {"VALUE", std::to_string(f.value)}});
  });
  v["STRUCTURE_PARAMS"] = fields;
}

// Storage directives of the line buffers and the path-cost rows, from the resource model's mapping.
void storage_values(const res::Inventory& inv, Values& v) {
  // The row reversals' memories (5 paths, kernels/row_reverse.hpp), bound as the model maps them.
  std::string reverse;
  const struct {
    const char *stage, *memory, *macro, *member;
  } reversals[] = {{"row_reverse", "row_reverse_cost", "COST", "cost_"},
                   {"row_reverse", "row_reverse_sum", "SUM", "sum_"},
                   {"row_unreverse", "row_reverse_codes", "CODES", "codes_"}};
  for (const auto& m : reversals)
    if (const res::MemoryItem* item = find_memory(inv, m.stage, m.memory))
      reverse += fragment("row_reverse_storage",
                          {{"MACRO", m.macro}, {"MEMBER", m.member}, {"IMPL", ram_impl(item->per_copy.storage)}});
  v["ROW_REVERSE_STORAGE"] = reverse;
  const res::MemoryItem* lb = find_memory(inv, "cost", "left_line_buffer");
  v["LINE_BUFFER_IMPL"] = lb ? ram_impl(lb->per_copy.storage) : "bram";
  const res::MemoryItem* row = nullptr;
  for (const char* n : {"row_path_up", "row_path_left", "row_path_right"})
    if (!row) row = find_memory(inv, "aggregate", n);
  v["ROW_IMPL"] = row ? ram_impl(row->per_copy.storage) : "bram";
}

}  // namespace parallax::hlsx::detail
