// Function descriptions (functions.hpp): loading, matching and instantiation with muparser.
#include "parallax/resources/functions.hpp"

#include <muParser.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>
#include <utility>

#include "parallax/config/config.hpp"

namespace parallax::res {

namespace data {
// Generated at configure time from models/data/functions/*.yaml (cmake/embed.cmake).
extern const char* const* const function_files;
extern const char* const* const function_texts;
extern const int function_count;
}  // namespace data

namespace {

[[noreturn]] void bad(const std::string& where, const std::string& what) {
  throw config::ConfigError(where + ": " + what);
}

std::string need_string(const YAML::Node& n, const char* key, const std::string& where) {
  if (!n[key] || !n[key].IsScalar() || n[key].Scalar().empty()) bad(where, std::string("missing field '") + key + "'");
  return n[key].Scalar();
}

mu::value_type fn_ceil(mu::value_type x) {
  return std::ceil(x - 1e-9);
}
mu::value_type fn_floor(mu::value_type x) {
  return std::floor(x + 1e-9);
}
mu::value_type fn_ceil_div(mu::value_type a, mu::value_type b) {
  return b != 0 ? std::ceil(a / b - 1e-9) : 0.0;
}
// Bits to hold the values 0..n (bits(255) = 8, bits(256) = 9, bits(0) = 1).
mu::value_type fn_bits(mu::value_type n) {
  int b = 1;
  while (b < 62 && std::ldexp(1.0, b) <= n) ++b;
  return b;
}
// ceil(log2(n)) for n >= 1 (log2c(1) = 0, log2c(5) = 3).
mu::value_type fn_log2c(mu::value_type n) {
  int b = 0;
  while (b < 62 && std::ldexp(1.0, b) < n) ++b;
  return b;
}

// One description's evaluation context: the row's variables plus the description's flags and
// lets, and the place being evaluated (for messages).
class Evaluator {
 public:
  Evaluator(const FunctionDescription& fn, const RowVariables& row) : fn_(fn), row_(row), vars_(row.values) {
    parser_.DefineFun("ceil", fn_ceil, false);
    parser_.DefineFun("floor", fn_floor, false);
    parser_.DefineFun("ceil_div", fn_ceil_div, false);
    parser_.DefineFun("bits", fn_bits, false);
    parser_.DefineFun("log2c", fn_log2c, false);
    for (auto& kv : vars_) parser_.DefineVar(kv.first, &kv.second);
  }
  void define(const std::string& name, double value) {
    auto it = vars_.find(name);
    if (it != vars_.end()) {
      it->second = value;
      return;
    }
    it = vars_.emplace(name, value).first;
    parser_.DefineVar(name, &it->second);
  }
  double eval(const YAML::Node& expr, const std::string& where) {
    if (!expr.IsScalar()) bad(fn_.file + ": " + where, "must be a number or an expression");
    try {
      parser_.SetExpr(expr.Scalar());
      const double v = parser_.Eval();
      if (!std::isfinite(v)) bad(fn_.file + ": " + where, "'" + expr.Scalar() + "' is not finite");
      return v;
    } catch (const mu::Parser::exception_type& e) {
      const std::string& token = e.GetToken();
      if (e.GetCode() == mu::ecUNASSIGNABLE_TOKEN && row_.unstated.count(token))
        throw NotDescribable(token + " not stated in the row (needed by " + fn_.function + ")");
      bad(fn_.file + ": " + where, "cannot evaluate '" + expr.Scalar() + "': " + e.GetMsg());
    }
  }
  // A field that must be a non-negative integer (sizes, counts); absent: `fallback`.
  int64_t integer(const YAML::Node& item, const char* key, const std::string& where, int64_t fallback = -1) {
    const YAML::Node n = item[key];
    if (!n) {
      if (fallback >= 0) return fallback;
      bad(fn_.file + ": " + where, std::string("missing field '") + key + "'");
    }
    const double v = eval(n, where + "." + key);
    const double r = std::round(v);
    if (std::fabs(v - r) > 1e-6 || r < 0)
      bad(fn_.file + ": " + where + "." + key,
          "'" + n.Scalar() + "' is " + std::to_string(v) + ", not a non-negative integer (use ceil_div)");
    return int64_t(r);
  }

