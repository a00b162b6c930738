// The operator table of the resource model (models/data/operators.csv, issue 42) is what Yosys
// maps: a sample of its rows is characterised again by the script that wrote it and must come
// out cell for cell the same; and the table covers what the kernels need and is sane (a wider
// adder never costs fewer LUTs, a wider mux more). Skipped, saying why, when yosys or python3 is
// absent (`bash cmake/setup.sh test` installs both).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "parallax/resources/operators.hpp"

namespace {

const std::string kRoot = PARALLAX_SOURCE_DIR;

struct Table {
  std::vector<std::string> header;
  std::map<std::tuple<std::string, int, int, int>, std::vector<std::string>> rows;  // (kind, width, fan-in, b)
  std::string version_line;
};

Table parse(std::istream& in) {
  Table t;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      if (line.find("Yosys") != std::string::npos && t.version_line.empty()) t.version_line = line;
      continue;
    }
    std::vector<std::string> f;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) f.push_back(cell);
    if (t.header.empty()) {
      t.header = f;
      continue;
    }
    if (f.size() != t.header.size()) continue;
    t.rows[{f[0], std::stoi(f[1]), std::stoi(f[2]), std::stoi(f[3])}] = f;
  }
  return t;
}

Table committed() {
  std::ifstream in(kRoot + "/models/data/operators.csv");
  EXPECT_TRUE(in.good()) << "models/data/operators.csv missing";
  return parse(in);
}

int col(const Table& t, const std::vector<std::string>& row, const std::string& name) {
  for (std::size_t i = 0; i < t.header.size(); ++i)
    if (t.header[i] == name) return std::stoi(row[i]);
  ADD_FAILURE() << "no column " << name;
  return -1;
}

bool have(const char* cmd) {
  return std::system((std::string("command -v ") + cmd + " >/dev/null 2>&1").c_str()) == 0;
}

