// The resource model: a design's inventory (what its kernels declare, plus the FIFOs between
// them) mapped to BRAM_18K, LUT, FF and DSP with per-operator costs whose coefficients are data
// (models/data/resource_model.yaml, fitted by `parallax fit-resources`), and a power estimate.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "parallax/config/config.hpp"
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
  MemoryMapping per_copy;  // the default storage of one copy
};
struct OpItem {
  std::string stage, name;
  kern::OpKind kind = kern::kOpAdd;
  int width_bits = 0;  // multipliers: the wider operand
  int b_bits = 0;      // multipliers: the narrower operand
  int64_t count = 0;
};
struct RegisterItem {
  std::string stage, name;
  int width_bits = 0;
  int64_t count = 0;
};

struct Inventory {
  std::vector<std::string> stages;  // in pipeline order
  std::vector<MemoryItem> memories;
  std::vector<OpItem> ops;
  std::vector<RegisterItem> registers;
};

// The sink the kernels' declare() methods call (kern::resources.hpp), for one stage.
class Collector {
 public:
  Collector(Inventory& inv, std::string stage);
  void memory(const char* name, int64_t depth, int width_bits, int copies, bool true_dual_port);
  void registers(const char* name, int width_bits, int count);
  void op(const char* name, kern::OpKind kind, int width_bits, int count);
  void mul(const char* name, int a_bits, int b_bits, int count);

 private:
  Inventory& inv_;
  std::string stage_;
};

// A whole design: its stages as the kernels declare them for the configuration at its ROI size,
// and its FIFOs (named as in the cycle model, with the configured depths).
Inventory design_inventory(const config::PipelineConfig& cfg, int width_px, int height_px);
// Single stages, for the published points of stand-alone vendor kernels.
Inventory median_inventory(int width_px, int height_px, int k, int value_bits);
Inventory rectify_inventory(int width_px, int height_px, int mode, int frac_bits, int buffer_rows);

// Per-operator cost coefficients (models/data/resource_model.yaml). Structural costs per bit
// are fixed by the operator's shape; the fitted ones scale and add overheads.
struct Coefficients {
  double lut_per_bit[kern::kOpKindCount] = {};  // structural LUTs per result bit (mul: per a*b bit pair)
  int dsp_min_operand_bits = 10;                // multipliers with both operands wider go to DSP48E2
  int dsp_a_bits = 27, dsp_b_bits = 18;         // one DSP48E2 multiplies 27 x 18
  // Fitted:
  double lut_scale = 1.0;       // x structural LUTs of the operators
  double lut_per_stage = 0.0;   // control, handshakes, FSM per stage
  double lut_per_memory = 0.0;  // address and enable logic per memory (copy)
  double ff_per_op_bit = 0.0;   // pipeline registers per operator result bit
  double ff_per_stage = 0.0;
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
std::string coefficients_yaml(const Coefficients& c);  // round trip, used by fit-resources

struct Usage {
  int64_t bram18k = 0, uram = 0, lut = 0, ff = 0, dsp = 0;
  int64_t lutram_luts = 0, srl_luts = 0;  // of lut: memories in LUTs
};
struct StageUsage {
  std::string stage;
  Usage usage;
};
struct Estimate {
  Usage total;
  std::vector<StageUsage> stages;
};
Estimate estimate(const Inventory& inv, const Coefficients& c = default_coefficients());

// The structural parts an estimate is linear in (for fitting): estimate = base + sum(k_i x f_i).
struct Features {
  double op_luts = 0;      // structural LUTs of the operators in LUTs (not DSP)
  double memory_luts = 0;  // LUTRAM + SRL LUTs
  double stages = 0;
  double memories = 0;       // memory copies
  double register_bits = 0;  // declared registers and SRL output registers
  double op_bits = 0;        // result bits of the operators
  int64_t bram18k = 0, dsp = 0;
};
Features features(const Inventory& inv, const Coefficients& c = default_coefficients());

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
