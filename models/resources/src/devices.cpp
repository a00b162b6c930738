#include "parallax/resources/devices.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <set>
#include <stdexcept>

namespace parallax::res {
namespace data {
// Generated at configure time from models/data/devices.yaml (cmake/embed.cmake).
extern const char* const devices_yaml;
}  // namespace data

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  return s;
}

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw std::logic_error("devices.yaml: " + where + ": " + what);
}

std::string get_string(const YAML::Node& dev, const std::string& where, const char* field) {
  const YAML::Node v = dev[field];
  if (!v) fail(where, std::string("missing field '") + field + "'");
  if (!v.IsScalar() || v.Scalar().empty()) fail(where, std::string("field '") + field + "' must be a non-empty string");
  return v.Scalar();
}

int64_t get_count(const YAML::Node& dev, const std::string& where, const char* field) {
  const YAML::Node v = dev[field];
  if (!v) fail(where, std::string("missing field '") + field + "'");
  int64_t x = -1;
  try {
    if (v.IsScalar()) x = v.as<int64_t>();
  } catch (const YAML::Exception&) {
    x = -1;
  }
  if (x < 0)
    fail(where, std::string("field '") + field + "' must be an integer >= 0" +
                    (v.IsScalar() ? ", got '" + v.Scalar() + "'" : std::string()));
  return x;
}

}  // namespace

std::vector<Device> parse_devices(const std::string& yaml_text) {
  static const std::set<std::string> known = {"name", "family", "source", "bram18k", "uram", "dsp", "ff", "lut"};
  static const std::set<std::string> families = {"zynq-ultrascale+", "zynq-7000"};
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw std::logic_error(std::string("devices.yaml: not valid YAML: ") + e.what());
  }
  if (!root.IsSequence()) throw std::logic_error("devices.yaml: the top level must be a list of devices");

  std::vector<Device> out;
  std::set<std::string> seen;
  for (std::size_t i = 0; i < root.size(); ++i) {
    const YAML::Node dev = root[i];
    std::string where = "device #" + std::to_string(i + 1);
    if (!dev.IsMap()) fail(where, "must be a map of fields");
    for (const auto& kv : dev) {
      const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : std::string("?");
      if (!known.count(key)) fail(where, "unknown field '" + key + "'");
    }
    Device d;
    d.name = get_string(dev, where, "name");
    where += " (" + d.name + ")";
    d.family = get_string(dev, where, "family");
    if (!families.count(d.family))
      fail(where, "field 'family' must be zynq-ultrascale+ or zynq-7000, got '" + d.family + "'");
    d.source = get_string(dev, where, "source");
    d.bram18k = get_count(dev, where, "bram18k");
    d.uram = get_count(dev, where, "uram");
    d.dsp = get_count(dev, where, "dsp");
    d.ff = get_count(dev, where, "ff");
    d.lut = get_count(dev, where, "lut");
    if (!seen.insert(lower(d.name)).second) fail(where, "field 'name' repeats an earlier device");
    out.push_back(std::move(d));
  }
  if (out.empty()) throw std::logic_error("devices.yaml: no devices");
  return out;
}

const std::vector<Device>& devices() {
  static const std::vector<Device> all = parse_devices(data::devices_yaml);
  return all;
}

const Device* find_device(const std::string& name) {
  const std::string key = lower(name);
  for (const Device& d : devices())
    if (lower(d.name) == key) return &d;
  return nullptr;
}

std::string device_names() {
  std::string s;
  for (const Device& d : devices()) s += (s.empty() ? "" : ", ") + d.name;
  return s;
}

}  // namespace parallax::res
