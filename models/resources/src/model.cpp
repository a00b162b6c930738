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
#include "parallax/kernels/sad.hpp"
#include "parallax/kernels/sgm.hpp"
#include "parallax/kernels/wta_lr.hpp"

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
  if (cfg.rectify != "none") {
    const kern::RectifyParams rp = cfg.rectify_params(width_px, height_px);
    auto st = std::make_unique<kern::Rectify<kern::kMaxWidthPx, 256>>();
    st->configure(rp);
    for (const char* name : {"rectify_left", "rectify_right"}) {
      Collector c(inv, name);
      st->declare(c);
    }
  }
  {
    Collector c(inv, "cost");
    if (p.cost == kern::kCostCensus) {
      auto st = std::make_unique<kern::CensusCostStage<DeclCaps>>();
      st->configure(p);
      st->declare(c);
    } else {
      auto st = std::make_unique<kern::SadCostStage<DeclCaps>>();
      st->configure(p);
      st->declare(c);
    }
  }
  const bool two_pass = (p.path_mask & kern::kBackwardPaths) != 0;
  {
    auto agg = std::make_unique<kern::SgmAggregate<DeclCaps, uint32_t>>();
    agg->configure(p, kern::stream_kinds(p.path_mask, false), false, two_pass);
    Collector c(inv, "aggregate");
    agg->declare(c, cfg.row_packing, cfg.row_banks);
    if (two_pass) {
      // The frame buffer's writer: its on-chip reversal (kernels/frame_buffer.hpp).
      Collector w(inv, "ddr_write");
      kern::declare_frame_segment_buffer(w, p);
    }
    if (two_pass) {
      agg->configure(p, kern::stream_kinds(p.path_mask, true), true, false);
      Collector b(inv, "aggregate_back");
      agg->declare(b, cfg.row_packing, cfg.row_banks);
    }
  }
  {
    auto wta = std::make_unique<kern::WtaLr<DeclCaps, uint32_t>>();
    wta->configure(p, two_pass);
    Collector c(inv, "wta_lr");
    wta->declare(c);
  }
  if (p.median >= 3) {
    auto med = std::make_unique<kern::Median<DeclCaps>>();
    med->configure(p);
    Collector c(inv, "median");
    med->declare(c, db);
  }
  if (two_pass) {
    // The map writer of two passes: the codes' on-chip reversal (kernels/frame_buffer.hpp).
    Collector c(inv, "sink");
    kern::declare_map_segment_buffer(c, p);
  }
  // The FIFOs of the design's variant, from the pipeline table (kernels/pipeline.hpp), at their
  // tokens' widths.
  const unsigned conditions = kern::pipeline_conditions(p, cfg.rectify != "none");
  for (const kern::PipelineFifo& f : kern::kPipelineFifos)
    if (kern::pipeline_has(f.when, conditions)) add_fifo(inv, cfg, f.name, kern::token_bits(f.token, p));
  return inv;
}

Inventory median_inventory(int width_px, int height_px, int k, int value_bits) {
  kern::StereoParams p{};
  p.width_px = width_px;
  p.height_px = height_px;
  p.median = k;
  p.disparities = 1;
  p.parallel_units = 1;
  auto med = std::make_unique<kern::Median<DeclCaps>>();
  med->configure(p);
  Inventory inv;
  Collector c(inv, "median");
  med->declare(c, value_bits);
  return inv;
}

Inventory rectify_inventory(int width_px, int height_px, int mode, int frac_bits, int buffer_rows) {
  auto st = std::make_unique<kern::Rectify<kern::kMaxWidthPx, 256>>();
  st->configure(kern::RectifyParams{width_px, height_px, mode, frac_bits, buffer_rows});
  Inventory inv;
  Collector c(inv, "rectify");
  st->declare(c);
  return inv;
}

// --- coefficients -------------------------------------------------------------------------

