// The VCD writer of the cycle model's trace (vcd_trace.hpp).
#include "vcd_trace.hpp"

#include <algorithm>
#include <fstream>

#include "internal_error.hpp"

namespace parallax::sim::detail {

namespace {
std::string vcd_id(int index) {
  std::string id;
  do {
    id += char(33 + index % 94);
    index /= 94;
  } while (index > 0);
  return id;
}
std::string vcd_value(int64_t v, int width, const std::string& id) {
  if (width == 1) return std::string(v ? "1" : "0") + id;
  std::string bits;
  for (int b = width - 1; b >= 0; --b) bits += ((v >> b) & 1) ? '1' : '0';
  const auto first = bits.find('1');
  return "b" + (first == std::string::npos ? std::string("0") : bits.substr(first)) + " " + id;
}
}  // namespace

void Trace::write(const std::string& path, const std::string& scope) const {
  std::ofstream out(path);
  if (!out) internal_error("cannot write VCD file " + path);
  std::vector<Event> ev = events_;
  std::stable_sort(ev.begin(), ev.end(), [](const Event& a, const Event& b) { return a.cycle < b.cycle; });
  std::vector<int64_t> level(names_.size(), 0);
  for (std::size_t i = 0; i < pre_level_.size() && i < level.size(); ++i) level[i] = pre_level_[i];
  out << "$comment parallax cycle model: one time unit = one processing-clock cycle $end\n";
  out << "$timescale 1ns $end\n$scope module " << scope << " $end\n";
  for (std::size_t i = 0; i < names_.size(); ++i)
    out << "$var wire " << widths_[i] << " " << vcd_id(int(i)) << " " << names_[i] << " $end\n";
  out << "$upscope $end\n$enddefinitions $end\n";
  std::size_t k = 0;
  for (; k < ev.size() && ev[k].cycle <= from_; ++k)
    level[ev[k].sig] = ev[k].delta ? level[ev[k].sig] + ev[k].v : ev[k].v;
  out << "#" << from_ << "\n$dumpvars\n";
  for (std::size_t i = 0; i < names_.size(); ++i) out << vcd_value(level[i], widths_[i], vcd_id(int(i))) << "\n";
  out << "$end\n";
  while (k < ev.size() && ev[k].cycle < to_) {
    const int64_t c = ev[k].cycle;
    std::vector<int64_t> before = level;
    for (; k < ev.size() && ev[k].cycle == c; ++k)
      level[ev[k].sig] = ev[k].delta ? level[ev[k].sig] + ev[k].v : ev[k].v;
    bool header = false;
    for (std::size_t i = 0; i < names_.size(); ++i) {
      if (level[i] == before[i]) continue;
      if (!header) {
        out << "#" << c << "\n";
        header = true;
      }
      out << vcd_value(level[i], widths_[i], vcd_id(int(i))) << "\n";
    }
  }
  out << "#" << to_ << "\n";
}

}  // namespace parallax::sim::detail
