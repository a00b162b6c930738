// reject: the CLI's answer to bad input is one clear message naming the file or field and a
// non-zero exit, never a crash; and the happy paths write what they promise.
#include <gtest/gtest.h>

#include <sqlite3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <opencv2/core/persistence.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "../../common/shell.hpp"

namespace {

namespace fs = std::filesystem;

using CliRun = parallax::test::Shell;

CliRun run_cli(const std::string& args) {
  return parallax::test::shell(std::string(PARALLAX_CLI) + " " + args);
}

fs::path temp_dir(const std::string& name) {
  // The pid: test runs of several checkouts share /tmp.
  const fs::path d = fs::temp_directory_path() / ("parallax_cli_test_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

const std::string kData = PARALLAX_DATA_DIR "/kitti2015-640x360/training";
const std::string kCensus = PARALLAX_CONFIG_DIR "/ruf2018-census.yaml";

TEST(Cli, HelpOnEveryCommand) {
  for (const char* c : {"run", "eval", "score", "baseline", "config", "crop-dataset", "sim", "bench", "fit-resources",
                        "sweep", "pareto", "merge", "report", "avoid", "scene", "fly", "import-hls", "export-hls"}) {
    const CliRun r = run_cli(std::string(c) + " --help");
    EXPECT_EQ(r.status, 0) << c;
    EXPECT_NE(r.output.find("Usage"), std::string::npos) << c;
  }
}

TEST(Cli, RunWritesKittiPngAndColourAndScores) {
  const fs::path d = temp_dir("run");
  const CliRun r = run_cli("run --config " + kCensus + " --left " + kData + "/image_2/000001_10.png --right " + kData +
                           "/image_3/000001_10.png --gt " + kData + "/disp_noc_0/000001_10.png --out " +
                           (d / "d.png").string() + " --json");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("\"correct_3px_pct\""), std::string::npos);
  EXPECT_NE(r.output.find("colour input converted to grey"), std::string::npos);
  const cv::Mat disp = cv::imread((d / "d.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(disp.type(), CV_16UC1);
  EXPECT_EQ(disp.cols, 640);
  EXPECT_EQ(disp.rows, 360);
  const cv::Mat colour = cv::imread((d / "d_colour.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(colour.type(), CV_8UC3);
}

// fly on one and on two threads: the same trace row for row (design flights first, each kind in
// seed order), whatever order the flights end in.
TEST(Cli, FlyTraceDoesNotDependOnTheThreads) {
  const fs::path d = temp_dir("fly_threads");
  const std::string base =
      "fly --config " + kCensus + " --scenario corridor --seeds 2 --size 96 --time-limit-s 3 --trace-csv ";
  const CliRun one = run_cli(base + (d / "one.csv").string() + " --threads 1");
  const CliRun two = run_cli(base + (d / "two.csv").string() + " --threads 2");
  ASSERT_EQ(one.status, 0) << one.output;
  ASSERT_EQ(two.status, 0) << two.output;
  auto read = [](const fs::path& f) {
    std::ifstream in(f);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  const std::string a = read(d / "one.csv"), b = read(d / "two.csv");
  EXPECT_EQ(a, b);
  EXPECT_NE(a.find("\ndesign,1,"), std::string::npos);
  EXPECT_LT(a.find("\ndesign,2,"), a.find("\noracle,1,"));
}

TEST(Cli, MissingImageNamesTheFile) {
  const CliRun r = run_cli("run --config " + kCensus + " --left /nonexistent/left.png --right " + kData +
                           "/image_3/000001_10.png --out /tmp/x.png");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("/nonexistent/left.png"), std::string::npos) << r.output;
}

TEST(Cli, UnreadableImageNamesTheFile) {
  const fs::path d = temp_dir("unreadable");
  std::ofstream(d / "junk.png") << "not a png";
  const CliRun r = run_cli("run --config " + kCensus + " --left " + (d / "junk.png").string() + " --right " + kData +
                           "/image_3/000001_10.png --out " + (d / "o.png").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("junk.png"), std::string::npos) << r.output;
}

TEST(Cli, SizeMismatchIsRejected) {
  const fs::path d = temp_dir("mismatch");
  cv::Mat small(100, 700, CV_8UC1, cv::Scalar(7));
  cv::imwrite((d / "small.png").string(), small);
  const CliRun r = run_cli("run --config " + kCensus + " --left " + kData + "/image_2/000001_10.png --right " +
                           (d / "small.png").string() + " --out " + (d / "o.png").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("small.png"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "o.png"));
}

TEST(Cli, GroundTruthOfAnotherSizeIsRejected) {
  const fs::path d = temp_dir("gt");
  cv::imwrite((d / "gt.png").string(), cv::Mat(50, 50, CV_16UC1, cv::Scalar(256)));
  const CliRun r =
      run_cli("run --config " + kCensus + " --left " + kData + "/image_2/000001_10.png --right " + kData +
              "/image_3/000001_10.png --gt " + (d / "gt.png").string() + " --out " + (d / "o.png").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("gt.png"), std::string::npos) << r.output;
}

TEST(Cli, EveryViolatedConfigFieldIsNamed) {
  const fs::path d = temp_dir("cfg");
  std::ofstream(d / "bad.yaml") << "cost: census\nwindow: 6x5\ndisparities: 300\nparallel_units: 7\np1: 40\np2: 20\n"
                                   "median: 4\nfrobnicate: 1\n";
  const CliRun r = run_cli("config --config " + (d / "bad.yaml").string());
  EXPECT_EQ(r.status, 2);
  for (const char* field :
       {"bad.yaml", "'window'", "'disparities'", "'parallel_units'", "'p2'", "'median'", "'frobnicate'"})
    EXPECT_NE(r.output.find(field), std::string::npos) << field << " not named in:\n" << r.output;
}

TEST(Cli, BadOverrideIsNamed) {
  const CliRun r = run_cli("config --config " + kCensus + " --set paths=6");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("'paths'"), std::string::npos) << r.output;
}

TEST(Cli, MissingConfigFileIsNamed) {
  const CliRun r = run_cli("config --config /nonexistent/design.yaml");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("/nonexistent/design.yaml"), std::string::npos) << r.output;
}

TEST(Cli, UnknownFrameIsRejected) {
  const CliRun r = run_cli("eval --config " + kCensus + " --dataset " + kData + " --frames 000002 --quiet");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("000002"), std::string::npos) << r.output;
}

TEST(Cli, EvalJsonCarriesTheMetricKeys) {
  const CliRun r = run_cli("eval --config " + kCensus + " --dataset " + kData + " --json 2>/dev/null");
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* k : {"density_pct", "density_gt_pct", "correct_3px_pct", "d1_all_pct", "d1_all_filled_pct",
                        "mean_abs_error_px", "per_frame"})
    EXPECT_NE(r.output.find(std::string("\"") + k + "\""), std::string::npos) << k;
}

TEST(Cli, ScoreAcceptsFullSizeAndRoiSizePredictions) {
  const fs::path d = temp_dir("score");
  const CliRun e = run_cli("eval --config " + kCensus + " --dataset " + kData + " --save " + d.string() + " --quiet");
  ASSERT_EQ(e.status, 0) << e.output;
  const CliRun s = run_cli("score --pred " + d.string() + " --dataset " + kData);
  ASSERT_EQ(s.status, 0) << s.output;
  // The saved maps scored by `score` give the same pooled line as `eval`.
  const auto pooled = [](const std::string& out) { return out.substr(out.find("pooled")); };
  EXPECT_EQ(pooled(e.output).substr(0, 70), pooled(s.output).substr(0, 70));
  cv::imwrite((d / "000001_10.png").string(), cv::Mat(10, 10, CV_16UC1, cv::Scalar(0)));
  const CliRun bad = run_cli("score --pred " + d.string() + " --dataset " + kData);
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("000001_10.png"), std::string::npos) << bad.output;
}

}  // namespace

