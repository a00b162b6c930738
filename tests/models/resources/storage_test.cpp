// unit: the resource model's registers and memories are the members' own (issue 14, item 4).
// Every kernel describes its hardware members once (storage(), resources.hpp); declare() declares
// that description. Here the kernels are instantiated as the HLS export does (FIXED Caps of the
// design) for the seed design and variants, and the test checks (1) each description against its
// member (a complete-partitioned register member's element count, a memory's depth x partitions
// against the member's extent, the bit width against the element type), (2) that the kernels'
// declarations are exactly the description plus a short list of non-member registers (tokens and
// counters), (3) that the described members account for the kernel object (sizeof) up to its
// control scalars, (4) that the model's inventory (models/resources, software instantiation)
// equals the FIXED instantiation's, and (5) the median's comparators are the pair network's.
// Mutation checks: stand-ins whose declaration drifts from their members fail the same checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "parallax/config/config.hpp"
#include "parallax/kernels/census.hpp"
#include "parallax/kernels/median.hpp"
#include "parallax/kernels/rectify.hpp"
#include "parallax/kernels/sad.hpp"
#include "parallax/kernels/row_reverse.hpp"
#include "parallax/kernels/sgm.hpp"
#include "parallax/kernels/wta_lr.hpp"
#include "parallax/resources/model.hpp"

namespace parallax::test {
namespace {

const std::string kRoot = PARALLAX_SOURCE_DIR;

template <class T>
struct Extent {
  static constexpr int64_t n = 1;
  typedef T elem;
};
template <class T, size_t N>
struct Extent<T[N]> {
  static constexpr int64_t n = int64_t(N) * Extent<T>::n;
  typedef typename Extent<T>::elem elem;
};

typedef std::tuple<std::string, int64_t, int64_t, int64_t> Row;  // name, width, count|depth, copies

// The storage visitor of the test: checks each description against the member it names.
struct StorageCheck {
  std::vector<std::string> failures;
  std::vector<Row> regs, mems;
  int64_t bytes = 0;  // sizeof the described members

