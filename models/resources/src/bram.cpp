#include "parallax/resources/bram.hpp"

#include <limits>
#include <stdexcept>
#include <string>

namespace parallax::res {
namespace {

void check_shape(const char* fn, int64_t depth, int width_bits) {
  if (depth < 1) throw std::invalid_argument(std::string(fn) + ": depth must be >= 1, got " + std::to_string(depth));
  if (width_bits < 1)
    throw std::invalid_argument(std::string(fn) + ": width_bits must be >= 1, got " + std::to_string(width_bits));
}

int64_t ceil_div(int64_t a, int64_t b) {
  return a / b + (a % b != 0 ? 1 : 0);
}

}  // namespace

const std::vector<Ramb18Mode>& ramb18_modes() {
  static const std::vector<Ramb18Mode> modes = {
      {16384, 1, true}, {8192, 2, true}, {4096, 4, true}, {2048, 9, true}, {1024, 18, true}, {512, 36, false},
  };
  return modes;
}

BramFit bram18k_for(int64_t depth, int width_bits, bool needs_true_dual_port) {
  check_shape("bram18k_for", depth, width_bits);
  BramFit best;
  for (const Ramb18Mode& m : ramb18_modes()) {
    if (needs_true_dual_port && !m.true_dual_port) continue;
    const int64_t columns = ceil_div(width_bits, m.width_bits);
    const int64_t rows = ceil_div(depth, m.depth);
    if (rows > std::numeric_limits<int64_t>::max() / columns) continue;  // would overflow
    const int64_t n = rows * columns;
    if (best.bram18k == 0 || n < best.bram18k) {
      best.bram18k = n;
      best.mode_depth = m.depth;
      best.mode_width_bits = m.width_bits;
    }
  }
  if (best.bram18k == 0)
    throw std::overflow_error("bram18k_for: " + std::to_string(depth) + " x " + std::to_string(width_bits) +
                              " bits needs more RAMB18 than int64_t holds");
  return best;
}

const char* storage_name(Storage s) {
  switch (s) {
    case Storage::registers:
      return "registers";
    case Storage::lutram:
      return "lutram";
    case Storage::srl:
      return "srl";
    case Storage::bram:
      return "bram";
  }
  return "unknown";
}

MemoryMapping map_memory(MemoryKind kind, int64_t depth, int width_bits, bool needs_true_dual_port) {
  check_shape("map_memory", depth, width_bits);
  MemoryMapping m{Storage::registers};
  if (depth <= kRegisterMaxDepth) {
    m.ffs = width_bits;
    return m;
  }
  // depth * width_bits <= kDistributedMaxBits, written so that it cannot overflow.
  const bool small = depth <= kDistributedMaxBits / width_bits;
  if (small && kind == MemoryKind::array) {
    m.storage = Storage::lutram;
    m.luts = int64_t(width_bits) * ceil_div(depth, kLutramDepthPerLut) * (needs_true_dual_port ? 2 : 1);
    return m;
  }
  if (small && kind == MemoryKind::fifo) {
    m.storage = Storage::srl;
    m.luts = int64_t(width_bits) * ceil_div(depth, kSrlDepthPerLut);
    m.ffs = width_bits;
    return m;
  }
  m.storage = Storage::bram;
  m.bram18k = bram18k_for(depth, width_bits, needs_true_dual_port).bram18k;
  return m;
}

}  // namespace parallax::res
