// unit: RAMB18 geometry (bram18k_for against a brute force over a boundary table) and the
// default storage mapping of memories (map_memory at each threshold).
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "parallax/resources/bram.hpp"

namespace parallax::res {
namespace {

// The RAMB18 aspect ratios written out again here (not taken from the library): words, bits,
// true dual port.
struct Shape {
  int64_t words;
  int64_t bits;
  bool tdp;
};
const Shape kShapes[] = {{16384, 1, true}, {8192, 2, true},  {4096, 4, true},
                         {2048, 9, true},  {1024, 18, true}, {512, 36, false}};

// Brute force: for each shape, tile the memory by laying down RAMB18s one at a time, a column
// of blocks (filling words) for every slice of the width (filling bits), with no division;
// keep the smallest count over the allowed shapes.
int64_t brute_force(int64_t depth, int64_t width, bool tdp) {
  int64_t best = -1;
  for (const Shape& s : kShapes) {
    if (tdp && !s.tdp) continue;
    int64_t blocks = 0;
    for (int64_t bits_done = 0; bits_done < width; bits_done += s.bits)
      for (int64_t words_done = 0; words_done < depth; words_done += s.words) ++blocks;
    if (best < 0 || blocks < best) best = blocks;
  }
  return best;
}

TEST(Bram, ModesAreTheSixRamb18AspectRatios) {
  const auto& modes = ramb18_modes();
  ASSERT_EQ(modes.size(), 6u);
  for (std::size_t i = 0; i < modes.size(); ++i) {
    EXPECT_EQ(modes[i].depth, kShapes[i].words);
    EXPECT_EQ(modes[i].width_bits, kShapes[i].bits);
    EXPECT_EQ(modes[i].true_dual_port, kShapes[i].tdp);
  }
}

TEST(Bram, MatchesBruteForceOnEveryModeBoundary) {
  const std::vector<int64_t> depths = {1,     2,     511,   512,   513,  1023, 1024, 1025, 2047,
                                       2048,  2049,  4095,  4096,  4097, 8191, 8192, 8193, 16383,
                                       16384, 16385, 20000, 65536, 640,  1920, 1280};
  int checked = 0;
  for (const bool tdp : {false, true})
    for (const int64_t d : depths)
      for (int w = 1; w <= 72; ++w) {
        const BramFit fit = bram18k_for(d, w, tdp);
        const std::string what = std::to_string(d) + " x " + std::to_string(w) + (tdp ? " TDP" : " SDP");
        ASSERT_EQ(fit.bram18k, brute_force(d, w, tdp)) << what;
        // The reported mode exists, is allowed, and achieves the count.
        bool allowed = false;
        for (const Shape& s : kShapes)
          if (s.words == fit.mode_depth && s.bits == fit.mode_width_bits) allowed = !tdp || s.tdp;
        EXPECT_TRUE(allowed) << what << ": mode " << fit.mode_depth << " x " << fit.mode_width_bits;
        const int64_t cols = (w + fit.mode_width_bits - 1) / fit.mode_width_bits;
        const int64_t rows = (d + fit.mode_depth - 1) / fit.mode_depth;
        EXPECT_EQ(cols * rows, fit.bram18k) << what;
        // Never fewer blocks than the bits demand (a RAMB18 holds at most 2048 x 9 bits).
        EXPECT_GE(fit.bram18k * 18432, d * w) << what;
        ++checked;
      }
  EXPECT_EQ(checked, 2 * 25 * 72);
}

TEST(Bram, HandCheckedRows) {
  // 1920 x 8: one 2K x 9 (16K x 1 would need 8, 8K x 2 four, 4K x 4 two).
  EXPECT_EQ(bram18k_for(1920, 8, false).bram18k, 1);
  EXPECT_EQ(bram18k_for(1920, 8, false).mode_depth, 2048);
  EXPECT_EQ(bram18k_for(1920, 8, false).mode_width_bits, 9);
  // 2048 x 9 fills one 2K x 9 exactly.
  EXPECT_EQ(bram18k_for(2048, 9, false).bram18k, 1);
  // 2049 x 9: one word too many; 2K x 9 needs 2 deep, 1K x 18 needs 3, 4K x 4 needs 3 wide.
  EXPECT_EQ(bram18k_for(2049, 9, false).bram18k, 2);
  // 640 x 36 true dual port: no 512 x 36, so two 1K x 18 side by side.
  EXPECT_EQ(bram18k_for(640, 36, true).bram18k, 2);
  // 512 x 36 simple dual port: exactly one 512 x 36.
  EXPECT_EQ(bram18k_for(512, 36, false).bram18k, 1);
  EXPECT_EQ(bram18k_for(512, 36, false).mode_width_bits, 36);
  // 512 x 36 true dual port: two 1K x 18 (half of each unused).
  EXPECT_EQ(bram18k_for(512, 36, true).bram18k, 2);
  // 1920 x 16: two 2K x 9 side by side, or two 1K x 18 stacked (1920 > 1024 words).
  EXPECT_EQ(bram18k_for(1920, 16, false).bram18k, 2);
  // 16384 x 1: one 16K x 1.
  EXPECT_EQ(bram18k_for(16384, 1, false).bram18k, 1);
  EXPECT_EQ(bram18k_for(16384, 1, true).bram18k, 1);
  // 640 x 6: one 1K x 18 (or 2K x 9), mostly empty.
  EXPECT_EQ(bram18k_for(640, 6, false).bram18k, 1);
  // 64 x 1: still one whole block.
  EXPECT_EQ(bram18k_for(64, 1, false).bram18k, 1);
}

TEST(Bram, InvalidShapesThrowNamingTheValue) {
  for (const int64_t d : {int64_t(0), int64_t(-7)}) {
    try {
      bram18k_for(d, 8, false);
      ADD_FAILURE() << "depth " << d << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("depth"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(std::to_string(d)), std::string::npos) << e.what();
    }
  }
  for (const int w : {0, -3}) {
    try {
      bram18k_for(100, w, true);
      ADD_FAILURE() << "width " << w << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("width_bits"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(std::to_string(w)), std::string::npos) << e.what();
    }
  }
}

TEST(Storage, Names) {
  EXPECT_STREQ(storage_name(Storage::registers), "registers");
  EXPECT_STREQ(storage_name(Storage::lutram), "lutram");
  EXPECT_STREQ(storage_name(Storage::srl), "srl");
  EXPECT_STREQ(storage_name(Storage::bram), "bram");
}

TEST(MapMemory, DepthOneIsRegisters) {
  for (const MemoryKind k : {MemoryKind::array, MemoryKind::fifo})
    for (const int w : {1, 36, 2000}) {
      const MemoryMapping m = map_memory(k, 1, w, true);
      EXPECT_EQ(m.storage, Storage::registers);
      EXPECT_EQ(m.ffs, w);
      EXPECT_EQ(m.luts, 0);
      EXPECT_EQ(m.bram18k, 0);
    }
}

TEST(MapMemory, ArrayLutramUpTo1024BitsThenBram) {
  ASSERT_EQ(kDistributedMaxBits, 1024);
  // 64 x 16 = 1024 bits: LUTRAM, 16 LUTs (one 64 x 1 per bit), 32 when true dual port.
  MemoryMapping m = map_memory(MemoryKind::array, 64, 16, false);
  EXPECT_EQ(m.storage, Storage::lutram);
  EXPECT_EQ(m.luts, 16);
  EXPECT_EQ(m.ffs, 0);
  EXPECT_EQ(m.bram18k, 0);
  EXPECT_EQ(map_memory(MemoryKind::array, 64, 16, true).luts, 32);
  // 128 x 8 = 1024 bits: 8 bits x 2 LUTs deep.
  m = map_memory(MemoryKind::array, 128, 8, false);
  EXPECT_EQ(m.storage, Storage::lutram);
  EXPECT_EQ(m.luts, 16);
  // 65 x 1: depth rounds up to two 64-deep LUTs.
  EXPECT_EQ(map_memory(MemoryKind::array, 65, 1, false).luts, 2);
  // 1025 x 1 = 1025 bits: one bit beyond, BRAM.
  m = map_memory(MemoryKind::array, 1025, 1, false);
  EXPECT_EQ(m.storage, Storage::bram);
  EXPECT_EQ(m.bram18k, 1);
  EXPECT_EQ(m.luts, 0);
  // 1024 x 1 = 1024 bits: still LUTRAM (16 LUTs).
  m = map_memory(MemoryKind::array, 1024, 1, false);
  EXPECT_EQ(m.storage, Storage::lutram);
  EXPECT_EQ(m.luts, 16);
  // 2048 x 1 = 2048 bits: BRAM, one block.
  m = map_memory(MemoryKind::array, 2048, 1, false);
  EXPECT_EQ(m.storage, Storage::bram);
  EXPECT_EQ(m.bram18k, 1);
  // 512 x 36: BRAM, 1 simple dual port, 2 true dual port.
  EXPECT_EQ(map_memory(MemoryKind::array, 512, 36, false).bram18k, 1);
  EXPECT_EQ(map_memory(MemoryKind::array, 512, 36, true).bram18k, 2);
}

TEST(MapMemory, FifoSrlUpTo1024BitsThenBram) {
  // Depth 2 x 16 bits: SRL, 16 LUTs and a 16-bit output register.
  MemoryMapping m = map_memory(MemoryKind::fifo, 2, 16, false);
  EXPECT_EQ(m.storage, Storage::srl);
  EXPECT_EQ(m.luts, 16);
  EXPECT_EQ(m.ffs, 16);
  EXPECT_EQ(m.bram18k, 0);
  // 32 x 32 = 1024 bits: SRL, one 32-deep LUT per bit.
  m = map_memory(MemoryKind::fifo, 32, 32, false);
  EXPECT_EQ(m.storage, Storage::srl);
  EXPECT_EQ(m.luts, 32);
  EXPECT_EQ(m.ffs, 32);
  // 33 x 31 = 1023 bits: SRL, depth rounds up to two LUTs per bit.
  m = map_memory(MemoryKind::fifo, 33, 31, false);
  EXPECT_EQ(m.storage, Storage::srl);
  EXPECT_EQ(m.luts, 62);
  // 1024 x 1: SRL, 32 LUTs; 1025 x 1: BRAM.
  EXPECT_EQ(map_memory(MemoryKind::fifo, 1024, 1, false).luts, 32);
  m = map_memory(MemoryKind::fifo, 1025, 1, false);
  EXPECT_EQ(m.storage, Storage::bram);
  EXPECT_EQ(m.bram18k, 1);
  EXPECT_EQ(m.luts, 0);
  EXPECT_EQ(m.ffs, 0);
  // 33 x 32 = 1056 bits: BRAM.
  EXPECT_EQ(map_memory(MemoryKind::fifo, 33, 32, false).storage, Storage::bram);
}

TEST(MapMemory, InvalidArgumentsThrowNamingTheValue) {
  try {
    map_memory(MemoryKind::array, 0, 8, false);
    ADD_FAILURE() << "depth 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("depth must be >= 1, got 0"), std::string::npos) << e.what();
  }
  try {
    map_memory(MemoryKind::fifo, 16, -5, false);
    ADD_FAILURE() << "width -5 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("width_bits must be >= 1, got -5"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace parallax::res
