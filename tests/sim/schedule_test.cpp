// unit: each stage's II derived from its kernel's counted memory accesses and declared recurrences
// (sim/schedule.hpp): known cases, mutations that must raise it, and the cycle model using it.
#include <gtest/gtest.h>

#include <string>

#include "parallax/kernels/access.hpp"
#include "parallax/sim/cycle.hpp"
#include "parallax/sim/schedule.hpp"

namespace parallax::sim {
namespace {

kern::StereoParams seed() {
  kern::StereoParams p{640, 360, kern::kCostCensus, 5, 5, 60, 6, kern::kForwardPaths, 8, 32, true, 1, 5, 0, 0};
  return p;
}

const kern::RectifyParams kNoRectify{640, 360, kern::kRectifyNone, 0, 1};

StageSchedule stage(const kern::StereoParams& p, double mhz, const std::string& name) {
  for (const auto& s : stage_schedules(p, kNoRectify, mhz * 1e6))
    if (s.stage == name) return s;
  ADD_FAILURE() << "no stage " << name;
  return {};
}

TEST(DerivedII, SeedDesignAt200MHz) {
  // The pixel path's minimum recurs from one firing to the next: a subtraction and two
  // compare-selects into a register, 4.08 ns (-1 speed grade) against 3.65 ns of a 5 ns cycle:
  // II = 2. Its previous-pixel register file is read at fixed entries (pix_read), so the
  // register-file chain keeps the kernel's distance of C - 1 firings.
  const StageSchedule agg = stage(seed(), 200, "aggregate");
  EXPECT_EQ(agg.ii, 2);
  EXPECT_EQ(agg.rec_mii, 2);
  EXPECT_EQ(agg.res_mii, 1);
  EXPECT_NE(agg.limit.find("pixel_path_minimum"), std::string::npos) << agg.limit;
  for (const Recurrence& r : agg.recurrences)
    if (r.name == "pixel_path_registers") {
      EXPECT_EQ(r.distance, 9) << "no run-time-banked register on it";
    }
  // Window registers with one column per row memory (cost, median), counted window corners in
  // the plan, and the WTA's open right candidates in registers rotated per chunk (each lane
  // updates a fixed register): II = 1.
  for (const char* name : {"cost", "wta_lr", "median"}) EXPECT_EQ(stage(seed(), 200, name).ii, 1) << name;
}

TEST(DerivedII, ClockAndPathsMoveTheAggregation) {
  EXPECT_EQ(stage(seed(), 100, "aggregate").ii, 1);  // 7.30 ns per cycle hold the chain
  kern::StereoParams no_pixel_path = seed();
  no_pixel_path.path_mask = kern::kPath45 | kern::kPath90 | kern::kPath135;
  EXPECT_EQ(stage(no_pixel_path, 200, "aggregate").ii, 1);  // no recurrence through M
  // A faster clock never lowers the II.
  int last = 1;
  for (double mhz = 50; mhz <= 600; mhz += 50) {
    const int ii = stage(seed(), mhz, "aggregate").ii;
    EXPECT_GE(ii, last) << mhz << " MHz";
    last = ii;
  }
  EXPECT_GE(last, 3);
}

const MemoryPorts* memory(const StageSchedule& s, const std::string& name) {
  for (const auto& m : s.memories)
    if (m.name == name) return &m;
  return nullptr;
}

TEST(DerivedII, MemoriesAreCountedNotDeclared) {
  // The seed's memories as the counting run saw them (probe frame): one read and one write per
  // bank and firing, on the simple dual-port RAMs the kernels bind them to.
  const StageSchedule cost = stage(seed(), 200, "cost");
  for (const char* name : {"left_line_buffer", "right_line_buffer"}) {
    const MemoryPorts* m = memory(cost, name);
    ASSERT_NE(m, nullptr) << name;
    EXPECT_EQ(m->storage, kern::kStorageRamS2p) << name;
    EXPECT_EQ(m->banks, 5) << name;  // the 5 x 5 window's rows
    EXPECT_EQ(m->reads, 1) << name;
    EXPECT_EQ(m->writes, 1) << name;
  }
  const StageSchedule agg = stage(seed(), 200, "aggregate");
  const MemoryPorts* row = memory(agg, "row_path");
  ASSERT_NE(row, nullptr);
  EXPECT_EQ(row->banks, 3);  // the seed's three row paths
  EXPECT_EQ(row->runtime_banked_sites, 0);
  EXPECT_EQ(row->mii(), 1);
  EXPECT_NE(memory(stage(seed(), 200, "median"), "median_line_buffer"), nullptr);
  // Five paths, the 180-degree one on reversed rows: the row-reversal stages' memories too.
  kern::StereoParams reversed = seed();
  reversed.path_mask = kern::kForwardPaths | kern::kPath180;
  const StageSchedule rev = stage(reversed, 200, "row_reverse");
  for (const char* name : {"row_reverse_cost", "row_reverse_sum"}) {
    const MemoryPorts* m = memory(rev, name);
    ASSERT_NE(m, nullptr) << name;
    EXPECT_EQ(m->reads, 1) << name;  // a chunk's lanes are one word
    EXPECT_EQ(m->writes, 1) << name;
  }
  EXPECT_NE(memory(stage(reversed, 200, "row_unreverse"), "row_reverse_codes"), nullptr);
}

TEST(DerivedII, AnAddedAccessRaisesResMII) {
  StageSchedule cost = stage(seed(), 200, "cost");
  ASSERT_EQ(cost.ii, 1);
  MemoryPorts* left = nullptr;
  for (auto& m : cost.memories)
    if (m.name == "left_line_buffer") left = &m;
  ASSERT_NE(left, nullptr);
  left->reads += 2;  // e.g. a window reloaded from the line buffer: 3 reads on one read port
  derive_ii(cost, 200e6);
  EXPECT_EQ(cost.res_mii, 3);
  EXPECT_EQ(cost.ii, 3);
  EXPECT_NE(cost.limit.find("left_line_buffer (ram_s2p, counted): 3 reads + 1 writes"), std::string::npos)
      << cost.limit;
}

TEST(DerivedII, ALongerChainRaisesRecMII) {
  StageSchedule median = stage(seed(), 200, "median");
  ASSERT_EQ(median.ii, 1);
  for (int i = 0; i < 4; ++i) median.recurrences.front().chain.push_back({kern::kOpAdd, 16, 1});
  derive_ii(median, 200e6);
  EXPECT_EQ(median.ii, 2);
}

TEST(DerivedII, ARunTimeBankedRegisterFileOnAChainAddsItsMuxAndDistanceOne) {
  // The chain of the WTA's right candidates, as if its register file were indexed by the chunk
  // (10 registers per lane's site): the derivation adds the 10:1 read mux (2 LUT levels) and the
  // 4-bit index decoder, and the scheduler's distance of 1.
  const StageSchedule wta = stage(seed(), 200, "wta_lr");
  ASSERT_EQ(wta.ii, 1);
  Recurrence rc;
  for (const Recurrence& r : wta.recurrences)
    if (r.name == "right_candidates") rc = r;
  ASSERT_EQ(rc.name, "right_candidates");
  EXPECT_EQ(rc.distance, 9) << "rotated registers: the kernel's own distance, C - 1";
  StageSchedule banked;
  banked.stage = "wta_lr";
  MemoryPorts m;
  m.name = "right_candidate_costs";
  m.storage = kern::kStorageRegisters;
  m.max_banks_per_site = 10;
  banked.memories.push_back(m);
  rc.via = {"right_candidate_costs"};
  banked.recurrences.push_back(rc);
  add_banking_muxes(banked);
  derive_ii(banked, 200e6);
  EXPECT_EQ(banked.recurrences[0].distance, 1);
  bool decoder = false;
  for (const ChainOp& op : banked.recurrences[0].chain)
    decoder = decoder || (op.kind == kern::kOpCompare && op.width_bits == 4);
  EXPECT_TRUE(decoder) << "a 4-bit index compare for 10 registers per site";
  EXPECT_EQ(banked.ii, 2);  // 4.02 ns against 3.65 ns
}

TEST(DerivedII, DelaysComeFromTheTableWithSources) {
  ASSERT_FALSE(operator_delays().empty());
  for (const auto& d : operator_delays()) {
    EXPECT_GT(d.delay_ns, 0.0) << d.kind;
    EXPECT_FALSE(d.source.empty()) << d.kind;
    // The default part's speed grade (xczu3eg-sbva484-1-e): every figure from a -1 report.
    EXPECT_NE(d.source.find("-1"), std::string::npos) << d.kind << ": " << d.source;
  }
  EXPECT_DOUBLE_EQ(operator_delay_ns(kern::kOpAdd, 8), 0.96);
  EXPECT_DOUBLE_EQ(operator_delay_ns(kern::kOpAdd, 32), 1.20);
  EXPECT_DOUBLE_EQ(operator_delay_ns(kern::kOpMux, 8), 0.45);
}

TEST(DerivedII, TheCycleModelUsesIt) {
  for (double mhz : {100.0, 200.0, 300.0}) {
    const TimingModel t = default_timing(seed(), mhz * 1e6);
    for (const auto& s : stage_schedules(seed(), kNoRectify, mhz * 1e6))
      EXPECT_EQ(t.at(s.stage).ii_cycles, s.ii) << s.stage << " at " << mhz << " MHz";
  }
  kern::StereoParams eight = seed();
  eight.path_mask = kern::kAllPaths;
  const TimingModel t = default_timing(eight, 200e6);
  EXPECT_EQ(t.at("aggregate_back").ii_cycles, stage(eight, 200, "aggregate_back").ii);
}

}  // namespace
}  // namespace parallax::sim
