// The `func` run: the kernels of kernels/ fired by a plain dataflow scheduler over small bounded
// FIFOs, as fast as software allows. Bit-identical to the cycle run and the golden model.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "parallax/kernels/common.hpp"
#include "parallax/kernels/params.hpp"

namespace parallax::sim {

struct GreyImage {
  int width_px = 0;
  int height_px = 0;
  std::vector<uint8_t> px;  // row-major
};

// Disparity codes, row-major; code == disparities means invalid, a valid code c is the disparity
// min_disparity + c (docs/algorithm.md §5).
struct DisparityCodes {
  int width_px = 0;
  int height_px = 0;
  int disparities = 0;
  int min_disparity = 0;
  int subpixel_bits = 0;  // f: code c is the disparity min_disparity + c / 2^f; D * 2^f is invalid
  std::vector<uint16_t> code;
};

struct FuncOptions {
  // false: fire the disparity stages with the widest lanes this build carries (a divisor of D,
  // at most 64), which gives the same bits as the design's PU and runs fastest; true: use the
  // configured parallel_units (the equivalence tests do).
  bool use_design_pu = false;
};

// Problems with the parameters that the kernels cannot run (empty when runnable). The full,
// user-facing validation lives in models/config; this is the kernels' own guard.
std::vector<std::string> func_param_errors(const kern::StereoParams& p);

// The matching costs of one frame as the cost stage streams them, recorded once and replayed
// into every design that shares the cost stage: work sharing for sweeps over the later stages
// (penalties, paths, LR check, median). Opaque; see FuncPipeline::record_costs.
class CostRecording {
 public:
  CostRecording();
  ~CostRecording();
  CostRecording(CostRecording&&) noexcept;
  CostRecording& operator=(CostRecording&&) noexcept;
  struct Impl;
  std::unique_ptr<Impl> impl;
};

// Designs with equal keys (cost, window, disparities, size) produce the same cost tokens in the
// func run; "" for designs that cannot replay costs (the 8-path variant's two passes).
std::string cost_sharing_key(const kern::StereoParams& p);

// Reusable pipeline: keeps its (large) stage objects between frames.
class FuncPipeline {
 public:
  FuncPipeline();
  ~FuncPipeline();
  FuncPipeline(const FuncPipeline&) = delete;
  FuncPipeline& operator=(const FuncPipeline&) = delete;

  // Runs one frame. Aborts on parameters rejected by func_param_errors (callers validate).
  DisparityCodes run(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                     const FuncOptions& opt = {});
  // The cost stage alone on one frame, into `rec` (at the func run's lanes).
  void record_costs(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p, CostRecording& rec);
  // The rest of the design fed with a recording of a design of the same cost_sharing_key: the
  // codes of run() on the frame (tested). Aborts when the keys differ.
  DisparityCodes run_from_costs(const CostRecording& rec, const kern::StereoParams& p);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The rectification stage alone (one camera), fired over a whole frame: map entries are the
// fixed-point source positions of every output pixel, row-major.
struct RectifyOutput {
  GreyImage image;
  int64_t window_misses = 0;
};
RectifyOutput run_rectify_func(const GreyImage& in, const std::vector<kern::MapEntry>& map,
                               const kern::RectifyParams& p);

DisparityCodes run_func(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                        const FuncOptions& opt = {});

}  // namespace parallax::sim
