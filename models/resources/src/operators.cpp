#include "parallax/resources/operators.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace parallax::res {
namespace data {
extern const char* const operators_csv;
}

MappedCost& MappedCost::operator+=(const MappedCost& o) {
  lut += o.lut;
  ff += o.ff;
  carry8 += o.carry8;
  srl += o.srl;
  muxf += o.muxf;
  dsp += o.dsp;
  return *this;
}

MappedCost MappedCost::operator*(double k) const {
  MappedCost c = *this;
  c.lut *= k;
  c.ff *= k;
  c.carry8 *= k;
  c.srl *= k;
  c.muxf *= k;
  c.dsp *= k;
  return c;
}

namespace {

const char* const kColumns[] = {"kind",   "width_bits", "fan_in", "b_bits", "lut", "ff",
                                "carry4", "carry8",     "srl",    "muxf",   "dsp", "lutram"};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> f;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) f.push_back(cell);
  return f;
}

// Linear interpolation of cost over x in sorted points; beyond the last point, scaled by x / x_last;
// below the first, the first.
MappedCost interpolate(const std::vector<std::pair<int, MappedCost>>& pts, double x) {
  if (pts.empty()) throw std::logic_error("operator table: no points");
  if (x <= pts.front().first) return pts.front().second;
  for (std::size_t i = 1; i < pts.size(); ++i)
    if (x <= pts[i].first) {
      const double t = (x - pts[i - 1].first) / double(pts[i].first - pts[i - 1].first);
      MappedCost c = pts[i - 1].second * (1 - t);
      c += pts[i].second * t;
      return c;
    }
  return pts.back().second * (x / pts.back().first);
}

std::vector<std::pair<int, MappedCost>> along_width(const std::vector<OperatorRow>& t, const std::string& kind,
                                                    int fan_in) {
  std::vector<std::pair<int, MappedCost>> p;
  for (const OperatorRow& r : t)
    if (r.kind == kind && r.fan_in == fan_in) p.emplace_back(r.width_bits, r.cost);
  std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return p;
}

// The points of a one-bit-wide kind along its fan-in (decoders, SRL depths).
std::vector<std::pair<int, MappedCost>> along_fan_in(const std::vector<OperatorRow>& t, const std::string& kind) {
  std::vector<std::pair<int, MappedCost>> p;
  for (const OperatorRow& r : t)
    if (r.kind == kind) p.emplace_back(r.fan_in, r.cost);
  if (p.empty()) throw std::invalid_argument("operator table: no " + kind + " rows");
  std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return p;
}

std::vector<int> fan_ins(const std::vector<OperatorRow>& t, const std::string& kind) {
  std::vector<int> n;
  for (const OperatorRow& r : t)
    if (r.kind == kind && std::find(n.begin(), n.end(), r.fan_in) == n.end()) n.push_back(r.fan_in);
  std::sort(n.begin(), n.end());
  return n;
}

// A mux of fan_in inputs at width w: interpolated in width at the table's fan-ins around fan_in,
// then in fan-in; wider than the table's widest, a tree of the widest muxes.
MappedCost mux_cost(const std::vector<OperatorRow>& t, int w, int n) {
  const std::vector<int> ns = fan_ins(t, "mux");
  if (ns.empty()) throw std::invalid_argument("operator table: no mux rows");
  if (n <= 1) return MappedCost{};
  const int widest = ns.back();
  if (n > widest) {  // groups of the widest mux, then a mux over the groups
    const int groups = (n + widest - 1) / widest;
    MappedCost c = mux_cost(t, w, widest) * double(groups);
    c += mux_cost(t, w, groups);
    return c;
  }
  std::vector<std::pair<int, MappedCost>> by_n;
  for (int k : ns) by_n.emplace_back(k, interpolate(along_width(t, "mux", k), w));
  return interpolate(by_n, n);
}

}  // namespace

