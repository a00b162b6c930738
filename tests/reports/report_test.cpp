// browser + unit: reports of a small sweep on the shipped frames: CSV columns in their documented
// order, JSON with the same content, an HTML page that fetches nothing, and that page in Debian's
// headless chromium: it loads without console errors, its sections and plots exist after the
// scripts ran, and its screenshot is not blank.
#include <gtest/gtest.h>

#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "parallax/config/config.hpp"
#include "parallax/reports/report.hpp"
#include "parallax/search/sweep.hpp"

namespace parallax::test {
namespace {

namespace fs = std::filesystem;
const std::string kData = PARALLAX_DATA_DIR "/kitti2015-640x360";
const std::string kCensus = PARALLAX_CONFIG_DIR "/ruf2018-census.yaml";

std::string run(const std::string& cmd, int* status = nullptr) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return out;
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), int(buf.size()), p)) out += buf.data();
  const int st = pclose(p);
  if (status) *status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return out;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct Fixture {
  fs::path dir;
  std::string db;
  Fixture() {
    dir = fs::temp_directory_path() / ("parallax_report_test_" + std::to_string(getpid()));  // checkouts share /tmp
    fs::remove_all(dir);
    fs::create_directories(dir);
    db = (dir / "r.db").string();
    search::SweepSpec s;
    s.name = "small";
    s.base = kCensus;
    s.frames = "1,5";
    search::add_axis(s, "p2=32,64");
    search::add_axis(s, "paths=1,4");
    search::add_axis(s, "disparities=60,61");  // 61: invalid (PU 6)
    search::ResultStore store(db);
    search::SweepRunOptions ro;
    ro.dataset = kData;
    search::run_sweep(s, store, ro);
    int st = -1;
    run(std::string(PARALLAX_CLI) + " report --db " + db + " --html " + (dir / "r.html").string() + " --csv " +
            (dir / "d.csv").string() + " --frames-csv " + (dir / "f.csv").string() + " --json " +
            (dir / "r.json").string() + " --dataset " + kData + " 2>&1",
        &st);
    ok = st == 0;
  }
  bool ok = false;
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

TEST(Report, CsvColumnsInTheirDocumentedOrder) {
  ASSERT_TRUE(fixture().ok);
  std::istringstream csv(slurp(fixture().dir / "d.csv"));
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(
      header.rfind(
          "hash,sweep,status,reason,name,roi,cost,census,window,disparities,min_disparity,parallel_units,paths,p1,p2,",
          0),
      0u)
      << header;
  // The metrics follow the configuration, in metric_columns() order.
  std::size_t pos = header.find(",density_pct,");
  ASSERT_NE(pos, std::string::npos);
  for (const auto& m : reports::metric_columns()) {
    const std::size_t at = header.find("," + m, pos);
    EXPECT_NE(at, std::string::npos) << m;
    pos = at == std::string::npos ? pos : at + 1;
  }
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 8);
  std::istringstream frames(slurp(fixture().dir / "f.csv"));
  int frame_rows = -1;
  while (std::getline(frames, line)) ++frame_rows;
  EXPECT_EQ(frame_rows, 4 * 2);  // 4 valid designs x 2 frames
}

TEST(Report, JsonCarriesTheSameDesigns) {
  ASSERT_TRUE(fixture().ok);
  const auto j = nlohmann::json::parse(slurp(fixture().dir / "r.json"));
  ASSERT_EQ(j.size(), 8u);
  int invalid = 0;
  for (const auto& d : j) {
    EXPECT_TRUE(d.contains("configuration") && d.contains("metrics") && d.contains("hash"));
    if (d["status"] == "invalid") {
      ++invalid;
      EXPECT_NE(d["reason"].get<std::string>().find("disparities"), std::string::npos);
    } else {
      EXPECT_EQ(d["frames"].size(), 2u);
      EXPECT_TRUE(d["metrics"].contains("correct_3px_pct"));
    }
  }
  EXPECT_EQ(invalid, 4);
}

TEST(Report, HtmlFetchesNothing) {
  ASSERT_TRUE(fixture().ok);
  const std::string html = slurp(fixture().dir / "r.html");
  for (const char* bad : {"src=\"http", "href=\"http", "src='http", "url(http", "<link ", "@import"})
    EXPECT_EQ(html.find(bad), std::string::npos) << bad;
  EXPECT_NE(html.find("data:image/png;base64,"), std::string::npos);
}

