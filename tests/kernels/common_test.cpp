// unit: the kernels' building blocks whose software form differs from what synthesis sees
// (kernels/common.hpp): the popcount adder tree against the CPU's count, and the shift register's
// ring (software) against its registers (the exported, FIXED form), over seeded random use.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>

#include "parallax/kernels/common.hpp"

namespace parallax::kern {
namespace {

TEST(PopcountTree, AdderTreeEqualsTheCpuCountOnEveryWidth) {
  std::mt19937_64 rng(14);
  for (int i = 0; i < 100000; ++i) {
    const uint64_t v = rng();
    ASSERT_EQ(popcount_adder_tree<64>(v), __builtin_popcountll(v)) << std::hex << v;
    ASSERT_EQ(popcount_adder_tree<24>(v), __builtin_popcountll(v & 0xFFFFFFull)) << std::hex << v;
    ASSERT_EQ(popcount_tree<24>(v), popcount_adder_tree<24>(v)) << std::hex << v;
    ASSERT_EQ(popcount_tree<62>(v), popcount_adder_tree<62>(v)) << std::hex << v;
  }
  EXPECT_EQ(popcount_adder_tree<64>(~uint64_t(0)), 64);
  EXPECT_EQ(popcount_adder_tree<1>(3u), 1);
}

// Every entry < n of the two forms is equal after any sequence of shifts in both directions
// and writes, for several n within N.
TEST(ShiftReg, RingEqualsRegisters) {
  std::mt19937 rng(1414);
  for (int n : {1, 2, 7, 60, 64}) {
    ShiftReg<uint32_t, 64, true> regs;
    ShiftReg<uint32_t, 64, false> ring;
    for (int k = 0; k < n; ++k) {
      regs.set(k, uint32_t(k));
      ring.set(k, uint32_t(k));
    }
    for (int step = 0; step < 5000; ++step) {
      const uint32_t x = uint32_t(rng());
      switch (rng() % 3) {
        case 0:
          regs.shift_in(x, n);
          ring.shift_in(x, n);
          break;
        case 1:
          regs.shift_back(x, n);
          ring.shift_back(x, n);
          break;
        default: {
          const int k = int(rng() % uint32_t(n));
          regs.set(k, x);
          ring.set(k, x);
        }
      }
      for (int k = 0; k < n; ++k) ASSERT_EQ(regs.at(k), ring.at(k)) << "n " << n << " step " << step << " entry " << k;
    }
  }
}

}  // namespace
}  // namespace parallax::kern
