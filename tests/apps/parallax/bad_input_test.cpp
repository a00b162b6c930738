// Bad and unusual input across every command (issue 15, item 1): each case must end with a
// non-zero user-error status (2), exactly one "parallax: error:" message that names the file,
// field or option at fault, within a time bound, and never abort, hang, report an internal error
// or exit 0 having done nothing. The cases are a table; the fixture files are written here.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "../../common/shell.hpp"

namespace fs = std::filesystem;
using parallax::test::shell;

namespace {

struct Case {
  const char* name;
  std::string args;    // after `parallax`; $T = fixture folder, $C = a good config, $D = the shipped dataset
  std::string expect;  // a substring the message must hold (the file, field or option named)
};

void write(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

void put_be32(std::string& s, uint32_t v) {
  for (int k = 3; k >= 0; --k) s.push_back(char((v >> (8 * k)) & 0xFF));
}

std::string png_chunk(const std::string& type, const std::string& data) {
  std::string c;
  put_be32(c, uint32_t(data.size()));
  const std::string td = type + data;
  c += td;
  put_be32(c, uint32_t(crc32(0, reinterpret_cast<const Bytef*>(td.data()), uInt(td.size()))));
  return c;
}

// A PNG whose header claims width x height (8-bit grey) with a tiny body: a forged header.
std::string forged_png(uint32_t width, uint32_t height) {
  std::string ihdr;
  put_be32(ihdr, width);
  put_be32(ihdr, height);
  ihdr += std::string("\x08\x00\x00\x00\x00", 5);
  std::string out = std::string("\x89PNG\r\n\x1a\n", 8) + png_chunk("IHDR", ihdr);
  out += png_chunk("IDAT", std::string("\x78\x9c\x63\x00\x00\x00\x01\x00\x01", 9));
  out += png_chunk("IEND", "");
  return out;
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
    s.replace(p, from.size(), to);
  return s;
}

class BadInput : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("parallax_bad_input_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "folder");
    fs::create_directories(dir_ / "readonly");
    const fs::path& t = dir_;
    write(t / "empty.yaml", "");
    write(t / "text.txt", "just some text\n");
    write(t / "list.yaml", "- 1\n- 2\n");
    write(t / "alias.yaml", "disparities: &d 64\np2: *d\nbogus: *d\n");
    write(t / "seqkey.yaml", "[1, 2]: 3\n");
    write(t / "mapkey.yaml", "{a: 1}: 3\n");
    write(t / "nested.yaml", "paths: [[0, 90]]\n");
    write(t / "mapvalue.yaml", "disparities: {a: 1}\n");
    write(t / "unknown.yaml", "disparitees: 64\n");
    write(t / "zero_d.yaml", "disparities: 0\n");
    write(t / "p1p2.yaml", "p1: 100\np2: 50\n");
    write(t / "even_window.yaml", "window: 4x5\n");
    write(t / "nan.yaml", "clock_mhz: nan\n");
    write(t / "huge_number.yaml", "disparities: 99999999999999999999\n");
    write(t / "fifo_typo.yaml", "fifo_depth_costt: 8\n");
    write(t / "ii_typo.yaml", "ii_aggregat: 2\n");
    write(t / "bad_paths.yaml", "paths: [0, 7]\n");
    write(t / "bad_cost.yaml", "cost: ssd\n");
    write(t / "tabs.yaml", "disparities:\t64\n\tp2: [\n");
    write(t / "big.yaml", std::string(5 << 20, '#'));
    write(t / "sweep_strategy.yaml", "base: $C\nstrategy: annealing\n");
    write(t / "sweep_field.yaml", "base: $C\nbogus: 1\n");
    write(t / "sweep_nested_axis.yaml", "base: $C\naxes: {p2: [[1, 2]]}\n");
    write(t / "sweep_axes_list.yaml", "base: $C\naxes: [p2, p1]\n");
    write(t / "sweep_objective.yaml", "base: $C\naxes: {p2: [64, 96]}\nobjectives: [max happiness]\n");
    write(t / "sweep_objective_form.yaml", "base: $C\nobjectives: [correct_3px_pct]\n");
    write(t / "sweep_samples.yaml", "base: $C\nstrategy: lhs\nsamples: many\n");
    write(t / "sweep_device.yaml", "base: $C\nconstraints: {device: XC7Z999}\n");
    write(t / "sweep_gt.yaml", "base: $C\ngt: all\n");
    write(t / "sweep_constraint.yaml", "base: $C\nconstraints: {max_lut: 5000}\n");
    write(t / "sweep_flight.yaml", "base: $C\nflight: {scenario: forest.yaml, speed: 3}\n");
    write(t / "sweep_flight_size.yaml", "base: $C\nflight: {scenario: forest, size_px: 20}\n");
    write(t / "sweep_seqkey.yaml", "base: $C\n[1]: 2\n");
    write(t / "scenario_kind.yaml", "kind: jungle\n");
    write(t / "scenario_nokind.yaml", "name: x\n");
    write(t / "scenario_type.yaml", "kind: forest\ndensity_per_100m2: [1, 2]\n");
    write(t / "scenario_list.yaml", "- kind\n");
    write(t / "points_nolist.yaml", "points: 3\n");
    write(t / "frames.txt", "1\n\n# a comment\n2 3\n");
    write(t / "frames_empty.txt", "# nothing\n");
    write(t / "not_xml.xml", "this is not XML <<<");
    write(t / "no_profile.xml", "<report/>");
    write(t / "clock_zero.xml",
          "<profile><UserAssignments><TargetClockPeriod>0</TargetClockPeriod></UserAssignments></profile>");
    write(t / "clock_nan.xml",
          "<profile><UserAssignments><TargetClockPeriod>nan</TargetClockPeriod></UserAssignments></profile>");
    write(t / "ii_zero.xml",
          "<profile><UserAssignments><TargetClockPeriod>5</TargetClockPeriod></UserAssignments><PerformanceEstimates>"
          "<SummaryOfTimingAnalysis><EstimatedClockPeriod>4</EstimatedClockPeriod></SummaryOfTimingAnalysis>"
          "<SummaryOfLoopLatency><cost_loop><PipelineII>0</PipelineII></cost_loop></SummaryOfLoopLatency>"
          "</PerformanceEstimates><AreaEstimates><Resources/></AreaEstimates></profile>");
    write(t / "ii_text.xml",
          "<profile><UserAssignments><TargetClockPeriod>5</TargetClockPeriod></UserAssignments><PerformanceEstimates>"
          "<SummaryOfTimingAnalysis><EstimatedClockPeriod>4</EstimatedClockPeriod></SummaryOfTimingAnalysis>"
          "<SummaryOfLoopLatency><cost_loop><PipelineII>fast</PipelineII></cost_loop></SummaryOfLoopLatency>"
          "</PerformanceEstimates><AreaEstimates><Resources/></AreaEstimates></profile>");
    write(t / "not_a_png.png", "GIF89a not really");
    write(t / "huge.png", forged_png(100000, 100000));
    write(t / "truncated.png", forged_png(64, 48).substr(0, 40));
    write(t / "not_a_store.db", "plain text, not SQLite\n");
    cv::imwrite((t / "small.png").string(), cv::Mat(48, 64, CV_8UC1, cv::Scalar(100)));
    cv::imwrite((t / "other_size.png").string(), cv::Mat(40, 64, CV_8UC1, cv::Scalar(100)));
    cv::imwrite((t / "deep.png").string(), cv::Mat(48, 64, CV_16UC1, cv::Scalar(1000)));
    cv::imwrite((t / "deep_colour.png").string(), cv::Mat(48, 64, CV_16UC3, cv::Scalar(1, 2, 3)));
    // Configuration files refer to the good config by $C; resolve it now.
    for (const auto& e : fs::directory_iterator(t)) {
      if (e.path().extension() != ".yaml") continue;
      std::ifstream in(e.path(), std::ios::binary);
      std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      if (s.find("$C") == std::string::npos) continue;
      write(e.path(), replace_all(s, "$C", std::string(PARALLAX_CONFIG_DIR) + "/ruf2018-census.yaml"));
    }
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static fs::path dir_;
};
fs::path BadInput::dir_;

const std::vector<Case>& cases() {
  static const std::vector<Case> c = {
      // --- the command line itself
      {"no command", "", "subcommand"},
      {"unknown command", "fly-away", "fly-away"},
      {"unknown option", "config --config $C --colour red", "--colour"},
      {"missing value", "config --config", "--config"},
      {"missing required", "run --out $T/o.png", "--config"},
      {"number not a number", "bench --config $C --iterations many", "--iterations"},
      {"number out of range", "bench --config $C --iterations 0", "--iterations"},
      // --- configuration files
      {"config missing", "config --config $T/nothing.yaml", "nothing.yaml"},
      {"config is a folder", "config --config $T/folder", "folder"},
      {"config is /dev/zero", "config --config /dev/zero", "/dev/zero"},
      {"config empty", "config --config $T/empty.yaml", "empty.yaml"},
      {"config not a mapping", "config --config $T/list.yaml", "list.yaml"},
      {"config plain text", "config --config $T/text.txt", "text.txt"},
      {"config alias", "config --config $T/alias.yaml", "bogus"},
      {"config sequence key", "config --config $T/seqkey.yaml", "seqkey.yaml"},
      {"config mapping key", "config --config $T/mapkey.yaml", "mapkey.yaml"},
      {"config nested list", "config --config $T/nested.yaml", "paths"},
      {"config mapping value", "config --config $T/mapvalue.yaml", "disparities"},
      {"config unknown field", "config --config $T/unknown.yaml", "disparitees"},
      {"config D = 0", "config --config $T/zero_d.yaml", "disparities"},
      {"config p1 > p2", "config --config $T/p1p2.yaml", "p2"},
      {"config even window", "config --config $T/even_window.yaml", "window"},
      {"config NaN clock", "config --config $T/nan.yaml", "clock_mhz"},
      {"config huge number", "config --config $T/huge_number.yaml", "disparities"},
      {"config fifo typo", "config --config $T/fifo_typo.yaml", "fifo_depth_costt"},
      {"config stage typo", "config --config $T/ii_typo.yaml", "ii_aggregat"},
      {"config bad angle", "config --config $T/bad_paths.yaml", "paths"},
      {"config bad cost", "config --config $T/bad_cost.yaml", "cost"},
      {"config broken YAML", "config --config $T/tabs.yaml", "tabs.yaml"},
      {"config too big", "config --config $T/big.yaml", "big.yaml"},
      {"set without =", "config --config $C --set p2", "p2"},
      {"set unknown field", "config --config $C --set bogus=1", "bogus"},
      {"set bad value", "config --config $C --set p2=abc", "p2"},
      {"set NaN", "config --config $C --set input_gbps=nan", "input_gbps"},
      {"set negative", "config --config $C --set median=-3", "median"},
      // --- run
      {"run left missing", "run --config $C --left $T/none.png --right $T/small.png --out $T/o.png", "none.png"},
      {"run left not an image", "run --config $C --left $T/text.txt --right $T/small.png --out $T/o.png", "text.txt"},
      {"run left fake png", "run --config $C --left $T/not_a_png.png --right $T/small.png --out $T/o.png",
       "not_a_png.png"},
      {"run forged header", "run --config $C --left $T/huge.png --right $T/huge.png --out $T/o.png", "huge.png"},
      {"run truncated png", "run --config $C --left $T/truncated.png --right $T/small.png --out $T/o.png",
       "truncated.png"},
      {"run sizes differ", "run --config $C --left $T/small.png --right $T/other_size.png --out $T/o.png",
       "other_size.png"},
      {"run 16-bit input", "run --config $C --left $T/deep.png --right $T/deep.png --out $T/o.png", "deep.png"},
      {"run 16-bit colour", "run --config $C --left $T/deep_colour.png --right $T/small.png --out $T/o.png",
       "deep_colour.png"},
      {"run out is a folder", "run --config $C --left $T/small.png --right $T/small.png --out $T/folder", "--out"},
      {"run out jpeg", "run --config $C --left $T/small.png --right $T/small.png --out $T/o.jpg", "o.jpg"},
      {"run out no parent", "run --config $C --left $T/small.png --right $T/small.png --out $T/no/o.png", "no"},
      {"run colour folder",
       "run --config $C --left $T/small.png --right $T/small.png --out $T/o.png --colour $T/folder", "--colour"},
      {"run html folder", "run --config $C --left $T/small.png --right $T/small.png --out $T/o.png --html $T/folder",
       "--html"},
      {"run left directory", "run --config $C --left $T/folder --right $T/small.png --out $T/o.png", "folder"},
      // --- eval / score / baseline / avoid / crop-dataset
      {"eval dataset missing", "eval --config $C --dataset $T/nowhere", "nowhere"},
      {"eval unknown engine", "eval --config $C --dataset $D --engine gpu", "--engine"},
      {"sweep unknown engine", "sweep --base $C --grid p1=4,8 --dataset $D --db $T/e.db --engine hls", "--engine"},
      {"eval dataset is a file", "eval --config $C --dataset $T/text.txt", "text.txt"},
      {"eval dataset unknown layout", "eval --config $C --dataset $T/folder", "folder"},
      {"eval frames malformed", "eval --config $C --dataset $D --frames abc", "abc"},
      {"eval frames absent", "eval --config $C --dataset $D --frames 999999", "999999"},
      {"eval frames file missing", "eval --config $C --dataset $D --frames @$T/none.txt", "none.txt"},
      {"eval frames file two per line", "eval --config $C --dataset $D --frames @$T/frames.txt", "frames.txt"},
      {"eval frames file empty", "eval --config $C --dataset $D --frames @$T/frames_empty.txt", "frames_empty.txt"},
      {"eval gt kind", "eval --config $C --dataset $D --gt all", "--gt"},
      {"eval roi malformed", "eval --config $C --dataset $D --roi 64by48", "64by48"},
      {"eval threads NaN", "eval --config $C --dataset $D --threads nan", "--threads"},
      {"eval save is a file", "eval --config $C --dataset $D --save $T/text.txt", "text.txt"},
      {"score pred missing", "score --pred $T/nowhere --dataset $D", "nowhere"},
      {"score dataset missing", "score --pred $T/folder --dataset $T/nowhere", "nowhere"},
      {"baseline p1 >= p2", "baseline opencv-hh4 --dataset $D --p1 900 --p2 800", "--p1"},
      {"baseline D = 0", "baseline opencv-hh4 --dataset $D --disparities 0", "--disparities"},
      {"baseline D huge", "baseline opencv-hh4 --dataset $D --disparities 100000", "--disparities"},
      {"baseline even block", "baseline opencv-sgbm --dataset $D --block-size 4", "--block-size"},
      {"baseline block 0", "baseline opencv-sgbm --dataset $D --block-size 0", "--block-size"},
      {"baseline unknown method", "baseline opencv-bm --dataset $D", "opencv-bm"},
      {"avoid calib missing", "avoid --config $C --dataset $D --calib $T/none.txt", "none.txt"},
      {"avoid mavlink folder", "avoid --config $C --dataset $D --mavlink-out $T/folder", "--mavlink-out"},
      {"avoid mavlink bad udp", "avoid --config $C --dataset $D --mavlink-out udp:nowhere:x", "udp:nowhere:x"},
      {"crop out is a file", "crop-dataset --dataset $D --out $T/text.txt", "text.txt"},
      {"crop roi full", "crop-dataset --dataset $D --out $T/crop --roi full", "--roi"},
      // --- bench / sim
      {"bench left without right", "bench --config $C --left $T/small.png", "--right"},
      {"sim clock NaN", "sim --config $C --clock-mhz nan", "--clock-mhz"},
      {"sim clock zero", "sim --config $C --clock-mhz 0", "--clock-mhz"},
      {"sim vcd folder", "sim --config $C --vcd $T/folder", "--vcd"},
      {"sim out folder", "sim --config $C --out $T/folder", "--out"},
      {"sim out jpeg", "sim --config $C --out $T/o.jpg", "o.jpg"},
      {"sim calibrate inf", "sim --config $C --calibrate-fps inf", "--calibrate-fps"},
      {"sim calibrate NaN", "sim --config $C --calibrate-latency-ms nan", "--calibrate-latency-ms"},
      {"sim write-config folder", "sim --config $C --calibrate-fps 29 --write-config $T/folder", "--write-config"},
      {"sim write-config no parent", "sim --config $C --calibrate-fps 29 --write-config $T/no/c.yaml", "no"},
      {"sim vcd cycles", "sim --config $C --vcd $T/v.vcd --vcd-cycles 9:3", "--vcd-cycles"},
      // --- sweep
      {"sweep file missing", "sweep $T/none.yaml --dataset $D --db $T/s.db", "none.yaml"},
      {"sweep file /dev/zero", "sweep /dev/zero --dataset $D --db $T/s.db", "/dev/zero"},
      {"sweep strategy", "sweep $T/sweep_strategy.yaml --dataset $D --db $T/s.db", "strategy"},
      {"sweep unknown field", "sweep $T/sweep_field.yaml --dataset $D --db $T/s.db", "bogus"},
      {"sweep nested axis", "sweep $T/sweep_nested_axis.yaml --dataset $D --db $T/s.db", "sweep_nested_axis.yaml"},
      {"sweep axes not a map", "sweep $T/sweep_axes_list.yaml --dataset $D --db $T/s.db", "axes"},
      {"sweep sequence key", "sweep $T/sweep_seqkey.yaml --dataset $D --db $T/s.db", "sweep_seqkey.yaml"},
      {"sweep objective unknown", "sweep $T/sweep_objective.yaml --dataset $D --db $T/s.db", "happiness"},
      {"sweep objective form", "sweep $T/sweep_objective_form.yaml --dataset $D --db $T/s.db", "correct_3px_pct"},
      {"sweep samples text", "sweep $T/sweep_samples.yaml --dataset $D --db $T/s.db", "sweep_samples.yaml"},
      {"sweep device", "sweep $T/sweep_device.yaml --dataset $D --db $T/s.db", "XC7Z999"},
      {"sweep gt", "sweep $T/sweep_gt.yaml --dataset $D --db $T/s.db", "gt"},
      {"sweep unknown constraint", "sweep $T/sweep_constraint.yaml --dataset $D --db $T/s.db", "max_lut"},
      {"sweep unknown flight field", "sweep $T/sweep_flight.yaml --dataset $D --db $T/s.db", "speed"},
      {"sweep flight size", "sweep $T/sweep_flight_size.yaml --dataset $D --db $T/s.db", "size_px"},
      {"sweep --flight-size", "sweep --base $C --flight forest --flight-size 20 --dataset $D --db $T/s.db",
       "--flight-size"},
      {"sweep grid value", "sweep --base $C --grid p2=abc,def --dataset $D --db $T/s.db", "abc"},
      {"sweep grid axis", "sweep --base $C --grid bogus=1,2 --dataset $D --db $T/s.db", "bogus"},
      {"sweep grid form", "sweep --base $C --grid p2 --dataset $D --db $T/s.db", "--grid"},
      {"sweep too large",
       "sweep --base $C --grid p1=1,2,3,4,5,6,7,8,9,10 --grid p2=100,101,102,103,104,105,106,107,108,109 "
       "--grid lr_tolerance=0,1,2,3,4,5,6,7,8,9,10 --grid median=0,3,5,7,1 --grid clock_mhz=100,200 "
       "--dataset $D --db $T/s.db",
       "--yes"},
      {"sweep no base", "sweep --grid p2=64,96 --dataset $D --db $T/s.db", "base"},
      {"sweep frames malformed", "sweep --base $C --grid p2=64,96 --dataset $D --db $T/s.db --frames abc", "abc"},
      {"sweep dataset missing", "sweep --base $C --grid p2=64,96 --dataset $T/nowhere --db $T/s.db", "nowhere"},
      {"sweep shard", "sweep --base $C --grid p2=64,96 --dataset $D --db $T/s.db --shard 3/2", "--shard"},
      {"sweep all invalid", "sweep --base $C --grid p1=500,600 --dataset $D --db $T/invalid.db --frames 1",
       "no design"},
      {"sweep db is a folder", "sweep --base $C --grid p2=64,96 --dataset $D --db $T/folder", "folder"},
      // --- store readers
      {"pareto missing store", "pareto --db $T/none.db", "none.db"},
      {"pareto not a store", "pareto --db $T/not_a_store.db", "not_a_store.db"},
      {"report missing store", "report --db $T/none.db --csv $T/r.csv", "none.db"},
      {"report csv folder", "report --db $T/none.db --csv $T/folder", "--csv"},
      {"report nothing asked", "report --db $T/not_a_store.db", "--html"},
      {"merge input missing", "merge --db $T/m.db $T/absent.db", "absent.db"},
      {"export design without db", "export-hls --config $C --design 0123 --out $T/e", "--db"},
      // --- avoidance world
      {"scene scenario missing", "scene --scenario $T/none.yaml --out $T/scene", "none.yaml"},
      {"scene scenario folder", "scene --scenario $T/folder --out $T/scene", "folder"},
      {"scene kind", "scene --scenario $T/scenario_kind.yaml --out $T/scene", "jungle"},
      {"scene no kind", "scene --scenario $T/scenario_nokind.yaml --out $T/scene", "kind"},
      {"scene wrong type", "scene --scenario $T/scenario_type.yaml --out $T/scene", "scenario_type.yaml"},
      {"scene not a mapping", "scene --scenario $T/scenario_list.yaml --out $T/scene", "scenario_list.yaml"},
      {"scene out is a file", "scene --scenario $T/scenario_kind.yaml --out $T/text.txt", "text.txt"},
      {"scene step NaN", "scene --scenario $T/scenario_kind.yaml --out $T/scene --step-m nan", "--step-m"},
      {"fly scenario folder", "fly --config $C --scenario $T/folder", "folder"},
      {"fly scenario /dev/zero", "fly --config $C --scenario /dev/zero", "/dev/zero"},
      {"fly mavlink udp", "fly --config $C --scenario single-pole --mavlink-out udp:127.0.0.1:14540", "udp:127.0.0.1"},
      {"fly mavlink folder", "fly --config $C --scenario single-pole --mavlink-out $T/folder", "--mavlink-out"},
      {"fly mavlink frame", "fly --config $C --scenario single-pole --mavlink-frame enu", "--mavlink-frame"},
      {"fly first seed 0", "fly --config $C --scenario single-pole --first-seed 0", "--first-seed"},
      {"fly mavlink with search", "fly --config $C --scenario single-pole --find-max-speed --mavlink-out $T/m.mav",
       "--find-max-speed"},
      {"avoid truth missing", "avoid --config $C --dataset $D --truth $T/none.json", "--truth"},
      {"fly speed NaN", "fly --config $C --scenario $T/scenario_kind.yaml --speed-mps nan", "--speed-mps"},
      {"fly speed inf", "fly --config $C --scenario $T/scenario_kind.yaml --speed-mps inf", "--speed-mps"},
      // --- HLS
      {"export clock NaN", "export-hls --config $C --out $T/e --clock-mhz nan", "--clock-mhz"},
      {"export out is a file", "export-hls --config $C --out $T/text.txt", "text.txt"},
      {"import report missing", "import-hls --report $T/none.xml", "none.xml"},
      {"import report /dev/zero", "import-hls --report /dev/zero", "/dev/zero"},
      {"import not XML", "import-hls --report $T/not_xml.xml", "not_xml.xml"},
      {"import no profile", "import-hls --report $T/no_profile.xml", "no_profile.xml"},
      {"import clock zero", "import-hls --report $T/clock_zero.xml", "TargetClockPeriod"},
      {"import clock NaN", "import-hls --report $T/clock_nan.xml", "TargetClockPeriod"},
      {"import II zero", "import-hls --report $T/ii_zero.xml", "PipelineII"},
      {"import II text", "import-hls --report $T/ii_text.xml", "PipelineII"},
      {"fit points missing", "fit-resources --points $T/none.yaml", "none.yaml"},
      {"fit points shape", "fit-resources --points $T/points_nolist.yaml", "points"},
      {"fit write folder", "fit-resources --write $T/folder", "--write"},
  };
  return c;
}

TEST_F(BadInput, EveryCaseIsOneClearUserError) {
  const std::string cli = PARALLAX_CLI;
  const std::string config = std::string(PARALLAX_CONFIG_DIR) + "/ruf2018-census.yaml";
  const std::string dataset = std::string(PARALLAX_DATA_DIR) + "/kitti2015-640x360";
  ASSERT_GE(cases().size(), 80u);
  for (const Case& c : cases()) {
    std::string args = replace_all(replace_all(replace_all(c.args, "$T", dir_.string()), "$C", config), "$D", dataset);
    const auto r = shell("cd " + dir_.string() + " && timeout 120 " + cli + " " + args + " < /dev/null");
    SCOPED_TRACE(std::string(c.name) + ": parallax " + args + "\n" + r.output);
    EXPECT_NE(r.status, 124) << "timed out";
    EXPECT_NE(r.status, -1) << "killed by a signal";
    EXPECT_NE(r.status, 70) << "internal error";
    EXPECT_EQ(r.status, 2) << "a user error exits 2";
    std::size_t errors = 0;
    for (std::size_t p = r.output.find("parallax: error:"); p != std::string::npos;
         p = r.output.find("parallax: error:", p + 1))
      ++errors;
    EXPECT_EQ(errors, 1u) << "one message";
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << "the message names '" << c.expect << "'";
  }
}

// A malformed command line exits 2 like every other user error (CLI11's own codes are 105-109);
// --help and --version succeed.
TEST_F(BadInput, HelpAndVersionSucceed) {
  const std::string cli = PARALLAX_CLI;
  EXPECT_EQ(shell(cli + " --help").status, 0);
  EXPECT_EQ(shell(cli + " --version").status, 0);
  EXPECT_EQ(shell(cli + " sweep --help").status, 0);
}

}  // namespace