 private:
  const FunctionDescription& fn_;
  const RowVariables& row_;
  std::map<std::string, double> vars_;  // node-stable: the parser holds pointers to the values
  mu::Parser parser_;
};

// The ops of an adder tree of n inputs of w bits: level l has ceil(n / 2^l) / 2 adders of w + l bits.
void add_tree(Collector& c, const std::string& name, kern::OpKind kind, int64_t inputs, int width_bits, int64_t count,
              bool widen) {
  int64_t n = inputs;
  int level = 1;
  while (n > 1) {
    const int64_t adders = n / 2;
    OpItem o;
    o.name = name;
    o.kind = kind;
    o.width_bits = width_bits + (widen ? level : 0);
    o.count = adders * count;
    c.op_item(o);
    if (!widen) {  // a min or max tree: a compare and a select of the value per node
      OpItem m = o;
      m.kind = kern::kOpMux;
      c.op_item(m);
    }
    n -= adders;
    ++level;
  }
}

void instantiate_item(Evaluator& ev, Collector& c, const YAML::Node& item, const std::string& file,
                      const std::string& where) {
  const std::string kind = need_string(item, "kind", file + ": " + where);
  const std::string name = item["name"] ? item["name"].Scalar() : kind;
  const std::string at = where + " '" + name + "'";
  if (item["when"] && ev.eval(item["when"], at + ".when") == 0) return;
  auto I = [&](const char* key, int64_t fallback = -1) { return ev.integer(item, key, at, fallback); };
  if (kind == "line_buffer" || kind == "memory" || kind == "fifo") {
    MemoryItem m;
    m.name = name;
    m.kind = kind == "fifo" ? MemoryKind::fifo : MemoryKind::array;
    m.depth = I("depth");
    m.width_bits = int(I("width_bits"));
    m.copies = int(kind == "line_buffer" ? I("rows") : kind == "fifo" ? I("count", 1) : I("copies", 1));
    m.true_dual_port = I("true_dual_port", 0) != 0;
    m.uram = I("uram", 0) != 0;
    m.lutram = I("lutram", 0) != 0;
    c.memory_item(m);
  } else if (kind == "window") {
    c.registers(name.c_str(), int(I("width_bits")), int(I("rows") * I("cols") * I("count", 1)));
  } else if (kind == "registers") {
    c.registers(name.c_str(), int(I("width_bits")), int(I("count", 1)));
  } else if (kind == "add" || kind == "compare" || kind == "mux" || kind == "popcount" || kind == "xor") {
    const kern::OpKind k = kind == "add"        ? kern::kOpAdd
                           : kind == "compare"  ? kern::kOpCompare
                           : kind == "mux"      ? kern::kOpMux
                           : kind == "popcount" ? kern::kOpPopcount
                                                : kern::kOpXor;
    OpItem o;
    o.name = name;
    o.kind = k;
    o.width_bits = int(I("width_bits"));
    o.count = I("count", 1);
    o.bound_dsp = k == kern::kOpAdd && I("dsp", 0) != 0;
    if (k == kern::kOpMux) {  // fan_in: inputs per mux (count N:1 muxes); 2 by default
      o.fan_in = int(I("fan_in", 2));
      if (o.fan_in <= 1) return;
    }
    c.op_item(o);
  } else if (kind == "adder_tree" || kind == "min_tree" || kind == "max_tree") {
    const bool adder = kind == "adder_tree";
    const int64_t count = I("count", 1);
    add_tree(c, name, adder ? kern::kOpAdd : kern::kOpCompare, I("inputs"), int(I("width_bits")), count, adder);
    if (!adder && I("index_bits", 0) > 0) {  // the winner's index travels with it
      OpItem o;
      o.name = name + "_index";
      o.kind = kern::kOpMux;
      o.width_bits = int(I("index_bits", 0));
      o.count = std::max<int64_t>(0, I("inputs") - 1) * count;
      c.op_item(o);
    }
  } else if (kind == "mul" || kind == "mul_const") {
    OpItem o;
    o.name = name;
    o.kind = kern::kOpMul;
    const int a = int(I("a_bits")), b = int(I("b_bits"));
    o.width_bits = std::max(a, b);
    o.b_bits = std::min(a, b);
    o.constant_operand = kind == "mul_const";
    o.unsigned_operands = I("unsigned", 0) != 0;
    o.count = I("count", 1);
    if (o.b_bits > 0) c.op_item(o);
  } else if (kind == "fmul" || kind == "fadd" || kind == "fdiv" || kind == "fexp" || kind == "fconv") {
    OpItem o;
    o.name = name;
    o.kind = kind == "fmul" ? kern::kOpMul : kern::kOpAdd;
    o.width_bits = 32;
    o.float_kind = kind == "fmul"   ? kFloatMul
                   : kind == "fadd" ? kFloatAdd
                   : kind == "fdiv" ? kFloatDiv
                   : kind == "fexp" ? kFloatExp
                                    : kFloatConv;
    o.count = I("count", 1);
    c.op_item(o);
  } else if (kind == "divider") {  // restoring division: a subtract and a select per quotient bit
    const int64_t n = I("count", 1), q = I("width_bits"), d = I("divisor_bits");
    // sequential 1: a division outside any pipelined loop, which HLS binds to an iterative core
    // (`*_seq` dividers, one quotient bit per cycle): one subtract and select, the dividend and
    // quotient shift register, the partial remainder, the divisor and the step counter.
    const bool seq = I("sequential", 0) != 0;
    OpItem sub;
    sub.name = name + "_subtract";
    sub.kind = kern::kOpAdd;
    sub.width_bits = int(d + 1);
    sub.count = (seq ? 1 : q) * n;
    c.op_item(sub);
    OpItem sel = sub;
    sel.name = name + "_select";
    sel.kind = kern::kOpMux;
    sel.width_bits = int(d);
    c.op_item(sel);
    if (seq) {
      c.registers((name + "_state").c_str(), int(q + 2 * d + 1), int(n));
      OpItem step = sub;
      step.name = name + "_step";
      step.width_bits = kern::bits_for(uint64_t(q));
      c.op_item(step);
    }
  } else if (kind == "axis" || kind == "m_axi" || kind == "s_axilite") {
    c.interface(name.c_str(), kind, int(I("width_bits")), I("count", 1));
  } else {
    bad(file + ": " + at, "unknown item kind '" + kind + "'");
  }
}

}  // namespace

FunctionDescription parse_function(const std::string& text, const std::string& file) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    bad(file, std::string("not valid YAML: ") + e.what());
  }
  if (!root.IsMap()) bad(file, "a function description must be a map");
  FunctionDescription fn;
  fn.file = file;
  fn.function = need_string(root, "function", file);
  fn.family = root["family"] ? root["family"].Scalar() : fn.function;
  fn.group = need_string(root, "group", file);
  fn.matches = need_string(root, "matches", file);
  fn.source = need_string(root, "source", file);
  try {
    (void)std::regex(fn.matches);
  } catch (const std::regex_error& e) {
    bad(file + ": matches", "'" + fn.matches + "' is not a regular expression: " + e.what());
  }
  fn.flags = root["flags"];
  fn.let = root["let"];
  fn.stages = root["stages"];
  if (fn.flags && !fn.flags.IsMap()) bad(file + ": flags", "must be a map of NAME: REGEX");
  if (fn.let && !fn.let.IsMap()) bad(file + ": let", "must be a map of NAME: EXPRESSION");
  if (!fn.stages || !fn.stages.IsSequence() || fn.stages.size() == 0) bad(file, "missing list 'stages'");
  for (const auto& st : fn.stages) {
    const std::string sname = need_string(st, "stage", file + ": stages");
    if (!st["items"] || !st["items"].IsSequence()) bad(file + ": stage '" + sname + "'", "missing list 'items'");
  }
  return fn;
}

