// Speed benchmark of the func run against OpenCV's StereoSGBM on the same pair, single thread,
// measured in one run. Figures, never a pass/fail on timing.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "parallax/config/config.hpp"

namespace parallax::eval {

struct BenchRow {
  std::string method;
  double median_ms = 0.0;
  double min_ms = 0.0;
  double peak_rss_mib = 0.0;        // peak resident memory of a process that ran only this method
  double peak_extra_rss_mib = 0.0;  // the same minus an idle process's peak (images loaded)
  double ratio_to_peer = 0.0;       // median_ms / the first OpenCV row's median_ms
  double min_ratio_to_peer = 0.0;   // min_ms / the first OpenCV row's min_ms (less sensitive to load)
  double ratio_to_sgbm = 0.0;       // median_ms / OpenCV MODE_SGBM's median_ms, the speed peer
  double min_ratio_to_sgbm = 0.0;   // min_ms / MODE_SGBM's min_ms
};

// Runs each method `iterations` times in its own forked process (so that peak memory is its
// own), one thread each but one row. Rows: the design's func run, the func run at the design's
// PU (the cycle model's granularity), its cycle run (at the config's clock), on machines of two
// hardware threads the cycle run as `parallax sim` runs it (schedule and func run side by side,
// CycleOptions::threads), OpenCV MODE_HH4, OpenCV MODE_SGBM. Ratios are to MODE_HH4 (the accuracy peer) and to
// MODE_SGBM (the speed peer).
std::vector<BenchRow> bench_pair(const config::PipelineConfig& cfg, const cv::Mat& left_grey, const cv::Mat& right_grey,
                                 int iterations);

}  // namespace parallax::eval
