// Internal: one run of a pipeline graph, everything but the kernels and their wiring
// (engine.hpp). PipelineRun<kTimed> holds the design's parameters, the run's options (null: the
// func run) and report (null: none), the stages' timing model, the pipeline variant
// (kernels/pipeline.hpp), the VCD trace and the graph, all set by begin() for each run. It gives
// the depth of each FIFO, the cycle at which each input pixel arrives and the frame buffer's
// word rate and latency (func run: the func depths, every time 0), runs the graph's schedule
// (a deadlock goes into the report), and fills the report's FIFO and stage figures.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "parallax/kernels/frame_buffer.hpp"
#include "parallax/kernels/params.hpp"
#include "parallax/kernels/pipeline.hpp"
#include "parallax/sim/cycle.hpp"
#include "parallax/sim/fifo.hpp"
#include "scheduler.hpp"
#include "vcd_trace.hpp"

namespace parallax::sim::detail {

// Rate of a source that delivers `bytes_per_token` at `bytes_per_s`: token i is available at
// cycle floor(i * cycles_per_token) after `start`.
struct Rate {
  double cycles_per_token = 0.0;
  int64_t start = 0;
  int64_t at(int64_t i) const { return start + int64_t(std::floor(double(i) * cycles_per_token)); }
};

// Everything one run of the graph needs besides the kernels.
struct RunSetup {
  const CycleOptions* opt = nullptr;  // null: func run
  bool unbounded = false;             // timed: every FIFO unbounded (sizing run)
};

template <bool kTimed>
class PipelineRun {
 protected:
  // Starts a run: the timing model is default_timing() at the synthesis clock with the options'
  // overrides; a fresh graph (and trace, timed with a VCD path).
  void begin(const kern::StereoParams& p, const RunSetup& setup, CycleReport* rep) {
    p_ = p;
    setup_ = setup;
    rep_ = rep;
    // An untimed run (the func and counting runs) has no use for the timing, and the default
    // timing's II comes from a counting run (stage_schedules): only a timed run asks for it.
    timing_.clear();
    if (kTimed)
      timing_ = default_timing(p, !setup.opt                          ? 200e6
                                  : setup.opt->synthesis_clock_hz > 0 ? setup.opt->synthesis_clock_hz
                                                                      : setup.opt->clock_hz);
    if (kTimed && setup.opt)
      for (const auto& kv : setup.opt->timing) timing_[kv.first] = kv.second;
    conditions_ = kern::pipeline_conditions(p, rectifying());
    trace_.reset();
    if (kTimed && setup.opt && !setup.opt->vcd_path.empty())
      trace_ = std::make_unique<Trace>(setup.opt->vcd_from, setup.opt->vcd_to);
    graph_ = std::make_unique<Graph<kTimed>>(trace_.get());
    input_rate_ = input_rate();
  }

  int64_t frame_pixels() const { return int64_t(p_.width_px) * p_.height_px; }
  std::size_t depth_of(const std::string& name, std::size_t func_depth) const {
    if (!kTimed || !setup_.opt) return func_depth;
    if (setup_.unbounded) return 0;
    const auto it = setup_.opt->fifo_depths.find(name);
    return it != setup_.opt->fifo_depths.end() ? it->second : setup_.opt->fifo_depth;
  }
  bool rectifying() const {
    return kTimed && setup_.opt && setup_.opt->rectify.mode != kern::kRectifyNone && setup_.opt->rectify_map_left &&
           setup_.opt->rectify_map_right;
  }

  Rate input_rate() const {
    Rate r;
    if (!kTimed || !setup_.opt) return r;
    const CycleOptions& o = *setup_.opt;
    if (o.input == InputKind::memory)
      r.cycles_per_token = 2.0 * o.clock_hz / o.input_bytes_per_s;  // one left + one right byte
    else
      r.cycles_per_token = o.clock_hz / o.camera_pixel_hz;
    return r;
  }
  // Cycle at which input pixel i (raster order) arrives.
  int64_t input_arrival(int64_t i) const {
    if (!kTimed || !setup_.opt) return 0;
    const Rate& r = input_rate_;
    if (setup_.opt->input == InputKind::camera) {
      const int64_t row = i / p_.width_px, col = i % p_.width_px;
      return r.at(row * (p_.width_px + setup_.opt->camera_h_blank_px) + col);
    }
    return r.at(i);
  }
  int64_t input_period() const {
    if (!kTimed || !setup_.opt) return 0;
    if (setup_.opt->input == InputKind::camera)
      return input_rate().at(int64_t(p_.width_px + setup_.opt->camera_h_blank_px) *
                             (p_.height_px + setup_.opt->camera_v_blank_rows));
    return input_rate().at(int64_t(p_.width_px) * p_.height_px);
  }
  // One frame-buffer word (kernels/frame_buffer.hpp: the packed power-of-two word) per token of
  // this rate.
  Rate ddr_rate() const {
    Rate r;
    if (!kTimed || !setup_.opt) return r;
    r.cycles_per_token = double(kern::frame_word_bytes(p_)) * setup_.opt->clock_hz / setup_.opt->ddr_bytes_per_s;
    return r;
  }
  int64_t ddr_latency_cycles() const {
    if (!kTimed || !setup_.opt) return 0;
    return int64_t(std::ceil(setup_.opt->ddr_latency_s * setup_.opt->clock_hz));
  }

  bool schedule(const std::vector<std::function<bool()>>& pumps, const std::function<bool()>& finished) {
    if (graph_->schedule(pumps, finished)) return true;
    if (rep_) {
      rep_->deadlock = true;
      rep_->deadlock_cycle = graph_->deadlock_cycle();
      rep_->deadlock_message = graph_->deadlock_message();
    }
    return false;
  }
  void mark_done(const std::string& name) { graph_->mark_done(name); }

  // Moves the frame's FIFO statistics into the report (the FIFOs die with the run).
  template <class... F>
  void collect(F&&... fifos) {
    if (!rep_) return;
    auto one = [&](const FifoBase& f) {
      FifoReport r;
      r.name = f.name();
      r.producer = graph_->producer_of(&f);
      r.consumer = graph_->consumer_of(&f);
      r.depth = int64_t(f.depth());
      r.tokens = f.writes();
      r.high_water = int64_t(f.high_water());
      rep_->fifos.push_back(r);
    };
    (one(*fifos), ...);
  }

  void finish_report() {
    if (trace_ && setup_.opt) trace_->write(setup_.opt->vcd_path, "parallax");
    rep_->stages.clear();
    int64_t busiest = 0;
    for (const auto& n : graph_->nodes()) {
      rep_->stages.push_back(n->report());
      if (n->name() == "source") continue;  // its occupancy is the input's, counted below
      if (n->report().busy_cycles > busiest) {
        busiest = n->report().busy_cycles;
        rep_->bottleneck = n->name();
      }
    }
    rep_->input_period_cycles = input_period();
    rep_->cycles_per_frame = busiest;
    if (rep_->input_period_cycles > busiest) {
      rep_->cycles_per_frame = rep_->input_period_cycles;
      rep_->bottleneck = "input";
    }
  }

  kern::StereoParams p_{};
  RunSetup setup_;
  Rate input_rate_;  // of this run's source, computed once
  CycleReport* rep_ = nullptr;
  TimingModel timing_;
  std::unique_ptr<Trace> trace_;
  std::unique_ptr<Graph<kTimed>> graph_;
  unsigned conditions_ = 0;  // the pipeline variant (kernels/pipeline.hpp) of the current run
};

}  // namespace parallax::sim::detail