std::vector<FunctionDescription> load_functions(const std::string& directory) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(directory, ec))
    throw config::ConfigError(directory + ": not a directory of function descriptions");
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(directory, ec))
    if (e.path().extension() == ".yaml") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw config::ConfigError(directory + ": no *.yaml function descriptions");
  std::vector<FunctionDescription> out;
  for (const auto& f : files) out.push_back(parse_function(config::read_text_file(f, "function description"), f));
  return out;
}

const std::vector<FunctionDescription>& default_functions() {
  static const std::vector<FunctionDescription> fns = [] {
    std::vector<FunctionDescription> v;
    for (int i = 0; i < data::function_count; ++i)
      v.push_back(parse_function(data::function_texts[i], data::function_files[i]));
    return v;
  }();
  return fns;
}

const FunctionDescription* find_function(const std::vector<FunctionDescription>& fns, const std::string& kernel) {
  for (const auto& fn : fns)
    if (std::regex_search(kernel, std::regex(fn.matches))) return &fn;
  return nullptr;
}

Inventory instantiate(const FunctionDescription& fn, const RowVariables& row) {
  Evaluator ev(fn, row);
  if (fn.flags)
    for (const auto& kv : fn.flags)
      ev.define(kv.first.Scalar(), std::regex_search(row.text, std::regex(kv.second.Scalar(), std::regex::icase)));
  if (fn.let)
    for (const auto& kv : fn.let) ev.define(kv.first.Scalar(), ev.eval(kv.second, "let." + kv.first.Scalar()));
  Inventory inv;
  const auto versal = row.values.find("versal");
  if (versal != row.values.end() && versal->second != 0) inv.dsp_b_bits = 24;  // DSP58: 27 x 24
  for (const auto& st : fn.stages) {
    const std::string sname = st["stage"].Scalar();
    const std::string where = "stage '" + sname + "'";
    if (st["when"] && ev.eval(st["when"], where + ".when") == 0) continue;
    Collector c(inv, sname);
    int index = 0;
    for (const auto& item : st["items"])
      instantiate_item(ev, c, item, fn.file, where + " item " + std::to_string(index++));
  }
  return inv;
}

}  // namespace parallax::res
