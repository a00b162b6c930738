// The resource model (model.hpp): inventories from the kernels' own declarations, the default
// storage mapping, per-operator costs from data, utilisation and power.
#include "parallax/resources/model.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "parallax/kernels/caps.hpp"
#include "parallax/kernels/census.hpp"
#include "parallax/kernels/frame_buffer.hpp"
#include "parallax/kernels/median.hpp"
#include "parallax/kernels/pipeline.hpp"
#include "parallax/kernels/rectify.hpp"
#include "parallax/kernels/row_reverse.hpp"
#include "parallax/kernels/sad.hpp"
#include "parallax/kernels/sgm.hpp"
#include "parallax/kernels/wta_lr.hpp"
#include "parallax/resources/operators.hpp"

namespace parallax::res {

namespace data {
extern const char* const resource_model_yaml;
}

Collector::Collector(Inventory& inv, std::string stage) : inv_(inv), stage_(std::move(stage)) {
  if (std::find(inv_.stages.begin(), inv_.stages.end(), stage_) == inv_.stages.end()) inv_.stages.push_back(stage_);
}

void Collector::memory(const char* name, int64_t depth, int width_bits, int copies, bool true_dual_port) {
  if (copies <= 0 || depth <= 0 || width_bits <= 0) return;
  MemoryItem m;
  m.stage = stage_;
  m.name = name;
  m.kind = MemoryKind::array;
  m.depth = depth;
  m.width_bits = width_bits;
  m.copies = copies;
  m.true_dual_port = true_dual_port;
  m.per_copy = map_memory(m.kind, depth, width_bits, true_dual_port);
  inv_.memories.push_back(m);
}

void Collector::registers(const char* name, int width_bits, int count) {
  if (width_bits <= 0 || count <= 0) return;
  inv_.registers.push_back({stage_, name, width_bits, count});
}

void Collector::op(const char* name, kern::OpKind kind, int width_bits, int count) {
  if (width_bits <= 0 || count <= 0) return;
  OpItem o;
  o.stage = stage_;
  o.name = name;
  o.kind = kind;
  o.width_bits = width_bits;
  o.count = count;
  inv_.ops.push_back(o);
}

void Collector::mul(const char* name, int a_bits, int b_bits, int count) {
  if (a_bits <= 0 || b_bits <= 0 || count <= 0) return;
  OpItem o;
  o.stage = stage_;
  o.name = name;
  o.kind = kern::kOpMul;
  o.width_bits = std::max(a_bits, b_bits);
  o.b_bits = std::min(a_bits, b_bits);
  o.count = count;
  inv_.ops.push_back(o);
}

void Collector::mux(const char* name, int width_bits, int fan_in, int count) {
  if (fan_in <= 1) return;
  const std::size_t before = inv_.ops.size();
  op(name, kern::kOpMux, width_bits, count);
  if (inv_.ops.size() > before) inv_.ops.back().fan_in = fan_in;
}

void Collector::mul_const(const char* name, int a_bits, int b_bits, int64_t count) {
  if (a_bits <= 0 || b_bits <= 0 || count <= 0) return;
  OpItem o;
  o.name = name;
  o.kind = kern::kOpMul;
  o.width_bits = std::max(a_bits, b_bits);
  o.b_bits = std::min(a_bits, b_bits);
  o.constant_operand = true;
  o.count = count;
  op_item(std::move(o));
}

void Collector::op_item(OpItem o) {
  if (o.count <= 0 || o.width_bits <= 0) return;
  o.stage = stage_;
  inv_.ops.push_back(std::move(o));
}

void Collector::memory_item(MemoryItem m) {
  if (m.copies <= 0 || m.depth <= 0 || m.width_bits <= 0) return;
  m.stage = stage_;
  if (m.lutram) {
    m.per_copy = MemoryMapping{Storage::lutram};
    m.per_copy.luts =
        int64_t(m.width_bits) * ((m.depth + kLutramDepthPerLut - 1) / kLutramDepthPerLut) * (m.true_dual_port ? 2 : 1);
  } else if (m.uram) {
    // URAM288: 4K x 72 bits, one per ceil(width / 72) x ceil(depth / 4096).
    m.per_copy = MemoryMapping{Storage::bram};
    m.uram_per_copy = int64_t((m.width_bits + 71) / 72) * ((m.depth + 4095) / 4096);
  } else {
    m.per_copy = map_memory(m.kind, m.depth, m.width_bits, m.true_dual_port);
  }
  inv_.memories.push_back(std::move(m));
}

void Collector::interface(const char* name, const std::string& kind, int width_bits, int64_t count) {
  if (width_bits <= 0 || count <= 0) return;
  inv_.interfaces.push_back({stage_, name, kind, width_bits, count});
}

namespace {

// Kernel instances for declarations only: one lane of capacity (declare() reads the configured
// PU, not the instantiation's), allocated once per call.
using DeclCaps = kern::Caps<kern::kMaxWidthPx, kern::kMaxDisparities, 1>;

void add_fifo(Inventory& inv, const config::PipelineConfig& cfg, const std::string& name, int width_bits) {
  const auto it = cfg.fifo_depths.find(name);
  const int depth = it != cfg.fifo_depths.end() ? it->second : cfg.fifo_depth;
  if (std::find(inv.stages.begin(), inv.stages.end(), "fifos") == inv.stages.end()) inv.stages.push_back("fifos");
  MemoryItem m;
  m.stage = "fifos";
  m.name = name;
  m.kind = MemoryKind::fifo;
  m.depth = std::max(1, depth);
  m.width_bits = width_bits;
  m.copies = 1;
  m.per_copy = map_memory(MemoryKind::fifo, m.depth, width_bits, false);
  inv.memories.push_back(m);
}

}  // namespace

Inventory design_inventory(const config::PipelineConfig& cfg, int width_px, int height_px) {
  const kern::StereoParams p = cfg.stereo_params(width_px, height_px);
  Inventory inv;
  const int db = kern::disparity_bits(p);
  const bool two_pass = kern::two_pass_paths(p.path_mask);
  const bool rectify = cfg.rectify != "none";
  // The stages of the design's variant as the pipeline description lists them (kernels/
  // pipeline.hpp), each kernel configured as the description says; stages without hardware of
  // their own (source, map readers, ddr_read, the one-pass sink) declare nothing.
  auto agg = std::make_unique<kern::SgmAggregate<DeclCaps, uint32_t>>();
  auto declare_stage = [&](const kern::PipelineStage& st, const kern::StageSetup& setup) {
    const std::string name = st.name;
    if (name == "rectify_left" || name == "rectify_right") {
      auto rect = std::make_unique<kern::Rectify<kern::kMaxWidthPx, 256>>();
      rect->configure(cfg.rectify_params(width_px, height_px));
      Collector c(inv, name);
      rect->declare(c);
    } else if (name == "cost") {
      Collector c(inv, name);
      if (p.cost == kern::kCostCensus) {
        auto cost = std::make_unique<kern::CensusCostStage<DeclCaps>>();
        cost->configure(p);
        cost->declare(c);
      } else {
        auto cost = std::make_unique<kern::SadCostStage<DeclCaps>>();
        cost->configure(p);
        cost->declare(c);
      }
    } else if (name == "aggregate" || name == "aggregate_back" || name == "aggregate_row") {
      agg->configure(p, setup);
      inv.setups.emplace_back(name, agg->setup());
      Collector c(inv, name);
      agg->declare(c);
    } else if (name == "ddr_write") {  // the frame buffer's writer: its on-chip reversal (frame_buffer.hpp)
      Collector c(inv, name);
      kern::declare_frame_segment_buffer(c, p);
    } else if (name == "row_reverse") {  // the row memories of costs and forward sums (row_reverse.hpp)
      auto rev = std::make_unique<kern::RowReverse<DeclCaps, uint32_t>>();
      rev->configure(p);
      Collector c(inv, name);
      rev->declare(c);
    } else if (name == "wta_lr") {
      auto wta = std::make_unique<kern::WtaLr<DeclCaps, uint32_t>>();
      wta->configure(p, setup);
      inv.setups.emplace_back(name, wta->setup());
      Collector c(inv, name);
      wta->declare(c);
    } else if (name == "median" && p.median >= 3) {
      auto med = std::make_unique<kern::Median<DeclCaps>>();
      med->configure(p);
      Collector c(inv, name);
      med->declare(c, db);
    } else if (name == "row_unreverse") {  // the codes' row memory
      auto codes = std::make_unique<kern::RowReverseCodes<DeclCaps>>();
      codes->configure(p);
      Collector c(inv, name);
      codes->declare(c);
    } else if (name == "sink" && two_pass) {  // the map writer: the codes' on-chip reversal
      Collector c(inv, name);
      kern::declare_map_segment_buffer(c, p);
    }
  };
  kern::for_each_stage(p.path_mask, rectify, declare_stage);
  // The top's port adapters, as the exported top declares them (hls/templates): AXI4-Stream pixels
  // in, remap-table entries in (64-bit beats) when rectifying, disparity codes out (whole bytes; two
  // passes: AXI4 masters to the frame buffer and the map), and the AXI4-Lite control registers (p1,
  // p2, lr_tolerance, uniqueness_pct and ap_ctrl, 32 bits each; the top declares uniqueness_pct
  // whether or not the design has the check).
  {
    Collector c(inv, "interfaces");
    c.interface("left_in", "axis", 8, 1);
    c.interface("right_in", "axis", 8, 1);
    if (cfg.rectify != "none") c.interface("map_in", "axis", 64, 2);
    const int out_bits = ((db + 7) / 8) * 8;
    if (two_pass) {
      c.interface("frame_buffer", "m_axi", 64, 2);
      c.interface("disparity", "m_axi", out_bits, 1);
    } else {
      c.interface("disparity_out", "axis", out_bits, 1);
    }
    c.interface("control", "s_axilite", 32, 5);
  }
  // The FIFOs of the design's variant, from the pipeline table (kernels/pipeline.hpp), at their
  // tokens' widths.
  const unsigned conditions = kern::pipeline_conditions(p, cfg.rectify != "none");
  for (const kern::PipelineFifo& f : kern::kPipelineFifos)
    if (kern::pipeline_has(f.when, conditions)) add_fifo(inv, cfg, f.name, kern::token_bits(f.token, p));
  return inv;
}

// --- coefficients -------------------------------------------------------------------------

const char* feature_name(int f) {
  static const char* const names[kFeatureCount] = {"stage", "memory", "fifo", "interface", "pipeline", "dsp", "float"};
  return f >= 0 && f < kFeatureCount ? names[f] : "unknown";
}

const char* flavour_name(Flavour f) {
  return f == Flavour::routed ? "routed" : "csynth";
}

Flavour parse_flavour(const std::string& name) {
  if (name == "csynth") return Flavour::csynth;
  if (name == "routed") return Flavour::routed;
  throw std::invalid_argument("estimate must be csynth or routed, got '" + name + "'");
}

namespace {

double need_double(const YAML::Node& n, const std::string& key, const std::string& where) {
  if (!n[key]) throw std::logic_error(where + ": missing field '" + key + "'");
  try {
    return n[key].as<double>();
  } catch (const YAML::Exception&) {
    throw std::logic_error(where + ": field '" + key + "' is not a number");
  }
}

void need_features(const YAML::Node& n, const std::string& key, const std::string& where, double* out) {
  const YAML::Node m = n[key];
  if (!m || !m.IsMap()) throw std::logic_error(where + ": missing map '" + key + "'");
  for (int f = 0; f < kFeatureCount; ++f) out[f] = need_double(m, feature_name(f), where + "." + key);
}

void write_features(std::ostringstream& o, const char* key, const double* v) {
  o << "  " << key << ": {";
  for (int f = 0; f < kFeatureCount; ++f) o << (f ? ", " : "") << feature_name(f) << ": " << v[f];
  o << "}\n";
}

}  // namespace

Coefficients parse_coefficients(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw std::logic_error(source + ": " + e.what());
  }
  Coefficients c;
  const YAML::Node s = root["structural"];
  if (!s) throw std::logic_error(source + ": missing section 'structural'");
  c.dsp_a_bits = int(need_double(s, "dsp_a_bits", source + ": structural"));
  c.dsp_b_bits = int(need_double(s, "dsp_b_bits", source + ": structural"));
  need_features(s, "lut_prior", source + ": structural", c.lut_prior);
  need_features(s, "ff_prior", source + ": structural", c.ff_prior);
  const YAML::Node f = root["fitted"];
  if (!f) throw std::logic_error(source + ": missing section 'fitted'");
  c.fitted_on = f["fitted_on"] ? f["fitted_on"].as<std::string>() : "";
  c.dsp_min_bits_var = int(need_double(f, "dsp_min_bits_var", source + ": fitted"));
  c.dsp_min_bits_const = int(need_double(f, "dsp_min_bits_const", source + ": fitted"));
  c.dsp_per_fmul = int(need_double(f, "dsp_per_fmul", source + ": fitted"));
  c.dsp_per_fadd = int(need_double(f, "dsp_per_fadd", source + ": fitted"));
  c.dsp_per_fexp = int(need_double(f, "dsp_per_fexp", source + ": fitted"));
  need_features(f, "lut", source + ": fitted", c.lut);
  need_features(f, "ff", source + ": fitted", c.ff);
  const YAML::Node r = root["routed"];
  if (!r) throw std::logic_error(source + ": missing section 'routed'");
  c.routed_lut_ratio = need_double(r, "lut", source + ": routed");
  c.routed_ff_ratio = need_double(r, "ff", source + ": routed");
  c.routed_bram_ratio = need_double(r, "bram18k", source + ": routed");
  c.routed_dsp_ratio = need_double(r, "dsp", source + ": routed");
  c.routed_source = r["source"] ? r["source"].as<std::string>() : "";
  const YAML::Node pw = root["power"];
  if (!pw) throw std::logic_error(source + ": missing section 'power'");
  c.static_w = need_double(pw, "static_w", source + ": power");
  c.dynamic_mw_per_mhz_per_klut = need_double(pw, "dynamic_mw_per_mhz_per_klut", source + ": power");
  c.dynamic_mw_per_mhz_per_kff = need_double(pw, "dynamic_mw_per_mhz_per_kff", source + ": power");
  c.dynamic_mw_per_mhz_per_bram18k = need_double(pw, "dynamic_mw_per_mhz_per_bram18k", source + ": power");
  c.dynamic_mw_per_mhz_per_dsp = need_double(pw, "dynamic_mw_per_mhz_per_dsp", source + ": power");
  c.toggle_rate = need_double(pw, "toggle_rate", source + ": power");
  c.power_source = pw["source"] ? pw["source"].as<std::string>() : "";
  return c;
}