namespace {

// Writes an OpenCV remap table (float maps) that shifts the image down by dy rows.
void write_maps(const fs::path& file, int w, int h, float dy) {
  cv::Mat mx(h, w, CV_32FC1), my(h, w, CV_32FC1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      mx.at<float>(y, x) = float(x);
      my.at<float>(y, x) = float(y) - dy;
    }
  cv::FileStorage fsw(file.string(), cv::FileStorage::WRITE);
  fsw << "map_x" << mx << "map_y" << my;
}

TEST(Cli, RectifyWithIdentityMapsChangesNothing) {
  const fs::path d = temp_dir("rectify");
  write_maps(d / "id.yaml", 640, 360, 0.0f);
  std::ofstream(d / "design.yaml") << "name: r\ncost: census\ndisparities: 60\nparallel_units: 6\np1: 8\np2: 32\n"
                                      "rectify: bilinear\nrectify_rows: 4\nrectify_maps_left: id.yaml\n"
                                      "rectify_maps_right: id.yaml\n";
  const std::string pair = " --left " + kData + "/image_2/000001_10.png --right " + kData + "/image_3/000001_10.png";
  const CliRun a =
      run_cli("run --config " + (d / "design.yaml").string() + pair + " --out " + (d / "a.png").string() + " --json");
  ASSERT_EQ(a.status, 0) << a.output;
  EXPECT_NE(a.output.find("\"rectify_window_misses\": 0"), std::string::npos) << a.output;
  const CliRun b = run_cli("run --config " + (d / "design.yaml").string() + " --set rectify=none" + pair + " --out " +
                           (d / "b.png").string());
  ASSERT_EQ(b.status, 0) << b.output;
  const cv::Mat da = cv::imread((d / "a.png").string(), cv::IMREAD_UNCHANGED);
  const cv::Mat db = cv::imread((d / "b.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(cv::countNonZero(da != db), 0);
}

TEST(Cli, RectifyReportsALineBufferTooSmallForTheMap) {
  const fs::path d = temp_dir("rectify_small");
  write_maps(d / "down.yaml", 640, 360, 6.0f);  // reads 6 rows above: needs more than 2 buffered rows
  std::ofstream(d / "design.yaml") << "rectify: nearest\nrectify_rows: 2\nrectify_maps_left: down.yaml\n"
                                      "rectify_maps_right: down.yaml\n";
  const CliRun r =
      run_cli("run --config " + (d / "design.yaml").string() + " --left " + kData + "/image_2/000001_10.png --right " +
              kData + "/image_3/000001_10.png --out " + (d / "o.png").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("raise rectify_rows"), std::string::npos) << r.output;
}

TEST(Cli, RectifyNeedsItsMapsAndTheRightSize) {
  const fs::path d = temp_dir("rectify_bad");
  // No tables: identity (the images are already rectified), the output equals the design without
  // the stage; one table only: an error naming both fields.
  std::ofstream(d / "nomaps.yaml") << "rectify: nearest\nrectify_rows: 2\n";
  std::ofstream(d / "plain.yaml") << "rectify: none\n";
  const std::string pair = " --left " + kData + "/image_2/000001_10.png --right " + kData + "/image_3/000001_10.png";
  const CliRun id =
      run_cli("run --config " + (d / "nomaps.yaml").string() + pair + " --out " + (d / "id.png").string());
  const CliRun plain =
      run_cli("run --config " + (d / "plain.yaml").string() + pair + " --out " + (d / "plain.png").string());
  ASSERT_EQ(id.status, 0) << id.output;
  ASSERT_EQ(plain.status, 0) << plain.output;
  EXPECT_EQ(cv::countNonZero(cv::imread((d / "id.png").string(), cv::IMREAD_UNCHANGED) !=
                             cv::imread((d / "plain.png").string(), cv::IMREAD_UNCHANGED)),
            0);
  std::ofstream(d / "onemap.yaml") << "rectify: nearest\nrectify_maps_left: small.yaml\n";
  const CliRun a = run_cli("run --config " + (d / "onemap.yaml").string() + pair + " --out " + (d / "o.png").string());
  EXPECT_EQ(a.status, 2);
  EXPECT_NE(a.output.find("rectify_maps_right"), std::string::npos) << a.output;
  write_maps(d / "small.yaml", 100, 50, 0.0f);
  std::ofstream(d / "small_design.yaml")
      << "rectify: nearest\nrectify_maps_left: small.yaml\nrectify_maps_right: small.yaml\n";
  const CliRun b =
      run_cli("run --config " + (d / "small_design.yaml").string() + " --left " + kData +
              "/image_2/000001_10.png --right " + kData + "/image_3/000001_10.png --out " + (d / "o.png").string());
  EXPECT_EQ(b.status, 2);
  EXPECT_NE(b.output.find("small.yaml"), std::string::npos) << b.output;
}

}  // namespace

namespace {

TEST(CliSim, JsonCarriesTheTimingKeys) {
  const fs::path d = temp_dir("sim");
  const CliRun r = run_cli("sim --config " + kCensus + " --set roi=96x24 --json --out " + (d / "s.png").string() +
                           " --vcd " + (d / "t.vcd").string() + " --vcd-cycles 0:5000 2>/dev/null");
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* k :
       {"cycles_per_frame", "first_pixel_cycle", "last_pixel_cycle", "latency_ms", "frame_interval_ms", "fps",
        "bottleneck", "busy_cycles", "input_stall_cycles", "output_stall_cycles", "high_water", "stall_free_depth"})
    EXPECT_NE(r.output.find(std::string("\"") + k + "\""), std::string::npos) << k;
  EXPECT_TRUE(fs::exists(d / "s.png"));
  EXPECT_TRUE(fs::exists(d / "t.vcd"));
}

TEST(CliSim, SimOfAPairMatchesRun) {
  const fs::path d = temp_dir("sim_pair");
  const std::string pair = " --left " + kData + "/image_2/000005_10.png --right " + kData + "/image_3/000005_10.png";
  ASSERT_EQ(run_cli("sim --config " + kCensus + " --no-sizing" + pair + " --out " + (d / "c.png").string()).status, 0);
  ASSERT_EQ(run_cli("run --config " + kCensus + pair + " --out " + (d / "f.png").string()).status, 0);
  const cv::Mat c = cv::imread((d / "c.png").string(), cv::IMREAD_UNCHANGED);
  const cv::Mat f = cv::imread((d / "f.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(c.empty());
  EXPECT_EQ(cv::countNonZero(c != f), 0);
}

TEST(CliSim, JsonCarriesTheResourceKeys) {
  const CliRun r = run_cli("sim --config " + kCensus + " --no-sizing --device xczu9eg --json 2>/dev/null");
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* k : {"bram18k", "uram", "lut", "ff", "dsp", "fits_device", "utilisation_pct", "resource_stages",
                        "power_estimate_w", "energy_estimate_mj_per_frame"})
    EXPECT_NE(r.output.find(std::string("\"") + k + "\""), std::string::npos) << k;
  EXPECT_NE(r.output.find("\"XCZU9EG\""), std::string::npos);
}

TEST(CliSim, UnknownDeviceIsRejectedWithTheKnownOnes) {
  const CliRun r = run_cli("sim --config " + kCensus + " --device XC9000");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("XC9000"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("XCZU3EG"), std::string::npos) << r.output;
}

TEST(CliSim, BadVcdWindowIsRejected) {
  const CliRun r = run_cli("sim --config " + kCensus + " --set roi=32x8 --vcd /tmp/x.vcd --vcd-cycles 9:3");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--vcd-cycles"), std::string::npos) << r.output;
}

}  // namespace

namespace {

TEST(CliSim, RectifyingDesignSimulatesItsRectifyStages) {
  const fs::path d = temp_dir("sim_rect");
  write_maps(d / "id.yaml", 640, 360, 2.0f);
  std::ofstream(d / "design.yaml") << "cost: census\ndisparities: 60\nparallel_units: 6\nrectify: nearest\n"
                                      "rectify_rows: 8\nrectify_maps_left: id.yaml\nrectify_maps_right: id.yaml\n";
  const CliRun r = run_cli("sim --config " + (d / "design.yaml").string() + " --no-sizing --json --left " + kData +
                           "/image_2/000001_10.png --right " + kData + "/image_3/000001_10.png 2>/dev/null");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("\"rectify_left\""), std::string::npos);
  EXPECT_NE(r.output.find("\"rectify_window_misses\": 0"), std::string::npos) << r.output.substr(0, 400);
  write_maps(d / "small.yaml", 320, 180, 0.0f);
  std::ofstream(d / "small_design.yaml")
      << "rectify: nearest\nrectify_maps_left: small.yaml\nrectify_maps_right: small.yaml\n";
  const CliRun bad = run_cli("sim --config " + (d / "small_design.yaml").string() + " --no-sizing");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("small.yaml"), std::string::npos) << bad.output;
}

}  // namespace

