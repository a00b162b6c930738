// Shared by the HLS export tests: fresh folders and exporting a design with the CLI.
#pragma once

#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "../common/shell.hpp"

namespace parallax::test {

inline std::filesystem::path fresh_dir(const std::string& name) {
  const auto d =
      std::filesystem::temp_directory_path() / ("parallax_hls_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  return d;
}

// Exports with the CLI from the source tree (relative paths, so the generated text does not
// depend on where the tree lives). `extra`: more options (e.g. --set ...).
inline Shell export_design(const std::string& config, const std::filesystem::path& out, const std::string& extra = "") {
  return shell(std::string("cd ") + PARALLAX_SOURCE_DIR + " && " + PARALLAX_CLI + " export-hls --config " + config +
               " --left data/kitti2015-640x360/training/image_2/000001_10.png"
               " --right data/kitti2015-640x360/training/image_3/000001_10.png --out " +
               out.string() + " " + extra);
}

// The access count a `make csim` wrote (TB/csim_accesses.json, or the reduced frame's): every
// kernel stage of the project's stages.json is there with the II the simulator gives it (its
// PIPELINE pragma), it fired (but the rectify stages), memories were counted, and every memory's counts and
// every recurrence fit the stage's declared II.
inline void expect_accesses_fit(const std::filesystem::path& project, const char* file = "csim_accesses.json") {
  std::ifstream in(project / "tb" / file);
  ASSERT_TRUE(in.good()) << (project / "tb" / file);
  const nlohmann::json j = nlohmann::json::parse(in);
  std::ifstream st(project / "stages.json");
  ASSERT_TRUE(st.good());
  std::map<std::string, int> sim_ii;
  for (const auto& s : nlohmann::json::parse(st))
    sim_ii[s.at("name").get<std::string>()] = s.at("ii_cycles").get<int>();
  ASSERT_FALSE(j.at("stages").empty());
  int counted = 0;
  for (const auto& s : j.at("stages")) {
    const std::string name = s.at("name");
    const int declared = s.at("ii_declared");
    ASSERT_EQ(sim_ii.count(name), 1u) << name << " is not a stage of stages.json";
    EXPECT_EQ(declared, sim_ii[name]) << name << ": the count's declared II is not the simulator's";
    // The rectify stages are not counted (their memories are declared: docs/hls.md); every
    // other stage fired.
    if (name.rfind("rectify", 0) != 0) {
      EXPECT_GT(s.at("firings").get<long long>(), 0) << name;
    }
    EXPECT_LE(s.at("ii_forced").get<int>(), declared) << name;
    for (const auto& m : s.at("memories")) {
      ++counted;
      EXPECT_LE(m.at("ii_forced").get<int>(), declared) << name << " " << m.at("name");
      EXPECT_GE(m.at("banks").get<int>(), 1) << name << " " << m.at("name");
    }
    for (const auto& r : s.at("recurrences")) EXPECT_LE(r.at("ii_forced").get<int>(), declared) << name;
  }
  EXPECT_GE(counted, 3) << "line buffers and path-cost rows at least";
}

// The C simulation's storage widths (tb/csim_storage.json, written beside csim_accesses.json):
// every memory stores the word the resource model prices (so the BRAM the tool reports is the
// BRAM of the code), and every member has a price.
inline void expect_storage_fits(const std::filesystem::path& project, const char* file = "csim_storage.json") {
  std::ifstream in(project / "tb" / file);
  ASSERT_TRUE(in.good()) << (project / "tb" / file);
  const nlohmann::json j = nlohmann::json::parse(in);
  int memories = 0;
  for (const auto& w : j.at("storage")) {
    const std::string what = w.at("stage").get<std::string>() + " " + w.at("name").get<std::string>();
    EXPECT_TRUE(w.at("fits").get<bool>()) << what;
    EXPECT_GE(w.at("priced_word_bits").get<int>(), 1) << what << ": not priced";
    if (w.at("kind") == "memory") {
      ++memories;
      EXPECT_EQ(w.at("stored_word_bits").get<int>(), w.at("priced_word_bits").get<int>()) << what;
    }
  }
  EXPECT_GE(memories, 3) << "line buffers and path-cost rows at least";
}

}  // namespace parallax::test