const Coefficients& default_coefficients() {
  static const Coefficients c = parse_coefficients(data::resource_model_yaml, "models/data/resource_model.yaml");
  return c;
}

std::string coefficients_yaml(const Coefficients& c) {
  std::ostringstream o;
  o.precision(6);
  o << "# Coefficients of the resource and power model (models/resources, docs/resources.md).\n"
       "# Written by `parallax fit-resources --write`; compiled into parallax (rebuild after editing).\n"
       "structural:\n"
       "  # One DSP48E2 multiplies 27 x 18 bits.\n"
       "  dsp_a_bits: "
    << c.dsp_a_bits << "\n  dsp_b_bits: " << c.dsp_b_bits
    << "\n  # Priors of the Vitis overhead terms (docs/resources.md, section 3): per process an FSM and\n"
       "  # handshakes, per memory its address and enable logic, per FIFO its control, per interface bit\n"
       "  # an adapter's register slice, per operator output bit one pipeline register, per DSP slice its\n"
       "  # operand registers. The datapath itself is priced from models/data/operators.csv, not fitted.\n";
  write_features(o, "lut_prior", c.lut_prior);
  write_features(o, "ff_prior", c.ff_prior);
  o << "# Fitted by `parallax fit-resources` (Ceres, Cauchy loss on log residuals, non-negative) on the\n"
       "# kept published rows, and the DSP binding thresholds learned from them (the most rows exact).\n"
       "fitted:\n  fitted_on: \""
    << c.fitted_on << "\"\n  dsp_min_bits_var: " << c.dsp_min_bits_var
    << "\n  dsp_min_bits_const: " << c.dsp_min_bits_const << "\n  dsp_per_fmul: " << c.dsp_per_fmul
    << "\n  dsp_per_fadd: " << c.dsp_per_fadd << "\n  dsp_per_fexp: " << c.dsp_per_fexp << "\n";
  write_features(o, "lut", c.lut);
  write_features(o, "ff", c.ff);
  o << "# routed = csynth x ratio per resource (estimate: routed).\nrouted:\n  source: \"" << c.routed_source
    << "\"\n  lut: " << c.routed_lut_ratio << "\n  ff: " << c.routed_ff_ratio << "\n  bram18k: " << c.routed_bram_ratio
    << "\n  dsp: " << c.routed_dsp_ratio << "\npower:\n  source: \"" << c.power_source
    << "\"\n  static_w: " << c.static_w << "\n  dynamic_mw_per_mhz_per_klut: " << c.dynamic_mw_per_mhz_per_klut
    << "\n  dynamic_mw_per_mhz_per_kff: " << c.dynamic_mw_per_mhz_per_kff
    << "\n  dynamic_mw_per_mhz_per_bram18k: " << c.dynamic_mw_per_mhz_per_bram18k
    << "\n  dynamic_mw_per_mhz_per_dsp: " << c.dynamic_mw_per_mhz_per_dsp << "\n  toggle_rate: " << c.toggle_rate
    << "\n";
  return o.str();
}

