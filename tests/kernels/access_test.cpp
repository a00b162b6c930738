// The access count of the kernels' arrays (kernels/access.hpp, issue 41): it observes what the
// code indexes. A memory indexed by a run-time counter is flagged and charged on every bank it
// reaches; the same memory indexed by the unrolled lane alone is not.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "parallax/kernels/access.hpp"
#include "parallax/kernels/caps.hpp"

namespace parallax::kern {
namespace {

// A toy stage shaped like the SGM rows: D = 12 values per column, PU = 4 lanes per firing,
// C = 3 chunks. Layout: cyclic by PU over the disparities, so lane i of every chunk is bank i
// only when the chunk's base is a multiple of PU, which the scheduler cannot see when the base
// is a run-time counter.
template <bool COUNT>
class ToyStage {
 public:
  static constexpr int kD = 12, kPU = 4, kW = 8;
  typedef Caps<kW, kD, kPU, 1, 1, 0xFu, true, 0, COUNT> C;
  ToyStage() {
    PX_PARTITION_CYCLIC(rows_, kPU, 2)
    PX_BIND_RAM_S2P(rows_, bram)
    PX_PARTITION_COMPLETE(regs_, 1)
    PX_PARTITION_CYCLIC(words_, 1, 1)
    PX_BIND_RAM_S2P(words_, bram)
    PX_RESHAPE_COMPLETE(lanes_, 2)
    PX_BIND_RAM_S2P(lanes_, bram)
  }
  // One firing: PU lanes of chunk c of column x, the row memory indexed by the run-time base.
  void fire_runtime_banked(int x, int c) {
    const int lo = c * kPU;
  toy_lanes:
    for (int i = 0; i < kPU; ++i) {
      const uint16_t v = rows_[x][lo + i];
      rows_[x][lo + i] = uint16_t(v + 1);
      regs_[lo + i] = v;  // a register file indexed by the counter: a mux per lane
    }
  }
  // The same data as one word per chunk: one read and one write of one memory per firing.
  void fire_word(int x, int c) {
    const uint64_t w = words_[x * 3 + c];
    words_[x * 3 + c] = w + 1;
  toy_lanes_fixed:
    for (int i = 0; i < kPU; ++i) regs_[i] = uint16_t(w >> (16 * i));
  }
  // The same as PU lanes reshaped into one word per chunk: the lanes' accesses at one address
  // are one access of the word.
  void fire_reshaped(int x, int c) {
  toy_lanes_reshaped:
    for (int i = 0; i < kPU; ++i) {
      const uint16_t v = lanes_[x * 3 + c][i];
      lanes_[x * 3 + c][i] = uint16_t(v + 1);
    }
  }
  // A reshaped memory whose lanes address different words (lane i reads word i): one access per lane.
  void fire_reshaped_scattered(int x, int c) {
  toy_lanes_scattered:
    for (int i = 0; i < kPU; ++i) regs_[i] = lanes_[(x * 3 + c + i) % (kW * 3)][0];
  }
  typename C::template array<uint16_t, kW, kD> rows_{};
  typename C::template array<uint16_t, kD> regs_{};
  typename C::template array<uint64_t, kW * 3> words_{};
  typename C::template array<uint16_t, kW * 3, kPU> lanes_{};
};

// The report of firing `fire` at every chunk of every column of a counted toy stage; `layout`
// may restate a layout first.
template <class Fire, class Layout>
std::vector<MemoryAccesses> count_toy(Fire fire, Layout layout) {
  AccessRegistry::get().reset();
  {
    ToyStage<true> s;
    layout(s);
    for (int x = 0; x < ToyStage<true>::kW; ++x)
      for (int c = 0; c < 3; ++c) {
        AccessFiring f("toy");
        fire(s, x, c);
      }
  }
  return AccessRegistry::get().report();
}
template <class Fire>
std::vector<MemoryAccesses> count_toy(Fire fire) {
  return count_toy(fire, [](ToyStage<true>&) {});
}

const MemoryAccesses* find(const std::vector<MemoryAccesses>& r, const std::string& name) {
  for (const MemoryAccesses& m : r)
    if (m.name == name) return &m;
  return nullptr;
}

TEST(AccessCount, RuntimeIndexedMemoryIsFlaggedAndChargedOnEveryBankItReaches) {
  const std::vector<MemoryAccesses> r = count_toy([](ToyStage<true>& s, int x, int c) { s.fire_runtime_banked(x, c); });
  const MemoryAccesses* rows = find(r, "rows_");
  ASSERT_NE(rows, nullptr);
  EXPECT_EQ(rows->stage, "toy");
  EXPECT_EQ(rows->kind, "ram_s2p");
  EXPECT_EQ(rows->banks, 4);
  EXPECT_EQ(rows->firings, 24);
  // Lane i reaches banks (4c + i) mod 4 = i only: the cyclic factor equals PU, so the run-time
  // base never changes the bank. One read and one write per bank: no banking at run time.
  EXPECT_EQ(rows->runtime_banked_sites, 0);
  EXPECT_EQ(rows->max_reads_per_bank_per_firing, 1);
  EXPECT_EQ(rows->max_writes_per_bank_per_firing, 1);
  EXPECT_EQ(rows->ii_forced, 1);
  // The register file is banked per element: lane i reaches i, 4 + i, 8 + i, a 3:1 demux each.
  const MemoryAccesses* regs = find(r, "regs_");
  ASSERT_NE(regs, nullptr);
  EXPECT_EQ(regs->kind, "registers");
  EXPECT_EQ(regs->banks, 12);
  EXPECT_EQ(regs->runtime_banked_sites, 4);
  EXPECT_EQ(regs->max_banks_per_site, 3);
  EXPECT_EQ(regs->ii_forced, 1);
}

TEST(AccessCount, ABankingThatTheBaseMovesCostsEveryLaneOnEveryBank) {
  // The same code with the rows partitioned cyclic 3 (not a divisor pattern of PU = 4): lane i
  // of chunk c lands in bank (4c + i) mod 3, so every lane reaches all three banks and each bank
  // is charged with all four lanes' reads and writes: II 4 on a one-read, one-write port.
  const std::vector<MemoryAccesses> r =
      count_toy([](ToyStage<true>& s, int x, int c) { s.fire_runtime_banked(x, c); },
                [](ToyStage<true>& s) { access_partition(s.rows_, "rows_", kPartitionCyclic, 3, 2); });
  const MemoryAccesses* rows = find(r, "rows_");
  ASSERT_NE(rows, nullptr);
  EXPECT_EQ(rows->banks, 3);
  EXPECT_EQ(rows->runtime_banked_sites, 8);  // 4 lanes x (read, write)
  EXPECT_EQ(rows->max_banks_per_site, 3);
  EXPECT_EQ(rows->max_reads_per_bank_per_firing, 4);
  EXPECT_EQ(rows->max_writes_per_bank_per_firing, 4);
  EXPECT_EQ(rows->ii_forced, 4);
  EXPECT_FALSE(rows->runtime_sites.empty());
  EXPECT_NE(rows->runtime_sites[0].find("access_test.cpp:"), std::string::npos) << rows->runtime_sites[0];
}

TEST(AccessCount, OneWordPerChunkIsOneReadAndOneWriteAndFixedRegisters) {
  const std::vector<MemoryAccesses> r = count_toy([](ToyStage<true>& s, int x, int c) { s.fire_word(x, c); });
  const MemoryAccesses* words = find(r, "words_");
  ASSERT_NE(words, nullptr);
  EXPECT_EQ(words->banks, 1);
  EXPECT_EQ(words->max_reads_per_bank_per_firing, 1);
  EXPECT_EQ(words->max_writes_per_bank_per_firing, 1);
  EXPECT_EQ(words->runtime_banked_sites, 0);
  EXPECT_EQ(words->ii_forced, 1);
  const MemoryAccesses* regs = find(r, "regs_");
  ASSERT_NE(regs, nullptr);
  EXPECT_EQ(regs->runtime_banked_sites, 0);
  EXPECT_EQ(regs->max_banks_per_site, 1);
}

TEST(AccessCount, ReshapedLanesAtOneAddressAreOneAccessOfTheWord) {
  const std::vector<MemoryAccesses> r = count_toy([](ToyStage<true>& s, int x, int c) { s.fire_reshaped(x, c); });
  const MemoryAccesses* lanes = find(r, "lanes_");
  ASSERT_NE(lanes, nullptr);
  EXPECT_EQ(lanes->banks, 1);
  EXPECT_EQ(lanes->max_reads_per_bank_per_firing, 1);
  EXPECT_EQ(lanes->max_writes_per_bank_per_firing, 1);
  EXPECT_EQ(lanes->ii_forced, 1);
  // Lanes that address different words of the reshaped memory are accesses of their own.
  const std::vector<MemoryAccesses> scattered =
      count_toy([](ToyStage<true>& s, int x, int c) { s.fire_reshaped_scattered(x, c); });
  const MemoryAccesses* sc = find(scattered, "lanes_");
  ASSERT_NE(sc, nullptr);
  EXPECT_EQ(sc->max_reads_per_bank_per_firing, 4);
  EXPECT_EQ(sc->ii_forced, 4);
}

TEST(AccessCount, AccessesOutsideAFiringAndPortsOfEachBinding) {
  AccessRegistry::get().reset();
  {
    ToyStage<true> s;
    s.fire_runtime_banked(0, 1);  // no firing: set-up code, not counted
  }
  EXPECT_TRUE(AccessRegistry::get().report().empty());
  EXPECT_EQ(access_ii_forced(kStorageRamS2p, 2, 1), 2);
  EXPECT_EQ(access_ii_forced(kStorageRamT2p, 2, 1), 2);
  EXPECT_EQ(access_ii_forced(kStorageRamT2p, 1, 1), 1);
  EXPECT_EQ(access_ii_forced(kStorageRam1p, 1, 1), 2);
  EXPECT_EQ(access_ii_forced(kStorageRam2p, 1, 1), 1);
  EXPECT_EQ(access_ii_forced(kStorageRam2p, 0, 2), 2);
  EXPECT_EQ(access_ii_forced(kStorageRegisters, 9, 9), 1);
}

TEST(AccessCount, PlainInstantiationsAreRawArrays) {
  ToyStage<false> s;
  static_assert(sizeof(s.rows_) == sizeof(uint16_t) * 8 * 12, "a raw array");
  s.fire_runtime_banked(1, 2);
  EXPECT_EQ(s.regs_[8], 0);
}

}  // namespace
}  // namespace parallax::kern