// --- the results store: read-only commands, foreign files, outputs onto inputs, unreadable rows ---

namespace {

const std::string kStoreDataset = PARALLAX_DATA_DIR "/kitti2015-640x360";

// Every file of a folder with its bytes: to show that nothing was created or changed.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::directory_iterator(dir))
    m[e.path().filename().string()] = parallax::test::read_file(e.path());
  return m;
}

void sql(const std::string& db, const std::string& statements) {
  sqlite3* c = nullptr;
  ASSERT_EQ(sqlite3_open(db.c_str(), &c), SQLITE_OK);
  char* err = nullptr;
  EXPECT_EQ(sqlite3_exec(c, statements.c_str(), nullptr, nullptr, &err), SQLITE_OK) << (err ? err : "") << statements;
  sqlite3_free(err);
  sqlite3_close(c);
}

// A store of two designs on one frame.
std::string small_store(const fs::path& dir) {
  const std::string db = (dir / "s.db").string();
  const CliRun r =
      run_cli("sweep --base " + kCensus + " --grid p2=32,64 --dataset " + kStoreDataset + " --frames 1 --db " + db);
  EXPECT_EQ(r.status, 0) << r.output;
  return db;
}

// Exited (not killed by a signal, not aborted) with status 0 or 2.
::testing::AssertionResult exited_cleanly(const CliRun& r) {
  if (r.status == 0 || r.status == 2) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "status " << r.status << ": " << r.output;
}