// --- estimate -------------------------------------------------------------------------------

int64_t dsp_for(const OpItem& o, const Coefficients& c, int dsp_b_bits) {
  if (o.float_kind == kFloatMul) return int64_t(c.dsp_per_fmul) * o.count;
  if (o.float_kind == kFloatAdd) return int64_t(c.dsp_per_fadd) * o.count;
  if (o.float_kind == kFloatExp) return int64_t(c.dsp_per_fexp) * o.count;
  if (o.float_kind != 0) return 0;
  if (o.bound_dsp) return int64_t((o.width_bits + 47) / 48) * o.count;  // the slice's 48-bit ALU
  if (o.kind != kern::kOpMul) return 0;
  if (o.b_bits < (o.constant_operand ? c.dsp_min_bits_const : c.dsp_min_bits_var)) return 0;
  const int extra = o.unsigned_operands ? 1 : 0;  // a signed slice holds one bit less of an unsigned operand
  const int b_tile = dsp_b_bits > 0 ? dsp_b_bits : c.dsp_b_bits;
  const int64_t per = int64_t((o.width_bits + extra + c.dsp_a_bits - 1) / c.dsp_a_bits) *
                      int64_t((o.b_bits + extra + b_tile - 1) / b_tile);
  return per * o.count;
}

namespace {

// Bits an operator hands to the next stage of latency (what a pipeline register holds).
double output_bits(const OpItem& o) {
  switch (o.kind) {
    case kern::kOpCompare:
      return 1.0;
    case kern::kOpPopcount:
      return double(kern::bits_for(uint64_t(o.width_bits)));
    case kern::kOpMul:
      return double(o.width_bits + o.b_bits);
    default:
      return double(o.width_bits);
  }
}

// LUTs of one integer operator in fabric, from the operator table: its LUTs and its MUXF7/F8
// (a MUXF whose inputs no LUT drives is fed through LUTs used as route-throughs).
double luts_of(const MappedCost& m) {
  return m.lut + m.muxf;
}
double fabric_luts(const OpItem& o) {
  switch (o.kind) {
    case kern::kOpAdd:
      return luts_of(mapped_cost("add", o.width_bits));
    case kern::kOpCompare:
      return luts_of(mapped_cost("compare", o.width_bits));
    case kern::kOpMux:
      return luts_of(mapped_cost("mux", o.width_bits, std::max(2, o.fan_in)));
    case kern::kOpPopcount:
      return luts_of(mapped_cost("popcount", o.width_bits));
    case kern::kOpXor:
      return luts_of(mapped_cost("xor", o.width_bits));
    default:
      break;
  }
  if (o.constant_operand)  // shift-and-add: about one adder of the product's width per two constant bits
    return double(std::max(1, o.b_bits / 2)) * luts_of(mapped_cost("add", o.width_bits + o.b_bits));
  return luts_of(mapped_cost("mul_fabric", o.width_bits, 1, o.b_bits));
}

void add_op_features(const OpItem& o, const Coefficients& c, int dsp_b_bits, Features& f) {
  const double n = double(o.count);
  if (o.float_kind != 0) {
    f.dsp += dsp_for(o, c, dsp_b_bits);
    f.lut_f[kFeatFloat] += n * kFloatSize[o.float_kind];
    f.ff_f[kFeatFloat] += n * kFloatSize[o.float_kind];
    return;
  }
  const int64_t dsp = dsp_for(o, c, dsp_b_bits);
  if (dsp > 0) {  // on DSP slices: no fabric datapath, the slices' surroundings are overhead
    f.dsp += dsp;
    f.lut_f[kFeatDsp] += double(dsp);
    f.ff_f[kFeatDsp] += double(dsp);
    return;
  }
  const double luts = fabric_luts(o) * n;
  f.lut_base += luts;
  (o.kind == kern::kOpMux ? f.lut_parts.muxes : f.lut_parts.operators) += luts;
  f.lut_f[kFeatPipeline] += output_bits(o) * n;
  f.ff_f[kFeatPipeline] += output_bits(o) * n;
}

Features stage_features(const Inventory& inv, const std::string& stage, const Coefficients& c) {
  Features f;
  for (const auto& m : inv.memories)
    if (m.stage == stage) {
      f.bram18k += m.per_copy.bram18k * m.copies;
      f.uram += m.uram_per_copy * m.copies;
      f.lut_base += double(m.per_copy.luts * m.copies);
      f.ff_base += double(m.per_copy.ffs * m.copies);
      f.lut_parts.memories += double(m.per_copy.luts * m.copies);
      f.ff_parts.memories += double(m.per_copy.ffs * m.copies);
      if (m.kind == MemoryKind::fifo) {
        f.lut_f[kFeatFifo] += m.copies;
        f.ff_f[kFeatFifo] += m.copies;
      } else if (m.per_copy.storage == Storage::bram) {
        f.lut_f[kFeatMemory] += m.copies;
        f.ff_f[kFeatMemory] += m.copies;
      }
    }
  for (const auto& o : inv.ops)
    if (o.stage == stage) add_op_features(o, c, inv.dsp_b_bits, f);
  for (const auto& r : inv.registers)
    if (r.stage == stage) {
      const double bits = double(r.width_bits) * double(r.count);
      f.ff_base += bits;  // one FDRE per bit (the table's register row), its enable on CE
      f.ff_parts.registers += bits;
    }
  for (const auto& i : inv.interfaces)
    if (i.stage == stage) {
      f.lut_f[kFeatInterface] += double(i.width_bits) * double(i.count);
      f.ff_f[kFeatInterface] += double(i.width_bits) * double(i.count);
    }
  const double st = stage == "fifos" || stage == "interfaces" ? 0.0 : 1.0;
  f.lut_f[kFeatStage] = st;
  f.ff_f[kFeatStage] = st;
  return f;
}

Usage usage_of(const Features& f, const Coefficients& c, Breakdown* lut_parts = nullptr,
               Breakdown* ff_parts = nullptr) {
  Usage u;
  u.bram18k = f.bram18k;
  u.uram = f.uram;
  u.dsp = f.dsp;
  double lut_over = 0, ff_over = 0;
  for (int k = 0; k < kFeatureCount; ++k) {
    lut_over += c.lut[k] * f.lut_f[k];
    ff_over += c.ff[k] * f.ff_f[k];
  }
  u.lut = int64_t(std::llround(f.lut_base + lut_over));
  u.ff = int64_t(std::llround(f.ff_base + ff_over));
  if (lut_parts) {
    *lut_parts = f.lut_parts;
    lut_parts->overhead = lut_over;
  }
  if (ff_parts) {
    *ff_parts = f.ff_parts;
    ff_parts->overhead = ff_over;
  }
  return u;
}

int64_t scaled(int64_t v, double ratio) {
  return int64_t(std::llround(double(v) * ratio));
}

Usage routed(const Usage& u, const Coefficients& c) {
  Usage r = u;
  r.lut = scaled(u.lut, c.routed_lut_ratio);
  r.ff = scaled(u.ff, c.routed_ff_ratio);
  r.bram18k = scaled(u.bram18k, c.routed_bram_ratio);
  r.dsp = scaled(u.dsp, c.routed_dsp_ratio);
  r.lutram_luts = scaled(u.lutram_luts, c.routed_lut_ratio);
  r.srl_luts = scaled(u.srl_luts, c.routed_lut_ratio);
  return r;
}

}  // namespace

