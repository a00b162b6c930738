// `parallax export-hls`: the simulator's part of an HLS export. Runs the design on the
// testbench's pair through the cycle model to size its FIFOs, predict its timing with those
// depths, and write the golden output; the resource model predicts its resources on the part's
// device. hls/ then writes the project (parallax/hls/export.hpp).
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "parallax/config/config.hpp"
#include "parallax/hls/export.hpp"

namespace parallax::hls_flow {

struct ExportOptions {
  std::string part = "xczu3eg-sbva484-1-e";
  double clock_mhz = 0;  // 0: the configuration's clock_mhz
  // A stall-free depth above this is a backlog behind a faster producer: the configured depth
  // is kept instead (its cost in cycles is in the README).
  int64_t max_fifo_depth = 1024;
};

// The device of the resource model whose name starts the part number (case-insensitive), e.g.
// XCZU3EG for xczu3eg-sbva484-1-e; "" when the table has none.
std::string device_for_part(const std::string& part);

// left / right: grey pair of the design's processed size. Throws hlsx::ExportError for designs
// the export does not support or that deadlock with the chosen depths.
hlsx::ExportRequest prepare_export(const config::PipelineConfig& cfg, const cv::Mat& left, const cv::Mat& right,
                                   const std::string& origin, const std::string& pair_source, const ExportOptions& opt);

}  // namespace parallax::hls_flow