TEST(OperatorTable, ASampleMapsAgainCellForCell) {
  if (!have("yosys") || !have("python3"))
    GTEST_SKIP() << "yosys or python3 is not installed (bash cmake/setup.sh test installs them)";
  const Table t = committed();
  ASSERT_FALSE(t.rows.empty());
  const std::string cmd = "python3 " + kRoot + "/models/resources/tools/characterise_operators.py --sample 37 --jobs 2";
  FILE* p = popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string out;
  char buf[4096];
  for (std::size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
  ASSERT_EQ(pclose(p), 0) << out;
  std::stringstream ss(out);
  const Table again = parse(ss);
  ASSERT_GE(again.rows.size(), 5u) << out;
  EXPECT_EQ(again.version_line, t.version_line) << "the table was written by another Yosys; rerun the script";
  for (const auto& [key, row] : again.rows) {
    const auto it = t.rows.find(key);
    ASSERT_NE(it, t.rows.end()) << std::get<0>(key) << " " << std::get<1>(key) << " is not in the table";
    EXPECT_EQ(it->second, row) << std::get<0>(key) << " width " << std::get<1>(key) << " fan-in " << std::get<2>(key);
  }
}

TEST(OperatorTable, CoversTheKernelsAndIsMonotone) {
  const Table t = committed();
  // Every kind the kernels' declarations use, up to 64 bits (census codes), muxes up to 64:1.
  for (const char* kind : {"add", "compare", "equal", "min2", "xor", "mux", "decoder", "popcount", "mul", "mul_fabric",
                           "register", "srl"}) {
    bool found = false;
    for (const auto& [key, row] : t.rows) found = found || std::get<0>(key) == kind;
    EXPECT_TRUE(found) << kind;
  }
  EXPECT_EQ(t.rows.count({"add", 64, 1, 0}), 1u);
  EXPECT_EQ(t.rows.count({"mux", 16, 64, 0}), 1u);
  // Cost grows with width (adders, registers) and with fan-in (muxes of one width).
  int last_add = -1, last_mux = -1;
  for (const auto& [key, row] : t.rows) {
    if (std::get<0>(key) == "add") {
      const int luts = col(t, row, "lut") + col(t, row, "carry8");
      EXPECT_GE(luts, last_add) << "add " << std::get<1>(key);
      last_add = luts;
      EXPECT_EQ(col(t, row, "ff"), 0);
    }
    if (std::get<0>(key) == "register") {
      EXPECT_EQ(col(t, row, "ff"), std::get<1>(key));
    }
    if (std::get<0>(key) == "mux" && std::get<1>(key) == 8) {
      // A MUXF7/F8 that Yosys feeds from outside a LUT stands for a route-through LUT in the
      // device, so a mux's logic is counted as its LUTs and MUXFs together.
      const int luts = col(t, row, "lut") + col(t, row, "muxf");
      EXPECT_GE(luts, last_mux) << "mux 8 bits, fan-in " << std::get<2>(key);
      last_mux = luts;
    }
  }
}

// Lookup and interpolation on a small table of known numbers.
TEST(OperatorTable, InterpolatesBetweenAndScalesBeyondTheGrid) {
  const std::string text =
      "# Operators mapped onto UltraScale+ primitives by Yosys 9.9 (test)\n"
      "kind,width_bits,fan_in,b_bits,lut,ff,carry4,carry8,srl,muxf,dsp,lutram\n"
      "add,8,1,0,8,0,2,1,0,0,0,0\n"
      "add,16,1,0,16,0,4,2,0,0,0,0\n"
      "mux,8,2,0,8,0,0,0,0,0,0,0\n"
      "mux,8,4,0,8,0,0,0,0,0,0,0\n"
      "mux,16,2,0,16,0,0,0,0,0,0,0\n"
      "mux,16,4,0,16,0,0,0,0,0,0,0\n"
      "srl,1,16,0,0,0,0,0,1,0,0,0\n"
      "srl,1,32,0,0,0,0,0,1,0,0,0\n"
      "mul,16,1,16,0,0,0,0,0,0,1,0\n";
  std::string version;
  const auto t = parallax::res::parse_operator_table(text, &version);
  EXPECT_EQ(version, "9.9");
  ASSERT_EQ(t.size(), 9u);
  using parallax::res::mapped_cost;
  EXPECT_DOUBLE_EQ(mapped_cost(t, "add", 8).lut, 8);
  EXPECT_DOUBLE_EQ(mapped_cost(t, "add", 12).lut, 12);            // between the grid's widths
  EXPECT_DOUBLE_EQ(mapped_cost(t, "add", 32).carry8, 4);          // beyond: scaled with the width
  EXPECT_DOUBLE_EQ(mapped_cost(t, "add", 4).lut, 8);              // below: the narrowest
  EXPECT_DOUBLE_EQ(mapped_cost(t, "mux", 12, 3).lut, 12);         // width and fan-in
  EXPECT_DOUBLE_EQ(mapped_cost(t, "mux", 8, 16).lut, 4 * 8 + 8);  // a tree: four 4:1, then one 4:1
  EXPECT_DOUBLE_EQ(mapped_cost(t, "mux", 8, 1).lut, 0);           // one input: a wire
  EXPECT_DOUBLE_EQ(mapped_cost(t, "srl", 9, 24).srl, 9);          // per bit
  EXPECT_DOUBLE_EQ(mapped_cost(t, "mul", 10, 1, 12).dsp, 1);      // the smallest shape holding both
  EXPECT_THROW(mapped_cost(t, "divide", 8), std::invalid_argument);
  EXPECT_THROW(parallax::res::parse_operator_table("kind,width\nadd,1\n"), std::runtime_error);
}

// The compiled-in table is the committed file.
TEST(OperatorTable, TheCompiledInTableIsTheFile) {
  const Table t = committed();
  EXPECT_EQ(parallax::res::operator_table().size(), t.rows.size());
  EXPECT_FALSE(parallax::res::operator_table_yosys().empty());
  EXPECT_GT(parallax::res::mapped_cost("add", 10).lut, 0);
}

}  // namespace