Features features(const Inventory& inv, const Coefficients& c) {
  Features total;
  for (const auto& s : inv.stages) {
    const Features f = stage_features(inv, s, c);
    for (int k = 0; k < kFeatureCount; ++k) {
      total.lut_f[k] += f.lut_f[k];
      total.ff_f[k] += f.ff_f[k];
    }
    total.lut_base += f.lut_base;
    total.ff_base += f.ff_base;
    total.lut_parts += f.lut_parts;
    total.ff_parts += f.ff_parts;
    total.bram18k += f.bram18k;
    total.uram += f.uram;
    total.dsp += f.dsp;
  }
  return total;
}

namespace {

// The cost of a one-item inventory of `stage` without the stage's own overhead.
PricedItem price_alone(const Inventory& one, const Coefficients& c, std::string stage, std::string name,
                       std::string what) {
  Features f = stage_features(one, stage, c);
  f.lut_f[kFeatStage] = f.ff_f[kFeatStage] = 0;
  const Usage u = usage_of(f, c);
  PricedItem p{std::move(stage), std::move(name), std::move(what), 0, 0, u.dsp, u.bram18k};
  p.lut = f.lut_base;
  p.ff = f.ff_base;
  for (int k = 0; k < kFeatureCount; ++k) {
    p.lut += c.lut[k] * f.lut_f[k];
    p.ff += c.ff[k] * f.ff_f[k];
  }
  return p;
}

std::string times(int64_t n) {
  return n == 1 ? "" : " x" + std::to_string(n);
}

}  // namespace