  void fail(const char* name, const std::string& what) { failures.push_back(std::string(name) + ": " + what); }
  template <class M>
  void width_ok(const char* name, int bits, int per_element) {
    const int have = int(8 * sizeof(typename Extent<M>::elem)) * per_element;
    if (bits < 1 || bits > have)
      fail(name, "width " + std::to_string(bits) + " bits, the member holds " + std::to_string(have));
  }
  template <class M>
  void registers(const char* name, const M&, int count, int bits) {
    bytes += int64_t(sizeof(M));
    if (count != Extent<M>::n)
      fail(name, "declares " + std::to_string(count) + " registers, the member holds " + std::to_string(Extent<M>::n));
    width_ok<M>(name, bits, 1);
    regs.emplace_back(name, bits, count, 1);
  }
  template <class M>
  void registers_part(const char* name, const M&, int count, int bits) {
    bytes += int64_t(sizeof(M));
    if (count < 1 || count > Extent<M>::n)
      fail(name, "declares " + std::to_string(count) + " registers of a member of " + std::to_string(Extent<M>::n));
    width_ok<M>(name, bits, 1);
    regs.emplace_back(name, bits, count, 1);
  }
  template <class M>
  void window(const char* name, const M&, int cols, int rows, int bits) {
    bytes += int64_t(sizeof(M));
    static_assert(std::rank<M>::value == 2, "window registers are [rows][cols]");
    if (rows != int(std::extent<M, 0>::value))
      fail(name,
           "declares " + std::to_string(rows) + " rows, the member has " + std::to_string(std::extent<M, 0>::value));
    if (cols < 1 || cols > int(std::extent<M, 1>::value))
      fail(name,
           "declares " + std::to_string(cols) + " columns, the member has " + std::to_string(std::extent<M, 1>::value));
    width_ok<M>(name, bits, 1);
    regs.emplace_back(name, bits, int64_t(cols) * rows, 1);
  }
  template <class M>
  void unused(const char*, const M&) {
    bytes += int64_t(sizeof(M));
  }
  template <class M>
  void memory(const char* name, const M&, int64_t depth, int bits, int copies, bool, int per_word) {
    bytes += int64_t(sizeof(M));
    const int64_t held = depth * copies * per_word, n = Extent<M>::n;
    if (per_word == 1 ? held != n : (held < n || held >= 2 * n))
      fail(name, std::to_string(copies) + " x " + std::to_string(depth) + " words of " + std::to_string(per_word) +
                     " hold " + std::to_string(held) + " elements, the member " + std::to_string(n));
    width_ok<M>(name, bits, per_word);
    mems.emplace_back(name, bits, depth, copies);
  }
};

// Registers a kernel declares that are no member (stream tokens, raster counters, outputs).
bool non_member(const std::string& name) {
  for (const char* n : {"counters", "window_corner", "input_gate", "cost_token", "cost_in", "sum_token", "median_out",
                        "map_entry", "taps", "rectify_out", "row_reverse_tokens"})
    if (name == n) return true;
  return false;
}

// The undescribed bytes of a kernel object: its control scalars (StereoParams, the raster
// counters, the window corner and input gate, the line buffers' input positions).
constexpr int64_t kControlBytes = 288;

// (2) and (3): the declared registers and memories of one stage are the description's.
std::vector<std::string> compare(const res::Inventory& inv, const std::string& stage, const StorageCheck& c,
                                 int64_t object_bytes) {
  std::vector<std::string> out = c.failures;
  std::vector<Row> regs, mems;
  for (const auto& r : inv.registers)
    if (r.stage == stage && !non_member(r.name)) regs.emplace_back(r.name, r.width_bits, r.count, 1);
  for (const auto& m : inv.memories)
    if (m.stage == stage) mems.emplace_back(m.name, m.width_bits, m.depth, m.copies);
  auto want_regs = c.regs, want_mems = c.mems;
  std::sort(regs.begin(), regs.end());
  std::sort(mems.begin(), mems.end());
  std::sort(want_regs.begin(), want_regs.end());
  std::sort(want_mems.begin(), want_mems.end());
  if (regs != want_regs) out.push_back(stage + ": declared registers differ from the members' description");
  if (mems != want_mems) out.push_back(stage + ": declared memories differ from the members' description");
  if (object_bytes - c.bytes > kControlBytes)
    out.push_back(stage + ": " + std::to_string(object_bytes - c.bytes) +
                  " bytes of the kernel object are not described");
  return out;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += "\n  " + x;
  return s;
}

// The ops of one stage, for comparing the model's inventory with the FIXED instantiation's.
std::vector<std::tuple<std::string, int, int, int64_t>> ops(const res::Inventory& inv, const std::string& stage) {
  std::vector<std::tuple<std::string, int, int, int64_t>> v;
  for (const auto& o : inv.ops)
    if (o.stage == stage) v.emplace_back(o.name, o.width_bits, o.b_bits, o.count);
  std::sort(v.begin(), v.end());
  return v;
}
std::vector<Row> regs_of(const res::Inventory& inv, const std::string& stage) {
  std::vector<Row> v;
  for (const auto& r : inv.registers)
    if (r.stage == stage) v.emplace_back(r.name, r.width_bits, r.count, 1);
  for (const auto& m : inv.memories)
    if (m.stage == stage) v.emplace_back(m.name, m.width_bits, m.depth, m.copies);
  std::sort(v.begin(), v.end());
  return v;
}

config::PipelineConfig seed() {
  return config::load_config(kRoot + "/configs/ruf2018-census.yaml");
}

// Instantiates the design's kernels with FIXED capacities (as parallax_config.hpp.in does),
// checks every stage and returns the failures; also checks the model's inventory against them.
template <int W, int D, int PU, int WR, int MR, int M = 0>
void check_design(const config::PipelineConfig& cfg) {
  typedef kern::Caps<W, D, PU, WR, MR, 0xFu, true, M> Caps;
  const int H = 360;
  const kern::StereoParams p = cfg.stereo_params(W, H);
  ASSERT_EQ(p.disparities, D);
  ASSERT_EQ(p.parallel_units, PU);
  ASSERT_EQ(p.window_h, WR);
  ASSERT_EQ(p.min_disparity, M);
  res::Inventory inv;
  const res::Inventory model = res::design_inventory(cfg, W, H);
  {
    res::Collector r(inv, "cost");
    StorageCheck c;
    std::vector<std::string> f;
    if (p.cost == kern::kCostCensus) {
      auto st = std::make_unique<kern::CensusCostStage<Caps>>();
      st->configure(p);
      st->declare(r);
      st->storage(c);
      f = compare(inv, "cost", c, int64_t(sizeof(*st)));
    } else {
      auto st = std::make_unique<kern::SadCostStage<Caps>>();
      st->configure(p);
      st->declare(r);
      st->storage(c);
      f = compare(inv, "cost", c, int64_t(sizeof(*st)));
    }
    EXPECT_TRUE(f.empty()) << cfg.name << join(f);
  }
  const bool two_pass = kern::two_pass_paths(p.path_mask);
  const bool row_reverse = kern::row_reverse_paths(p.path_mask);
  {
    auto agg = std::make_unique<kern::SgmAggregate<Caps, uint16_t>>();
    for (int pass = 0; pass < (two_pass ? 2 : 1); ++pass) {
      const std::string stage = pass == 0 ? "aggregate" : "aggregate_back";
      agg->configure(p, kern::stream_kinds(p.path_mask, pass == 1), pass == 1, (two_pass || row_reverse) && pass == 0);
      res::Collector r(inv, stage);
      agg->declare(r);
      StorageCheck c;
      agg->storage(c);
      const auto f = compare(inv, stage, c, int64_t(sizeof(*agg)));
      EXPECT_TRUE(f.empty()) << cfg.name << join(f);
    }
  }
  if (row_reverse) {  // the 180-degree path in one pass (kernels/row_reverse.hpp)
    auto rev = std::make_unique<kern::RowReverse<Caps, uint16_t>>();
    rev->configure(p);
    res::Collector r(inv, "row_reverse");
    rev->declare(r);
    StorageCheck c;
    rev->storage(c);
    auto f = compare(inv, "row_reverse", c, int64_t(sizeof(*rev)));
    EXPECT_TRUE(f.empty()) << cfg.name << join(f);
    auto row = std::make_unique<kern::SgmAggregate<kern::PixelPathCaps<Caps>, uint16_t>>();
    row->configure(p, kern::stream_kinds(kern::kPath180, true), true, false);
    res::Collector a(inv, "aggregate_row");
    row->declare(a);
    StorageCheck ca;
    row->storage(ca);
    f = compare(inv, "aggregate_row", ca, int64_t(sizeof(*row)));
    EXPECT_TRUE(f.empty()) << cfg.name << join(f);
    auto codes = std::make_unique<kern::RowReverseCodes<Caps>>();
    codes->configure(p);
    res::Collector u(inv, "row_unreverse");
    codes->declare(u);
    StorageCheck cu;
    codes->storage(cu);
    f = compare(inv, "row_unreverse", cu, int64_t(sizeof(*codes)));
    EXPECT_TRUE(f.empty()) << cfg.name << join(f);
  }
  {
    auto wta = std::make_unique<kern::WtaLr<Caps, uint16_t>>();
    wta->configure(p, two_pass || row_reverse);
    res::Collector r(inv, "wta_lr");
    wta->declare(r);
    StorageCheck c;
    wta->storage(c);
    const auto f = compare(inv, "wta_lr", c, int64_t(sizeof(*wta)));
    EXPECT_TRUE(f.empty()) << cfg.name << join(f);
  }
  if (p.median >= 3) {
    auto med = std::make_unique<kern::Median<Caps>>();
    med->configure(p);
    res::Collector r(inv, "median");
    const int db = kern::disparity_bits(p);
    med->declare(r, db);
    StorageCheck c;
    med->storage(c, db);
    const auto f = compare(inv, "median", c, int64_t(sizeof(*med)));
    EXPECT_TRUE(f.empty()) << cfg.name << join(f);
    // (5) the comparators of the pair network the FIXED instantiation unrolls: n(n-1)/2.
    const int n = p.median * p.median;
    const auto net = med->rank_network();
    EXPECT_EQ(net.keys, n);
    EXPECT_EQ(net.pairs, n * (n - 1) / 2);
    EXPECT_EQ(net.max_per_key, n - 1);
    EXPECT_LE(kern::bits_for(uint64_t(n - 1)), kern::Median<Caps>::kKeyIndexBits);
    EXPECT_LE(db + kern::Median<Caps>::kKeyIndexBits, 16);  // the key is a uint16_t
  }
  // (4) the model (software instantiation) declares what the FIXED instantiation declares.
  for (const std::string stage :
       {"cost", "aggregate", "aggregate_back", "row_reverse", "aggregate_row", "wta_lr", "median", "row_unreverse"}) {
    EXPECT_EQ(regs_of(model, stage), regs_of(inv, stage)) << cfg.name << " " << stage;
    EXPECT_EQ(ops(model, stage), ops(inv, stage)) << cfg.name << " " << stage;
  }
}

TEST(ResourcesStorage, SeedDesignDeclaresItsMembers) {
  check_design<640, 60, 6, 5, 5>(seed());
}

TEST(ResourcesStorage, SadVariant) {
  auto cfg = seed();
  cfg.name = "sad";
  cfg.cost = "sad";
  check_design<640, 60, 6, 5, 5>(cfg);
}

TEST(ResourcesStorage, EightPathsTwoPassKinds) {
  auto cfg = seed();
  cfg.name = "8 paths";
  cfg.path_mask = 0xFFu;
  check_design<640, 60, 6, 5, 5>(cfg);
}

TEST(ResourcesStorage, FivePathsRowReverse) {
  auto cfg = seed();
  cfg.name = "5 paths";
  cfg.path_mask = kern::kForwardPaths | kern::kPath180;
  check_design<640, 60, 6, 5, 5>(cfg);
}

// The right census codes and SAD columns are kept m columns longer.
TEST(ResourcesStorage, MinDisparity) {
  auto cfg = seed();
  cfg.name = "min_disparity 12";
  cfg.min_disparity = 12;
  check_design<640, 60, 6, 5, 5, 12>(cfg);
  cfg.name = "SAD, min_disparity 7";
  cfg.cost = "sad";
  cfg.p1 = 200;
  cfg.p2 = 800;
  cfg.min_disparity = 7;
  check_design<640, 60, 6, 5, 5, 7>(cfg);
}

// Adaptive P2: the aggregation's intensity row and registers, the row reversal's intensities.
TEST(ResourcesStorage, AdaptiveP2) {
  auto cfg = seed();
  cfg.name = "adaptive P2";
  cfg.p2_adaptive = 40;
  check_design<640, 60, 6, 5, 5>(cfg);
  cfg.name = "adaptive P2, 5 paths";
  cfg.path_mask = kern::kForwardPaths | kern::kPath180;
  check_design<640, 60, 6, 5, 5>(cfg);
}

// MGM: the pixel datapath's row memory, the second predecessors' lanes, the row-left window; the
// pairs 0 / 90 and 45 / 135 share a datapath; eight paths in two passes; with adaptive P2.
TEST(ResourcesStorage, MgmAggregation) {
  auto cfg = seed();
  cfg.aggregation = "mgm";
  cfg.name = "MGM, 4 paths";
  check_design<640, 60, 6, 5, 5>(cfg);
  cfg.name = "MGM, paths 0 and 45, adaptive P2";
  cfg.path_mask = kern::kPath0 | kern::kPath45;
  cfg.p2_adaptive = 40;
  check_design<640, 60, 6, 5, 5>(cfg);
  cfg.name = "MGM, path 135";
  cfg.p2_adaptive = 0;
  cfg.path_mask = kern::kPath135;
  check_design<640, 60, 6, 5, 5>(cfg);
  cfg.name = "MGM, 8 paths";
  cfg.path_mask = kern::kAllPaths;
  check_design<640, 60, 6, 5, 5>(cfg);
}

// Sub-pixel codes: the WTA's neighbour registers, the wider delayed left codes, median and row
// reversal of the wider codes.
TEST(ResourcesStorage, SubpixelCodes) {
  auto cfg = seed();
  cfg.name = "subpixel 4 bits";
  cfg.subpixel_bits = 4;
  check_design<640, 60, 6, 5, 5>(cfg);
  cfg.name = "subpixel 2 bits, 5 paths";
  cfg.subpixel_bits = 2;
  cfg.path_mask = kern::kForwardPaths | kern::kPath180;
  check_design<640, 60, 6, 5, 5>(cfg);
}

TEST(ResourcesStorage, MedianThreeAndSeven) {
  auto cfg = seed();
  cfg.name = "median 3";
  cfg.median = 3;
  check_design<640, 60, 6, 5, 3>(cfg);
  cfg.name = "median 7";
  cfg.median = 7;
  check_design<640, 60, 6, 5, 7>(cfg);
}

TEST(ResourcesStorage, OneFiringPerPixel) {
  auto cfg = seed();
  cfg.name = "PU = D";
  cfg.parallel_units = 60;
  check_design<640, 60, 60, 5, 5>(cfg);
}

TEST(ResourcesStorage, NoLrCheckAndOtherWindow) {
  auto cfg = seed();
  cfg.name = "census 7x5, no LR";
  cfg.window_w = 7;
  cfg.lr_check = false;
  check_design<640, 60, 6, 5, 5>(cfg);
}

TEST(ResourcesStorage, UniquenessCheck) {
  auto cfg = seed();
  cfg.name = "uniqueness 15 %";
  cfg.uniqueness_pct = 15;
  check_design<640, 60, 6, 5, 5>(cfg);
}

TEST(ResourcesStorage, TwoPaths) {
  auto cfg = seed();
  cfg.name = "paths 0/90";
  cfg.path_mask = kern::kPath0 | kern::kPath90;
  check_design<640, 60, 6, 5, 5>(cfg);
}

TEST(ResourcesStorage, RectifyLineBuffer) {
  auto st = std::make_unique<kern::Rectify<640, 16>>();
  st->configure(kern::RectifyParams{640, 360, kern::kRectifyBilinear, 5, 16});
  res::Inventory inv;
  res::Collector r(inv, "rectify");
  st->declare(r);
  StorageCheck c;
  st->storage(c);
  const auto f = compare(inv, "rectify", c, int64_t(sizeof(*st)));
  EXPECT_TRUE(f.empty()) << join(f);
}

// --- mutation checks: stand-ins that drift from their members -------------------------------

// A kernel of one register member and one memory member, declared through its description.
template <int REGS, int DECLARED_REGS, int ROWS, int DECLARED_ROWS, bool HAND_DECLARED>
struct StandIn {
  uint16_t pix_[REGS];
  uint16_t row_[ROWS][64];
  uint16_t undescribed_[HAND_DECLARED ? 1 : 1];
  template <class V>
  void storage(V& v) const {
    v.registers("pix", pix_, DECLARED_REGS, 12);
    v.memory("row", row_, 64, 12, DECLARED_ROWS, false, 1);
  }
  template <class R>
  void declare(R& r) const {
    if (HAND_DECLARED) {  // a declaration written by hand beside the description, one register off
      r.registers("pix", 12, REGS + 1);
      r.memory("row", 64, 12, ROWS, false);
    } else {
      kern::declare_storage(r, *this);
    }
    r.registers("counters", 10, 1);
  }
};

template <class K>
std::vector<std::string> check_stand_in() {
  const K k{};
  res::Inventory inv;
  res::Collector r(inv, "stand_in");
  k.declare(r);
  StorageCheck c;
  k.storage(c);
  return compare(inv, "stand_in", c, int64_t(sizeof(k)));
}

// A stand-in with a big member array nobody describes.
struct UndescribedMember {
  uint16_t pix_[8];
  uint16_t hold_[2][256];  // e.g. the old ping-pong registers, back without a declaration
  template <class V>
  void storage(V& v) const {
    v.registers("pix", pix_, 8, 12);
  }
  template <class R>
  void declare(R& r) const {
    kern::declare_storage(r, *this);
  }
};

TEST(ResourcesStorageMutation, AgreeingStandInPasses) {
  const auto f = check_stand_in<StandIn<8, 8, 3, 3, false>>();
  EXPECT_TRUE(f.empty()) << join(f);
}

TEST(ResourcesStorageMutation, RegisterCountDriftFails) {
  const auto f = check_stand_in<StandIn<8, 7, 3, 3, false>>();
  ASSERT_FALSE(f.empty());
  EXPECT_NE(f[0].find("declares 7 registers, the member holds 8"), std::string::npos) << join(f);
}

TEST(ResourcesStorageMutation, MemoryPartitionDriftFails) {
  const auto f = check_stand_in<StandIn<8, 8, 3, 2, false>>();
  ASSERT_FALSE(f.empty());
  EXPECT_NE(f[0].find("row: 2 x 64 words"), std::string::npos) << join(f);
}

TEST(ResourcesStorageMutation, HandWrittenDeclarationFails) {
  const auto f = check_stand_in<StandIn<8, 8, 3, 3, true>>();
  ASSERT_EQ(f.size(), 1u) << join(f);
  EXPECT_NE(f[0].find("declared registers differ"), std::string::npos) << join(f);
}

TEST(ResourcesStorageMutation, UndescribedMemberFails) {
  const auto f = check_stand_in<UndescribedMember>();
  ASSERT_EQ(f.size(), 1u) << join(f);
  EXPECT_NE(f[0].find("not described"), std::string::npos) << join(f);
}

}  // namespace
}  // namespace parallax::test
