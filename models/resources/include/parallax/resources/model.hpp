// The resource model: a design's inventory (what its kernels declare, plus the FIFOs between
// them) mapped to BRAM_18K, LUT, FF and DSP with per-operator costs whose coefficients are data
// (models/data/resource_model.yaml, fitted by `parallax fit-resources`), and a power estimate.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "parallax/config/config.hpp"
#include "parallax/kernels/pipeline.hpp"
#include "parallax/kernels/resources.hpp"
#include "parallax/resources/bram.hpp"
#include "parallax/resources/devices.hpp"

namespace parallax::res {

struct MemoryItem {
  std::string stage, name;
  MemoryKind kind = MemoryKind::array;
  int64_t depth = 0;
  int width_bits = 0;
  int copies = 1;
  bool true_dual_port = false;
  bool uram = false;       // bound to UltraRAM (URAM288, 4K x 72) instead of block RAM
  bool lutram = false;     // bound to LUTRAM whatever its size (BIND_STORAGE impl=lutram)
  MemoryMapping per_copy;  // the default storage of one copy (URAM: storage bram, bram18k 0)
  int64_t uram_per_copy = 0;
};
struct OpItem {
  std::string stage, name;
  kern::OpKind kind = kern::kOpAdd;
  int width_bits = 0;              // multipliers: the wider operand
  int b_bits = 0;                  // multipliers: the narrower operand
  bool constant_operand = false;   // multipliers: one operand is a synthesis-time constant
  bool unsigned_operands = false;  // multipliers: unsigned operands take one more bit on a signed DSP
  bool bound_dsp = false;          // adders the source binds to a DSP slice (core=AddSub_DSP / BIND_OP)
  int float_kind = 0;              // 0: integer; else a kFloat* core (single precision, count cores)
  int fan_in = 2;                  // muxes: inputs per mux (2: a 2:1 mux per bit)
  int64_t count = 0;
};
// Single-precision floating-point cores: multiply, add/subtract, divide, exp, conversion to or from
// an integer. Their DSP slices per core are learned (multiply, add, exp) or none (divide and
// conversions are built in logic); their logic is one `float` feature weighted by kFloatSize.
inline constexpr int kFloatMul = 1, kFloatAdd = 2, kFloatDiv = 3, kFloatExp = 4, kFloatConv = 5;
// Relative logic size of the cores (multiply = 1), an inference from the shapes of the
// floating-point operators (docs/resources.md, section 3).
inline constexpr double kFloatSize[6] = {0, 1.0, 2.5, 10.0, 7.0, 2.0};
struct RegisterItem {
  std::string stage, name;
  int width_bits = 0;
  int64_t count = 0;
};
// A stream or memory-mapped port adapter of the top function (AXI4-Stream: axis; AXI4 master:
// m_axi; AXI4-Lite control registers: s_axilite), width_bits of data each.
struct InterfaceItem {
  std::string stage, name, kind;
  int width_bits = 0;
  int64_t count = 0;
};

struct Inventory {
  std::vector<std::string> stages;  // in pipeline order
  std::vector<MemoryItem> memories;
  std::vector<OpItem> ops;
  std::vector<RegisterItem> registers;
  std::vector<InterfaceItem> interfaces;
  int dsp_b_bits = 0;  // the device's DSP slice B width when not the coefficients' (Versal DSP58: 24)
  // What design_inventory() configured each SGM and WTA stage with (tests hold it to
  // kern::stage_setup(), the pipeline description).
  std::vector<std::pair<std::string, kern::StageSetup>> setups;
};

// The sink the kernels' declare() methods call (kern::resources.hpp), for one stage.
class Collector {
 public:
  Collector(Inventory& inv, std::string stage);
  void memory(const char* name, int64_t depth, int width_bits, int copies, bool true_dual_port);
  void registers(const char* name, int width_bits, int count);
  void op(const char* name, kern::OpKind kind, int width_bits, int count);
  void mul(const char* name, int a_bits, int b_bits, int count);
  void mux(const char* name, int width_bits, int fan_in, int count);        // count N:1 muxes of width_bits
  void mul_const(const char* name, int a_bits, int b_bits, int64_t count);  // by a synthesis-time constant
  // Beyond the kernels' vocabulary (function descriptions, models/data/functions):
  void memory_item(MemoryItem m);
  void op_item(OpItem o);
  void interface(const char* name, const std::string& kind, int width_bits, int64_t count);