std::vector<PricedItem> priced_items(const Inventory& inv, const Coefficients& c) {
  std::vector<PricedItem> out;
  for (const auto& s : inv.stages) {
    Inventory none;
    none.stages = {s};
    Features f = stage_features(none, s, c);
    if (f.lut_f[kFeatStage] > 0)
      out.push_back({s, "(process)", "FSM and handshakes", c.lut[kFeatStage], c.ff[kFeatStage], 0, 0});
    for (const auto& m : inv.memories) {
      if (m.stage != s) continue;
      Inventory one;
      one.memories = {m};
      out.push_back(price_alone(one, c, s, m.name,
                                std::string(m.kind == MemoryKind::fifo ? "fifo " : "memory ") +
                                    std::to_string(m.depth) + "x" + std::to_string(m.width_bits) + "b" +
                                    times(m.copies)));
    }
    for (const auto& o : inv.ops) {
      if (o.stage != s) continue;
      Inventory one;
      one.ops = {o};
      one.dsp_b_bits = inv.dsp_b_bits;
      std::string what = o.float_kind ? "float core" : kern::op_kind_name(o.kind);
      what += " " + std::to_string(o.width_bits) + "b";
      if (o.kind == kern::kOpMul && !o.float_kind)
        what += " x " + std::to_string(o.b_bits) + "b" + (o.constant_operand ? " (constant)" : "");
      if (o.kind == kern::kOpMux && o.fan_in > 2) what += " " + std::to_string(o.fan_in) + ":1";
      out.push_back(price_alone(one, c, s, o.name, what + times(o.count)));
    }
    for (const auto& r : inv.registers) {
      if (r.stage != s) continue;
      Inventory one;
      one.registers = {r};
      out.push_back(price_alone(one, c, s, r.name, "registers " + std::to_string(r.width_bits) + "b" + times(r.count)));
    }
    for (const auto& i : inv.interfaces) {
      if (i.stage != s) continue;
      Inventory one;
      one.interfaces = {i};
      out.push_back(price_alone(one, c, s, i.name, i.kind + " " + std::to_string(i.width_bits) + "b" + times(i.count)));
    }
  }
  return out;
}

