// unit + reject: sweeps (design enumeration, materialisation, the results store, resuming after a
// SIGKILL, Pareto fronts). The evaluation runs on the shipped KITTI crops.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <set>
#include <thread>

#include "parallax/eval/dataset.hpp"
#include "frame_cache.hpp"  // explore/search/src: internal
#include "parallax/search/sweep.hpp"

namespace parallax::test {
namespace {

namespace fs = std::filesystem;
using search::ResultStore;
using search::SweepSpec;

const std::string kData = PARALLAX_DATA_DIR "/kitti2015-640x360";
const std::string kCensus = PARALLAX_CONFIG_DIR "/ruf2018-census.yaml";

fs::path fresh(const std::string& name) {
  // The pid: test runs of several checkouts share /tmp.
  const fs::path d = fs::temp_directory_path() / ("parallax_sweep_test_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(SweepSpec, GridIsTheFullProductInOdometerOrder) {
  SweepSpec s;
  search::add_axis(s, "p1=8,10");
  search::add_axis(s, "median=0,3,5");
  const auto d = search::enumerate_designs(s);
  ASSERT_EQ(d.size(), 6u);
  EXPECT_EQ(d[0].fields[0].second, "8");
  EXPECT_EQ(d[0].fields[1].second, "0");
  EXPECT_EQ(d[1].fields[1].second, "3");
  EXPECT_EQ(d[5].fields[0].second, "10");
  EXPECT_EQ(d[5].fields[1].second, "5");
  search::add_axis(s, "p1=12");  // replaces the axis
  EXPECT_EQ(search::enumerate_designs(s).size(), 3u);
}

TEST(SweepSpec, RandomAndLatinHypercubeAreSeededAndDistinct) {
  SweepSpec s;
  search::add_axis(s, "p1=4,6,8,10,12");
  search::add_axis(s, "p2=20,30,40,50,60,70");
  for (const char* strategy : {"random", "lhs"}) {
    s.strategy = strategy;
    s.samples = 10;
    s.seed = 7;
    const auto a = search::enumerate_designs(s), b = search::enumerate_designs(s);
    ASSERT_EQ(a.size(), b.size()) << strategy;
    std::set<std::string> keys;
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].fields, b[i].fields) << strategy;
      keys.insert(a[i].fields[0].second + "/" + a[i].fields[1].second);
    }
    EXPECT_EQ(keys.size(), a.size()) << strategy << ": duplicates";
    EXPECT_GE(a.size(), 8u) << strategy;
    s.seed = 8;
    EXPECT_NE(search::enumerate_designs(s)[0].fields, a[0].fields) << strategy;
  }
}

// strategy list: the designs as written, in order; the axes are the fields they set, with the
// values they take (for the checks and the report's columns); a round trip keeps them.
TEST(SweepSpec, ListIsTheDesignsAsWritten) {
  const SweepSpec s = search::parse_sweep(
      "strategy: list\ndesigns:\n  - {}\n  - {uniqueness_pct: 5}\n  - {paths: 5, window: 9x7}\n  - {paths: 8}\n",
      "list.yaml");
  const auto d = search::enumerate_designs(s);
  ASSERT_EQ(d.size(), 4u);
  EXPECT_TRUE(d[0].fields.empty());
  EXPECT_EQ(d[2].fields, (std::vector<std::pair<std::string, std::string>>{{"paths", "5"}, {"window", "9x7"}}));
  EXPECT_EQ(s.axes, (std::vector<std::pair<std::string, std::vector<std::string>>>{
                        {"uniqueness_pct", {"5"}}, {"paths", {"5", "8"}}, {"window", {"9x7"}}}));
  const SweepSpec t = search::parse_sweep(search::sweep_to_yaml(s), "round trip");
  EXPECT_EQ(t.designs, s.designs);
  EXPECT_EQ(t.axes, s.axes);
  EXPECT_THROW(search::parse_sweep("strategy: list\n", "s.yaml"), eval::InputError);
  EXPECT_THROW(search::parse_sweep("designs:\n  - {p1: 4}\n", "s.yaml"), eval::InputError);  // grid
}

TEST(SweepSpec, ShippedSweepsParse) {
  for (const char* f : {"ruf2018-neighbourhood.yaml", "census-penalties.yaml"}) {
    const SweepSpec s = search::load_sweep(std::string(PARALLAX_CONFIG_DIR) + "/sweeps/" + f);
    EXPECT_FALSE(s.axes.empty()) << f;
    EXPECT_FALSE(search::enumerate_designs(s).empty()) << f;
  }
}

TEST(SweepSpec, FileErrorsNameTheField) {
  EXPECT_THROW(search::parse_sweep("strategy: annealing\n", "s.yaml"), eval::InputError);
  try {
    search::parse_sweep("axes: {p1: [8]}\nbogus: 1\n", "s.yaml");
    FAIL();
  } catch (const eval::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bogus"), std::string::npos);
  }
  try {
    search::parse_sweep("objectives: [best correct_3px_pct]\n", "s.yaml");
    FAIL();
  } catch (const eval::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max KEY"), std::string::npos);
  }
  SweepSpec s;
  EXPECT_THROW(search::add_axis(s, "p1"), eval::InputError);
  // Round trip.
  search::add_axis(s, "p2=32,64");
  s.objectives = {{"bram18k", false}};
  const SweepSpec t = search::parse_sweep(search::sweep_to_yaml(s), "round trip");
  EXPECT_EQ(t.axes, s.axes);
  EXPECT_EQ(t.objectives.size(), 1u);
  EXPECT_FALSE(t.objectives[0].maximise);
}

