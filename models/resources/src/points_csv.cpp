// Published resource rows in CSV (points_csv.hpp).
#include "parallax/resources/points_csv.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <map>
#include <regex>

#include "parallax/config/config.hpp"

namespace parallax::res {

namespace {

// RFC 4180 records: fields separated by commas, quoted fields may hold commas, doubled quotes
// and newlines. Returns the records with the line each starts on.
std::vector<std::pair<int, std::vector<std::string>>> csv_records(const std::string& text, const std::string& file) {
  std::vector<std::pair<int, std::vector<std::string>>> out;
  std::vector<std::string> rec;
  std::string field;
  bool quoted = false, any = false;
  int line = 1, start = 1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char ch = text[i];
    if (quoted) {
      if (ch == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (ch == '"') {
        quoted = false;
      } else {
        if (ch == '\n') ++line;
        field += ch;
      }
      continue;
    }
    if (ch == '"') {
      quoted = true;
      any = true;
    } else if (ch == ',') {
      rec.push_back(field);
      field.clear();
      any = true;
    } else if (ch == '\n' || ch == '\r') {
      if (ch == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      if (any || !field.empty()) {
        rec.push_back(field);
        out.emplace_back(start, rec);
      }
      rec.clear();
      field.clear();
      any = false;
      start = ++line;
    } else {
      field += ch;
      any = true;
    }
  }
  if (quoted) throw config::ConfigError(file + ":" + std::to_string(start) + ": a quoted field is not closed");
  if (any || !field.empty()) {
    rec.push_back(field);
    out.emplace_back(start, rec);
  }
  return out;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

// A whole number, or false.
bool whole_number(const std::string& s, double& v) {
  static const std::regex re(R"(^\s*([0-9]+(\.[0-9]+)?)\s*$)");
  std::smatch m;
  if (!std::regex_match(s, m, re)) return false;
  v = std::strtod(m[1].str().c_str(), nullptr);
  return true;
}

void numeric_var(RowVariables& rv, const std::string& name, const std::string& cell) {
  double v = 0;
  if (whole_number(cell, v))
    rv.values[name] = v;
  else
    rv.unstated.insert(name);
}

void window_vars(RowVariables& rv, const std::string& window) {
  static const std::regex size(R"(([0-9]+)\s*[xX]\s*([0-9]+))");
  static const std::regex to(R"(\bTO\s+([0-9]+)\s*[xX]\s*([0-9]+))", std::regex::icase);
  static const std::regex named(R"(([A-Za-z_]+)\s*=\s*([0-9]+))");
  std::smatch m;
  if (std::regex_search(window, m, size)) {
    const double w = std::stod(m[1].str()), h = std::stod(m[2].str());
    rv.values["kw"] = w;
    rv.values["kh"] = h;
    rv.values["k"] = std::max(w, h);
  } else {
    for (const char* n : {"kw", "kh", "k"}) rv.unstated.insert(n);
  }
  if (std::regex_search(window, m, to)) {
    rv.values["out_width"] = std::stod(m[1].str());
    rv.values["out_height"] = std::stod(m[2].str());
  } else {
    rv.unstated.insert("out_width");
    rv.unstated.insert("out_height");
  }
  for (auto it = std::sregex_iterator(window.begin(), window.end(), named); it != std::sregex_iterator(); ++it) {
    std::string name = (*it)[1].str();
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    rv.values[name] = std::stod((*it)[2].str());
  }
}

int64_t published_cell(const std::string& cell, const std::string& where) {
  const std::string t = trim(cell);
  if (t.empty()) return -1;
  double v = 0;
  if (!whole_number(t, v)) throw config::ConfigError(where + ": '" + t + "' is not a number");
  return int64_t(v);
}

}  // namespace

std::vector<CsvPoint> parse_points_csv(const std::string& text, const std::string& file) {
  const auto recs = csv_records(text, file);
  if (recs.empty()) throw config::ConfigError(file + ": empty, expected a header row and published rows");
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < recs[0].second.size(); ++i) col[trim(recs[0].second[i])] = i;
  for (const char* need : {"kernel", "design"})
    if (!col.count(need)) throw config::ConfigError(file + ": missing column '" + std::string(need) + "'");
  std::vector<CsvPoint> out;
  for (std::size_t r = 1; r < recs.size(); ++r) {
    const int line = recs[r].first;
    const std::vector<std::string>& cells = recs[r].second;
    auto cell = [&](const char* name) {
      const auto it = col.find(name);
      return it != col.end() && it->second < cells.size() ? trim(cells[it->second]) : std::string();
    };
    const std::string where = file + ":" + std::to_string(line);
    CsvPoint p;
    p.line = line;
    p.kernel = cell("kernel");
    p.design = cell("design");
    if (p.kernel.empty()) throw config::ConfigError(where + ": empty 'kernel'");
    RowVariables& rv = p.vars;
    rv.text = p.kernel + " | " + p.design + " | " + cell("notes");
    numeric_var(rv, "width", cell("width"));
    numeric_var(rv, "height", cell("height"));
    numeric_var(rv, "clock_mhz", cell("clock_mhz"));
    numeric_var(rv, "disparities", cell("disparities"));
    numeric_var(rv, "pu", cell("parallel_units"));
    numeric_var(rv, "paths", cell("paths"));
    const std::string npc = cell("npc");
    rv.values["npc"] =
        std::isdigit(static_cast<unsigned char>(npc.empty() ? 'x' : npc[0])) ? std::atof(npc.c_str()) : 1;
    window_vars(rv, cell("window"));
    static const std::regex three(R"(3ch|3-channel|BGR|channels=3)", std::regex::icase);
    static const std::regex uram(R"(URAM|UltraRAM)", std::regex::icase);
    rv.values["channels"] = std::regex_search(rv.text, three) ? 3 : 1;
    // The doc's table (source_detail) says UltraRAM where kernel, design and notes may not.
    rv.values["uram"] = std::regex_search(rv.text, uram) || std::regex_search(cell("source_detail"), uram) ? 1 : 0;
    const std::string device = cell("device");
    rv.values["versal"] = device.rfind("xcv", 0) == 0 ? 1 : 0;  // Versal parts: xcvc, xcve, xcvm, xcvp
    p.published.bram18k = published_cell(cell("bram18k"), where + ": bram18k");
    p.published.uram = published_cell(cell("uram"), where + ": uram");
    p.published.dsp = published_cell(cell("dsp"), where + ": dsp");
    p.published.ff = published_cell(cell("ff"), where + ": ff");
    p.published.lut = published_cell(cell("lut"), where + ": lut");
    out.push_back(std::move(p));
  }
  return out;
}

std::vector<CsvPoint> load_points_csv(const std::string& path) {
  return parse_points_csv(config::read_text_file(path, "published points CSV"), path);
}

}  // namespace parallax::res
