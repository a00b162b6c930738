// Block RAM geometry and the default storage mapping of one on-chip memory.
//
// RAMB18 (Xilinx 7-series and UltraScale+, identical): aspect-ratio modes 16K x 1, 8K x 2,
// 4K x 4, 2K x 9 and 1K x 18 are true dual port; 512 x 36 is simple dual port only (one read
// port and one write port). A RAMB36 counts as two BRAM_18K.
//
// One memory of depth D words and width W bits built from a single aspect-ratio mode (d, w)
// takes ceil(W / w) * ceil(D / d) RAMB18; bram18k_for() returns the minimum over the modes
// the memory may use (not 512 x 36 when it needs true dual port).
//
// map_memory() is the contract for how Vitis HLS implements one memory by default, per copy
// (a partitioned array is several copies; the caller multiplies):
//   1. depth == kRegisterMaxDepth (a completely partitioned element, array or FIFO):
//      registers, ffs = width_bits.
//   2. array with depth * width_bits <= kDistributedMaxBits: LUTRAM, kLutramDepthPerLut x 1
//      bits per LUT6 for simple dual port: luts = width_bits * ceil(depth / 64); twice that
//      when needs_true_dual_port.
//   3. FIFO with depth * width_bits <= kDistributedMaxBits: SRL (shift-register LUTs,
//      kSrlDepthPerLut deep per LUT): luts = width_bits * ceil(depth / 32),
//      ffs = width_bits (output register).
//   4. otherwise: BRAM, bram18k = bram18k_for(depth, width_bits, needs_true_dual_port).
// Every function throws std::invalid_argument, naming the value, when depth < 1 or
// width_bits < 1.
#pragma once

#include <cstdint>
#include <vector>

namespace parallax::res {

struct Ramb18Mode {
  int depth;
  int width_bits;
  bool true_dual_port;
};

// The six RAMB18 modes, deepest first.
const std::vector<Ramb18Mode>& ramb18_modes();

struct BramFit {
  int64_t bram18k = 0;
  int mode_depth = 0;  // the mode that achieves bram18k
  int mode_width_bits = 0;
};

// Smallest BRAM_18K count for one memory of depth words of width_bits bits. Ties go to the
// deeper mode (the first in ramb18_modes()). Throws std::invalid_argument when depth < 1 or
// width_bits < 1, std::overflow_error when the count does not fit in int64_t.
BramFit bram18k_for(int64_t depth, int width_bits, bool needs_true_dual_port);

enum class Storage { registers, lutram, srl, bram };

// "registers", "lutram", "srl", "bram".
const char* storage_name(Storage s);

struct MemoryMapping {
  Storage storage;
  int64_t bram18k = 0;
  int64_t luts = 0;
  int64_t ffs = 0;
};

enum class MemoryKind { array, fifo };

// Thresholds of the default mapping (see the contract above).
inline constexpr int64_t kRegisterMaxDepth = 1;       // depth at or below which: registers
inline constexpr int64_t kDistributedMaxBits = 1024;  // depth * width at or below: LUTRAM / SRL
inline constexpr int64_t kLutramDepthPerLut = 64;     // RAM64X1D-style: 64 x 1 bits per LUT6
inline constexpr int64_t kSrlDepthPerLut = 32;        // SRLC32E: 32 stages per LUT

// How Vitis HLS implements one memory by default (the rules above), per copy.
MemoryMapping map_memory(MemoryKind kind, int64_t depth, int width_bits, bool needs_true_dual_port);

}  // namespace parallax::res