// The store keeps the dataset folder of each sweep: without --dataset the report renders the
// front designs' images from it while it exists, and says so when it is gone.
TEST(Report, ImagesFromTheSweepsOwnDatasetWhileItExists) {
  ASSERT_TRUE(fixture().ok);
  const fs::path html = fixture().dir / "no-dataset.html";
  int st = -1;
  run(std::string(PARALLAX_CLI) + " report --db " + fixture().db + " --details 1 --html " + html.string() + " 2>&1",
      &st);
  ASSERT_EQ(st, 0);
  EXPECT_NE(slurp(html).find("left image, frame 000001"), std::string::npos);
  EXPECT_NE(slurp(html).find("--dataset " + fs::canonical(kData).string()), std::string::npos);  // reproduce command

  const fs::path d = fs::temp_directory_path() / ("parallax_report_test_gone_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  fs::copy(kData, d / "kitti", fs::copy_options::recursive);
  const std::string db = (d / "g.db").string();
  {
    search::SweepSpec s;
    s.name = "gone";
    s.base = kCensus;
    s.frames = "1";
    search::ResultStore store(db);
    search::SweepRunOptions ro;
    ro.dataset = (d / "kitti").string();
    search::run_sweep(s, store, ro);
  }
  fs::remove_all(d / "kitti");
  const std::string out =
      run(std::string(PARALLAX_CLI) + " report --db " + db + " --html " + (d / "g.html").string() + " 2>&1", &st);
  ASSERT_EQ(st, 0) << out;
  EXPECT_NE(out.find("dataset " + (d / "kitti").string() + " is gone"), std::string::npos) << out;
  EXPECT_EQ(slurp(d / "g.html").find("left image, frame"), std::string::npos);
  fs::remove_all(d);
}

// The design table and the sensitivity plots follow the sweep's own axes, whatever they are: a
// sweep of window, census and p1 shows those columns and plots, and none of an axis it did not
// sweep (disparities, paths).
TEST(Report, TableAndSensitivityFollowTheSweepAxes) {
  search::SweepSpec spec;
  spec.name = "axes";
  spec.base = kCensus;
  search::add_axis(spec, "window=5x5,9x7");
  search::add_axis(spec, "census=full,sparse");
  search::add_axis(spec, "p1=8,12");
  std::vector<search::ResultStore::Row> rows;
  int n = 0;
  for (const char* window : {"5x5", "9x7"})
    for (const char* census : {"full", "sparse"})
      for (int p1 : {8, 12}) {
        config::PipelineConfig c = config::load_config(kCensus);
        config::set_field(c, "window", window);
        config::set_field(c, "census", census);
        c.p1 = p1;
        search::ResultStore::Row r;
        r.hash = "h" + std::to_string(n);
        r.config_yaml = config::to_yaml(c);
        r.status = "ok";
        r.metrics = {{"correct_3px_pct", 85.0 + n}, {"density_pct", 90.0 - n}, {"bram18k", 140}, {"latency_ms", 20}};
        rows.push_back(r);
        ++n;
      }
  reports::ReportOptions opt;
  opt.details = 0;
  const std::string html = reports::html_report(spec, rows, opt);
  for (const char* want :
       {"id=\"sens-window\"", "id=\"sens-census\"", "id=\"sens-p1\"", "<th>window</th>", "<th>census</th>",
        "<th>p1</th>", "<td>9x7</td>", "<td>sparse</td>", "window (0 = 5x5, 1 = 9x7)"})
    EXPECT_NE(html.find(want), std::string::npos) << want;
  for (const char* absent :
       {"id=\"sens-disparities\"", "id=\"sens-d\"", "id=\"sens-paths\"", "<th>disparities</th>", "<th>paths</th>"})
    EXPECT_EQ(html.find(absent), std::string::npos) << absent;
}

// The Pareto plots mark the seed and the peers stored beside the sweep (black diamonds named
// beside them), only where the peer has both figures (no BRAM, no latency: the density plot),
// and the summary says how many front designs beat each peer.
TEST(Report, ParetoPlotsMarkTheSeedAndThePeers) {
  search::SweepSpec spec;
  spec.name = "peers";
  spec.base = kCensus;
  search::add_axis(spec, "p1=8,12");
  std::vector<search::ResultStore::Row> rows;
  for (int p1 : {8, 12}) {
    config::PipelineConfig c = config::load_config(kCensus);
    c.p1 = p1;
    search::ResultStore::Row r;
    r.hash = p1 == 8 ? "seedhash" : "other";
    r.config_yaml = config::to_yaml(c);
    r.status = "ok";
    r.metrics = {{"correct_3px_pct", p1 == 8 ? 90.0 : 95.0},
                 {"density_pct", 88.0},
                 {"bram18k", 140},
                 {"latency_ms", 20},
                 {"fits_device", 1}};
    rows.push_back(r);
  }
  reports::ReportOptions opt;
  opt.details = 0;
  opt.seed_hash = "seedhash";
  for (const char* name : {"opencv-hh4", "opencv-sgbm"}) {
    search::ResultStore::Row peer;
    peer.hash = std::string("peer-") + name;
    peer.config_yaml = std::string("baseline: ") + name + "\n";
    peer.status = "peer";
    peer.metrics = {{"correct_3px_pct", 94.0}, {"density_pct", 87.0}};
    opt.peers.push_back(peer);
  }
  const std::string html = reports::html_report(spec, rows, opt);
  const std::size_t density = html.find("id=\"pareto-density\"");
  ASSERT_NE(density, std::string::npos);
  const std::string plot = html.substr(density, html.find("</svg>", density) - density);
  for (const char* want : {">seed</text>", ">opencv-hh4</text>", ">opencv-sgbm</text>", "class=\"ref\""})
    EXPECT_NE(plot.find(want), std::string::npos) << want;
  const std::size_t bram = html.find("id=\"pareto-bram\"");
  const std::string bram_plot = html.substr(bram, html.find("</svg>", bram) - bram);
  EXPECT_EQ(bram_plot.find("opencv-hh4"), std::string::npos);  // no BRAM figure: not drawn
  EXPECT_NE(bram_plot.find(">seed</text>"), std::string::npos);
  EXPECT_NE(html.find("peer opencv-hh4</td><td>correct 94 %, density 87 % on the same frames; beaten on both by 1"),
            std::string::npos);
}

// `run` and `sim` write the per-design section as a page of its own.
TEST(Report, RunAndSimWriteTheDesignSection) {
  const fs::path d = fs::temp_directory_path() / "parallax_report_test_pages";
  fs::remove_all(d);
  fs::create_directories(d);
  const std::string pair =
      " --left " + kData + "/training/image_2/000005_10.png --right " + kData + "/training/image_3/000005_10.png";
  int st = -1;
  run(std::string(PARALLAX_CLI) + " run --config " + kCensus + pair + " --gt " + kData +
          "/training/disp_noc_0/000005_10.png --out " + (d / "o.png").string() + " --html " +
          (d / "run.html").string() + " 2>&1",
      &st);
  ASSERT_EQ(st, 0);
  run(std::string(PARALLAX_CLI) + " sim --config " + kCensus + " --set roi=96x32 --no-sizing --html " +
          (d / "sim.html").string() + " 2>&1",
      &st);
  ASSERT_EQ(st, 0);
  for (const char* page : {"run.html", "sim.html"}) {
    const std::string html = slurp(d / page);
    EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u) << page;
    for (const char* want : {"class=\"design\"", "data:image/png;base64,", "class=\"plot\"", "fifo_depth", "parallax "})
      EXPECT_NE(html.find(want), std::string::npos) << page << ": " << want;
  }
  EXPECT_NE(slurp(d / "run.html").find("error: green within 3 px"), std::string::npos);
}