namespace {

double need_double(const YAML::Node& n, const std::string& key, const std::string& where) {
  if (!n[key]) throw std::logic_error(where + ": missing field '" + key + "'");
  try {
    return n[key].as<double>();
  } catch (const YAML::Exception&) {
    throw std::logic_error(where + ": field '" + key + "' is not a number");
  }
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
  const YAML::Node lpb = s["lut_per_bit"];
  if (!lpb) throw std::logic_error(source + ": missing field 'structural.lut_per_bit'");
  for (int k = 0; k < kern::kOpKindCount; ++k)
    c.lut_per_bit[k] = need_double(lpb, kern::op_kind_name(kern::OpKind(k)), source + ": structural.lut_per_bit");
  c.dsp_min_operand_bits = int(need_double(s, "dsp_min_operand_bits", source + ": structural"));
  c.dsp_a_bits = int(need_double(s, "dsp_a_bits", source + ": structural"));
  c.dsp_b_bits = int(need_double(s, "dsp_b_bits", source + ": structural"));
  const YAML::Node f = root["fitted"];
  if (!f) throw std::logic_error(source + ": missing section 'fitted'");
  c.lut_scale = need_double(f, "lut_scale", source + ": fitted");
  c.lut_per_stage = need_double(f, "lut_per_stage", source + ": fitted");
  c.lut_per_memory = need_double(f, "lut_per_memory", source + ": fitted");
  c.ff_per_op_bit = need_double(f, "ff_per_op_bit", source + ": fitted");
  c.ff_per_stage = need_double(f, "ff_per_stage", source + ": fitted");
  c.fitted_on = f["fitted_on"] ? f["fitted_on"].as<std::string>() : "";
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
  o << "structural:\n"
       "  # LUTs per result bit of one operator, from the LUT6/CARRY8 fabric: an adder or magnitude\n"
       "  # comparator is one LUT per bit on the carry chain; a 2:1 multiplexer or an XOR of two bits\n"
       "  # shares a LUT6 with its neighbour (dual output); a popcount of n bits is about n LUTs of\n"
       "  # 6:3 compressors and adders; a multiplier in LUTs about a x b / 2. Multipliers whose\n"
       "  # narrower operand has at least dsp_min_operand_bits go to DSP48E2 (27 x 18 each).\n"
       "  lut_per_bit: {";
  for (int k = 0; k < kern::kOpKindCount; ++k)
    o << (k ? ", " : "") << kern::op_kind_name(kern::OpKind(k)) << ": " << c.lut_per_bit[k];
  o << "}\n  dsp_min_operand_bits: " << c.dsp_min_operand_bits << "\n  dsp_a_bits: " << c.dsp_a_bits
    << "\n  dsp_b_bits: " << c.dsp_b_bits
    << "\n# Fitted by `parallax fit-resources` (Ceres, Huber loss on relative errors, non-negative):\n"
       "# lut = lut_scale x operator LUTs + memory LUTs + lut_per_stage x stages + lut_per_memory x memories;\n"
       "# ff = register bits + ff_per_op_bit x operator result bits + ff_per_stage x stages.\n"
       "fitted:\n  fitted_on: \""
    << c.fitted_on << "\"\n  lut_scale: " << c.lut_scale << "\n  lut_per_stage: " << c.lut_per_stage
    << "\n  lut_per_memory: " << c.lut_per_memory << "\n  ff_per_op_bit: " << c.ff_per_op_bit
    << "\n  ff_per_stage: " << c.ff_per_stage << "\npower:\n  source: \"" << c.power_source
    << "\"\n  static_w: " << c.static_w << "\n  dynamic_mw_per_mhz_per_klut: " << c.dynamic_mw_per_mhz_per_klut
    << "\n  dynamic_mw_per_mhz_per_kff: " << c.dynamic_mw_per_mhz_per_kff
    << "\n  dynamic_mw_per_mhz_per_bram18k: " << c.dynamic_mw_per_mhz_per_bram18k
    << "\n  dynamic_mw_per_mhz_per_dsp: " << c.dynamic_mw_per_mhz_per_dsp << "\n  toggle_rate: " << c.toggle_rate
    << "\n";
  return o.str();
}

// --- estimate -------------------------------------------------------------------------------

namespace {

int64_t dsp_for(const OpItem& o, const Coefficients& c) {
  if (o.kind != kern::kOpMul || o.b_bits < c.dsp_min_operand_bits) return 0;
  const int64_t per =
      int64_t((o.width_bits + c.dsp_a_bits - 1) / c.dsp_a_bits) * int64_t((o.b_bits + c.dsp_b_bits - 1) / c.dsp_b_bits);
  return per * o.count;
}

double op_luts(const OpItem& o, const Coefficients& c) {
  if (dsp_for(o, c) > 0) return 0.0;
  if (o.kind == kern::kOpMul) return c.lut_per_bit[kern::kOpMul] * o.width_bits * o.b_bits * double(o.count);
  return c.lut_per_bit[o.kind] * o.width_bits * double(o.count);
}

Features stage_features(const Inventory& inv, const std::string& stage, const Coefficients& c) {
  Features f;
  for (const auto& m : inv.memories)
    if (m.stage == stage) {
      f.bram18k += m.per_copy.bram18k * m.copies;
      f.memory_luts += double(m.per_copy.luts * m.copies);
      f.register_bits += double(m.per_copy.ffs * m.copies);
      f.memories += m.copies;
    }
  for (const auto& o : inv.ops)
    if (o.stage == stage) {
      f.dsp += dsp_for(o, c);
      f.op_luts += op_luts(o, c);
      f.op_bits += double(o.width_bits) * double(o.count);
    }
  for (const auto& r : inv.registers)
    if (r.stage == stage) f.register_bits += double(r.width_bits) * double(r.count);
  f.stages = stage == "fifos" ? 0 : 1;
  return f;
}

Usage usage_of(const Features& f, const Coefficients& c) {
  Usage u;
  u.bram18k = f.bram18k;
  u.dsp = f.dsp;
  u.lut = int64_t(std::llround(c.lut_scale * f.op_luts + f.memory_luts + c.lut_per_stage * f.stages +
                               c.lut_per_memory * f.memories));
  u.ff = int64_t(std::llround(f.register_bits + c.ff_per_op_bit * f.op_bits + c.ff_per_stage * f.stages));
  return u;
}

}  // namespace

Features features(const Inventory& inv, const Coefficients& c) {
  Features total;
  for (const auto& s : inv.stages) {
    const Features f = stage_features(inv, s, c);
    total.op_luts += f.op_luts;
    total.memory_luts += f.memory_luts;
    total.stages += f.stages;
    total.memories += f.memories;
    total.register_bits += f.register_bits;
    total.op_bits += f.op_bits;
    total.bram18k += f.bram18k;
    total.dsp += f.dsp;
  }
  return total;
}

Estimate estimate(const Inventory& inv, const Coefficients& c) {
  Estimate e;
  for (const auto& s : inv.stages) {
    const Features f = stage_features(inv, s, c);
    StageUsage su{s, usage_of(f, c)};
    for (const auto& m : inv.memories)
      if (m.stage == s) {
        if (m.per_copy.storage == Storage::lutram) su.usage.lutram_luts += m.per_copy.luts * m.copies;
        if (m.per_copy.storage == Storage::srl) su.usage.srl_luts += m.per_copy.luts * m.copies;
      }
    e.total.bram18k += su.usage.bram18k;
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
