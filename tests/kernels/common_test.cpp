// unit: the kernels' building blocks whose software form differs from what synthesis sees
// (kernels/common.hpp): the popcount adder tree against the CPU's count, the shift register's
// ring (software) against its registers (the exported, FIXED form), over seeded random use, and
// the aggregation's lane minimum, taken off the M recurrence in the FIXED form and directly in
// software (sgm.hpp), over whole frames of random costs at the widths' limits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <random>

#include <vector>

#include "parallax/kernels/common.hpp"
#include "parallax/kernels/shift_reg.hpp"
#include "parallax/kernels/row_reverse.hpp"
#include "parallax/kernels/sgm.hpp"

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

template <class T>
struct VecIn {
  const T* p;
  T read() { return *p++; }
};
template <class T>
struct VecOut {
  std::vector<T>* v;
  void write(const T& t) { v->push_back(t); }
};

// The sums of the FIXED instantiation (D = MAX_D, PU = LANES) and of the software one (run-time
// D and PU) on the same frame of seeded random costs in [0, cost_max].
template <int D, int PU, class Word>
void expect_same_sums(StereoParams p, unsigned kinds, uint32_t seed) {
  typedef Caps<32, D, PU, 9, 7, 0xFu, true> Fixed;
  typedef Caps<32, 256, 64, 9, 7, 0xFu, false> Soft;
  static_assert(PU <= 64, "within the software lanes");
  p.disparities = D;
  p.parallel_units = PU;
  const int chunks = D / PU;
  std::mt19937 rng(seed);
  const uint32_t cmax = cost_max(p);
  std::vector<CostLanes<PU>> fixed_in(std::size_t(p.width_px) * p.height_px * chunks);
  std::vector<CostLanes<64>> soft_in(fixed_in.size());
  for (std::size_t t = 0; t < fixed_in.size(); ++t)
    for (int i = 0; i < PU; ++i) {
      // Mostly high costs, so path costs reach the top of their range.
      const uint32_t c = rng() % 4 == 0 ? uint32_t(rng() % (cmax + 1)) : cmax - uint32_t(rng() % 3);
      fixed_in[t].v[i] = soft_in[t].v[i] = uint16_t(c);
      // The pixel's intensity (every token of a pixel carries the same; adaptive P2 reads it).
      fixed_in[t].px = soft_in[t].px = uint8_t((t / std::size_t(chunks)) * 2654435761u >> 13);
    }
  auto fixed = std::make_unique<SgmAggregate<Fixed, Word>>();
  auto soft = std::make_unique<SgmAggregate<Soft, Word>>();
  fixed->configure(p, kinds, false, false);
  soft->configure(p, kinds, false, false);
  std::vector<Lanes<Word, PU>> fixed_out;
  std::vector<Lanes<Word, 64>> soft_out;
  VecIn<CostLanes<PU>> fi{fixed_in.data()};
  VecIn<CostLanes<64>> si{soft_in.data()};
  VecOut<Lanes<Word, PU>> fo{&fixed_out};
  VecOut<Lanes<Word, 64>> so{&soft_out};
  NoStream<Lanes<Word, PU>> fnf;
  NoStream<CostLanes<PU>> fnt;
  NoStream<Lanes<Word, 64>> snf;
  NoStream<CostLanes<64>> snt;
  while (!fixed->done()) fixed->fire(fixed->plan(), fi, fnf, fo, fnt);
  while (!soft->done()) soft->fire(soft->plan(), si, snf, so, snt);
  ASSERT_EQ(fixed_out.size(), fixed_in.size());
  ASSERT_EQ(soft_out.size(), fixed_in.size());
  Word top = 0;
  for (std::size_t t = 0; t < fixed_out.size(); ++t)
    for (int i = 0; i < PU; ++i) {
      ASSERT_EQ(fixed_out[t].v[i], soft_out[t].v[i]) << "token " << t << " lane " << i << " path bits " << path_bits(p);
      top = fixed_out[t].v[i] > top ? fixed_out[t].v[i] : top;
    }
  // The costs reached the top of their range (the saturation cases were exercised).
  EXPECT_GE(uint64_t(top), uint64_t(cmax) - 2);
}