Estimate estimate(const Inventory& inv, const Coefficients& c, Flavour flavour) {
  Estimate e;
  e.flavour = flavour;
  for (const auto& s : inv.stages) {
    const Features f = stage_features(inv, s, c);
    StageUsage su;
    su.stage = s;
    su.usage = usage_of(f, c, &su.lut, &su.ff);
    for (const auto& m : inv.memories)
      if (m.stage == s) {
        if (m.per_copy.storage == Storage::lutram) su.usage.lutram_luts += m.per_copy.luts * m.copies;
        if (m.per_copy.storage == Storage::srl) su.usage.srl_luts += m.per_copy.luts * m.copies;
      }
    if (flavour == Flavour::routed) su.usage = routed(su.usage, c);
    e.total.bram18k += su.usage.bram18k;
    e.total.uram += su.usage.uram;
    e.total.lut += su.usage.lut;
    e.total.ff += su.usage.ff;
    e.total.dsp += su.usage.dsp;
    e.total.lutram_luts += su.usage.lutram_luts;
    e.total.srl_luts += su.usage.srl_luts;
    e.stages.push_back(su);
  }
  return e;
}

Utilisation utilisation(const Usage& u, const Device& d) {
  Utilisation r;
  r.device = &d;
  auto pct = [](int64_t used, int64_t avail) {
    return avail > 0 ? 100.0 * double(used) / double(avail) : (used > 0 ? 1e9 : 0.0);
  };
  r.bram18k_pct = pct(u.bram18k, d.bram18k);
  r.uram_pct = pct(u.uram, d.uram);
  r.lut_pct = pct(u.lut, d.lut);
  r.ff_pct = pct(u.ff, d.ff);
  r.dsp_pct = pct(u.dsp, d.dsp);
  r.fits = u.bram18k <= d.bram18k && u.uram <= d.uram && u.lut <= d.lut && u.ff <= d.ff && u.dsp <= d.dsp;
  return r;
}

Power power(const Usage& u, double clock_mhz, double frame_interval_ms, const Coefficients& c) {
  Power p;
  p.static_w = c.static_w;
  const double activity = clock_mhz * c.toggle_rate / 0.125;  // coefficients are given at the default 12.5 %
  p.dynamic_w =
      1e-3 * activity *
      (c.dynamic_mw_per_mhz_per_klut * double(u.lut) / 1000.0 + c.dynamic_mw_per_mhz_per_kff * double(u.ff) / 1000.0 +
       c.dynamic_mw_per_mhz_per_bram18k * double(u.bram18k) + c.dynamic_mw_per_mhz_per_dsp * double(u.dsp));
  p.total_w = p.static_w + p.dynamic_w;
  p.energy_mj_per_frame = p.total_w * frame_interval_ms;
  return p;
}

}  // namespace parallax::res