TEST(SweepRun, InvalidDesignsAreStoredWithTheReasonAndRerunsSkip) {
  const fs::path d = fresh("resume");
  SweepSpec s;
  s.name = "t";
  s.base = kCensus;
  s.frames = "1";
  search::add_axis(s, "disparities=60,61");  // 61 is not a multiple of PU 6
  ResultStore store((d / "r.db").string());
  search::SweepRunOptions ro;
  ro.dataset = kData;
  ro.jobs = 2;
  const auto first = search::run_sweep(s, store, ro);
  EXPECT_EQ(first.total, 2);
  EXPECT_EQ(first.invalid, 1);
  EXPECT_EQ(first.design_frames, 1) << "one valid design x one frame; the invalid one scores none";
  EXPECT_EQ(first.threads, 2);
  const auto rows = store.designs("t");
  ASSERT_EQ(rows.size(), 2u);
  int ok = 0;
  for (const auto& r : rows) {
    if (r.status == "invalid") {
      EXPECT_NE(r.reason.find("disparities"), std::string::npos) << r.reason;
    } else {
      ++ok;
      EXPECT_EQ(r.status, "ok");
      for (const char* k : {"correct_3px_pct", "density_pct", "latency_ms", "fps", "bram18k", "lut", "fits_device"})
        EXPECT_TRUE(r.metrics.count(k)) << k;
      EXPECT_GT(r.metrics.at("density_pct"), 50.0);
    }
  }
  EXPECT_EQ(ok, 1);
  const auto second = search::run_sweep(s, store, ro);
  EXPECT_EQ(second.skipped, 2);
  EXPECT_EQ(second.evaluated, 0);
  EXPECT_EQ(second.design_frames, 0) << "skipped designs are not counted";
  EXPECT_EQ(store.count_designs(), 2);
}

// SIGKILL mid-sweep, then rerun: every design stored once, the ones finished before the kill
// untouched.
TEST(SweepRun, KilledMidSweepLosesNothingAndDuplicatesNothing) {
  const fs::path d = fresh("kill");
  const std::string db = (d / "k.db").string();
  // Disparity ranges: no two designs share the cost stage, so each is stored as it finishes.
  const std::string args = "sweep --base " + kCensus + " --grid disparities=24,30,36,42,48,54 --dataset " + kData +
                           " --frames 1,5 --jobs 1 --db " + db;
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr)) _exit(126);
    execl("/bin/sh", "sh", "-c", (std::string(PARALLAX_CLI) + " " + args).c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Wait on state, not on the clock (a sanitizer build runs many times slower): until two designs
  // are stored, or the sweep has ended by itself. ctest's timeout bounds a sweep that hangs.
  std::vector<ResultStore::Row> before;
  bool exited = false;
  int st = 0;
  while (!exited) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    exited = waitpid(pid, &st, WNOHANG) == pid;
    if (!fs::exists(db)) continue;
    try {
      ResultStore peek(db);
      if (peek.count_designs() >= 2) {
        before = peek.designs();
        break;
      }
    } catch (const eval::InputError&) {  // the store is still being created
    }
  }
  kill(pid, SIGKILL);
  if (system(("pkill -9 -f 'sweep --base " + kCensus + " --grid disparities=24,30' >/dev/null 2>&1").c_str()) < 0)
    ADD_FAILURE();
  if (!exited) waitpid(pid, &st, 0);
  ASSERT_GE(before.size(), 2u) << "the sweep ended without storing two designs";
  ASSERT_LT(before.size(), 6u) << "the sweep finished before the kill; the test proves nothing";
  const int rc = system((std::string(PARALLAX_CLI) + " " + args + " >/dev/null 2>&1").c_str());
  ASSERT_EQ(WEXITSTATUS(rc), 0);
  ResultStore store(db);
  const auto after = store.designs();
  EXPECT_EQ(after.size(), 6u);
  std::set<std::string> hashes;
  for (const auto& r : after) hashes.insert(r.hash);
  EXPECT_EQ(hashes.size(), 6u);
  for (const auto& b : before)
    for (const auto& a : after)
      if (a.hash == b.hash) {
        EXPECT_EQ(a.finished_at, b.finished_at) << "re-evaluated " << a.hash;
        EXPECT_EQ(a.metrics, b.metrics);
      }
}

std::map<std::string, std::map<std::string, double>> by_hash(ResultStore& s) {
  std::map<std::string, std::map<std::string, double>> m;
  for (const auto& r : s.designs()) m[r.hash] = r.metrics;
  return m;
}

SweepSpec small_sweep() {
  SweepSpec s;
  s.name = "small";
  s.base = kCensus;
  s.frames = "1";
  search::add_axis(s, "p2=32,48,64");
  search::add_axis(s, "median=0,5");
  return s;
}

// Shards are disjoint, cover the sweep, and merge into the store one process writes.
TEST(SweepScale, ShardsMergeToTheWholeSweep) {
  const fs::path d = fresh("shards");
  const SweepSpec s = small_sweep();
  search::SweepRunOptions ro;
  ro.dataset = kData;
  ro.jobs = 1;
  ResultStore whole((d / "whole.db").string());
  search::run_sweep(s, whole, ro);
  int sizes = 0;
  for (int k = 1; k <= 3; ++k) {
    ResultStore part((d / ("part" + std::to_string(k) + ".db")).string());
    ro.shard_index = k;
    ro.shard_count = 3;
    sizes += search::run_sweep(s, part, ro).total;
  }
  EXPECT_EQ(sizes, 6);
  ResultStore merged((d / "merged.db").string());
  for (int k = 1; k <= 3; ++k) merged.merge_from((d / ("part" + std::to_string(k) + ".db")).string());
  EXPECT_EQ(merged.merge_from((d / "part1.db").string()), 0);  // merging twice adds nothing
  EXPECT_EQ(by_hash(merged), by_hash(whole));
  EXPECT_EQ(merged.sweeps().size(), 1u);
  EXPECT_EQ(merged.designs("small").size(), 6u);  // the sweep's membership came along
  ro.shard_index = 4;
  EXPECT_THROW(search::run_sweep(s, merged, ro), eval::InputError);
}

