// reject: the CLI's answer to bad input is one clear message naming the file or field and a
// non-zero exit, never a crash; and the happy paths write what they promise.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <opencv2/core/persistence.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "../common/shell.hpp"

namespace {

namespace fs = std::filesystem;

using CliRun = parallax::test::Shell;

CliRun run_cli(const std::string& args) { return parallax::test::shell(std::string(PARALLAX_CLI) + " " + args); }

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("parallax_cli_test_" + name);
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
  const CliRun r = run_cli("run --config " + kCensus + " --left " + kData + "/image_2/000001_10.png --right " + kData +
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
  for (const char* field : {"bad.yaml", "'window'", "'disparities'", "'parallel_units'", "'p2'", "'median'", "'frobnicate'"})
    EXPECT_NE(r.output.find(field), std::string::npos) << field << " not named in:\n" << r.output;
}

TEST(Cli, BadOverrideIsNamed) {
  const CliRun r = run_cli("config --config " + kCensus + " --set paths=5");
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
  const CliRun a = run_cli("run --config " + (d / "design.yaml").string() + pair + " --out " + (d / "a.png").string() + " --json");
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
  const CliRun r = run_cli("run --config " + (d / "design.yaml").string() + " --left " + kData +
                           "/image_2/000001_10.png --right " + kData + "/image_3/000001_10.png --out " +
                           (d / "o.png").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("raise rectify_rows"), std::string::npos) << r.output;
}

TEST(Cli, RectifyNeedsItsMapsAndTheRightSize) {
  const fs::path d = temp_dir("rectify_bad");
  std::ofstream(d / "nomaps.yaml") << "rectify: nearest\n";
  const CliRun a = run_cli("config --config " + (d / "nomaps.yaml").string());
  EXPECT_EQ(a.status, 2);
  EXPECT_NE(a.output.find("'rectify_maps_left'"), std::string::npos) << a.output;
  write_maps(d / "small.yaml", 100, 50, 0.0f);
  std::ofstream(d / "small_design.yaml") << "rectify: nearest\nrectify_maps_left: small.yaml\nrectify_maps_right: small.yaml\n";
  const CliRun b = run_cli("run --config " + (d / "small_design.yaml").string() + " --left " + kData +
                           "/image_2/000001_10.png --right " + kData + "/image_3/000001_10.png --out " +
                           (d / "o.png").string());
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
  for (const char* k : {"cycles_per_frame", "first_pixel_cycle", "last_pixel_cycle", "latency_ms", "frame_interval_ms",
                        "fps", "bottleneck", "busy_cycles", "input_stall_cycles", "output_stall_cycles", "high_water",
                        "stall_free_depth", "port_conflict_cycles"})
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
  std::ofstream(d / "small_design.yaml") << "rectify: nearest\nrectify_maps_left: small.yaml\nrectify_maps_right: small.yaml\n";
  const CliRun bad = run_cli("sim --config " + (d / "small_design.yaml").string() + " --no-sizing");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("small.yaml"), std::string::npos) << bad.output;
}

}  // namespace
