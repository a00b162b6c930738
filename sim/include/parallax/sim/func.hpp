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

// What computes a design's codes in the func run. Both give the same bits (tests/kernels/equiv):
// `fast` is the whole-row SIMD engine of models/fast (what users run by default), `kernels`
// fires the HLS kernels of kernels/ (what the hardware is). `automatic` is the process default:
// fast unless set_default_func_engine changed it (the CLI's --engine).
enum class FuncEngine { automatic, fast, kernels };
void set_default_func_engine(FuncEngine e);
FuncEngine default_func_engine();  // never automatic
// "fast" / "kernels"; parse returns false for anything else.
const char* to_string(FuncEngine e);
bool parse_func_engine(const std::string& name, FuncEngine& out);

struct FuncOptions {
  // false: fire the disparity stages with the widest lanes this build carries (a divisor of D,
  // at most 64), which gives the same bits as the design's PU and runs fastest; true: use the
  // configured parallel_units (the equivalence tests do). true implies the kernels engine.
  bool use_design_pu = false;
  FuncEngine engine = FuncEngine::automatic;
};
// The engine these options select (fast or kernels).
FuncEngine resolve_engine(const FuncOptions& opt);

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
// func run; "" for designs that cannot replay costs (the kernels' 8-path variant's two passes;
// the fast engine replays any design).
std::string cost_sharing_key(const kern::StereoParams& p, FuncEngine engine = FuncEngine::automatic);
// Designs with equal keys share the fast engine's aggregate volume too (they differ only in the
// WTA, LR check, uniqueness, sub-pixel bits or median); "" with the kernels engine.
std::string aggregate_sharing_key(const kern::StereoParams& p, FuncEngine engine = FuncEngine::automatic);
// Designs with equal keys have the same codes before the median (the fast engine then runs the
// median alone); "" with the kernels engine. All three keys are derived from which stage reads
// which field (kernels/param_table.hpp).
std::string selection_sharing_key(const kern::StereoParams& p, FuncEngine engine = FuncEngine::automatic);

// The cost volume a recording holds, in the golden model's layout C[(y*W + x)*D + d]
// (ref::volume_index): from the kernels' cost tokens (the func run's lanes, D/PU tokens per pixel)
// or the fast engine's padded volume. For the per-stage equality tests.
std::vector<uint32_t> recorded_cost_volume(const CostRecording& rec, const kern::StereoParams& p);

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
  // The cost stage alone on one frame, into `rec` (at the func run's lanes), with the engine of
  // opt; run_from_costs uses the recording's engine.
  void record_costs(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p, CostRecording& rec,
                    const FuncOptions& opt = {});
  // The rest of the design fed with a recording of a design of the same cost_sharing_key: the
  // codes of run() on the frame (tested). Aborts when the keys differ. With the fast engine and
  // keep_aggregate, the design's aggregate volume stays in `rec` for the next design of the same
  // aggregate_sharing_key, which then runs only its WTA, LR check and median.
  DisparityCodes run_from_costs(CostRecording& rec, const kern::StereoParams& p, bool keep_aggregate = false);
  // The kernels engine's aggregate volume of one frame: the sums its WTA stage reads (the func
  // run's lanes), in the golden model's layout S[(y*W + x)*D + d] whatever order the variant
  // streams them in (after a row reversal or the frame buffer). For the per-stage equality tests;
  // aborts on parameters rejected by func_param_errors.
  std::vector<uint32_t> kernels_aggregate_volume(const GreyImage& left, const GreyImage& right,
                                                 const kern::StereoParams& p);

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
