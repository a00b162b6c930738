// The operator table of the resource model (issue 42): what an operator of a kind, width and
// fan-in maps to on UltraScale+, as Yosys maps it (models/data/operators.csv, written by
// models/resources/tools/characterise_operators.py and compiled in). Between the widths and
// fan-ins the table holds, a cost is interpolated linearly; beyond the widest, it scales with the
// width; a mux wider than the table's fan-in is composed of the table's muxes in a tree.
#pragma once

#include <string>
#include <vector>

namespace parallax::res {

// Cells of one operator (fractional where interpolated).
struct MappedCost {
  double lut = 0, ff = 0, carry8 = 0, srl = 0, muxf = 0, dsp = 0;
  MappedCost& operator+=(const MappedCost& o);
  MappedCost operator*(double k) const;
};

struct OperatorRow {
  std::string kind;  // add, compare, equal, min2, xor, mux, decoder, popcount, mul, register, srl
  int width_bits = 0, fan_in = 1, b_bits = 0;
  MappedCost cost;
};

// The compiled-in table (rows in file order) and the Yosys version that wrote it.
const std::vector<OperatorRow>& operator_table();
const std::string& operator_table_yosys();
// Parses a table's text (the same CSV); throws std::runtime_error naming the line.
std::vector<OperatorRow> parse_operator_table(const std::string& csv_text, std::string* yosys_version = nullptr);

// The cost of one operator. kind as in the table; fan_in: mux inputs, decoder outputs, srl
// depth (1 otherwise); b_bits: a multiplier's second operand. Throws std::invalid_argument for a
// kind the table does not hold.
MappedCost mapped_cost(const std::string& kind, int width_bits, int fan_in = 1, int b_bits = 0);
MappedCost mapped_cost(const std::vector<OperatorRow>& table, const std::string& kind, int width_bits, int fan_in = 1,
                       int b_bits = 0);

}  // namespace parallax::res
