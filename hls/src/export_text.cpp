// The export's text helpers (export_parts.hpp): templates, fragments and names.
#include <cctype>
#include <cstdio>
#include <map>
#include <stdexcept>

#include "embedded.hpp"
#include "export_parts.hpp"

namespace parallax::hlsx::detail {

std::string fill(const std::string& name, const std::string& text, const Values& values) {
  std::string out;
  out.reserve(text.size() + 1024);
  std::size_t i = 0;
  while (i < text.size()) {
    if (text[i] == '@' && i + 1 < text.size() && std::isupper(static_cast<unsigned char>(text[i + 1]))) {
      std::size_t j = i + 1;
      while (j < text.size() && (std::isupper(static_cast<unsigned char>(text[j])) ||
                                 std::isdigit(static_cast<unsigned char>(text[j])) || text[j] == '_'))
        ++j;
      if (j < text.size() && text[j] == '@') {
        const std::string key = text.substr(i + 1, j - i - 1);
        const auto it = values.find(key);
        if (it == values.end())
          throw std::logic_error("hls export: template " + name + " uses @" + key + "@, which has no value");
        out += it->second;
        i = j + 1;
        continue;
      }
    }
    out += text[i++];
  }
  return out;
}

// A handful of small files: a linear search.
std::string template_text(const std::string& name) {
  for (const auto& t : detail::templates())
    if (name == t.name) return *t.text;
  throw std::logic_error("hls export: no template " + name);
}

std::string identifier(const std::string& s) {
  std::string out;
  for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  if (out.empty() || std::isdigit(static_cast<unsigned char>(out[0]))) out = "d_" + out;
  return out;
}

std::string depth_constant(const std::string& fifo) {
  std::string out = "kDepth";
  bool upper = true;
  for (char c : fifo) {
    if (c == '_') {
      upper = true;
      continue;
    }
    out += upper ? char(std::toupper(static_cast<unsigned char>(c))) : c;
    upper = false;
  }
  return out;
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string ram_impl(res::Storage s) {
  return s == res::Storage::bram ? "bram" : "lutram";
}
std::string fifo_impl(res::Storage s) {
  switch (s) {
    case res::Storage::bram:
      return "bram";
    case res::Storage::lutram:
      return "lutram";
    default:
      return "srl";
  }
}

const res::MemoryItem* find_memory(const res::Inventory& inv, const std::string& stage, const std::string& name) {
  for (const auto& m : inv.memories)
    if (m.stage == stage && m.name == name) return &m;
  return nullptr;
}

// fragments.in: a fragment starts at a line "%% NAME" ("%% NAME -n": without its final newline)
// and runs to the next "%%" line.
namespace {

// The fragments by name, parsed once (the embedded text never changes).
const std::map<std::string, std::string>& fragments() {
  static const std::map<std::string, std::string> parsed = [] {
    std::map<std::string, std::string> out;
    const std::string text = template_text("fragments");
    std::string* body = nullptr;
    bool drop_newline = false;
    auto finish = [&] {
      if (body && drop_newline && !body->empty()) body->pop_back();
    };
    std::size_t i = 0;
    while (i < text.size()) {
      std::size_t end = text.find('\n', i);
      if (end == std::string::npos) end = text.size();
      const std::string line = text.substr(i, end - i);
      i = end + 1;
      if (line.rfind("%% ", 0) == 0) {
        finish();
        const std::string head = line.substr(3);
        const std::size_t space = head.find(' ');
        body = &out[head.substr(0, space)];
        drop_newline = space != std::string::npos && head.substr(space + 1) == "-n";
        continue;
      }
      if (body) *body += line + "\n";
    }
    finish();
    return out;
  }();
  return parsed;
}

}  // namespace

bool has_fragment(const std::string& name) {
  return fragments().count(name) != 0;
}

std::string fragment(const std::string& name, const Values& values) {
  const auto it = fragments().find(name);
  if (it == fragments().end()) throw std::logic_error("hls export: no fragment " + name + " in fragments.in");
  return fill("fragments.in: " + name, it->second, values);
}

bool is_two_pass(const config::PipelineConfig& c) {
  return kern::two_pass_paths(c.path_mask);
}

}  // namespace parallax::hlsx::detail