TEST(SgmAggregate, LaneMinimumOffTheRecurrenceEqualsTheDirectOne) {
  StereoParams p{24, 9, kCostCensus, 9, 7, 0, 0, kForwardPaths, 7, 100, true, 1, 0, 0, 0};
  // Four paths, Census 9x7 (cost 6 bits), 16-bit words; one chunk and several.
  expect_same_sums<64, 64, uint16_t>(p, 0xFu, 1);
  expect_same_sums<64, 8, uint16_t>(p, 0xFu, 2);
  expect_same_sums<48, 16, uint16_t>(p, 0xFu, 3);
  // One path whose path cost needs all 16 bits (SAD 9x9, P2 30000): the widest Lr a 16-bit word
  // carries, where C + t (up to 20655 + 53422) leaves the word.
  StereoParams sad = p;
  sad.cost = kCostSad;
  sad.window_w = sad.window_h = 9;
  sad.p1 = 500;
  sad.p2 = 30000;
  sad.path_mask = kPath0;
  ASSERT_EQ(path_bits(sad), 16);
  expect_same_sums<32, 16, uint16_t>(sad, 1u << kKindPixel, 4);
  sad.path_mask = kPath90;
  expect_same_sums<32, 32, uint16_t>(sad, 1u << kKindRowUp, 5);
  // 32-bit words: two paths of the same SAD.
  sad.path_mask = kPath0 | kPath45;
  expect_same_sums<32, 8, uint32_t>(sad, (1u << kKindPixel) | (1u << kKindRowLeft), 6);
  // Adaptive P2 (a per-pixel, per-kind P2 in both lane-minimum forms), four kinds.
  p.p2_adaptive = 40;
  expect_same_sums<64, 8, uint16_t>(p, 0xFu, 7);
  expect_same_sums<48, 48, uint16_t>(p, 0xFu, 8);
}

// The row reversal's memory carries no dependence between firings (its DEPENDENCE inter false,
// row_reverse.hpp): walking the control's firings over whole frames, every memory slot a firing
// reads was written at least 3C firings before (C = tokens per pixel), the bypassed last pixel
// never touches the memory, and every token comes out in reversed pixel order, chunks ascending.
TEST(RowReverse, MemorySlotsComeBackAtLeastThreeTokensPerPixelLater) {
  for (int w : {1, 2, 3, 7, 16})
    for (int c : {1, 2, 5}) {
      const int h = 4;
      RowReverseControl ctl;
      ctl.configure(w, h, c);
      std::vector<int64_t> written(std::size_t(w) * std::size_t(c), -1);  // firing that wrote slot
      std::vector<std::pair<int, int>> in_tokens, out_tokens;             // (row, x * c + chunk)
      int64_t firing = 0, min_gap = INT64_MAX;
      int in_row = 0, in_tok = 0, out_row = 0, out_tok = 0;
      while (!ctl.done()) {
        const RowReversePlan pl = ctl.plan();
        ASSERT_TRUE(pl.read || pl.write) << "stuck at firing " << firing;
        if (pl.write) {
          const int x = w - 1 - out_tok / c;  // stream position j is image column W - 1 - j
          out_tokens.emplace_back(out_row, x * c + ctl.out_chunk());
          if (!ctl.out_first()) {
            const std::size_t a = std::size_t(ctl.out_slot()) * std::size_t(c) + std::size_t(ctl.out_chunk());
            ASSERT_GE(written[a], 0) << "read before any write";
            min_gap = std::min(min_gap, firing - written[a]);
          } else {
            EXPECT_EQ(x, w - 1);
          }
          if (++out_tok == w * c) out_tok = 0, ++out_row;
        }
        if (pl.read) {
          in_tokens.emplace_back(in_row, in_tok);
          if (!ctl.in_last())
            written[std::size_t(ctl.in_slot()) * std::size_t(c) + std::size_t(ctl.in_chunk())] = firing;
          else
            EXPECT_EQ(in_tok / c, w - 1);
          if (++in_tok == w * c) in_tok = 0, ++in_row;
        }
        ctl.advance(pl);
        ++firing;
      }
      EXPECT_EQ(firing, int64_t(h + 1) * w * c);
      if (w > 1) {
        EXPECT_GE(min_gap, 3 * c) << "W " << w << " C " << c;
      }
      ASSERT_EQ(out_tokens.size(), in_tokens.size());
      for (std::size_t i = 0; i < out_tokens.size(); ++i) {  // each row's pixels reversed
        const int row = int(i) / (w * c), t = int(i) % (w * c);
        EXPECT_EQ(out_tokens[i], std::make_pair(row, (w - 1 - t / c) * c + t % c)) << "W " << w << " C " << c;
      }
    }
}

}  // namespace
}  // namespace parallax::kern
