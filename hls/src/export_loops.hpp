// The values of the exported top's stage loops (export.cpp's templates): LOOP_TRIPCOUNT of each
// `while (!stage.done())` loop from the cycle model's firings (full and reduced frame), PIPELINE II
// from its stage timing, and ACCESS_STAGES, the testbench's table of the kernel stages' declared
// II and recurrences (csim_accesses.json).
#pragma once

#include <map>
#include <string>

#include "parallax/hls/export.hpp"
#include "parallax/resources/model.hpp"

namespace parallax::hlsx::detail {

// Sets the TRIPCOUNT_*, II_*, TRIPCOUNT_TABLE and ACCESS_STAGES values; ExportError when the cycle
// model's firings of a stage are missing.
void loop_values(const ExportRequest& r, std::map<std::string, std::string>& v);

// Sets PRICED_WIDTHS: the testbench's table of the storage the resource model prices (each
// memory's word width and each register's width, by stage and name), which the C simulation
// compares with the widths the kernels' members store (csim_storage.json).
void priced_width_values(const res::Inventory& inv, std::map<std::string, std::string>& v);

}  // namespace parallax::hlsx::detail