#ifdef PARALLAX_MPIEXEC
// The MPI mode on localhost with two ranks gives the results of one process.
TEST(SweepScale, MpiTwoRanksEqualOneProcess) {
  const fs::path d = fresh("mpi");
  const std::string db = (d / "mpi.db").string();
  // Under the sanitizers (debug preset): OpenMPI keeps its plugins loaded and allocations are
  // unwound fully, so that LeakSanitizer sees OpenMPI's own frames and its suppressions
  // (cmake/lsan.supp, by library file) apply; without a sanitizer these settings change nothing.
  const std::string cmd = std::string(
                              "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
                              "OMPI_MCA_mca_base_component_disable_dlclose=1 "
                              "ASAN_OPTIONS=\"${ASAN_OPTIONS}:fast_unwind_on_malloc=0\" ") +
                          PARALLAX_MPIEXEC + " --oversubscribe -np 2 " + PARALLAX_CLI + " sweep --base " + kCensus +
                          " --grid p2=32,48,64 --grid median=0,5 --dataset " + kData +
                          " --frames 1 --jobs 1 --mpi --db " + db + " >/dev/null 2>&1";
  ASSERT_EQ(WEXITSTATUS(system(cmd.c_str())), 0) << cmd;
  ResultStore mpi(db);
  ResultStore one((d / "one.db").string());
  search::SweepRunOptions ro;
  ro.dataset = kData;
  ro.jobs = 1;
  SweepSpec s = small_sweep();
  s.name = "sweep";  // the CLI's default name
  search::run_sweep(s, one, ro);
  EXPECT_EQ(mpi.count_designs(), 6);
  EXPECT_EQ(by_hash(mpi), by_hash(one));
}
#endif

// Designs sharing the cost stage (a penalty and median sweep) evaluated together give exactly the
// results of evaluating each on its own.
TEST(SweepSharing, SharedCostsGiveTheSameResults) {
  const fs::path d = fresh("sharing");
  SweepSpec s = small_sweep();
  s.frames = "1,5";
  search::add_axis(s, "p1=4,8");
  search::SweepRunOptions ro;
  ro.dataset = kData;
  ro.jobs = 2;
  ResultStore shared((d / "shared.db").string()), alone((d / "alone.db").string());
  search::run_sweep(s, shared, ro);
  ro.share_costs = false;
  search::run_sweep(s, alone, ro);
  EXPECT_EQ(shared.count_designs(), 12);
  EXPECT_EQ(by_hash(shared), by_hash(alone));
  // Census variants read other taps: they share no costs with each other (they once did, and a
  // sparse design scored the full census's figures).
  SweepSpec v;
  v.name = "variants";
  v.base = kCensus;
  v.frames = "1";
  search::add_axis(v, "census=full,sparse,symmetric");
  search::add_axis(v, "window=9x7");
  ResultStore shared_v((d / "shared_v.db").string()), alone_v((d / "alone_v.db").string());
  ro.share_costs = true;
  search::run_sweep(v, shared_v, ro);
  ro.share_costs = false;
  search::run_sweep(v, alone_v, ro);
  const auto variants = by_hash(shared_v);
  EXPECT_EQ(variants, by_hash(alone_v));
  std::set<double> correct;
  for (const auto& kv : variants) correct.insert(kv.second.at("correct_3px_pct"));
  EXPECT_EQ(correct.size(), 3u) << "census variants scored alike";
}

// Two threads cut each cost group's frames into chunks that either thread takes (sweep.cpp,
// frame_chunks): every design's per-frame rows come out in frame order with the figures one
// thread gives, and the pooled figures are the same.
TEST(SweepSharing, ThreadsSplittingFramesGiveTheOneThreadResults) {
  const fs::path d = fresh("chunks");
  SweepSpec s = small_sweep();
  s.frames = "";  // the four shipped frames
  search::add_axis(s, "disparities=48,60");
  search::SweepRunOptions ro;
  ro.dataset = kData;
  ResultStore one((d / "one.db").string()), two((d / "two.db").string());
  ro.jobs = 1;
  search::run_sweep(s, one, ro);
  ro.jobs = 2;
  search::run_sweep(s, two, ro);
  auto frames_by_hash = [](ResultStore& st) {
    std::map<std::string, std::vector<std::pair<std::string, std::map<std::string, double>>>> m;
    for (const auto& r : st.designs()) m[r.hash] = r.frames;
    return m;
  };
  EXPECT_EQ(one.count_designs(), 12);
  for (const auto& r : one.designs()) EXPECT_EQ(r.status, "ok") << r.reason;
  EXPECT_EQ(by_hash(two), by_hash(one));
  const auto f1 = frames_by_hash(one), f2 = frames_by_hash(two);
  EXPECT_EQ(f2, f1);
  ASSERT_FALSE(f1.empty());
  const auto& rows = f1.begin()->second;
  ASSERT_EQ(rows.size(), 4u);
  for (std::size_t i = 1; i < rows.size(); ++i) EXPECT_LT(rows[i - 1].first, rows[i].first) << "frames out of order";
}

