// The HLS export's generated sources against golden files (PARALLAX_REGENERATE=1 rewrites them),
// the copies of the kernels, and the export's refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <regex>
#include <set>

#include "export_util.hpp"
#include "parallax/config/config.hpp"
#include "parallax/kernels/pipeline.hpp"
#include "parallax/search/sweep.hpp"

namespace {

namespace fs = std::filesystem;
using parallax::test::export_design;
using parallax::test::fresh_dir;
using parallax::test::read_file;
using parallax::test::shell;
namespace kern = parallax::kern;

const fs::path kSource = PARALLAX_SOURCE_DIR;

// The files the export generates (the rest are copies, checked below, and binary data).
const char* const kGenerated[] = {"src/parallax_config.hpp",
                                  "src/parallax_top.hpp",
                                  "src/parallax_top.cpp",
                                  "tb/parallax_tb.cpp",
                                  "Makefile",
                                  "run_hls.tcl",
                                  "hls_config.cfg",
                                  "hls_config_reduced.cfg",
                                  "README.md",
                                  "design.yaml"};

// The designs whose generated sources are held byte for byte: the seed (one pass), the frontier
// (the 180-degree path on reversed rows), the seed with eight paths (two passes through DDR) and
// the synthesised seed (rectification on the FPGA): one per variant of the top.
struct GoldenDesign {
  const char* folder;
  const char* config;
  const char* extra;
};
const GoldenDesign kGoldenDesigns[] = {{"ruf2018-census", "configs/ruf2018-census.yaml", ""},
                                       {"frontier-census", "configs/frontier-census.yaml", ""},
                                       {"two-pass-census", "configs/ruf2018-census.yaml", "--set paths=8"},
                                       {"ruf2018-synthesised", "configs/ruf2018-synthesised.yaml", ""}};

TEST(HlsExport, GeneratedSourcesMatchGoldenFiles) {
  const char* regen = std::getenv("PARALLAX_REGENERATE");
  const bool rewrite = regen && std::string(regen) == "1";
  for (const GoldenDesign& d : kGoldenDesigns) {
    SCOPED_TRACE(d.folder);
    const fs::path out = fresh_dir(std::string("golden_") + d.folder);
    const auto r = export_design(d.config, out, d.extra);
    ASSERT_EQ(r.status, 0) << r.output;
    const fs::path golden = kSource / "tests/hls/golden" / d.folder;
    for (const char* f : kGenerated) {
      if (rewrite) {
        fs::create_directories((golden / f).parent_path());
        fs::copy_file(out / f, golden / f, fs::copy_options::overwrite_existing);
        continue;
      }
      ASSERT_TRUE(fs::exists(golden / f)) << golden / f << " missing; run with PARALLAX_REGENERATE=1 once";
      EXPECT_EQ(read_file(out / f), read_file(golden / f))
          << f << " differs from its golden file; if the change is intended, rerun with PARALLAX_REGENERATE=1 and "
          << "review the diff of tests/hls/golden";
    }
    fs::remove_all(out);
  }
  if (rewrite) GTEST_SKIP() << "PARALLAX_REGENERATE=1: rewrote tests/hls/golden";
}

TEST(HlsExport, KernelsAndCompatHeadersAreExactCopies) {
  const fs::path out = fresh_dir("copies");
  const auto r = export_design("configs/ruf2018-sad.yaml", out);
  ASSERT_EQ(r.status, 0) << r.output;
  int kernels = 0;
  for (const auto& e : fs::directory_iterator(kSource / "kernels/include/parallax/kernels")) {
    EXPECT_EQ(read_file(out / "src/parallax/kernels" / e.path().filename()), read_file(e.path())) << e.path();
    ++kernels;
  }
  EXPECT_GE(kernels, 10);
  for (const char* h : {"ap_int.h", "ap_axi_sdata.h", "hls_stream.h"})
    EXPECT_EQ(read_file(out / "compat" / h), read_file(kSource / "hls/compat" / h)) << h;
  // The SAD preset picks the SAD stage and its penalty registers.
  const std::string top = read_file(out / "src/parallax_top.cpp"), cfg = read_file(out / "src/parallax_config.hpp");
  EXPECT_NE(top.find("kern::SadCostStage<DesignCaps>"), std::string::npos);
  EXPECT_NE(cfg.find("constexpr unsigned kDefaultP2 = 800;"), std::string::npos);
  EXPECT_NE(cfg.find("constexpr int kPenaltyBits = 10;"), std::string::npos);
  fs::remove_all(out);
}

TEST(HlsExport, RefusesAnInvalidConfigurationAndWritesNothing) {
  const fs::path out = fresh_dir("refuse");
  auto r = export_design("configs/ruf2018-census.yaml", out, "--set p1=40");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("p1"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
  auto maps = export_design(
      "configs/ruf2018-census.yaml", out,
      "--set rectify=nearest --set rectify_maps_left=/nonexistent/l.yml --set rectify_maps_right=/nonexistent/r.yml");
  EXPECT_EQ(maps.status, 2) << maps.output;
  EXPECT_NE(maps.output.find("/nonexistent/l.yml"), std::string::npos) << maps.output;
  EXPECT_FALSE(fs::exists(out));
}

TEST(HlsExport, RefusesAForeignFolderAndKeepsItsFiles) {
  const fs::path out = fresh_dir("foreign");
  fs::create_directories(out);
  { std::ofstream(out / "notes.txt") << "mine"; }
  const auto r = export_design("configs/ruf2018-census.yaml", out);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("not empty"), std::string::npos) << r.output;
  EXPECT_EQ(read_file(out / "notes.txt"), "mine");
  EXPECT_FALSE(fs::exists(out / "Makefile"));
  EXPECT_EQ(r.output.find("simulating"), std::string::npos) << "refused before simulating";
  // An earlier export's folder is overwritten.
  fs::remove_all(out);
  ASSERT_EQ(export_design("configs/ruf2018-census.yaml", out).status, 0);
  const auto again = export_design("configs/ruf2018-census.yaml", out);
  EXPECT_EQ(again.status, 0) << again.output;
  fs::remove_all(out);
}

TEST(HlsExport, NeedsExactlyOneSource) {
  const fs::path out = fresh_dir("source");
  const std::string cli = PARALLAX_CLI;
  auto none = shell(cli + " export-hls --out " + out.string());
  EXPECT_EQ(none.status, 2) << none.output;
  EXPECT_NE(none.output.find("either --config"), std::string::npos) << none.output;
  auto both = shell(cli + " export-hls --config " + (kSource / "configs/ruf2018-census.yaml").string() +
                    " --db x.db --design abcd --out " + out.string());
  EXPECT_EQ(both.status, 2) << both.output;
  auto missing = shell(cli + " export-hls --db /nonexistent/x.db --design abcd --out " + out.string());
  EXPECT_EQ(missing.status, 2) << missing.output;
  EXPECT_NE(missing.output.find("/nonexistent/x.db"), std::string::npos) << missing.output;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace

namespace {

// A design picked from a results store by a hash prefix exports like its configuration.
TEST(HlsExport, ExportsADesignOfAResultsStore) {
  const fs::path dir = fresh_dir("db");
  fs::create_directories(dir);
  const std::string db = (dir / "sweep.db").string();
  {
    parallax::search::ResultStore store(db);
    parallax::config::PipelineConfig c =
        parallax::config::load_config((kSource / "configs/ruf2018-census.yaml").string());
    c.name = "from-store";
    c.p2 = 48;
    parallax::search::ResultStore::Row row;
    row.hash = "0123456789abcdef";
    row.sweep = "test";
    row.config_yaml = parallax::config::to_yaml(c);
    row.status = "ok";
    store.put_design(row);
    row.hash = "0123ffffffffffff";
    row.status = "invalid";
    row.reason = "field 'p1': too big";
    store.put_design(row);
  }
  const std::string cli = std::string("cd ") + PARALLAX_SOURCE_DIR + " && " + PARALLAX_CLI + " export-hls --db " + db;
  auto ambiguous = shell(cli + " --design 0123 --out " + (dir / "a").string());
  EXPECT_EQ(ambiguous.status, 2) << ambiguous.output;
  EXPECT_NE(ambiguous.output.find("2 designs start with '0123'"), std::string::npos) << ambiguous.output;
  auto invalid = shell(cli + " --design 0123f --out " + (dir / "b").string());
  EXPECT_EQ(invalid.status, 2) << invalid.output;
  EXPECT_NE(invalid.output.find("too big"), std::string::npos) << invalid.output;
  auto ok = shell(cli + " --design 01234567 --out " + (dir / "c").string());
  ASSERT_EQ(ok.status, 0) << ok.output;
  const std::string cfg = read_file(dir / "c/src/parallax_config.hpp");
  EXPECT_NE(cfg.find("Design from-store"), std::string::npos);
  EXPECT_NE(cfg.find("design 0123456789abcdef"), std::string::npos);
  EXPECT_NE(cfg.find("constexpr unsigned kDefaultP2 = 48;"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace

namespace {

// The page of `import-hls --html`: the model's figures beside the synthesis report's.
TEST(HlsImport, PageShowsModelAndSynthesisSideBySide) {
  const fs::path dir = fresh_dir("import");
  fs::create_directories(dir);
  const auto r = shell(std::string(PARALLAX_CLI) + " import-hls --report " +
                       (kSource / "tests/explore/hls_flow/data/csynth_sample.xml").string() + " --config " +
                       (kSource / "configs/ruf2018-census.yaml").string() + " --html " + (dir / "p.html").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("model vs synthesis"), std::string::npos) << r.output;
  const std::string page = read_file(dir / "p.html");
  EXPECT_NE(page.find("Model and synthesis"), std::string::npos);
  EXPECT_NE(page.find("4631240"), std::string::npos);  // the report's worst latency
  EXPECT_NE(page.find("II aggregate_loop"), std::string::npos);
  const auto bad = shell(std::string(PARALLAX_CLI) + " import-hls --report " +
                         (kSource / "tests/explore/hls_flow/data/csynth_sample.xml").string() + " --html " +
                         (dir / "q.html").string());
  EXPECT_EQ(bad.status, 2) << bad.output;
  fs::remove_all(dir);
}

}  // namespace

namespace {

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

// The directives the issue asks of the generated project, named: DATAFLOW, PIPELINE, STREAM
// depth, BIND_STORAGE, ARRAY_PARTITION (through the kernels' hooks), AXI4-Stream and AXI4-Lite
// interfaces, labelled loops, and the scripts' steps.
TEST(HlsExport, ProjectCarriesTheDirectivesAndSteps) {
  const fs::path out = fresh_dir("directives");
  ASSERT_EQ(export_design("configs/ruf2018-census.yaml", out).status, 0);
  const std::string top = read_file(out / "src/parallax_top.cpp");
  const std::string cfg = read_file(out / "src/parallax_config.hpp");
  for (const char* s :
       {"#pragma HLS DATAFLOW", "#pragma HLS PIPELINE II=1", "#pragma HLS STREAM variable=sum depth=30",
        "#pragma HLS BIND_STORAGE variable=cost type=fifo", "#pragma HLS INTERFACE mode=axis port=left_in",
        "#pragma HLS INTERFACE mode=axis port=disparity_out",
        "#pragma HLS INTERFACE mode=s_axilite port=p1 bundle=control",
        "#pragma HLS INTERFACE mode=s_axilite port=p2 bundle=control",
        "#pragma HLS INTERFACE mode=s_axilite port=lr_tolerance bundle=control",
        "cost_loop:", "aggregate_loop:", "wta_lr_loop:", "median_loop:"})
    EXPECT_NE(top.find(s), std::string::npos) << s;
  for (const char* s :
       {"#define PX_HLS_SGM_ROW_IMPL bram", "HLS BIND_STORAGE variable=mem_", "constexpr int kCostBits = 5;",
        "constexpr int kAggregateBits = 9;", "constexpr int kDepthSum = 30;"})
    EXPECT_NE(cfg.find(s), std::string::npos) << s;
  // The hooks that place the storage directives, and the kernels' own structural directives, are
  // in the kernels the project carries (in the constructors, beside the members).
  const std::string sgm = read_file(out / "src/parallax/kernels/sgm.hpp");
  const std::string lb = read_file(out / "src/parallax/kernels/line_buffer.hpp");
  EXPECT_NE(sgm.find("PX_BIND_RAM_S2P(row_, PX_HLS_SGM_ROW_IMPL)"), std::string::npos);
  EXPECT_NE(sgm.find("PX_RESHAPE_COMPLETE(row_, 3)"), std::string::npos);  // a word of PU lanes per chunk
  EXPECT_NE(lb.find("PX_PARTITION_COMPLETE(mem_, 1)"), std::string::npos);
  // DEPENDENCE sits in the per-firing member functions that access the arrays (not in a
  // constructor, outside any loop: review R3), and each stage function inlines its kernel's calls
  // into its pipelined loop (INLINE recursive), so the pragma lands in the loop body.
  const std::string access = read_file(out / "src/parallax/kernels/access.hpp");
  EXPECT_NE(access.find("PX_PRAGMA_TEXT_(HLS DEPENDENCE variable=VAR type=inter direction=RAW dependent=false)"),
            std::string::npos);
  const std::size_t fire = sgm.find("void fire(const AggPlan& pl");
  const std::size_t row_dependence = sgm.find("PX_NO_DEPENDENCE(row_)");
  ASSERT_NE(fire, std::string::npos);
  ASSERT_NE(row_dependence, std::string::npos);
  EXPECT_LT(fire, row_dependence);
  EXPECT_LT(row_dependence - fire, 300u);                    // the first lines of fire()'s body
  EXPECT_EQ(sgm.find("HLS DEPENDENCE"), std::string::npos);  // no other DEPENDENCE left behind
  // The line buffers carry none: a waiting stage reads, at the next firing, the column the last
  // firing pushed (a true read-after-write at distance 1, review S1).
  EXPECT_EQ(lb.find("PX_NO_DEPENDENCE"), std::string::npos);
  EXPECT_EQ(lb.find("HLS DEPENDENCE"), std::string::npos);
  const std::size_t stages = count_of(top, " stage;\n");
  EXPECT_EQ(stages, 4u);  // cost, aggregate, wta_lr, median
  EXPECT_EQ(count_of(top, "#pragma HLS INLINE recursive\n"), stages);
  EXPECT_NE(lb.find("HLS ARRAY_PARTITION variable=v_ type=complete dim=0"), std::string::npos);
  const std::string tcl = read_file(out / "run_hls.tcl");
  for (const char* s : {"csim_design", "csynth_design", "cosim_design", "export_design", "create_clock -period 5.000"})
    EXPECT_NE(tcl.find(s), std::string::npos) << s;
  const std::string hcfg = read_file(out / "hls_config.cfg");
  for (const char* s :
       {"part=xczu3eg-sbva484-1-e", "clock=5.000ns", "syn.top=parallax_top", "tb.file=tb/parallax_tb.cpp"})
    EXPECT_NE(hcfg.find(s), std::string::npos) << s;
  const std::string readme = read_file(out / "README.md");
  EXPECT_NE(readme.find("cycle 4610656 = 23.05 ms"), std::string::npos);
  EXPECT_NE(readme.find("| **total** | **80**"),
            std::string::npos);  // the model's 78 and the 2 of the sum FIFO, 30 deep
  fs::remove_all(out);
}

}  // namespace

namespace {

const char kPair[] =
    " --left data/kitti2015-640x360/training/image_2/000001_10.png"
    " --right data/kitti2015-640x360/training/image_3/000001_10.png";

// The cycle model's stage of each loop of the top that runs until its stage is done.
std::string loop_stage(const std::string& label) {
  return label.substr(0, label.size() - std::string("_loop").size());
}

// The body of each function defined at the start of a line ("void name(" ... "{" ... "}"), by name.
std::map<std::string, std::string> function_bodies(const std::string& src) {
  std::map<std::string, std::string> out;
  static const std::regex def(R"(\n(?:template <[^>]*>\n)?void (\w+)\()");
  for (auto it = std::sregex_iterator(src.begin(), src.end(), def); it != std::sregex_iterator(); ++it) {
    const std::size_t open = src.find(") {", std::size_t(it->position(0)));
    const std::size_t semi = src.find(");", std::size_t(it->position(0)));
    if (open == std::string::npos || (semi != std::string::npos && semi < open)) continue;  // a declaration
    std::size_t i = open + 2;
    int depth = 0;
    const std::size_t start = i;
    for (; i < src.size(); ++i) {
      if (src[i] == '{') ++depth;
      if (src[i] == '}' && --depth == 0) break;
    }
    out[(*it)[1]] = src.substr(start, i + 1 - start);
  }
  return out;
}

// Every loop of the top whose trip count is known only at run time (`while (!stage.done())`)
// carries LOOP_TRIPCOUNT min = max = avg = its stage's firings per frame in `parallax sim --json`
// for the same design and pair (full frame; the reduced frame's are checked by counting the
// iterations in C simulation, csim_test.cpp).
class HlsTripCount : public ::testing::TestWithParam<const char*> {};

TEST_P(HlsTripCount, EveryRunTimeLoopCarriesTheSimulatorsFirings) {
  const fs::path out = fresh_dir("tripcount");
  ASSERT_EQ(export_design("configs/ruf2018-census.yaml", out, GetParam()).status, 0);
  const auto sim = shell(std::string("cd ") + PARALLAX_SOURCE_DIR + " && " + PARALLAX_CLI +
                         " sim --config configs/ruf2018-census.yaml " + GetParam() + kPair + " --json --no-sizing");
  ASSERT_EQ(sim.status, 0) << sim.output;
  std::map<std::string, long long> fires;
  static const std::regex stage(R"re("fires":\s*(\d+),[^{}]*"name":\s*"(\w+)")re");
  for (auto it = std::sregex_iterator(sim.output.begin(), sim.output.end(), stage); it != std::sregex_iterator(); ++it)
    fires[(*it)[2]] = std::stoll((*it)[1]);
  ASSERT_GE(fires.size(), 5u) << sim.output;
  // II and pipeline depth of every stage, as the simulator reports them: stages.json carries the
  // same, and each loop's PIPELINE pragma the same II.
  std::map<std::string, std::pair<long long, long long>> timing;
  static const std::regex stage_timing(
      R"re("ii_cycles":\s*(\d+),[^{}]*"latency_cycles":\s*(\d+),[^{}]*"name":\s*"(\w+)")re");
  for (auto it = std::sregex_iterator(sim.output.begin(), sim.output.end(), stage_timing); it != std::sregex_iterator();
       ++it)
    timing[(*it)[3]] = {std::stoll((*it)[1]), std::stoll((*it)[2])};
  ASSERT_EQ(timing.size(), fires.size()) << sim.output;
  const std::string stages_json = read_file(out / "stages.json");
  static const std::regex json_entry(R"re(\{"name": "(\w+)", "ii_cycles": (\d+), "depth_cycles": (\d+)\})re");
  std::map<std::string, std::pair<long long, long long>> exported;
  for (auto it = std::sregex_iterator(stages_json.begin(), stages_json.end(), json_entry); it != std::sregex_iterator();
       ++it)
    exported[(*it)[1]] = {std::stoll((*it)[2]), std::stoll((*it)[3])};
  EXPECT_EQ(exported, timing) << stages_json;

  const std::string top = read_file(out / "src/parallax_top.cpp");
  static const std::regex loop(
      R"((\w+_loop):\n\s*while \(!stage\.done\(\)\) \{\n#pragma HLS PIPELINE II=(\d+)\n)"
      R"(#ifndef PARALLAX_REDUCED_FRAME\n#pragma HLS LOOP_TRIPCOUNT min=(\d+) max=(\d+) avg=(\d+)\n)"
      R"(#else\n#pragma HLS LOOP_TRIPCOUNT min=(\d+) max=(\d+) avg=(\d+)\n#endif\n)");
  std::set<std::string> labels;
  for (auto it = std::sregex_iterator(top.begin(), top.end(), loop); it != std::sregex_iterator(); ++it) {
    const std::string label = (*it)[1];
    labels.insert(label);
    ASSERT_EQ(fires.count(loop_stage(label)), 1u) << label << " has no stage in parallax sim --json";
    const long long want = fires[loop_stage(label)];
    EXPECT_EQ(std::stoll((*it)[2]), timing[loop_stage(label)].first) << label << ": PIPELINE II is the derived II";
    EXPECT_EQ(std::stoll((*it)[3]), want) << label;
    EXPECT_EQ(std::stoll((*it)[4]), want) << label;
    EXPECT_EQ(std::stoll((*it)[5]), want) << label;
    EXPECT_EQ((*it)[6], (*it)[7]) << label << ": reduced frame, min = max";
    EXPECT_LT(std::stoll((*it)[6]), want / 10) << label << ": the reduced frame is 16 of 360 rows";
  }
  // Every run-time loop was matched, i.e. has its LOOP_TRIPCOUNT.
  std::size_t whiles = 0;
  for (std::size_t at = top.find("while (!stage.done())"); at != std::string::npos;
       at = top.find("while (!stage.done())", at + 1))
    ++whiles;
  EXPECT_EQ(labels.size(), whiles) << top;
  std::set<std::string> want = {"cost_loop", "aggregate_loop", "wta_lr_loop", "median_loop"};
  if (std::string(GetParam()).find("paths=8") != std::string::npos) want.insert("aggregate_back_loop");
  EXPECT_EQ(labels, want);
  fs::remove_all(out);
}

INSTANTIATE_TEST_SUITE_P(Designs, HlsTripCount, ::testing::Values("", "--set paths=8"),
                         [](const ::testing::TestParamInfo<const char*>& i) {
                           return std::string(i.param[0] ? "eight_paths" : "one_pass");
                         });

// Two passes: the frame buffer and the map in memory are accessed only at ascending addresses
// in burst-friendly loops (UG1399): every m_axi access is the innermost loop's counter plus a term
// the loop does not change, sits directly in the body of a pipelined loop with a compile-time
// bound (no condition around it), and each direction has its bundle: pass 1's frame writes on
// gmem_wr, pass 2's reads on gmem_rd, the map on gmem_map; bursts as long as a segment.
TEST(HlsExport, TwoPassMemoryAccessesAreAscendingBursts) {
  const fs::path out = fresh_dir("bursts");
  ASSERT_EQ(export_design("configs/ruf2018-census.yaml", out, "--set paths=8").status, 0);
  static const std::regex comments(R"(//[^\n]*)");
  const std::string top = std::regex_replace(read_file(out / "src/parallax_top.cpp"), comments, "");
  static const std::regex access(R"(\b(frame|disparity)\[([^\]]*)\])");
  std::multiset<std::string> seen;
  for (auto it = std::sregex_iterator(top.begin(), top.end(), access); it != std::sregex_iterator(); ++it) {
    seen.insert((*it)[0]);
    // The line and the nearest loop header above it: the access is in that loop's body itself.
    const std::size_t at = std::size_t(it->position(0));
    const std::size_t line_start = top.rfind('\n', at) + 1;
    const std::size_t indent = top.find_first_not_of(' ', line_start) - line_start;
    const std::size_t loop_at = top.rfind("for (int ", at);
    ASSERT_NE(loop_at, std::string::npos);
    const std::size_t loop_line = top.rfind('\n', loop_at) + 1;
    const std::string header = top.substr(loop_at, top.find('\n', loop_at) - loop_at);
    static const std::regex counted(R"(for \(int (\w) = \d+; \1 < k\w+; \+\+\1\) \{)");
    std::smatch m;
    ASSERT_TRUE(std::regex_match(header, m, counted)) << header << ": not a loop with a compile-time bound";
    EXPECT_EQ(indent, loop_at - loop_line + 2) << (*it)[0] << ": not directly in the body of " << header;
    const std::string index = (*it)[2];
    EXPECT_TRUE(index == m[1].str() || (index.size() > 4 && index.substr(index.size() - 4) == " + " + m[1].str()))
        << (*it)[0] << ": the index is not the counter of " << header << " plus a constant of the loop";
    EXPECT_EQ(top.substr(loop_at, at - loop_at).find("if ("), std::string::npos) << (*it)[0] << ": under a condition";
    EXPECT_NE(top.substr(loop_at, at - loop_at).find("#pragma HLS PIPELINE II=1"), std::string::npos) << (*it)[0];
  }
  const std::multiset<std::string> want = {"frame[(kFrameSegments - j) * kFrameSegmentWords + k]", "frame[k]",
                                           "frame[i]", "disparity[(kMapSegments - j) * kMapSegmentPixels + k]",
                                           "disparity[k]"};
  EXPECT_EQ(seen, want);
  for (const char* pragma : {"port=frame_write offset=slave bundle=gmem_wr depth=2304000 max_write_burst_length=256",
                             "port=frame_read offset=slave bundle=gmem_rd depth=2304000 max_read_burst_length=256",
                             "port=disparity offset=slave bundle=gmem_map depth=230400 max_write_burst_length=256",
                             "port=frame_write offset=slave bundle=gmem_wr depth=102400",
                             "port=frame_read offset=slave bundle=gmem_rd depth=102400"})
    EXPECT_NE(top.find(pragma), std::string::npos) << pragma;
  static const std::regex m_axi(R"(mode=m_axi port=(\w+) offset=slave bundle=(\w+))");
  std::map<std::string, std::set<std::string>> bundles;
  for (auto it = std::sregex_iterator(top.begin(), top.end(), m_axi); it != std::sregex_iterator(); ++it)
    bundles[(*it)[2]].insert((*it)[1]);
  const std::map<std::string, std::set<std::string>> one_per_direction = {
      {"gmem_wr", {"frame_write"}}, {"gmem_rd", {"frame_read"}}, {"gmem_map", {"disparity"}}};
  EXPECT_EQ(bundles, one_per_direction);
  // The seed's pair is 6 x (5 + 10) = 90 bits: one 128-bit word per firing.
  const std::string header = read_file(out / "src/parallax_top.hpp");
  EXPECT_NE(header.find("kFrameWordBits = parallax::kern::frame_word_bits_of(kFramePairBits);  // 128"),
            std::string::npos);
  EXPECT_NE(header.find("kFrameWords == 2304000 && kFrameSegmentPixels == 25 && kMapSegmentPixels == 256"),
            std::string::npos);
  fs::remove_all(out);
}

// The top reads the AXI4-Lite registers into locals and passes them to a separate DATAFLOW function
// (INLINE off): no register port is touched inside a DATAFLOW region, one pass or two.
TEST(HlsExport, RegistersAreReadOutsideTheDataflowRegion) {
  for (const char* sets : {"", "--set paths=8"}) {
    const fs::path out = fresh_dir("registers");
    ASSERT_EQ(export_design("configs/ruf2018-census.yaml", out, sets).status, 0);
    const auto bodies = function_bodies(read_file(out / "src/parallax_top.cpp"));
    ASSERT_EQ(bodies.count("parallax_top"), 1u);
    ASSERT_EQ(bodies.count("parallax_dataflow"), 1u);
    const std::string& top = bodies.at("parallax_top");
    EXPECT_EQ(top.find("#pragma HLS DATAFLOW"), std::string::npos) << sets << top;
    for (const char* s :
         {"#pragma HLS INTERFACE mode=s_axilite port=p1 bundle=control", "= p1.to_uint();", "= p2.to_uint();",
          "= lr_tolerance.to_uint();", "= uniqueness_pct.to_uint();", "parallax_dataflow("})
      EXPECT_NE(top.find(s), std::string::npos) << sets << ": " << s;
    EXPECT_NE(bodies.at("parallax_dataflow").find("#pragma HLS INLINE off\n#pragma HLS DATAFLOW\n"), std::string::npos);
    static const std::regex port(R"(\b(p1|p2|lr_tolerance|uniqueness_pct)\b|to_uint\(\))");
    int regions = 0;
    for (const auto& kv : bodies) {
      if (kv.second.find("#pragma HLS DATAFLOW") == std::string::npos) continue;
      ++regions;
      EXPECT_FALSE(std::regex_search(kv.second, port))
          << sets << ": a register port inside DATAFLOW " << kv.first << kv.second;
    }
    EXPECT_EQ(regions, std::string(sets).empty() ? 1 : 3) << sets;  // parallax_dataflow (+ forward_pass, backward_pass)
    fs::remove_all(out);
  }
}

// Each stage function takes only the registers its kernel reads: P1 and P2 the SGM aggregation
// (kernels/sgm.hpp), the tolerance the WTA / left-right check (kernels/wta_lr.hpp), none the cost
// and median stages; one pass or two.
TEST(HlsExport, StagesTakeOnlyTheRegistersTheirKernelsRead) {
  const std::map<std::string, std::set<std::string>> reads = {{"cost_stage", {}},
                                                              {"aggregate_stage", {"p1", "p2"}},
                                                              {"aggregate_back_stage", {"p1", "p2"}},
                                                              {"wta_lr_stage", {"lr_tolerance", "uniqueness_pct"}},
                                                              {"median_stage", {}}};
  for (const char* sets : {"", "--set paths=8"}) {
    const fs::path out = fresh_dir("stage_registers");
    ASSERT_EQ(export_design("configs/ruf2018-census.yaml", out, sets).status, 0);
    const std::string src = read_file(out / "src/parallax_top.cpp");
    static const std::regex def(R"(\nvoid (\w+)\(([^)]*)\) \{)");
    static const std::regex value(R"(\bunsigned (\w+))");
    std::map<std::string, std::set<std::string>> taken;
    for (auto it = std::sregex_iterator(src.begin(), src.end(), def); it != std::sregex_iterator(); ++it) {
      if (!reads.count((*it)[1])) continue;
      const std::string params = (*it)[2];
      std::set<std::string>& names = taken[(*it)[1]];
      for (auto v = std::sregex_iterator(params.begin(), params.end(), value); v != std::sregex_iterator(); ++v)
        names.insert((*v)[1]);
    }
    const std::set<std::string> stages =
        std::string(sets).empty()
            ? std::set<std::string>{"cost_stage", "aggregate_stage", "wta_lr_stage", "median_stage"}
            : std::set<std::string>{"cost_stage", "aggregate_stage", "aggregate_back_stage", "wta_lr_stage",
                                    "median_stage"};
    for (const std::string& st : stages) {
      ASSERT_EQ(taken.count(st), 1u) << sets << ": no stage function " << st;
      EXPECT_EQ(taken.at(st), reads.at(st)) << sets << ": " << st;
    }
    fs::remove_all(out);
  }
}

// The DATAFLOW regions are the pipeline table's variant (kernels/pipeline.hpp): one call per
// stage, each stream declared in the region of its pass and passed to exactly two calls, its
// producer's (where it comes after the stage's inputs) and its consumer's; one pass, the 180-degree
// path on reversed rows, two passes, and with rectification.
TEST(HlsExport, TheDataflowRegionsAreThePipelineTable) {
  struct Variant {
    const char* config;
    const char* sets;
    unsigned paths;
    bool rectify;
  };
  for (const Variant& v :
       {Variant{"configs/ruf2018-census.yaml", "", kern::kForwardPaths, false},
        Variant{"configs/ruf2018-census.yaml", "--set paths=5", kern::kForwardPaths | kern::kPath180, false},
        Variant{"configs/ruf2018-census.yaml", "--set paths=8", kern::kAllPaths, false},
        Variant{"configs/ruf2018-synthesised.yaml", "", kern::kForwardPaths, true}}) {
    SCOPED_TRACE(std::string(v.config) + " " + v.sets);
    const fs::path out = fresh_dir("dataflow");
    ASSERT_EQ(export_design(v.config, out, v.sets).status, 0);
    const auto bodies = function_bodies(read_file(out / "src/parallax_top.cpp"));
    // The calls of the regions, as argument lists.
    std::vector<std::vector<std::string>> calls;
    std::map<std::string, int> declared;
    static const std::regex call(R"(\n  ([\w<>]+)\(([^;]*)\);)"), stream(R"(hls::stream<[^>]+> (\w+)\(")"),
        arg(R"(\w+)");
    for (const char* region : {"parallax_dataflow", "forward_pass", "backward_pass"}) {
      if (!bodies.count(region)) continue;
      const std::string& body = bodies.at(region);
      for (auto it = std::sregex_iterator(body.begin(), body.end(), stream); it != std::sregex_iterator(); ++it)
        ++declared[(*it)[1]];
      for (auto it = std::sregex_iterator(body.begin(), body.end(), call); it != std::sregex_iterator(); ++it) {
        if ((*it)[1] == "forward_pass" || (*it)[1] == "backward_pass") continue;  // the regions themselves
        const std::string args = (*it)[2];
        std::vector<std::string> names;
        for (auto a = std::sregex_iterator(args.begin(), args.end(), arg); a != std::sregex_iterator(); ++a)
          names.push_back((*a)[0]);
        calls.push_back(names);
      }
    }
    kern::StereoParams p{};
    p.path_mask = v.paths;
    const unsigned cond = kern::pipeline_conditions(p, v.rectify);
    int stages = 0, fifos = 0;
    for (const kern::PipelineStage& st : kern::kPipelineStages) stages += kern::pipeline_has(st.when, cond) ? 1 : 0;
    // source: one call per camera; with rectification, map_left/map_right/rectify_* one each.
    EXPECT_EQ(int(calls.size()), stages + 1) << "one call per stage (the source: one per camera)";
    for (const kern::PipelineFifo& f : kern::kPipelineFifos) {
      if (!kern::pipeline_has(f.when, cond)) continue;
      ++fifos;
      int uses = 0;
      for (const auto& c : calls) uses += int(std::count(c.begin(), c.end(), std::string(f.name)));
      EXPECT_EQ(uses, 2) << f.name << ": passed to its producer and its consumer only";
      EXPECT_EQ(declared[f.name], 1) << f.name << ": declared once";
    }
    EXPECT_EQ(int(declared.size()), fifos) << "no stream the table does not name";
    fs::remove_all(out);
  }
}

// `make vitis` with either flow: the dry run (`make -n`) prints the commands; the configuration
// files have the unified flow's keys and the reduced frame's define.
TEST(HlsExport, MakeVitisRunsEitherFlow) {
  const fs::path out = fresh_dir("flows");
  ASSERT_EQ(export_design("configs/ruf2018-census.yaml", out).status, 0);
  const std::string make = "cd " + out.string() + " && env -u FLOW -u COSIM_FULL make -n vitis";
  const std::string c = "parallax_ruf2018_census";

  const auto tcl = shell(make + " FLOW=vitis_hls");
  ASSERT_EQ(tcl.status, 0) << tcl.output;
  EXPECT_EQ(tcl.output, "COSIM_FULL=0 vitis_hls -f run_hls.tcl\n");
  const auto tcl_full = shell(make + " FLOW=vitis_hls COSIM_FULL=1");
  EXPECT_EQ(tcl_full.output, "COSIM_FULL=1 vitis_hls -f run_hls.tcl\n");

  const auto vpp = shell(make + " FLOW=vpp");
  ASSERT_EQ(vpp.status, 0) << vpp.output;
  EXPECT_EQ(vpp.output, "vitis-run --mode hls --csim --config hls_config.cfg --work_dir " + c +
                            "\n"
                            "v++ -c --mode hls --config hls_config.cfg --work_dir " +
                            c +
                            "\n"
                            "v++ -c --mode hls --config hls_config_reduced.cfg --work_dir " +
                            c +
                            "_reduced\n"
                            "vitis-run --mode hls --cosim --config hls_config_reduced.cfg --work_dir " +
                            c +
                            "_reduced\n"
                            "vitis-run --mode hls --package --config hls_config.cfg --work_dir " +
                            c + "\n");
  const auto vpp_full = shell(make + " FLOW=vpp COSIM_FULL=1");
  EXPECT_EQ(vpp_full.output, "vitis-run --mode hls --csim --config hls_config.cfg --work_dir " + c +
                                 "\n"
                                 "v++ -c --mode hls --config hls_config.cfg --work_dir " +
                                 c +
                                 "\n"
                                 "vitis-run --mode hls --cosim --config hls_config.cfg --work_dir " +
                                 c +
                                 "\n"
                                 "vitis-run --mode hls --package --config hls_config.cfg --work_dir " +
                                 c + "\n");
  const auto bad = shell("cd " + out.string() + " && make vitis FLOW=quartus");
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_NE(bad.output.find("give FLOW=vitis_hls or FLOW=vpp"), std::string::npos) << bad.output;

  // Without FLOW: the command on the PATH (stand-ins here).
  const fs::path bin = out / "fake-bin";
  fs::create_directories(bin / "both");
  fs::create_directories(bin / "vpp");
  for (const fs::path& f : {bin / "both/vitis_hls", bin / "both/v++", bin / "vpp/v++"}) {
    std::ofstream(f) << "#!/bin/sh\nexit 0\n";
    fs::permissions(f, fs::perms::owner_all);
  }
  const std::string sys = "/usr/local/bin:/usr/bin:/bin";
  const auto both =
      shell("cd " + out.string() + " && env -u FLOW PATH=" + (bin / "both").string() + ":" + sys + " make -n vitis");
  EXPECT_EQ(both.output, "COSIM_FULL=0 vitis_hls -f run_hls.tcl\n");
  const auto only_vpp =
      shell("cd " + out.string() + " && env -u FLOW PATH=" + (bin / "vpp").string() + ":" + sys + " make -n vitis");
  EXPECT_NE(only_vpp.output.find("v++ -c --mode hls --config hls_config.cfg"), std::string::npos) << only_vpp.output;
  const auto none = shell("cd " + out.string() + " && env -u FLOW PATH=" + sys + " make vitis");
  EXPECT_EQ(none.status, 2) << none.output;  // make's status for a failed recipe
  EXPECT_NE(none.output.find("neither vitis_hls nor v++ is on the PATH"), std::string::npos) << none.output;

  // The configurations: part= before any section, the rest under [hls].
  auto keys = [](const std::string& text, std::string& before) {
    std::multimap<std::string, std::string> kv;
    bool in_hls = false;
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line)) {
      if (line.empty() || line[0] == '#') continue;
      if (line == "[hls]") {
        in_hls = true;
        continue;
      }
      const auto eq = line.find('=');
      if (!in_hls)
        before += line + "\n";
      else if (eq != std::string::npos)
        kv.emplace(line.substr(0, eq), line.substr(eq + 1));
    }
    return kv;
  };
  std::string before;
  const auto full = keys(read_file(out / "hls_config.cfg"), before);
  EXPECT_EQ(before, "part=xczu3eg-sbva484-1-e\n");
  for (const char* k : {"flow_target", "clock", "syn.top", "syn.file", "syn.cflags", "tb.file", "tb.cflags",
                        "csim.argv", "cosim.argv", "package.output.format"})
    EXPECT_EQ(full.count(k) > 0, true) << k;
  EXPECT_EQ(full.find("clock")->second, "5.000ns");
  EXPECT_EQ(full.find("syn.top")->second, "parallax_top");
  EXPECT_EQ(full.find("syn.cflags")->second, "-std=c++14 -Isrc");
  EXPECT_EQ(full.count("tb.file"), 4u);
  before.clear();
  const auto reduced = keys(read_file(out / "hls_config_reduced.cfg"), before);
  EXPECT_EQ(before, "part=xczu3eg-sbva484-1-e\n");
  EXPECT_EQ(reduced.find("syn.cflags")->second, "-std=c++14 -Isrc -DPARALLAX_REDUCED_FRAME");
  EXPECT_EQ(reduced.find("tb.cflags")->second, "-std=c++14 -Isrc -DPARALLAX_REDUCED_FRAME");
  std::set<std::string> tb;
  for (auto r = reduced.equal_range("tb.file"); r.first != r.second; ++r.first) tb.insert(r.first->second);
  EXPECT_EQ(tb.count("tb/golden_disparity_reduced.pgm"), 1u);
  EXPECT_EQ(reduced.find("cosim.argv")->second, ".");
  // The Tcl script: the reduced project with the define, the full cosim behind COSIM_FULL.
  const std::string script = read_file(out / "run_hls.tcl");
  for (const char* s :
       {"::env(COSIM_FULL)", "parallax_project parallax_ruf2018_census \"\" golden_disparity.pgm",
        "parallax_project parallax_ruf2018_census_reduced \"-DPARALLAX_REDUCED_FRAME\" golden_disparity_reduced.pgm",
        "add_files src/parallax_top.cpp -cflags \"-std=c++14 -Isrc $defines\"", "cosim_design -argv {.}"})
    EXPECT_NE(script.find(s), std::string::npos) << s;
  fs::remove_all(out);
}

}  // namespace