 private:
  Inventory& inv_;
  std::string stage_;
};

// A whole design: its stages as the kernels declare them for the configuration at its ROI size,
// and its FIFOs (named as in the cycle model, with the configured depths).
Inventory design_inventory(const config::PipelineConfig& cfg, int width_px, int height_px);

// LUT and FF of a design are a structural part and a fitted part (issue 42, docs/resources.md
// section 3). The structural part is the datapath priced operator by operator from the operator
// table (operators.hpp: what Yosys maps each kind, width and fan-in to on UltraScale+), the
// declared registers (one FF per bit) and the memories in LUTs or SRLs. The fitted part is what
// Vitis adds around a datapath, one feature per kind of overhead, each linear in a count the
// inventory states:
enum Feature : int {
  kFeatStage = 0,  // per dataflow process: the pipelined loop's FSM, start/done/continue handshakes
  kFeatMemory,     // per block or UltraRAM memory: address, enable and output-select logic
  kFeatFifo,       // per stream FIFO: full/empty control and the valid/ready handshake
  kFeatInterface,  // per bit of a top-level port adapter (AXI4-Stream, AXI4, AXI4-Lite)
  kFeatPipeline,   // per bit an operator outputs: the pipeline registers between stages of latency
  kFeatDsp,        // per DSP slice: operand alignment and the registers outside the slice
  kFeatFloat,      // per floating-point core (Vitis IP, not mapped here), weighted by kFloatSize
  kFeatureCount
};
const char* feature_name(int f);  // "stage", "memory", ..., "float"

// Estimate flavour: what Vitis HLS C synthesis reports (csynth, like the published rows), or
// after place and route (routed: csynth x the documented per-resource ratios).
enum class Flavour { csynth, routed };
const char* flavour_name(Flavour f);  // "csynth" | "routed"
// Throws std::invalid_argument naming the value unless "csynth" or "routed".
Flavour parse_flavour(const std::string& name);

// Per-operator cost coefficients (models/data/resource_model.yaml).
struct Coefficients {
  // LUT and FF per unit of each overhead feature: the fitted values and the priors the fit is
  // pulled towards where the rows do not pin a feature.
  double lut[kFeatureCount] = {}, ff[kFeatureCount] = {};
  double lut_prior[kFeatureCount] = {}, ff_prior[kFeatureCount] = {};
  // DSP binding (learned from the rows, `parallax fit-resources`): a multiplier goes to DSP48E2
  // slices when its narrower operand has at least dsp_min_bits_var bits (by a variable) or
  // dsp_min_bits_const bits (by a constant); one slice multiplies dsp_a_bits x dsp_b_bits.
  int dsp_min_bits_var = 10, dsp_min_bits_const = 10;
  int dsp_per_fmul = 3, dsp_per_fadd = 2, dsp_per_fexp = 7;  // DSP slices per floating-point core (learned)
  int dsp_a_bits = 27, dsp_b_bits = 18;
  // Routed / csynth per resource, and where the ratios come from.
  double routed_lut_ratio = 1.0, routed_ff_ratio = 1.0, routed_bram_ratio = 1.0, routed_dsp_ratio = 1.0;
  std::string routed_source;
  // Power (estimate): static by device, dynamic per resource per MHz of toggling logic.
  double static_w = 0.0;
  double dynamic_mw_per_mhz_per_klut = 0.0;
  double dynamic_mw_per_mhz_per_kff = 0.0;
  double dynamic_mw_per_mhz_per_bram18k = 0.0;
  double dynamic_mw_per_mhz_per_dsp = 0.0;
  double toggle_rate = 0.125;
  std::string power_source;
  std::string fitted_on;  // what the fitted values were fitted on (provenance)
};
const Coefficients& default_coefficients();  // the compiled-in data file
Coefficients parse_coefficients(const std::string& yaml_text, const std::string& source_name);
std::string coefficients_yaml(const Coefficients& c);  // round trip, used by fit-resources --write

struct Usage {
  int64_t bram18k = 0, uram = 0, lut = 0, ff = 0, dsp = 0;
  int64_t lutram_luts = 0, srl_luts = 0;  // of lut: memories in LUTs
};
// Where a stage's LUT and FF come from (csynth, before any routed ratio): the datapath operators
// (adders, comparators, popcounts, XORs, multipliers in fabric), the muxes and write decoders,
// memories in LUTs or SRLs, the declared registers, and the fitted Vitis overheads.
struct Breakdown {
  double operators = 0, muxes = 0, memories = 0, registers = 0, overhead = 0;
  double total() const { return operators + muxes + memories + registers + overhead; }
  Breakdown& operator+=(const Breakdown& o) {
    operators += o.operators;
    muxes += o.muxes;
    memories += o.memories;
    registers += o.registers;
    overhead += o.overhead;
    return *this;
  }
};
struct StageUsage {
  std::string stage;
  Usage usage;
  Breakdown lut, ff;
};
struct Estimate {
  Flavour flavour = Flavour::csynth;
  Usage total;
  std::vector<StageUsage> stages;
};
Estimate estimate(const Inventory& inv, const Coefficients& c = default_coefficients(),
                  Flavour flavour = Flavour::csynth);

// The parts a csynth estimate is linear in (for fitting):
// LUT = lut_base + sum(lut[i] x lut_f[i]), FF = ff_base + sum(ff[i] x ff_f[i]).
struct Features {
  double lut_f[kFeatureCount] = {}, ff_f[kFeatureCount] = {};
  double lut_base = 0;            // structural: operators, muxes, LUTRAM and SRL LUTs (the operator table)
  double ff_base = 0;             // structural: declared registers, SRL output registers
  Breakdown lut_parts, ff_parts;  // lut_base and ff_base by origin (overhead 0 here)
  int64_t bram18k = 0, uram = 0, dsp = 0;
};
Features features(const Inventory& inv, const Coefficients& c = default_coefficients());
// One priced line of a design: an inventory item (or a stage's own overhead, name "(process)")
// with what it costs under c, csynth; `what` describes it ("add 13b x2", "mux 8b 10:1 x6", ...).
struct PricedItem {
  std::string stage, name, what;
  double lut = 0, ff = 0;
  int64_t dsp = 0, bram18k = 0;
};
std::vector<PricedItem> priced_items(const Inventory& inv, const Coefficients& c = default_coefficients());

// The DSP48 slices one multiplier or floating-point item takes under c's binding rule (0: in
// LUTs); dsp_b_bits: the device's slice B width when not c's (Inventory::dsp_b_bits).
int64_t dsp_for(const OpItem& o, const Coefficients& c, int dsp_b_bits = 0);

struct Utilisation {
  const Device* device = nullptr;
  double bram18k_pct = 0, uram_pct = 0, lut_pct = 0, ff_pct = 0, dsp_pct = 0;
  bool fits = false;
};
Utilisation utilisation(const Usage& u, const Device& d);

struct Power {
  double static_w = 0, dynamic_w = 0, total_w = 0;
  double energy_mj_per_frame = 0;  // total_w x frame interval
};
Power power(const Usage& u, double clock_mhz, double frame_interval_ms, const Coefficients& c = default_coefficients());

}  // namespace parallax::res