// The sweep's frame cache (explore/search/src/frame_cache.hpp): a frame is decoded once and
// kept while the budget lasts, the same object for every group; past the budget it is decoded
// per use and not kept; either way the crops equal the decoded frame's.
TEST(SweepSharing, FrameCacheKeepsEachFrameOnceWithinItsBudget) {
  const eval::Dataset ds = eval::open_dataset(kData);
  const std::vector<eval::FrameRef> refs = eval::list_frames(ds, eval::GtKind::noc, "");
  ASSERT_GE(refs.size(), 2u);
  eval::RoiSize roi;
  roi.full = false;
  roi.width_px = 320;
  roi.height_px = 200;
  search::detail::FrameCache kept(std::size_t(64) << 20), none(0);
  const auto a = kept.get(refs[0], roi), b = kept.get(refs[0], roi), c = kept.get(refs[1], roi);
  EXPECT_EQ(a.get(), b.get());
  EXPECT_NE(a.get(), c.get());
  EXPECT_EQ(kept.kept_frames(), 2u);
  const auto d = none.get(refs[0], roi), e = none.get(refs[0], roi);
  EXPECT_NE(d.get(), e.get());
  EXPECT_EQ(none.kept_frames(), 0u);
  // A budget of one frame keeps the first and not the second; two threads asking for one frame
  // at once get one decoded copy.
  search::detail::FrameCache one(a->bytes());
  EXPECT_EQ(one.get(refs[0], roi).get(), one.get(refs[0], roi).get());
  EXPECT_NE(one.get(refs[1], roi).get(), one.get(refs[1], roi).get());
  EXPECT_EQ(one.kept_frames(), 1u);
  search::detail::FrameCache shared(std::size_t(64) << 20);
  std::shared_ptr<const search::detail::CroppedFrame> t1, t2;
  std::thread first([&] { t1 = shared.get(refs[1], roi); });
  std::thread second([&] { t2 = shared.get(refs[1], roi); });
  first.join();
  second.join();
  EXPECT_EQ(t1.get(), t2.get());
  const eval::Frame f = eval::load_frame(refs[0]);
  const eval::Roi r = eval::resolve_roi(roi, f.left.cols, f.left.rows);
  EXPECT_EQ(a->id, f.id);
  EXPECT_EQ(a->left.cols, 320);
  EXPECT_EQ(a->left.rows, 200);
  for (const auto* x : {a.get(), d.get()}) {
    EXPECT_EQ(cv::norm(x->left, eval::crop_to_roi(f.left, r), cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(x->right, eval::crop_to_roi(f.right, r), cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(x->gt_disparity_px, eval::crop_to_roi(f.gt_disparity_px, r), cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(x->gt_mask, eval::crop_to_roi(f.gt_mask, r), cv::NORM_INF), 0.0);
    EXPECT_TRUE(x->left.isContinuous());  // a compact copy, not a view of the whole frame
  }
}

// With avoidance on, every design carries the avoidance stage's scores, shared or not.
TEST(SweepRun, AvoidanceScoresBecomeMetrics) {
  const fs::path d = fresh("avoid");
  SweepSpec s = small_sweep();
  s.avoidance = true;
  search::SweepRunOptions ro;
  ro.dataset = kData;
  ro.jobs = 2;
  ResultStore shared((d / "a.db").string()), alone((d / "b.db").string());
  search::run_sweep(s, shared, ro);
  ro.share_costs = false;
  search::run_sweep(s, alone, ro);
  const auto rows = shared.designs();
  ASSERT_EQ(rows.size(), 6u);
  for (const auto& r : rows)
    for (const char* k :
         {"obstacle_precision", "obstacle_recall", "range_error_m", "decision_agreement_pct", "mean_ms_per_frame"})
      EXPECT_TRUE(r.metrics.count(k)) << k;
  // Timing differs run to run; everything else is the same either way.
  auto strip = [](std::map<std::string, std::map<std::string, double>> m) {
    for (auto& kv : m) kv.second.erase("mean_ms_per_frame");
    return m;
  };
  EXPECT_EQ(strip(by_hash(shared)), strip(by_hash(alone)));
}

// Flights as metrics (and so as objectives): one design, one seed of the single pole.
TEST(SweepRun, FlightScoresBecomeMetrics) {
  const fs::path d = fresh("flight");
  SweepSpec s;
  s.name = "fl";
  s.base = kCensus;
  s.frames = "1";
  s.flight_scenario = std::string(PARALLAX_CONFIG_DIR) + "/scenarios/single-pole.yaml";
  s.flight_seeds = 1;
  s.flight_speed_mps = 4.0;
  s.flight_size_px = 160;  // quick: the default is the design's own 640 px
  s.objectives = {{"flight_success_rate", true}, {"flight_min_clearance_m", true}};
  ResultStore store((d / "f.db").string());
  search::SweepRunOptions ro;
  ro.dataset = kData;
  search::run_sweep(s, store, ro);
  const auto rows = store.designs();
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_DOUBLE_EQ(rows[0].metrics.at("flight_success_rate"), 100.0);
  EXPECT_DOUBLE_EQ(rows[0].metrics.at("flight_collisions"), 0.0);
  EXPECT_GT(rows[0].metrics.at("flight_min_clearance_m"), 0.0);
  EXPECT_EQ(search::pareto_front(s, rows).size(), 1u);
  // The spec round-trips its flight.
  const SweepSpec t = search::parse_sweep(search::sweep_to_yaml(s), "round trip");
  EXPECT_EQ(t.flight_scenario, s.flight_scenario);
  EXPECT_EQ(t.flight_seeds, 1);
  EXPECT_EQ(t.flight_size_px, 160);
  EXPECT_EQ(SweepSpec{}.flight_size_px, 0);  // by default a design flies at its own size
}

// NSGA-II: seeded, only new designs cost an evaluation, and it finds the front of a small space
// that the grid also enumerates.
TEST(SweepNsga2, SeededAndFindsTheGridFront) {
  const fs::path d = fresh("nsga2");
  SweepSpec s;
  s.name = "evo";
  s.base = kCensus;
  s.frames = "1";
  s.strategy = "nsga2";
  s.samples = 4;
  s.generations = 3;
  s.seed = 11;
  s.require_fit = true;
  s.objectives = {{"correct_3px_pct", true}, {"bram18k", false}};
  search::add_axis(s, "median=0,3,5");
  search::add_axis(s, "disparities=48,60");
  search::add_axis(s, "paths=2,4");
  search::SweepRunOptions ro;
  ro.dataset = kData;
  ro.jobs = 2;
  ResultStore a((d / "a.db").string()), b((d / "b.db").string());
  const auto sa = search::run_sweep(s, a, ro);
  search::run_sweep(s, b, ro);
  EXPECT_EQ(by_hash(a), by_hash(b)) << "not deterministic under a seed";
  EXPECT_LE(sa.total, 12);
  EXPECT_EQ(a.count_designs(), sa.total);
  // The grid of the same 12-point space, and its front: NSGA-II's front is a subset of it
  // (it cannot contain a dominated design of the whole space) and not empty.
  SweepSpec g = s;
  g.strategy = "grid";
  g.name = "grid";
  ResultStore c((d / "c.db").string());
  search::run_sweep(g, c, ro);
  std::set<std::string> grid_front;
  for (const auto& r : search::pareto_front(g, c.designs())) grid_front.insert(r.hash);
  const auto evo_front = search::pareto_front(s, a.designs());
  ASSERT_FALSE(evo_front.empty());
  int on_grid_front = 0;
  for (const auto& r : evo_front) on_grid_front += grid_front.count(r.hash) ? 1 : 0;
  EXPECT_GE(on_grid_front, 1);
}

TEST(SweepPareto, NonDominatedUnderConstraints) {
  SweepSpec s;
  s.objectives = {{"correct_3px_pct", true}, {"bram18k", false}};
  s.min_fps = 29;
  auto row = [](const char* h, double correct, double bram, double fps, double fits = 1) {
    ResultStore::Row r;
    r.hash = h;
    r.status = "ok";
    r.metrics = {{"correct_3px_pct", correct}, {"bram18k", bram}, {"fps", fps}, {"fits_device", fits}};
    return r;
  };
  std::vector<ResultStore::Row> rows = {row("a", 90, 200, 40), row("b", 88, 100, 40),   row("c", 87, 150, 40),
                                        row("d", 95, 50, 20),  row("e", 99, 10, 40, 0), row("f", 90, 200, 40)};
  rows.push_back(row("g", 91, 300, 40));
  ResultStore::Row bad = row("h", 99, 1, 99);
  bad.status = "invalid";
  rows.push_back(bad);
  std::set<std::string> front;
  for (const auto& r : search::pareto_front(s, rows)) front.insert(r.hash);
  // c is dominated by b; d is too slow; e does not fit; h is invalid; a and f tie (both stay).
  EXPECT_EQ(front, (std::set<std::string>{"a", "b", "f", "g"}));
  // one_pass: a design that needs the second pass through DDR (passes 2) leaves the front.
  s.one_pass = true;
  rows[1].metrics["passes"] = 2;  // b
  for (auto& r : rows)
    if (!r.metrics.count("passes")) r.metrics["passes"] = 1;
  front.clear();
  for (const auto& r : search::pareto_front(s, rows)) front.insert(r.hash);
  EXPECT_EQ(front, (std::set<std::string>{"a", "c", "f", "g"}));
}

// The peers (SweepSpec::baselines) and the seed are measured on the sweep's frames and stored
// beside its designs: designs() never lists a peer, peers() lists exactly them, a rerun reuses
// them, and an unknown peer is refused by name.
TEST(SweepRun, PeersAndSeedStoredBesideTheDesigns) {
  const fs::path d = fresh("peers");
  SweepSpec s = search::parse_sweep("name: p\nbase: " + kCensus +
                                        "\naxes:\n  p1: [6]\n  paths: [4, 5]\nbaselines: [opencv-hh4, opencv-sgbm]\n"
                                        "frames: \"1-2\"\nconstraints:\n  one_pass: true\n",
                                    "peers.yaml");
  ASSERT_EQ(s.baselines, (std::vector<std::string>{"opencv-hh4", "opencv-sgbm"}));
  EXPECT_TRUE(s.one_pass);
  EXPECT_EQ(search::parse_sweep(search::sweep_to_yaml(s), "round trip").baselines, s.baselines);
  ResultStore store((d / "r.db").string());
  search::SweepRunOptions ro;
  ro.dataset = kData;
  ro.jobs = 2;
  search::run_sweep(s, store, ro);
  const auto designs = store.designs("p");
  ASSERT_EQ(designs.size(), 3u);  // two points and the seed (p1 8, paths 4)
  const std::string seed = search::seed_hash(s);
  EXPECT_EQ(std::count_if(designs.begin(), designs.end(), [&](const ResultStore::Row& r) { return r.hash == seed; }),
            1);
  for (const auto& r : designs) {
    EXPECT_EQ(r.status, "ok");
    EXPECT_EQ(r.metrics.at("passes"), 1.0);
  }
  const auto peers = store.peers("p");
  ASSERT_EQ(peers.size(), 2u);
  for (const auto& r : peers) {
    EXPECT_EQ(r.status, "peer");
    EXPECT_NE(r.config_yaml.find("baseline: opencv-"), std::string::npos) << r.config_yaml;
    EXPECT_EQ(r.metrics.at("frames"), designs[0].metrics.at("frames"));  // the designs' frames
    EXPECT_GT(r.metrics.at("correct_3px_pct"), 50.0);
    EXPECT_EQ(r.frames.size(), designs[0].frames.size());
  }
  const auto again = search::run_sweep(s, store, ro);
  EXPECT_EQ(again.evaluated, 0);
  EXPECT_EQ(store.peers("p").size(), 2u);
  EXPECT_EQ(store.count_designs(), 5);
  try {
    search::parse_sweep("baselines: [opencv-bm]\n", "bad.yaml");
    ADD_FAILURE() << "an unknown peer was accepted";
  } catch (const eval::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("opencv-bm"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace parallax::test

namespace parallax::test {
namespace {

// designs(sweep, with_frames): frames only of that sweep's designs, none when not wanted.
TEST(SweepStore, DesignsFilterFramesBySweepAndCanSkipThem) {
  const auto path =
      std::filesystem::temp_directory_path() / ("parallax_store_frames_" + std::to_string(::getpid()) + ".db");
  std::filesystem::remove(path);
  {
    search::ResultStore store(path.string());
    for (const char* sweep : {"a", "b"}) {
      search::ResultStore::Row row;
      row.hash = std::string(sweep) + "000000000000000";
      row.sweep = sweep;
      row.config_yaml = "name: x\n";
      row.status = "ok";
      row.metrics = {{"correct_pct", 90.0}};
      row.frames = {{"000001_10", {{"correct_pct", 89.0}}}, {"000005_10", {{"correct_pct", 91.0}}}};
      store.put_design(row);
    }
    const auto a = store.designs("a");
    ASSERT_EQ(a.size(), 1u);
    EXPECT_EQ(a[0].frames.size(), 2u);
    EXPECT_EQ(a[0].frames[1].first, "000005_10");
    const auto all = store.designs("", false);
    ASSERT_EQ(all.size(), 2u);
    EXPECT_TRUE(all[0].frames.empty());
    EXPECT_EQ(all[1].metrics.at("correct_pct"), 90.0);
    EXPECT_EQ(store.designs("").at(1).frames.size(), 2u);
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace parallax::test

// --- a results store that cannot lie (issue 15, items 4 and 5) ---------------------------------

#include <sqlite3.h>

#include <cmath>
#include <fstream>
#include <regex>

#include "../../common/shell.hpp"

namespace parallax::test {
namespace {

namespace fs = std::filesystem;

const std::string kStoreData = PARALLAX_DATA_DIR "/kitti2015-640x360";
const std::string kStoreCensus = PARALLAX_CONFIG_DIR "/ruf2018-census.yaml";
const std::string kCli = PARALLAX_CLI;

fs::path store_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("parallax_store_test_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// A copy of the shipped KITTI crops (the tests alter it).
fs::path copy_dataset(const fs::path& dir) {
  const fs::path d = dir / "kitti";
  fs::copy(kStoreData, d, fs::copy_options::recursive);
  return d;
}

void sql(const std::string& db, const std::string& statements) {
  sqlite3* c = nullptr;
  ASSERT_EQ(sqlite3_open(db.c_str(), &c), SQLITE_OK);
  char* err = nullptr;
  const int rc = sqlite3_exec(c, statements.c_str(), nullptr, nullptr, &err);
  EXPECT_EQ(rc, SQLITE_OK) << (err ? err : "") << "\n" << statements;
  sqlite3_free(err);
  sqlite3_close(c);
}

SweepSpec two_designs(const std::string& name) {
  SweepSpec s;
  s.name = name;
  s.base = kStoreCensus;
  s.frames = "1";
  search::add_axis(s, "p2=32,64");
  return s;
}

search::SweepRunOptions on(const std::string& dataset) {
  search::SweepRunOptions ro;
  ro.dataset = dataset;
  ro.jobs = 2;
  return ro;
}

std::set<std::string> hashes(const std::vector<ResultStore::Row>& rows) {
  std::set<std::string> h;
  for (const auto& r : rows) h.insert(r.hash);
  return h;
}

// Sum of "N evaluated" over the summary lines of sweeps.
int evaluated_in(const std::string& output) {
  int n = 0;
  static const std::regex re(R"((\d+) evaluated)");
  for (auto it = std::sregex_iterator(output.begin(), output.end(), re); it != std::sregex_iterator(); ++it)
    n += std::stoi((*it)[1].str());
  return n;
}

// Results are keyed by the design and by what it was measured on: another --frames, --gt or
// dataset evaluates anew (and the sweep then lists the new results); going back reuses.
TEST(SweepStoreKeys, RerunOnOtherFramesGroundTruthOrDatasetEvaluatesAnew) {
  const fs::path d = store_dir("keys");
  ResultStore store((d / "k.db").string());
  SweepSpec s = two_designs("k");
  auto first = search::run_sweep(s, store, on(kStoreData));
  EXPECT_EQ(first.evaluated, 2);
  s.frames = "5";
  auto other = search::run_sweep(s, store, on(kStoreData));
  EXPECT_EQ(other.evaluated, 2) << "results measured on frame 1 reused for frame 5";
  EXPECT_EQ(other.skipped, 0);
  EXPECT_FALSE(other.notes.empty());  // the sweep's measurement changed: said so
  auto rows = store.designs("k");
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& r : rows) {
    ASSERT_EQ(r.frames.size(), 1u);
    EXPECT_EQ(r.frames[0].first, "000005");
    EXPECT_NE(r.measurement.find("\"000005\""), std::string::npos) << r.measurement;
  }
  s.frames = "1";
  auto back = search::run_sweep(s, store, on(kStoreData));
  EXPECT_EQ(back.evaluated, 0);
  EXPECT_EQ(back.skipped, 2);
  for (const auto& r : store.designs("k")) EXPECT_EQ(r.frames.at(0).first, "000001");
  s.gt = "occ";
  EXPECT_EQ(search::run_sweep(s, store, on(kStoreData)).evaluated, 2);
  s.gt = "noc";
  const fs::path copy = copy_dataset(d);
  EXPECT_EQ(search::run_sweep(s, store, on(copy.string())).evaluated, 2);
  EXPECT_EQ(store.sweep_dataset("k"), fs::canonical(copy).string());
  EXPECT_EQ(store.count_designs(), 8);
  // The measurement names the contract version, so a new contract never reuses old results.
  EXPECT_NE(store.designs("k").at(0).measurement.find(search::kResultsContract), std::string::npos);
}

// A sweep name lists exactly its own designs, also those another sweep evaluated first.
TEST(SweepStoreKeys, OverlappingSweepNamesListExactlyTheirOwnDesigns) {
  const fs::path d = store_dir("names");
  const std::string db = (d / "n.db").string();
  std::set<std::string> a_hashes, b_hashes;
  {
    ResultStore store(db);
    SweepSpec a = two_designs("a");
    search::add_axis(a, "p2=32,48,64");
    SweepSpec b = two_designs("b");
    search::add_axis(b, "p2=48,64,96");
    EXPECT_EQ(search::run_sweep(a, store, on(kStoreData)).evaluated, 3);
    const auto sb = search::run_sweep(b, store, on(kStoreData));
    EXPECT_EQ(sb.evaluated, 1);
    EXPECT_EQ(sb.skipped, 2);
    a_hashes = hashes(store.designs("a"));
    b_hashes = hashes(store.designs("b"));
    const config::PipelineConfig base = config::load_config(kStoreCensus);
    std::set<std::string> want_a, want_b;
    for (const auto& p : search::enumerate_designs(a)) want_a.insert(search::materialise(base, p).hash);
    for (const auto& p : search::enumerate_designs(b)) want_b.insert(search::materialise(base, p).hash);
    EXPECT_EQ(a_hashes, want_a);
    EXPECT_EQ(b_hashes, want_b);
    EXPECT_EQ(store.count_designs(), 4);
  }
  // The same through the CLI: report --csv of b has b's three designs.
  const Shell r = shell(kCli + " report --db " + db + " --sweep b --csv " + (d / "b.csv").string());
  ASSERT_EQ(r.status, 0) << r.output;
  std::istringstream csv(read_file(d / "b.csv"));
  std::string line;
  std::getline(csv, line);
  std::set<std::string> listed;
  while (std::getline(csv, line)) listed.insert(line.substr(0, line.find(',')));
  EXPECT_EQ(listed, b_hashes);
}

// A design that failed because of its inputs is not reused: fix the input and rerun, and it is
// evaluated. Inputs that would fail every design fail the sweep before anything is stored.
TEST(SweepStoreKeys, FailedDesignsAreNotReused) {
  const fs::path d = store_dir("failed");
  const fs::path data = copy_dataset(d);
  const fs::path frame = data / "training/image_2/000005_10.png";
  const std::string good = read_file(frame);
  std::ofstream(frame, std::ios::binary | std::ios::trunc) << good.substr(0, 200);  // truncated
  ResultStore store((d / "f.db").string());
  SweepSpec s = two_designs("f");
  s.frames = "1,5";
  auto broken = search::run_sweep(s, store, on(data.string()));
  EXPECT_EQ(broken.failed, 2);
  for (const auto& r : store.designs("f")) {
    EXPECT_EQ(r.status, "error");
    EXPECT_NE(r.reason.find("000005_10.png"), std::string::npos) << r.reason;
  }
  std::ofstream(frame, std::ios::binary | std::ios::trunc) << good;  // fixed
  auto fixed = search::run_sweep(s, store, on(data.string()));
  EXPECT_EQ(fixed.evaluated, 2);
  EXPECT_EQ(fixed.failed, 0);
  EXPECT_EQ(fixed.skipped, 0);
  for (const auto& r : store.designs("f")) EXPECT_EQ(r.status, "ok");
  EXPECT_EQ(store.count_designs(), 2);  // the failed rows were replaced
  // A bad frame filter or a missing flight scenario: an error, nothing stored.
  SweepSpec bad = two_designs("bad");
  bad.frames = "99";
  EXPECT_THROW(search::run_sweep(bad, store, on(data.string())), eval::InputError);
  bad.frames = "1";
  bad.flight_scenario = (d / "no-such-scenario.yaml").string();
  EXPECT_THROW(search::run_sweep(bad, store, on(data.string())), eval::InputError);
  EXPECT_EQ(store.count_designs(), 2);
  for (const auto& sw : store.sweeps()) EXPECT_NE(sw.name, "bad");
}

// NaN never reaches the store (a missing metric is absent), and a design without a metric ranks
// last on it: it fails a bound on it, and it never dominates on it.
TEST(SweepStoreNan, MissingMetricsAreAbsentAndRankLast) {
  const fs::path d = store_dir("nan");
  ResultStore store((d / "n.db").string());
  ResultStore::Row r;
  r.hash = "00000000000000aa";
  r.sweep = "n";
  r.config_yaml = "name: x\n";
  r.status = "ok";
  r.metrics = {
      {"correct_3px_pct", std::nan("")}, {"density_pct", 70.0}, {"fps", std::numeric_limits<double>::infinity()}};
  r.frames = {{"000001", {{"correct_3px_pct", std::nan("")}, {"density_pct", 70.0}}}};
  store.put_design(r);
  const auto rows = store.designs("n");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].metrics, (std::map<std::string, double>{{"density_pct", 70.0}}));
  EXPECT_EQ(rows[0].frames.at(0).second, (std::map<std::string, double>{{"density_pct", 70.0}}));

  SweepSpec s;
  s.require_fit = false;
  s.objectives = {{"correct_3px_pct", true}, {"density_pct", true}};
  auto row = [](const char* h, std::map<std::string, double> m) {
    ResultStore::Row x;
    x.hash = h;
    x.status = "ok";
    x.metrics = std::move(m);
    return x;
  };
  const std::vector<ResultStore::Row> pts = {
      row("a", {{"density_pct", 99}}),                                         // no correct: -inf there
      row("b", {{"correct_3px_pct", 50}, {"density_pct", 50}}), row("c", {}),  // nothing: dominated
      row("d", {{"correct_3px_pct", std::nan("")}, {"density_pct", 40}})};     // NaN in memory: as absent
  std::set<std::string> front;
  for (const auto& p : search::pareto_front(s, pts)) front.insert(p.hash);
  EXPECT_EQ(front, (std::set<std::string>{"a", "b"}));
  s.max_latency_ms = 50;  // a bound on a metric the design has not: not met
  EXPECT_FALSE(search::meets_constraints(s, pts[1]));
  EXPECT_EQ(search::objective_value(pts[3], s.objectives[0]), -std::numeric_limits<double>::infinity());
}

// Stores holding null metrics (as NaN was written before) or a NULL metrics column: NSGA-II
// ranks those designs (last on the missing objective) while it continues the sweep, and pareto,
// report (CSV, frames CSV, JSON, HTML) and export-hls read the store, with empty cells.
TEST(SweepStoreNan, NullMetricsNeverCrashNsga2OrTheReaders) {
  const fs::path d = store_dir("nulls");
  const std::string db = (d / "n.db").string();
  SweepSpec s = two_designs("evo");
  s.strategy = "nsga2";
  s.samples = 4;
  s.generations = 1;
  search::add_axis(s, "median=0,3,5");
  {
    ResultStore store(db);
    search::run_sweep(s, store, on(kStoreData));
  }
  sql(db,
      "UPDATE results SET metrics = json_set(metrics, '$.correct_3px_pct', NULL);"
      "UPDATE frames SET metrics = json_set(metrics, '$.correct_3px_pct', NULL);"
      "UPDATE results SET metrics = NULL WHERE rowid = (SELECT MIN(rowid) FROM results);");
  std::string hash;
  {
    ResultStore store(db);
    const auto before = store.designs("evo");
    ASSERT_FALSE(before.empty());
    for (const auto& r : before) {
      EXPECT_EQ(r.status, "ok") << r.reason;  // a missing metric is not an unreadable row
      EXPECT_FALSE(r.metrics.count("correct_3px_pct"));
    }
    EXPECT_TRUE(before[0].metrics.empty());
    hash = before[0].hash;
    s.generations = 3;  // continue: the stored population is ranked with its missing objective
    const auto sum = search::run_sweep(s, store, on(kStoreData));
    EXPECT_GE(sum.skipped, int(before.size()));
    std::set<std::string> front;
    for (const auto& r : search::pareto_front(s, store.designs("evo"))) front.insert(r.hash);
    EXPECT_FALSE(front.count(hash)) << "a design without metrics on the front";
  }
  const Shell p = shell(kCli + " pareto --db " + db + " --sweep evo");
  EXPECT_EQ(p.status, 0) << p.output;
  EXPECT_EQ(shell(kCli + " pareto --json --db " + db + " --sweep evo").status, 0);
  const Shell r =
      shell(kCli + " report --db " + db + " --sweep evo --csv " + (d / "d.csv").string() + " --frames-csv " +
            (d / "f.csv").string() + " --json " + (d / "r.json").string() + " --html " + (d / "r.html").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(read_file(d / "r.json").find("null"), std::string::npos);
  EXPECT_EQ(read_file(d / "d.csv").find("nan"), std::string::npos);
  EXPECT_EQ(read_file(d / "f.csv").find("nan"), std::string::npos);
  const Shell e = shell(kCli + " export-hls --db " + db + " --design " + hash + " --out " + (d / "hls").string());
  EXPECT_EQ(e.status, 0) << e.output;
}

// Two identical sweeps at once on one store share the work: each design evaluated once in all.
TEST(SweepStoreConcurrency, IdenticalSweepsAtOnceEvaluateEachDesignOnce) {
  const fs::path d = store_dir("concurrent");
  const std::string db = (d / "c.db").string();
  const std::string args = " sweep --base " + kStoreCensus + " --grid disparities=30,24,36,42,48,54 --dataset " +
                           kStoreData + " --frames 1,5 --jobs 1 --no-sharing --db " + db;
  const Shell both = shell("(" + kCli + args + " 2>/dev/null & " + kCli + args + " 2>/dev/null & wait)");
  EXPECT_EQ(evaluated_in(both.output), 6) << both.output;
  EXPECT_NE(both.output.find("already in"), std::string::npos) << both.output;
  ResultStore store(db);
  EXPECT_EQ(store.count_designs(), 6);
  EXPECT_EQ(store.designs("sweep").size(), 6u);
  for (const auto& r : store.designs("sweep")) EXPECT_EQ(r.status, "ok");
}

// A claim left by a process that died does not block: the next sweep takes it over.
TEST(SweepStoreConcurrency, ClaimOfADeadProcessIsTakenOver) {
  const fs::path d = store_dir("stale");
  const std::string db = (d / "s.db").string();
  SweepSpec s = two_designs("s");
  { ResultStore create(db); }
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);  // a pid that no longer runs
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  const config::PipelineConfig base = config::load_config(kStoreCensus);
  const std::string measurement = search::measurement_of(s, fs::canonical(kStoreData).string(), {"000001"});
  for (const auto& p : search::enumerate_designs(s)) {
    const std::string key = search::result_key(search::materialise(base, p).hash, measurement);
    sql(db, "INSERT INTO claims(key, owner, host, pid, started, claimed_at) VALUES('" + key + "', 'dead', '" + host +
                "', " + std::to_string(child) + ", 12345, strftime('%s','now'))");
  }
  ResultStore store(db);
  const auto sum = search::run_sweep(s, store, on(kStoreData));
  EXPECT_EQ(sum.evaluated, 2);
  EXPECT_EQ(store.designs("s").size(), 2u);
}

// Another connection holding the write lock longer than the notice time: the sweep waits,
// says so, and finishes.
TEST(SweepStoreConcurrency, LockHeldByAnotherConnectionIsWaitedOut) {
  const fs::path d = store_dir("lock");
  const std::string db = (d / "l.db").string();
  { ResultStore create(db); }
  sqlite3* c = nullptr;
  ASSERT_EQ(sqlite3_open(db.c_str(), &c), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(c, "BEGIN EXCLUSIVE", nullptr, nullptr, nullptr), SQLITE_OK);
  std::thread holder([c] {
    std::this_thread::sleep_for(std::chrono::seconds(3));
    sqlite3_exec(c, "COMMIT", nullptr, nullptr, nullptr);
  });
  const auto t0 = std::chrono::steady_clock::now();
  const Shell r = shell("PARALLAX_LOCK_NOTICE_MS=300 " + kCli + " sweep --base " + kStoreCensus + " --dataset " +
                        kStoreData + " --frames 1 --db " + db);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  holder.join();
  sqlite3_close(c);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("waiting for lock on " + db), std::string::npos) << r.output;
  EXPECT_GE(s, 2.5);  // it did wait
  ResultStore store(db);
  EXPECT_EQ(store.count_designs(), 1);
}

}  // namespace
}  // namespace parallax::test