TEST(CliStore, ReadOnlyCommandsOnAMissingPathCreateNothing) {
  const fs::path d = temp_dir("store_missing");
  const std::string db = (d / "none.db").string();
  for (const std::string& cmd : {"pareto --db " + db, "report --db " + db + " --csv " + (d / "x.csv").string(),
                                 "export-hls --db " + db + " --design abcd --out " + (d / "hls").string()}) {
    const CliRun r = run_cli(cmd);
    EXPECT_EQ(r.status, 2) << cmd << "\n" << r.output;
    EXPECT_NE(r.output.find(db + ": results store not found"), std::string::npos) << r.output;
  }
  EXPECT_TRUE(fs::is_empty(d)) << "a read-only command created a file";
}

// Another program's SQLite file, and a file that is not SQLite: every command refuses it with a
// message naming it, and it stays byte-identical (no tables added, no journal mode switched).
TEST(CliStore, ForeignFilesAreRefusedAndLeftByteIdentical) {
  const fs::path d = temp_dir("store_foreign");
  const std::string foreign = (d / "app.sqlite").string(), text = (d / "notes.txt").string();
  sql(foreign, "CREATE TABLE people(name TEXT); INSERT INTO people VALUES('ada');");
  std::ofstream(text) << "not a database\n";
  const auto before = snapshot(d);
  for (const std::string& db : {foreign, text}) {
    for (const std::string& cmd : {"pareto --db " + db, "report --db " + db + " --csv " + (d / "x.csv").string(),
                                   "export-hls --db " + db + " --design abcd --out " + (d / "hls").string(),
                                   "sweep --base " + kCensus + " --dataset " + kStoreDataset + " --frames 1 --db " + db,
                                   "merge --db " + (d / "m.db").string() + " " + db}) {
      const CliRun r = run_cli(cmd);
      EXPECT_EQ(r.status, 2) << cmd << "\n" << r.output;
      EXPECT_NE(r.output.find(db + ": "), std::string::npos) << r.output;
      EXPECT_NE(r.output.find("not a Parallax results store"), std::string::npos) << r.output;
    }
  }
  fs::remove(d / "m.db");  // merge's own target (a new store) may exist
  EXPECT_EQ(snapshot(d), before);
}

