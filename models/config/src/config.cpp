// PipelineConfig's library: every function here iterates the configuration table
// (field_table.hpp); none names a field but load_config (relative map paths) and the conversions
// to the kernels' parameters.
#include "parallax/config/config.hpp"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "field_table.hpp"

namespace parallax::config {
namespace {

// The row of `key`: a plain field by its name, else the first pattern row whose prefix starts it.
const detail::FieldRow* find_row(const std::string& key) {
  const auto& rows = detail::field_table();
  for (const auto& r : rows)
    if (r.prefix.empty() && r.name == key) return &r;
  for (const auto& r : rows)
    if (!r.prefix.empty() && key.rfind(r.prefix, 0) == 0) return &r;
  return nullptr;
}

}  // namespace

const std::vector<std::string>& field_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& r : detail::field_table()) n.push_back(r.name);
    return n;
  }();
  return names;
}

std::string field_documentation() {
  std::string out;
  for (const auto& r : detail::field_table())
    out += r.name + (r.is_register ? " (register)" : "") + ": " + r.doc + (r.values.empty() ? "" : "; " + r.values) +
           "; read by " + detail::readers_text(r.readers) + "\n";
  out += "rules between fields:\n";
  for (const auto* rules : {&detail::cross_rules(), &detail::whole_design_rules()})
    for (const auto& rule : *rules)
      out += std::string("  ") + rule.name + " (field " + rule.field + "): " + rule.doc + "\n";
  return out;
}

void set_field(PipelineConfig& c, const std::string& key, const std::string& raw) {
  const detail::FieldRow* row = find_row(key);
  // Fields of earlier versions whose meaning is gone: say why, not only that they are unknown.
  if (key == "row_packing" || key == "row_banks")
    throw ConfigError("field '" + key +
                      "' was removed: the aggregation's row memories now hold one word of PU lanes per chunk (one "
                      "read and one write per firing, issue 41); delete the line");
  if (!row) {
    std::string known;
    for (const auto& n : field_names()) known += (known.empty() ? "" : ", ") + n;
    throw ConfigError("unknown field '" + key + "' (known fields: " + known + ")");
  }
  row->parse(c, key, detail::trim(raw));
}

// Row by row: the row's own check, then the rules that run after it; the whole-design rules last,
// only when nothing else is violated (they assume a valid design).
std::vector<FieldError> validate(const PipelineConfig& c) {
  std::vector<FieldError> e;
  auto apply = [&](const detail::CrossRule& rule) {
    std::string msg = rule.violation(c);
    if (!msg.empty()) e.push_back({rule.field, std::move(msg)});
  };
  for (const auto& row : detail::field_table()) {
    if (row.check) row.check(c, e);
    for (const auto& rule : detail::cross_rules())
      if (row.name == rule.after) apply(rule);
  }
  if (e.empty())
    for (const auto& rule : detail::whole_design_rules()) apply(rule);
  return e;
}

std::string to_yaml(const PipelineConfig& c) {
  std::ostringstream o;
  o.precision(12);
  for (const auto& row : detail::field_table()) row.write(c, o);
  return o.str();
}

int census_kind(const std::string& census) {
  return census == "full"        ? kern::kCensusFull
         : census == "sparse"    ? kern::kCensusSparse
         : census == "symmetric" ? kern::kCensusSymmetric
                                 : -1;
}

kern::StereoRegisters PipelineConfig::registers() const {
  return {p1, p2, lr_tolerance, uniqueness_pct};
}

kern::StereoParams PipelineConfig::stereo_params(int width_px, int height_px) const {
  kern::StereoParams p{};
  p.width_px = width_px;
  p.height_px = height_px;
  for (const auto& row : detail::field_table())
    if (row.to_params) row.to_params(*this, p);
  return p;
}

kern::RectifyParams PipelineConfig::rectify_params(int width_px, int height_px) const {
  kern::RectifyParams r{};
  r.width_px = width_px;
  r.height_px = height_px;
  r.mode = rectify == "bilinear"  ? kern::kRectifyBilinear
           : rectify == "nearest" ? kern::kRectifyNearest
                                  : kern::kRectifyNone;
  r.frac_bits = rectify == "bilinear" ? rectify_frac_bits : 0;
  r.buffer_rows = rectify_rows;
  return r;
}

PipelineConfig parse_config(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& ex) {
    throw ConfigError(source + ": not valid YAML: " + ex.what());
  }
  if (!root.IsMap()) throw ConfigError(source + ": expected a mapping of field: value");
  PipelineConfig c;
  std::vector<std::string> problems;
  for (const auto& kv : root) {
    if (!kv.first.IsScalar()) {
      problems.push_back("line " + std::to_string(kv.first.Mark().line + 1) +
                         ": a key must be a field name, not a list or mapping");
      continue;
    }
    const std::string key = kv.first.Scalar();
    std::string value;
    if (kv.second.IsSequence()) {
      bool flat = true;
      for (const auto& item : kv.second) {
        if (!item.IsScalar()) {
          flat = false;
          break;
        }
        value += (value.empty() ? "" : ",") + item.Scalar();
      }
      if (!flat) {
        problems.push_back("field '" + key + "': a list of values, not of lists or mappings");
        continue;
      }
      value = "[" + value + "]";  // a list stays a list: paths [0] is an angle, not a count
    } else if (kv.second.IsScalar()) {
      value = kv.second.Scalar();
    } else {
      problems.push_back("field '" + key + "': expected a value or a list");
      continue;
    }
    try {
      set_field(c, key, value);
    } catch (const ConfigError& ex) {
      problems.push_back(ex.what());
    }
  }
  for (const auto& fe : validate(c)) problems.push_back("field '" + fe.field + "': " + fe.message);
  if (!problems.empty()) {
    std::string msg = source + ": invalid configuration:";
    for (const auto& p : problems) msg += "\n  - " + p;
    throw ConfigError(msg);
  }
  return c;
}

std::string read_text_file(const std::string& path, const std::string& what, std::size_t max_bytes) {
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(st)) throw ConfigError(path + ": " + what + " not found");
  if (std::filesystem::is_directory(st)) throw ConfigError(path + ": is a folder, not a " + what);
  if (!std::filesystem::is_regular_file(st))
    throw ConfigError(path + ": not a regular file (a " + what + " is a text file)");
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw ConfigError(path + ": cannot read the " + what + ": " + ec.message());
  if (size > max_bytes)
    throw ConfigError(path + ": " + std::to_string(size) + " bytes; a " + what + " may have at most " +
                      std::to_string(max_bytes) + " bytes");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path + ": cannot open the " + what);
  std::string text(std::size_t(size), '\0');
  in.read(&text[0], std::streamsize(size));
  if (std::size_t(in.gcount()) != size) throw ConfigError(path + ": cannot read the " + what + " (short read)");
  return text;
}

PipelineConfig load_config(const std::string& path) {
  PipelineConfig c = parse_config(read_text_file(path, "configuration file"), path);
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  for (std::string* maps : {&c.rectify_maps_left, &c.rectify_maps_right})
    if (!maps->empty() && std::filesystem::path(*maps).is_relative()) *maps = (dir / *maps).string();
  return c;
}

}  // namespace parallax::config