#ifdef PARALLAX_CHROMIUM
TEST(ReportBrowser, LoadsCleanlyWithSectionsPlotsAndAPicture) {
  ASSERT_TRUE(fixture().ok);
  const std::string url = "file://" + (fixture().dir / "r.html").string();
  const std::string flags =
      std::string(PARALLAX_CHROMIUM) +
      " --headless --no-sandbox --disable-gpu --disable-dev-shm-usage --enable-logging=stderr --v=0 ";
  const std::string log = (fixture().dir / "console.log").string();
  int st = -1;
  const std::string dom = run(flags + "--dump-dom " + url + " 2>" + log, &st);
  ASSERT_EQ(st, 0) << slurp(log);
  for (const char* id :
       {"id=\"summary\"", "id=\"pareto\"", "id=\"sensitivity\"", "id=\"table\"", "id=\"designs-detail\"",
        "id=\"pareto-bram\"", "id=\"pareto-latency\"", "id=\"pareto-density\"", "id=\"sens-p2\"", "id=\"designs\""})
    EXPECT_NE(dom.find(id), std::string::npos) << id;
  std::size_t plots = 0, points = 0;
  for (std::size_t p = dom.find("class=\"plot\""); p != std::string::npos; p = dom.find("class=\"plot\"", p + 1))
    ++plots;
  for (std::size_t p = dom.find("class=\"pt\""); p != std::string::npos; p = dom.find("class=\"pt\"", p + 1)) ++points;
  EXPECT_GE(plots, 6u);
  EXPECT_GE(points, 12u);
  // Console: chromium logs every page message (console.error, uncaught exceptions) as a CONSOLE
  // line without its level; the page writes none, so any such line is a failure.
  std::istringstream lines(slurp(log));
  std::string line;
  while (std::getline(lines, line)) {
    EXPECT_EQ(line.find("CONSOLE"), std::string::npos) << line;
  }
  // A screenshot that is not blank.
  const std::string shot = (fixture().dir / "shot.png").string();
  run(flags + "--window-size=1280,1600 --screenshot=" + shot + " " + url + " >/dev/null 2>&1", &st);
  const cv::Mat img = cv::imread(shot, cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(img.empty()) << "no screenshot";
  cv::Scalar mean, sd;
  cv::meanStdDev(img, mean, sd);
  EXPECT_GT(sd[0], 10.0) << "blank page";
  EXPECT_GT(cv::countNonZero(img < 200), int(img.total() / 200)) << "almost nothing drawn";
}
#else
TEST(ReportBrowser, LoadsCleanlyWithSectionsPlotsAndAPicture) {
  GTEST_SKIP() << "chromium not found at configure time";
}
#endif

}  // namespace
}  // namespace parallax::test