std::vector<OperatorRow> parse_operator_table(const std::string& csv_text, std::string* yosys_version) {
  std::vector<OperatorRow> rows;
  std::istringstream in(csv_text);
  std::string line;
  std::vector<std::string> header;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty()) continue;
    if (line[0] == '#') {
      const std::size_t at = line.find("Yosys ");
      if (yosys_version && yosys_version->empty() && at != std::string::npos) {
        std::istringstream v(line.substr(at + 6));
        v >> *yosys_version;
      }
      continue;
    }
    const std::vector<std::string> f = split(line);
    if (header.empty()) {
      header = f;
      if (header.size() != std::size(kColumns) || !std::equal(header.begin(), header.end(), std::begin(kColumns)))
        throw std::runtime_error("operator table, line " + std::to_string(line_no) + ": unexpected header '" + line +
                                 "'");
      continue;
    }
    if (f.size() != header.size())
      throw std::runtime_error("operator table, line " + std::to_string(line_no) + ": " + std::to_string(f.size()) +
                               " fields, expected " + std::to_string(header.size()));
    try {
      OperatorRow r;
      r.kind = f[0];
      r.width_bits = std::stoi(f[1]);
      r.fan_in = std::stoi(f[2]);
      r.b_bits = std::stoi(f[3]);
      r.cost.lut = std::stod(f[4]);
      r.cost.ff = std::stod(f[5]);
      r.cost.carry8 = std::stod(f[7]);
      r.cost.srl = std::stod(f[8]);
      r.cost.muxf = std::stod(f[9]);
      r.cost.dsp = std::stod(f[10]);
      rows.push_back(r);
    } catch (const std::logic_error&) {
      throw std::runtime_error("operator table, line " + std::to_string(line_no) + ": not a number in '" + line + "'");
    }
  }
  if (rows.empty()) throw std::runtime_error("operator table: no rows");
  return rows;
}

namespace {
// The compiled-in table and its Yosys version, parsed once.
struct CompiledTable {
  std::string yosys;
  std::vector<OperatorRow> rows = parse_operator_table(data::operators_csv, &yosys);
};
const CompiledTable& compiled_table() {
  static const CompiledTable t;
  return t;
}
}  // namespace

const std::vector<OperatorRow>& operator_table() {
  return compiled_table().rows;
}

const std::string& operator_table_yosys() {
  return compiled_table().yosys;
}

MappedCost mapped_cost(const std::vector<OperatorRow>& t, const std::string& kind, int width_bits, int fan_in,
                       int b_bits) {
  const int w = std::max(1, width_bits);
  if (kind == "mux") return mux_cost(t, w, fan_in);
  if (kind == "decoder") return interpolate(along_fan_in(t, kind), std::max(1, fan_in));
  if (kind == "srl") return interpolate(along_fan_in(t, kind), std::max(1, fan_in)) * double(w);  // per bit
  if (kind == "mul_fabric") {  // the shape of the nearest area (a x b), scaled to the area
    const int a = std::max(w, b_bits), b = std::max(1, std::min(w, b_bits > 0 ? b_bits : w));
    const OperatorRow* best = nullptr;
    for (const OperatorRow& r : t)
      if (r.kind == kind &&
          (!best || std::abs(r.width_bits * r.b_bits - a * b) < std::abs(best->width_bits * best->b_bits - a * b)))
        best = &r;
    if (!best) throw std::invalid_argument("operator table: no mul_fabric rows");
    return best->cost * (double(a) * b / (double(best->width_bits) * best->b_bits));
  }
  if (kind == "mul") {  // the smallest characterised shape that holds both operands, else scaled by area
    const int a = std::max(w, b_bits), b = std::max(1, std::min(w, b_bits > 0 ? b_bits : w));
    const OperatorRow* best = nullptr;
    const OperatorRow* largest = nullptr;
    for (const OperatorRow& r : t) {
      if (r.kind != kind) continue;
      if (!largest || r.width_bits * r.b_bits > largest->width_bits * largest->b_bits) largest = &r;
      if (r.width_bits >= a && r.b_bits >= b && (!best || r.width_bits * r.b_bits < best->width_bits * best->b_bits))
        best = &r;
    }
    if (!largest) throw std::invalid_argument("operator table: no mul rows");
    if (best) return best->cost;
    return largest->cost * (double(a) * b / (double(largest->width_bits) * largest->b_bits));
  }
  const auto p = along_width(t, kind, 1);
  if (p.empty()) throw std::invalid_argument("operator table: no operator '" + kind + "'");
  return interpolate(p, w);
}

MappedCost mapped_cost(const std::string& kind, int width_bits, int fan_in, int b_bits) {
  return mapped_cost(operator_table(), kind, width_bits, fan_in, b_bits);
}

}  // namespace parallax::res
