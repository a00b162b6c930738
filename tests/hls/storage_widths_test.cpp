// The exported C simulation's storage check (kernels/storage_widths.hpp, issue 41 N6): it reads
// the element type of every member a kernel's storage descriptor names and compares it with the
// width the resource model prices. Told nothing of what it should find, it flags the seed's
// aggregation built on the software store (16-bit words for 7-bit path costs) and passes the same
// kernel built on the export's ap_uint store.
#include <gtest/gtest.h>

#include <ap_int.h>

#include <memory>
#include <string>
#include <vector>

#include "parallax/config/config.hpp"
#include "parallax/kernels/sgm.hpp"
#include "parallax/resources/model.hpp"

namespace {

using namespace parallax;

const std::string kRoot = PARALLAX_SOURCE_DIR;

TEST(StoredBits, ReadsTheElementTypeThroughArraysAndStandIns) {
  EXPECT_EQ(kern::StoredBits<uint16_t>::value, 16);
  EXPECT_EQ(kern::StoredBits<uint64_t>::value, 64);
  EXPECT_EQ(kern::StoredBits<bool>::value, 1);
  EXPECT_EQ(kern::StoredBits<ap_uint<7>>::value, 7);
  EXPECT_EQ(kern::StoredBits<ap_uint<7>[3][4]>::value, 7);
  EXPECT_EQ((kern::StoredBits<kern::Counted<ap_uint<9>, 3, 4>>::value), 9);
  EXPECT_EQ((kern::StoredBits<kern::ShiftReg<ap_uint<5>, 8, true, false>>::value), 5);
  const ap_uint<7> row[2][3] = {};
  EXPECT_EQ(kern::stored_bits(row), 7);
}

TEST(StoredBits, FromStoreReadsPlainAndCountedElements) {
  ap_uint<7> plain[2] = {};
  plain[1] = 100;
  EXPECT_EQ(kern::from_store<uint16_t>(plain[1]), 100);
  kern::Counted<ap_uint<7>, 2> counted;
  counted[1] = uint16_t(300);  // wraps to 7 bits as the RTL's memory would
  EXPECT_EQ(kern::from_store<uint16_t>(counted[1]), 300 % 128);
}

// The software store, but with the export's path-cost width (the seed's 7 bits).
template <int PATH_BITS>
struct PathBitsStore : kern::HostStore {
  template <class Word>
  struct path {
    typedef ap_uint<PATH_BITS> type;
  };
};

// The seed's aggregation instantiated with its exact sizes on STORE, its storage recorded as the
// exported top does after configure(), priced from the resource model's inventory of the seed.
template <class Store>
std::vector<kern::StorageWidth> seed_aggregate(const config::PipelineConfig& cfg, const res::Inventory& inv) {
  const kern::StereoParams p = cfg.stereo_params(640, 360);
  typedef kern::Caps<640, 60, 6, 5, 5, 0xFu, true, 0, false, Store> C;
  auto agg = std::make_unique<kern::SgmAggregate<C, uint16_t>>();
  agg->configure(p, kern::stream_kinds(p.path_mask, false), false, false);
  kern::storage_width_rows().clear();
  kern::record_storage_widths("aggregate", *agg);
  std::vector<kern::PricedWidth> priced;
  for (const res::MemoryItem& m : inv.memories) priced.push_back({m.stage.c_str(), m.name.c_str(), true, m.width_bits});
  for (const res::RegisterItem& r : inv.registers)
    priced.push_back({r.stage.c_str(), r.name.c_str(), false, r.width_bits});
  std::vector<kern::StorageWidth> rows = kern::storage_width_rows();
  kern::apply_priced_widths(rows, priced);
  return rows;
}

TEST(StorageWidths, FlagsRowMemoriesStoredWiderThanPriced) {
  const config::PipelineConfig cfg = config::load_config(kRoot + "/configs/ruf2018-census.yaml");
  const kern::StereoParams p = cfg.stereo_params(640, 360);
  ASSERT_EQ(p.disparities, 60);
  ASSERT_EQ(p.parallel_units, 6);
  ASSERT_EQ(kern::path_bits(p), 7);  // PathBitsStore<7> below
  const res::Inventory inv = res::design_inventory(cfg, 640, 360);

  int row_memories = 0;
  for (const kern::StorageWidth& w : seed_aggregate<kern::HostStore>(cfg, inv)) {
    ASSERT_GE(w.priced_bits, 1) << w.name << " has no price";
    if (w.memory && w.name.rfind("row_path_", 0) == 0) {
      ++row_memories;
      EXPECT_EQ(w.per_word, 6) << w.name;
      EXPECT_EQ(w.priced_bits, 42) << w.name;  // PU x path_bits
      EXPECT_EQ(w.stored_word_bits(), 96) << w.name;
      EXPECT_FALSE(w.fits()) << w.name;
    }
  }
  EXPECT_EQ(row_memories, 3);  // left, up, right

  row_memories = 0;
  for (const kern::StorageWidth& w : seed_aggregate<PathBitsStore<7>>(cfg, inv)) {
    if (!w.memory) continue;
    EXPECT_TRUE(w.fits()) << w.name << ": " << w.stored_word_bits() << " stored, " << w.priced_bits << " priced";
    if (w.name.rfind("row_path_", 0) == 0) ++row_memories;
  }
  EXPECT_EQ(row_memories, 3);
  const std::string json = kern::storage_widths_json("seed", kern::storage_width_rows());
  EXPECT_NE(json.find("\"name\": \"row_path_up\", \"kind\": \"memory\", \"lanes_per_word\": 6"), std::string::npos)
      << json;
}

}  // namespace
