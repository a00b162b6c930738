// Seeded fuzz tests of the readers of user files (issue 15, item 8): a few hundred mutated inputs
// per reader, derived from valid seeds by bit flips, byte changes, insertions of format tokens,
// deletions, duplications and truncations. Every input must either parse or be refused with the
// reader's documented error type; any other exception fails, and a crash or a sanitizer report
// (the debug preset builds with ASan + UBSan) fails the run. Same seed, same inputs.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "parallax/config/config.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/disparity_io.hpp"
#include "parallax/hls_flow/hls_report.hpp"
#include "parallax/uav/scene.hpp"
#include "parallax/uav/truth.hpp"
#include "parallax/search/sweep.hpp"
#include "eval/pfm_writer.hpp"

namespace fs = std::filesystem;
using namespace parallax;

namespace {

constexpr int kInputsPerReader = 300;

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_all(const fs::path& p, const std::string& s) {
  std::ofstream out(p, std::ios::binary);
  out << s;
}

// One to four random edits of `seed`; `tokens` are fragments of the format (keys, brackets,
// numbers) that make the edits reach deeper than random bytes would.
std::string mutate(const std::string& seed, std::mt19937& rng, const std::vector<std::string>& tokens) {
  std::string s = seed;
  auto pick = [&](std::size_t n) { return n == 0 ? std::size_t(0) : std::size_t(rng() % n); };
  const int edits = 1 + int(rng() % 4);
  for (int e = 0; e < edits; ++e) {
    switch (rng() % 7) {
      case 0:  // flip a bit
        if (!s.empty()) s[pick(s.size())] ^= char(1 << (rng() % 8));
        break;
      case 1:  // any byte
        if (!s.empty()) s[pick(s.size())] = char(rng() & 0xFF);
        break;
      case 2:  // a format token
        s.insert(pick(s.size() + 1), tokens[pick(tokens.size())]);
        break;
      case 3: {  // delete a range
        if (s.empty()) break;
        const std::size_t a = pick(s.size());
        s.erase(a, 1 + pick(std::min<std::size_t>(64, s.size() - a)));
        break;
      }
      case 4: {  // duplicate a range
        if (s.empty()) break;
        const std::size_t a = pick(s.size());
        s.insert(pick(s.size() + 1), s.substr(a, 1 + pick(std::min<std::size_t>(64, s.size() - a))));
        break;
      }
      case 5:  // truncate
        s.resize(pick(s.size() + 1));
        break;
      default: {  // a run of one byte (long lines, deep nesting)
        s.insert(pick(s.size() + 1), std::string(1 + pick(200), "[{:-\n 9#&*"[pick(11)]));
        break;
      }
    }
  }
  return s;
}

// Runs `read` on kInputsPerReader mutations of the seeds. `refused` says whether an exception is
// the reader's documented refusal; anything else fails the test with the input that caused it.
void fuzz(const char* reader, const std::vector<std::string>& seeds, const std::vector<std::string>& tokens,
          uint32_t rng_seed, const std::function<void(const std::string&)>& read,
          const std::function<bool(std::exception_ptr)>& refused) {
  std::mt19937 rng(rng_seed);
  int parsed = 0, refusals = 0;
  for (int i = 0; i < kInputsPerReader; ++i) {
    const std::string input = mutate(seeds[std::size_t(i) % seeds.size()], rng, tokens);
    try {
      read(input);
      ++parsed;
    } catch (...) {
      if (refused(std::current_exception())) {
        ++refusals;
        continue;
      }
      std::string what = "an exception of unknown type";
      try {
        throw;
      } catch (const std::exception& e) {
        what = e.what();
      } catch (...) {
      }
      ADD_FAILURE() << reader << ", input " << i << " (seed " << rng_seed << "): undocumented exception: " << what
                    << "\n--- input ---\n"
                    << input.substr(0, 2000);
    }
  }
  // Both outcomes occur, so the mutations reach past the first check and the test can fail.
  EXPECT_GT(refusals, 0) << reader;
  EXPECT_EQ(parsed + refusals, kInputsPerReader) << reader;
  std::printf("%s: %d inputs, %d parsed, %d refused\n", reader, kInputsPerReader, parsed, refusals);
}

// Recomputes the CRC of every whole chunk of a (mutated) PNG, so that half of the inputs get past
// libpng's checksums into the decoder and the reader's own checks.
std::string fix_png_crcs(std::string s) {
  std::size_t p = 8;
  while (p + 12 <= s.size()) {
    const uint32_t len = uint32_t(uint8_t(s[p])) << 24 | uint32_t(uint8_t(s[p + 1])) << 16 |
                         uint32_t(uint8_t(s[p + 2])) << 8 | uint32_t(uint8_t(s[p + 3]));
    if (len > s.size() - p - 12) break;
    const uint32_t crc = uint32_t(crc32(0, reinterpret_cast<const Bytef*>(s.data() + p + 4), uInt(len + 4)));
    for (int k = 0; k < 4; ++k) s[p + 8 + len + std::size_t(k)] = char((crc >> (24 - 8 * k)) & 0xFF);
    p += 12 + len;
  }
  return s;
}

template <class E>
bool is(std::exception_ptr ep) {
  try {
    std::rethrow_exception(ep);
  } catch (const E&) {
    return true;
  } catch (...) {
    return false;
  }
}

class Fuzz : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("parallax_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

const std::vector<std::string> kYamlTokens = {":",    "- ",     "[",    "]",     "{",
                                              "}",    ",",      "\n",   "  ",    "&a ",
                                              "*a",   "!!str ", "? ",   "|\n",   ">\n",
                                              "'",    "\"",     "#",    "---\n", "...\n",
                                              "nan",  "inf",    "-1",   "1e308", "99999999999999999999",
                                              "0x10", "true",   "null", "~",     "\t"};

TEST_F(Fuzz, ConfigurationReader) {
  std::vector<std::string> seeds;
  for (const char* f : {"ruf2018-census.yaml", "ruf2018-sad.yaml"})
    seeds.push_back(read_all(fs::path(PARALLAX_CONFIG_DIR) / f));
  seeds.push_back("paths: [0, 90, 180]\nwindow: 7x5\nfifo_depth_cost: 4\nii_aggregate: 2\nrectify: bilinear\n");
  std::vector<std::string> tokens = kYamlTokens;
  for (const auto& f : config::field_names()) tokens.push_back(f + ": ");
  fuzz(
      "configuration", seeds, tokens, 15001,
      [](const std::string& text) { (void)config::parse_config(text, "fuzz.yaml"); }, is<config::ConfigError>);
}

TEST_F(Fuzz, SweepReader) {
  std::vector<std::string> seeds;
  for (const auto& e : fs::directory_iterator(fs::path(PARALLAX_CONFIG_DIR) / "sweeps"))
    if (e.path().extension() == ".yaml") seeds.push_back(read_all(e.path()));
  ASSERT_FALSE(seeds.empty());
  std::vector<std::string> tokens = kYamlTokens;
  for (const char* k : {"axes: ", "objectives: ", "constraints: ", "flight: ", "strategy: ", "samples: ", "max ",
                        "min ", "p2: [", "device: ", "gt: "})
    tokens.emplace_back(k);
  fuzz(
      "sweep", seeds, tokens, 15002, [](const std::string& text) { (void)search::parse_sweep(text, "fuzz.yaml"); },
      is<eval::InputError>);
}

TEST_F(Fuzz, ScenarioReader) {
  std::vector<std::string> seeds;
  for (const auto& e : fs::directory_iterator(fs::path(PARALLAX_CONFIG_DIR) / "scenarios"))
    if (e.path().extension() == ".yaml") seeds.push_back(read_all(e.path()));
  ASSERT_FALSE(seeds.empty());
  const fs::path file = dir_ / "scenario.yaml";
  fuzz(
      "scenario", seeds, kYamlTokens, 15003,
      [&](const std::string& text) {
        write_all(file, text);
        (void)uav::load_scenario(file.string());
      },
      is<eval::InputError>);
}

// The obstacle list `scene` writes and `avoid` reads (obstacles.json).
TEST_F(Fuzz, ObstacleListReader) {
  uav::Scene scene;
  scene.cylinders.push_back({0.5, 10.0, 0.3, 8.0});
  scene.boxes.push_back({-3.0, 3.0, 15.0, 15.5, 6.0});
  const uav::Rig rig = uav::rig_of(uav::RigSpec{}, 640, 360);
  const fs::path file = dir_ / "obstacles.json";
  uav::write_truth(file.string(), {uav::obstacles_in_view(scene, rig, 640, Eigen::Vector3d(0, -1.6, 0), 40.0)});
  const std::vector<std::string> seeds = {read_all(file)};
  const std::vector<std::string> tokens = {"{",          "}",
                                           "[",          "]",
                                           ",",          ":",
                                           "\"",         "null",
                                           "-1",         "1e999",
                                           "\"box\"",    "\"cylinder\"",
                                           "\"frames\"", "\"obstacles\"",
                                           "\"id\""};
  fuzz(
      "obstacles", seeds, tokens, 15011,
      [&](const std::string& text) {
        write_all(file, text);
        (void)uav::read_truth(file.string());
      },
      is<eval::InputError>);
}

TEST_F(Fuzz, CsynthReportReader) {
  const std::vector<std::string> seeds = {read_all(fs::path(PARALLAX_TEST_DATA_DIR) / "csynth_sample.xml")};
  const std::vector<std::string> tokens = {"<",
                                           ">",
                                           "</",
                                           "/>",
                                           "<PipelineII>",
                                           "</PipelineII>",
                                           "<TargetClockPeriod>",
                                           "undef",
                                           "-",
                                           "0",
                                           "-5",
                                           "nan",
                                           "1e99",
                                           "&amp;",
                                           "<![CDATA[",
                                           "]]>",
                                           "\"",
                                           "<!--",
                                           "-->",
                                           "99999999999999999999"};
  const fs::path file = dir_ / "csynth.xml";
  fuzz(
      "csynth.xml", seeds, tokens, 15004,
      [&](const std::string& text) {
        write_all(file, text);
        (void)hls_flow::read_csynth_xml(file.string());
      },
      is<eval::InputError>);
}

TEST_F(Fuzz, KittiDisparityPng) {
  cv::Mat d(24, 40, CV_16UC1);
  for (int y = 0; y < d.rows; ++y)
    for (int x = 0; x < d.cols; ++x) d.at<uint16_t>(y, x) = uint16_t((x * 256 + y * 37) % 65536);
  std::vector<uchar> png;
  ASSERT_TRUE(cv::imencode(".png", d, png));
  const std::vector<std::string> seeds = {std::string(png.begin(), png.end())};
  const std::vector<std::string> tokens = {"IHDR",
                                           "IDAT",
                                           "IEND",
                                           "PLTE",
                                           std::string("\0\0\0\0", 4),
                                           std::string("\xff\xff\xff\xff", 4),
                                           std::string("\x00\x01\x00\x00", 4)};
  const fs::path file = dir_ / "d.png";
  int n = 0;
  fuzz(
      "KITTI disparity PNG", seeds, tokens, 15005,
      [&](const std::string& bytes) {
        write_all(file, ++n % 2 == 0 ? fix_png_crcs(bytes) : bytes);
        (void)eval::read_kitti_disparity(file);
      },
      is<eval::InputError>);
}

TEST_F(Fuzz, PfmDisparity) {
  cv::Mat v(12, 20, CV_32FC1);
  for (int y = 0; y < v.rows; ++y)
    for (int x = 0; x < v.cols; ++x) v.at<float>(y, x) = (x + y) % 7 == 0 ? INFINITY : float(x) * 1.5f + float(y);
  const std::vector<std::string> seeds = {parallax::test::pfm_bytes(v, true), parallax::test::pfm_bytes(v, false)};
  const std::vector<std::string> tokens = {"Pf\n", "PF\n",        "P6\n", "\n",   " ",
                                           "-1.0", "1.0",         "0",    "-0",   "nan",
                                           "inf",  "99999999999", "-5",   "1e39", std::string("\0\0\x80\x7f", 4)};
  const fs::path file = dir_ / "disp0.pfm";
  fuzz(
      "PFM disparity", seeds, tokens, 15006,
      [&](const std::string& bytes) {
        write_all(file, bytes);
        (void)eval::read_pfm_disparity(file);
      },
      is<eval::InputError>);
}

// A small real store (a sweep, three results with frames), its bytes mutated: opened read-only and
// read as pareto and report read it. Then its metrics column rewritten with mutated JSON.
TEST_F(Fuzz, ResultStore) {
  const fs::path good = dir_ / "good.db";
  {
    search::ResultStore store(good.string());
    search::SweepSpec spec;
    spec.name = "fuzz";
    spec.base = std::string(PARALLAX_CONFIG_DIR) + "/ruf2018-census.yaml";
    store.put_sweep(spec, "/data/kitti", "{}");
    for (int k = 0; k < 3; ++k) {
      search::ResultStore::Row r;
      r.hash = "00000000000000a" + std::to_string(k);
      r.sweep = "fuzz";
      r.config_yaml = "p2: " + std::to_string(40 + k) + "\n";
      r.status = "ok";
      r.metrics = {{"correct_3px_pct", 90.0 + k}, {"bram18k", 100.0 - k}, {"fps", 29.5}};
      r.frames = {{"000001", {{"correct_3px_pct", 91.0}}}, {"000005", {{"correct_3px_pct", 89.0}}}};
      r.measurement = "{}";
      store.put_design(r);
    }
  }
  const std::string bytes = read_all(good);
  ASSERT_GT(bytes.size(), 1000u);
  const fs::path file = dir_ / "store.db";
  auto read_store = [&](const fs::path& f) {
    search::ResultStore store(f.string(), search::ResultStore::Access::read);
    for (const auto& s : store.sweeps()) (void)store.designs(s.name, false);
    (void)store.designs("", true);
    (void)store.count_designs();
  };
  const std::vector<std::string> tokens = {std::string(16, '\0'),
                                           std::string(4, '\xff'),
                                           "SQLite format 3",
                                           "{",
                                           "}",
                                           "\"correct_3px_pct\":",
                                           "NaN",
                                           "null",
                                           "[",
                                           "]"};
  fuzz(
      "store file", {bytes}, tokens, 15007,
      [&](const std::string& b) {
        fs::remove(file);
        write_all(file, b);
        read_store(file);
      },
      is<eval::InputError>);
  // The metrics column: what another program (or an older Parallax) may have written there.
  const std::vector<std::string> json_seeds = {"{\"correct_3px_pct\": 91.5, \"bram18k\": 120, \"fps\": 29.5}",
                                               "{\"a\": [1, 2], \"b\": {\"c\": null}}"};
  const std::vector<std::string> json_tokens = {"{",   "}",         "[",     "]",     ",",    ":",       "\"", "null",
                                                "NaN", "-Infinity", "1e999", "\"x\"", "true", "\\u0000", "-"};
  fuzz(
      "store metrics JSON", json_seeds, json_tokens, 15008,
      [&](const std::string& text) {
        fs::remove(file);
        fs::copy_file(good, file);
        sqlite3* db = nullptr;
        ASSERT_EQ(sqlite3_open(file.c_str(), &db), SQLITE_OK);
        sqlite3_stmt* st = nullptr;
        ASSERT_EQ(sqlite3_prepare_v2(db, "UPDATE results SET metrics = ?1", -1, &st, nullptr), SQLITE_OK);
        sqlite3_bind_text(st, 1, text.data(), int(text.size()), SQLITE_TRANSIENT);
        EXPECT_EQ(sqlite3_step(st), SQLITE_DONE);
        sqlite3_finalize(st);
        sqlite3_close(db);
        read_store(file);
        throw eval::InputError("read");  // counted as a refusal: reading must not throw anything else
      },
      is<eval::InputError>);
}

}  // namespace
