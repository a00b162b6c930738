// unit: the counted II holds for the five reviewed designs (issue 41): on a counted frame, every
// stage's memories fit their ports, and every recurrence its budget, at the II the design states
// (ii_declared, from stage_schedules: the II the cycle model, the report and the export use).
// The probe frame behind ii_declared gives the same counts as a frame of the design's own size.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "parallax/config/config.hpp"
#include "parallax/sim/accesses.hpp"
#include "parallax/sim/schedule.hpp"

namespace parallax::sim {
namespace {

const std::string kConfigs = PARALLAX_SOURCE_DIR "/configs/";

// A seeded texture; the right image the left shifted by `shift_px`.
GreyImage texture(int w, int h, int shift_px, uint32_t seed) {
  GreyImage g;
  g.width_px = w;
  g.height_px = h;
  g.px.resize(std::size_t(w) * std::size_t(h));
  for (int y = 0; y < h; ++y) {
    uint32_t s = seed + uint32_t(y) * 7919u;
    std::vector<uint8_t> row(std::size_t(w + shift_px));
    for (auto& v : row) {
      s = s * 1103515245u + 12345u;
      v = uint8_t(s >> 23);
    }
    for (int x = 0; x < w; ++x) g.px[std::size_t(y) * std::size_t(w) + std::size_t(x)] = row[std::size_t(x + shift_px)];
  }
  return g;
}

struct Design {
  const char* name;
  const char* file;
  std::vector<std::pair<std::string, std::string>> overrides;
};

const std::vector<Design>& designs() {
  static const std::vector<Design> d = {
      {"seed", "ruf2018-census.yaml", {}},
      {"seed-8-paths", "ruf2018-census.yaml", {{"paths", "8"}}},
      {"frontier", "frontier-census.yaml", {}},
      {"synthesised", "ruf2018-synthesised.yaml", {}},
      {"mgm-subpixel-uniqueness",
       "ruf2018-census.yaml",
       {{"aggregation", "mgm"}, {"subpixel_bits", "4"}, {"uniqueness_pct", "10"}}},
  };
  return d;
}

kern::StereoParams params(const Design& d, int w, int h) {
  config::PipelineConfig c = config::load_config(kConfigs + d.file);
  for (const auto& kv : d.overrides) config::set_field(c, kv.first, kv.second);
  return c.stereo_params(w, h);
}

nlohmann::json count(const kern::StereoParams& p, uint32_t seed) {
  const GreyImage l = texture(p.width_px, p.height_px, 0, seed);
  const GreyImage r = texture(p.width_px, p.height_px, p.min_disparity + p.disparities / 3, seed);
  AccessRunOptions o;
  o.design = "test";
  return nlohmann::json::parse(count_accesses_json(l, r, p, o));
}

TEST(CountedII, EveryStageFitsTheIIItStates) {
  for (const Design& d : designs()) {
    const nlohmann::json j = count(params(d, 160, 48), 11);
    ASSERT_FALSE(j.at("stages").empty()) << d.name;
    for (const auto& s : j.at("stages")) {
      const int declared = s.at("ii_declared").get<int>();
      for (const auto& m : s.at("memories"))
        EXPECT_LE(m.at("ii_forced").get<int>(), declared)
            << d.name << " stage " << s.at("name") << " memory " << m.at("name") << ": " << m.dump();
      for (const auto& r : s.at("recurrences"))
        EXPECT_LE(r.at("ii_forced").get<int>(), declared)
            << d.name << " stage " << s.at("name") << " recurrence " << r.at("name");
    }
  }
}

TEST(CountedII, TheSeedMeetsItsTargets) {
  // The seed: aggregation at most 2, every other stage 1 (issue 41's targets), its row memories
  // one read and one write per bank and firing, and its register files on a recurrence (the
  // previous pixel's Lr, the WTA's open candidates) one register per site.
  const nlohmann::json j = count(params(designs()[0], 160, 48), 5);
  for (const auto& s : j.at("stages")) {
    const std::string name = s.at("name");
    EXPECT_LE(s.at("ii_declared").get<int>(), name == "aggregate" ? 2 : 1) << name;
    for (const auto& m : s.at("memories"))
      if (m.at("name") == "pixel_path_previous" || m.at("name") == "right_candidate_costs") {
        EXPECT_EQ(m.at("max_banks_per_site").get<int>(), 1) << m.at("name");
      }
    for (const auto& m : s.at("memories"))
      if (m.at("kind") != "registers") {
        EXPECT_EQ(m.at("max_reads_per_bank_per_firing").get<int>(), 1) << name << " " << m.at("name");
        EXPECT_LE(m.at("max_writes_per_bank_per_firing").get<int>(), 1) << name << " " << m.at("name");
      }
  }
}

TEST(CountedII, TheProbeFrameCountsAsALargerFrame) {
  // The II comes from a probe frame; a frame of another size and content counts the same
  // memories the same. Register files have no ports: their counts may depend on the data (the
  // LR check reads the right disparity at the left result's age), not the II they force.
  for (const Design& d : {designs()[0], designs()[2]}) {
    const kern::StereoParams p = params(d, 320, 90);
    const std::vector<kern::MemoryAccesses> probe = probe_memory_accesses(p);
    const nlohmann::json j = count(p, 99);
    int compared = 0;
    for (const auto& s : j.at("stages"))
      for (const auto& m : s.at("memories"))
        for (const auto& q : probe)
          if (q.stage == s.at("name") && q.name == m.at("name")) {
            EXPECT_EQ(q.ii_forced, m.at("ii_forced").get<int>()) << q.name;
            if (q.kind == "registers") continue;
            EXPECT_EQ(q.max_reads_per_bank_per_firing, m.at("max_reads_per_bank_per_firing").get<int>()) << q.name;
            EXPECT_EQ(q.max_writes_per_bank_per_firing, m.at("max_writes_per_bank_per_firing").get<int>()) << q.name;
            EXPECT_EQ(q.runtime_banked_sites, m.at("runtime_banked_sites").get<int>()) << q.name;
            ++compared;
          }
    EXPECT_GE(compared, 4) << d.name;
  }
}

TEST(CountedII, PenaltiesChangeNoMemorysCounts) {
  // The probe is shared by designs that differ only in P1/P2 of the same widths (accesses.cpp,
  // probe_params). Counted on frames with their own penalties, two such designs count every RAM
  // alike, bank their register files alike (the banking muxes of add_banking_muxes come from
  // them), and every memory fits the II declared from the shared probe. Census, SAD, adaptive P2.
  struct Case {
    Design d;
    std::pair<std::string, std::string> extra;
  };
  const std::vector<Case> cases = {{designs()[0], {"", ""}},
                                   {designs()[4], {"", ""}},
                                   {{"sad", "ruf2018-sad.yaml", {}}, {"", ""}},
                                   {designs()[0], {"p2_adaptive", "4"}}};
  for (const Case& c : cases) {
    Design d = c.d;
    if (!c.extra.first.empty()) d.overrides.push_back(c.extra);
    kern::StereoParams a = params(d, 160, 48), b = a;
    a.p1 = 5;
    a.p2 = 40;
    b.p1 = 17;
    b.p2 = 63;
    ASSERT_EQ(kern::aggregate_bits(a), kern::aggregate_bits(b)) << d.name;
    const nlohmann::json ja = count(a, 3), jb = count(b, 3);
    ASSERT_EQ(ja.at("stages").size(), jb.at("stages").size());
    std::set<std::string> via;  // "stage/memory" of the register files on a recurrence
    const kern::RectifyParams none{a.width_px, a.height_px, kern::kRectifyNone, 0, 1};
    for (const StageSchedule& st : stage_schedules(a, none, 200e6))
      for (const Recurrence& r : st.recurrences)
        for (const std::string& m : r.via) via.insert(st.stage + "/" + m);
    int compared = 0, via_compared = 0;
    for (std::size_t i = 0; i < ja.at("stages").size(); ++i) {
      const auto &sa = ja.at("stages")[i], &sb = jb.at("stages")[i];
      ASSERT_EQ(sa.at("memories").size(), sb.at("memories").size()) << d.name << " " << sa.at("name");
      for (std::size_t k = 0; k < sa.at("memories").size(); ++k) {
        const auto &ma = sa.at("memories")[k], &mb = sb.at("memories")[k];
        for (const auto* m : {&ma, &mb})
          EXPECT_LE(m->at("ii_forced").get<int>(), sa.at("ii_declared").get<int>()) << d.name << " " << ma.at("name");
        if (ma.at("kind") == "registers") {
          // A register file on a recurrence adds its banking's mux to the chain (schedule.cpp,
          // add_banking_muxes): the same for both. Others may follow the data (the LR check's
          // right disparities are read at the left result's age) and force no II.
          if (via.count(sa.at("name").get<std::string>() + "/" + ma.at("name").get<std::string>()) != 0) {
            EXPECT_EQ(ma.at("max_banks_per_site"), mb.at("max_banks_per_site")) << d.name << " " << ma.at("name");
            ++via_compared;
          }
          continue;
        }
        EXPECT_EQ(ma, mb) << d.name;
        ++compared;
      }
    }
    EXPECT_GE(compared, 4) << d.name;
    EXPECT_GE(via_compared, 1) << d.name;
  }
}

}  // namespace
}  // namespace parallax::sim
