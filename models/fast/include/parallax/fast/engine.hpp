// The fast functional engine: docs/algorithm.md §2-§5 computed whole rows at a time with SIMD
// over the disparities (as OpenCV's StereoSGBM does), bit for bit the codes of the golden model
// and of the kernels (tests/models/fast). It shares nothing with either but the parameter
// header. The kernels stay the hardware's description (cycle model, resources, export); this is
// what `run`, `eval`, `sweep` and `fly` use to compute a design's disparities.
//
// SIMD: the hot loops are compiled for baseline x86-64, x86-64-v3 (AVX2) and x86-64-v4
// (AVX-512) and the best level the CPU supports is chosen at run time; PARALLAX_SIMD=baseline |
// avx2 | avx512 in the environment forces a level (one the CPU supports).
//
// Work sharing: costs and aggregates can be recorded once per frame and replayed into every
// design that agrees up to that stage (cost_key / aggregate_key); the replay gives the codes of
// run() (tested).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "parallax/kernels/params.hpp"

namespace parallax::fast {

// The instruction-set level in use ("baseline", "avx2", "avx512").
const char* simd_level();
// The levels this CPU can run ("baseline" always); set_simd_level switches every engine of the
// process to one of them (tests and benchmarks compare the levels in one run). Throws
// std::invalid_argument for a level the CPU lacks.
std::vector<std::string> supported_simd_levels();
void set_simd_level(const std::string& name);

// Problems with p that the engine cannot run (empty when runnable): the violations of
// kern::for_each_param_violation (kernels/param_table.hpp), one text each.
std::vector<std::string> param_errors(const kern::StereoParams& p);

// The sharing key of a stage (a kern::ParamReader bit): every field that stage or one before it
// reads (kern::for_each_param), as "name=value" words. Designs with equal keys compute the same
// values up to that stage's output.
std::string stage_key(const kern::StereoParams& p, unsigned stage);
// stage_key of the cost: designs with equal keys have the same cost volume.
std::string cost_key(const kern::StereoParams& p);
// stage_key of the aggregation: designs with equal keys have the same aggregate volume, and
// differ only in what the selection and the median read.
std::string aggregate_key(const kern::StereoParams& p);

// A frame's cost volume [H][W][D rounded up to 32] with the left image (adaptive P2 reads it).
struct CostVolume {
  std::string key;
  int width_px = 0, height_px = 0, disparities = 0;
  std::vector<uint16_t> cost;
  std::vector<uint8_t> left;
};

// stage_key of the selection (WTA, LR check, uniqueness, sub-pixel): designs with equal keys have
// the same codes before the median.
std::string selection_key(const kern::StereoParams& p);

// A frame's aggregate volume [H][W][lanes], 16- or 32-bit (the narrowest that cannot overflow);
// lanes is D or D rounded up to 32, as the design's engine runs it. It also keeps the codes
// before the median of the last design run from it (selection_key), so that a design differing
// only in the median runs the median alone.
struct AggregateVolume {
  std::string key;
  int width_px = 0, height_px = 0, disparities = 0;
  bool wide = false;
  std::vector<uint16_t> sum16;
  std::vector<uint32_t> sum32;
  std::string selected_key;
  std::vector<uint16_t> selected;
};

// Reusable: keeps its row buffers between frames. Not thread-safe; one per thread.
class Engine {
 public:
  Engine();
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // The codes of one frame (row-major, docs §5). left and right are W x H grey, row-major.
  // Throws std::invalid_argument when param_errors(p) is not empty.
  std::vector<uint16_t> run(const uint8_t* left, const uint8_t* right, const kern::StereoParams& p);

  void record_costs(const uint8_t* left, const uint8_t* right, const kern::StereoParams& p, CostVolume& out);
  // Throws std::invalid_argument when the volume's key is not cost_key(p).
  std::vector<uint16_t> run_from_costs(const CostVolume& costs, const kern::StereoParams& p);

  void record_aggregate(const CostVolume& costs, const kern::StereoParams& p, AggregateVolume& out);
  // Throws std::invalid_argument when the volume's key is not aggregate_key(p).
  std::vector<uint16_t> run_from_aggregate(AggregateVolume& agg, const kern::StereoParams& p);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace parallax::fast
