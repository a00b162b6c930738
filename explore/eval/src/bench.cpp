#include "parallax/eval/bench.hpp"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <functional>
#include <stdexcept>

#include "parallax/eval/evaluate.hpp"
#include "parallax/eval/simulate.hpp"
#include "parallax/fast/engine.hpp"
#include "parallax/sim/cycle.hpp"
#include "parallax/sim/func.hpp"

namespace parallax::eval {
namespace {

struct Measured {
  double median_ms = 0.0;
  double min_ms = 0.0;
  double peak_rss_mib = 0.0;
};

// Forks, runs `work` `iterations` times in the child, sends the times back through a pipe, and
// reads the child's peak RSS from wait4().
Measured measure_in_child(const std::function<void()>& work, int iterations) {
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error("bench: pipe() failed");
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("bench: fork() failed");
  if (pid == 0) {
    close(fds[0]);
    cv::setNumThreads(1);
    for (int i = 0; i < iterations; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      work();
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      if (write(fds[1], &ms, sizeof ms) != ssize_t(sizeof ms)) _exit(3);
    }
    close(fds[1]);
    _exit(0);
  }
  close(fds[1]);
  std::vector<double> times;
  double ms = 0.0;
  while (read(fds[0], &ms, sizeof ms) == ssize_t(sizeof ms)) times.push_back(ms);
  close(fds[0]);
  int status = 0;
  struct rusage ru {};
  if (wait4(pid, &status, 0, &ru) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error("bench: the measuring process failed");
  Measured m;
  m.peak_rss_mib = double(ru.ru_maxrss) / 1024.0;
  if (!times.empty()) {
    std::sort(times.begin(), times.end());
    m.median_ms = times[times.size() / 2];
    m.min_ms = times.front();
  }
  return m;
}

}  // namespace

std::vector<BenchRow> bench_pair(const config::PipelineConfig& cfg, const cv::Mat& left, const cv::Mat& right,
                                 int iterations) {
  const Measured idle = measure_in_child([] {}, 1);
  std::vector<BenchRow> rows;
  auto add = [&](const std::string& name, const std::function<void()>& work) {
    const Measured m = measure_in_child(work, iterations);
    BenchRow r;
    r.method = name;
    r.median_ms = m.median_ms;
    r.min_ms = m.min_ms;
    r.peak_rss_mib = m.peak_rss_mib;
    r.peak_extra_rss_mib = std::max(0.0, m.peak_rss_mib - idle.peak_rss_mib);
    rows.push_back(r);
  };
  // The fast engine at every SIMD level this CPU runs (the best one is the default), then the
  // kernels fired one by one.
  const std::vector<std::string> levels = fast::supported_simd_levels();
  for (auto it = levels.rbegin(); it != levels.rend(); ++it) {
    add("parallax func " + cfg.name + " (fast, " + *it + ")", [&cfg, &left, &right, level = *it] {
      fast::set_simd_level(level);
      static sim::FuncPipeline pipe;  // one per child process; reused across iterations
      sim::FuncOptions o;
      o.engine = sim::FuncEngine::fast;
      (void)run_design(cfg, left, right, pipe, o);
    });
  }
  add("parallax func " + cfg.name + " (kernels)", [&] {
    static sim::FuncPipeline pipe;  // one per child process; reused across iterations
    sim::FuncOptions o;
    o.engine = sim::FuncEngine::kernels;
    (void)run_design(cfg, left, right, pipe, o);
  });
  add("parallax func, design PU", [&] {
    static sim::FuncPipeline pipe;
    sim::FuncOptions design;
    design.use_design_pu = true;
    (void)run_design(cfg, left, right, pipe, design);
  });
  const kern::StereoParams params = cfg.stereo_params(left.cols, left.rows);
  const sim::GreyImage grey_l{left.cols, left.rows, std::vector<uint8_t>(left.datastart, left.dataend)};
  const sim::GreyImage grey_r{right.cols, right.rows, std::vector<uint8_t>(right.datastart, right.dataend)};
  auto cycle_run = [&](int threads) {
    sim::CycleOptions opt = cycle_options(cfg, cfg.clock_mhz);
    opt.threads = threads;
    (void)sim::run_cycle(grey_l, grey_r, params, opt);
  };
  add("parallax cycle " + cfg.name, [&] { cycle_run(1); });
  if (std::thread::hardware_concurrency() >= 2)  // what `parallax sim` does by default
    add("  schedule beside func (2 threads)", [&] { cycle_run(2); });
  add("  its timing run alone",
      [&] { (void)sim::run_timing(grey_l, grey_r, params, cycle_options(cfg, cfg.clock_mhz)); });
  add("parallax cycle, coupled", [&] {
    sim::CycleOptions opt = cycle_options(cfg, cfg.clock_mhz);
    opt.coupled = true;
    (void)sim::run_cycle(grey_l, grey_r, params, opt);
  });
  BaselineParams bp;
  bp.disparities = cfg.disparities;
  bp.block_size = cfg.window_w;
  add("opencv StereoSGBM MODE_HH4", [&] { (void)run_baseline(Baseline::opencv_hh4, bp, left, right); });
  add("opencv StereoSGBM MODE_SGBM", [&] { (void)run_baseline(Baseline::opencv_sgbm, bp, left, right); });
  double peer = 0.0, peer_min = 0.0, sgbm = 0.0, sgbm_min = 0.0;
  for (const auto& r : rows) {
    if (r.method == "opencv StereoSGBM MODE_HH4") {
      peer = r.median_ms;
      peer_min = r.min_ms;
    } else if (r.method == "opencv StereoSGBM MODE_SGBM") {
      sgbm = r.median_ms;
      sgbm_min = r.min_ms;
    }
  }
  for (auto& r : rows) {
    r.ratio_to_peer = peer > 0 ? r.median_ms / peer : 0.0;
    r.min_ratio_to_peer = peer_min > 0 ? r.min_ms / peer_min : 0.0;
    r.ratio_to_sgbm = sgbm > 0 ? r.median_ms / sgbm : 0.0;
    r.min_ratio_to_sgbm = sgbm_min > 0 ? r.min_ms / sgbm_min : 0.0;
  }
  return rows;
}

}  // namespace parallax::eval