// A store of schema 1 (results keyed by design only) is refused with what to do, untouched.
TEST(CliStore, OlderSchemaIsRefusedWithHowToProceed) {
  const fs::path d = temp_dir("store_v1");
  const std::string db = (d / "old.db").string();
  sql(db,
      "PRAGMA journal_mode=WAL;"
      "CREATE TABLE sweeps(name TEXT PRIMARY KEY, spec TEXT NOT NULL, created_at TEXT NOT NULL);"
      "CREATE TABLE designs(hash TEXT PRIMARY KEY, sweep TEXT NOT NULL, config TEXT NOT NULL, status TEXT NOT NULL,"
      " reason TEXT, metrics TEXT, model_version TEXT, started_at TEXT, finished_at TEXT);"
      "CREATE TABLE frames(hash TEXT NOT NULL, frame TEXT NOT NULL, metrics TEXT NOT NULL, PRIMARY KEY(hash, frame));"
      "INSERT INTO sweeps VALUES('s', 'name: s', '2026-01-01');");
  const auto before = snapshot(d);
  for (const std::string& cmd :
       {"pareto --db " + db, "report --db " + db + " --json " + (d / "x.json").string(),
        "sweep --base " + kCensus + " --dataset " + kStoreDataset + " --frames 1 --db " + db}) {
    const CliRun r = run_cli(cmd);
    EXPECT_EQ(r.status, 2) << cmd << "\n" << r.output;
    EXPECT_NE(r.output.find(db + ": a results store of an earlier Parallax (schema 1)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("Rerun the sweep into a new store"), std::string::npos) << r.output;
  }
  EXPECT_EQ(snapshot(d), before);
}

// A read-only store (file 0444, folder 0555) is read by pareto and report, which write nothing
// into it or beside it. Run as root the modes do not stop writes, so when the tests run as root
// the commands also run as nobody (setpriv), for whom they do.
TEST(CliStore, ReadOnlyStoreIsReadAndNotTouched) {
  const fs::path d = temp_dir("store_readonly");
  const fs::path store = d / "ro";
  fs::create_directories(store);
  const fs::path out = d / "out";
  fs::create_directories(out);
  fs::permissions(out, fs::perms::all);
  small_store(store);
  const std::string db = (store / "s.db").string();
  fs::permissions(db, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  fs::permissions(store, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read | fs::perms::group_exec |
                             fs::perms::others_read | fs::perms::others_exec);
  const auto before = snapshot(store);
  std::vector<std::string> as = {""};
  if (geteuid() == 0 && parallax::test::shell("command -v setpriv").status == 0)
    as.push_back("setpriv --reuid=65534 --regid=65534 --clear-groups ");
  for (const auto& who : as) {
    const CliRun p = parallax::test::shell(who + PARALLAX_CLI + " pareto --db " + db);
    EXPECT_EQ(p.status, 0) << who << p.output;
    EXPECT_NE(p.output.find("2 designs stored"), std::string::npos) << p.output;
    const std::string csv = (out / "d.csv").string();
    fs::remove(csv);
    const CliRun r = parallax::test::shell(who + PARALLAX_CLI + " report --db " + db + " --csv " + csv);
    EXPECT_EQ(r.status, 0) << who << r.output;
    EXPECT_TRUE(fs::exists(csv));
  }
  EXPECT_EQ(snapshot(store), before);
  fs::permissions(store, fs::perms::owner_all);
}

// Outputs never overwrite inputs: the store, its journal, the dataset, or another output.
TEST(CliStore, ReportNeverWritesOntoItsInputs) {
  const fs::path d = temp_dir("store_outputs");
  const std::string db = small_store(d);
  const std::string bytes = parallax::test::read_file(db);
  const std::string in_dataset = kStoreDataset + "/training/report.csv";
  struct Case {
    std::string args, option;
  };
  for (const Case& c :
       {Case{"--csv " + db, "--csv"}, Case{"--html " + db, "--html"}, Case{"--json " + db, "--json"},
        Case{"--frames-csv " + db + "-journal", "--frames-csv"}, Case{"--csv " + in_dataset, "--csv"},
        Case{"--html " + kStoreDataset, "--html"},
        Case{"--csv " + (d / "a.csv").string() + " --frames-csv " + (d / "a.csv").string(), "--frames-csv"}}) {
    const CliRun r = run_cli("report --db " + db + " " + c.args);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.option), std::string::npos) << r.output;
  }
  EXPECT_EQ(parallax::test::read_file(db), bytes);
  EXPECT_FALSE(fs::exists(in_dataset));
  EXPECT_FALSE(fs::exists(d / "a.csv"));
}

// Rows whose metrics are NULL, hold nulls, are not JSON or hold strings: pareto, report and
// export-hls never abort; an unreadable row is named (store and row) and shown as an error.
TEST(CliStore, UnreadableOrMissingMetricsNeverCrash) {
  const fs::path d = temp_dir("store_rows");
  const std::string db = small_store(d);
  sql(db,
      "UPDATE results SET metrics = '{\"correct_3px_pct\": null, \"density_pct\": 80, \"fits_device\": 1}' WHERE rowid "
      "= 1;"
      "UPDATE frames SET metrics = NULL WHERE rowid = 1;");
  // export-hls (a simulation of a few seconds) only when asked.
  auto readers = [&](const std::string& tag, bool with_export) {
    std::vector<CliRun> runs = {
        run_cli("pareto --db " + db), run_cli("pareto --json --db " + db),
        run_cli("report --db " + db + " --csv " + (d / "d.csv").string() + " --frames-csv " + (d / "f.csv").string() +
                " --json " + (d / "r.json").string() + " --html " + (d / "r.html").string())};
    if (with_export)
      runs.push_back(run_cli("export-hls --db " + db + " --design " + tag + " --out " + (d / "hls").string()));
    for (const auto& r : runs) EXPECT_TRUE(exited_cleanly(r));
    return runs;
  };
  sqlite3* c = nullptr;
  ASSERT_EQ(sqlite3_open(db.c_str(), &c), SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(c, "SELECT hash FROM results ORDER BY rowid", -1, &st, nullptr), SQLITE_OK);
  std::vector<std::string> hashes;
  while (sqlite3_step(st) == SQLITE_ROW) hashes.push_back(reinterpret_cast<const char*>(sqlite3_column_text(st, 0)));
  sqlite3_finalize(st);
  sqlite3_close(c);
  ASSERT_EQ(hashes.size(), 2u);
  auto nulls = readers(hashes[0], true);
  EXPECT_EQ(nulls[0].status, 0) << nulls[0].output;
  EXPECT_EQ(nulls[2].status, 0) << nulls[2].output;
  EXPECT_EQ(nulls[3].status, 0) << nulls[3].output;
  for (const char* bad : {"'not json'", "'{\"fps\": \"fast\"}'", "'[1, 2]'"}) {
    sql(db, std::string("UPDATE results SET metrics = ") + bad + " WHERE rowid = 2;");
    auto runs = readers(hashes[1], bad[1] == 'n');
    EXPECT_EQ(runs[0].status, 0) << runs[0].output;
    EXPECT_NE(runs[0].output.find(db + ": results row 2, metrics (design " + hashes[1]), std::string::npos)
        << runs[0].output;
    EXPECT_EQ(runs[2].status, 0) << runs[2].output;
    const std::string csv = parallax::test::read_file(d / "d.csv");
    EXPECT_NE(csv.find(hashes[1] + ",sweep,error,"), std::string::npos) << csv;
  }
}

}  // namespace
