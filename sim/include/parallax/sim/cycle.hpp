// The cycle model: the kernels of kernels/ fired under a cycle-level scheduler. A stage fires at
// most once every II cycles, only when every token its plan reads is visible and every FIFO its
// plan writes has space; a written token becomes visible after the stage's pipeline latency.
// Every stage fires as early as these rules allow, so the firing times are the unique solution
// of a max-plus system; the scheduler computes them event by event (no per-cycle loop), which is
// exact for this firing rule and costs a few operations per firing.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "parallax/kernels/common.hpp"
#include "parallax/kernels/params.hpp"
#include "parallax/kernels/pipeline.hpp"
#include "parallax/sim/func.hpp"

namespace parallax::sim {

struct StageTiming {
  int ii_cycles = 1;       // initiation interval of the stage's pipelined loop
  int latency_cycles = 1;  // cycles from a firing to its outputs being visible
  int setup_cycles = 0;    // per-frame set-up (e.g. memory initialisation loops) before the first firing
};

// Per-stage timing. Defaults come from the kernel structure (default_timing); calibration data
// (e.g. read back from a synthesis report) overrides them per stage name.
using TimingModel = std::map<std::string, StageTiming>;

// Stage names used in reports, FIFO names and timing overrides.
//   source, cost, aggregate, wta_lr, median, sink; two-pass designs add ddr_write,
//   ddr_read and aggregate_back; rectifying designs add map_left, map_right, rectify_left and
//   rectify_right.
// II of the kernel stages is derived from the kernels' schedule declarations at clock_hz
// (schedule.hpp: memory ports and loop-carried recurrences); the other stages fire at II = 1.
// Latencies are pipeline depths of the kernels' per-firing work.
TimingModel default_timing(const kern::StereoParams& p, double clock_hz = 200e6);

enum class InputKind { memory, camera };

struct CycleOptions {
  double clock_hz = 200e6;  // processing clock
  // The clock the design was synthesised for, which sets the stages' II (default_timing); 0: the
  // processing clock. A bitstream built for 200 MHz and run at 100 MHz keeps its cycles.
  double synthesis_clock_hz = 0;
  InputKind input = InputKind::memory;
  // Memory-mapped input: the left+right pixel pairs stream from DDR at this rate.
  double input_bytes_per_s = 4.0e9;
  // Camera input: pixels at the pixel clock, with blanking after each line and frame.
  double camera_pixel_hz = 25e6;
  int camera_h_blank_px = 0;
  int camera_v_blank_rows = 0;
  // Off-chip frame buffer of the 8-path variant.
  double ddr_bytes_per_s = 4.0e9;
  double ddr_latency_s = 150e-9;
  // FIFO depths: default for all, then per FIFO name. 0 = unbounded.
  std::size_t fifo_depth = 2;
  std::map<std::string, std::size_t> fifo_depths;
  TimingModel timing;  // overrides on top of default_timing()
  // Rectification in front of the cost stage (mode kRectifyNone: none). The maps are the
  // fixed-point source positions of every pixel of the processed size; their entries stream from
  // memory at input_bytes_per_s (8 bytes each).
  kern::RectifyParams rectify{0, 0, kern::kRectifyNone, 0, 1};
  const std::vector<kern::MapEntry>* rectify_map_left = nullptr;
  const std::vector<kern::MapEntry>* rectify_map_right = nullptr;
  // false (default): the schedule runs the kernels' control path (plan() and step()) at the
  // design's PU, and the codes come from the func run of the same kernels; true: the kernels'
  // datapath fires inside the schedule at the design's PU, token by token. Plans depend on
  // counters only, so both give the same report and codes (tested); coupled is the slower proof
  // that the datapath streams at the design's granularity.
  bool coupled = false;
  // Let the control-path schedule advance whole rows at once once they repeat exactly (see
  // docs/simulator.md); false simulates every firing. Same report either way (tested).
  bool fast_forward = true;
  // Threads of the control-path run (coupled false): 2 runs the schedule and the func run of the
  // codes side by side (they share no state: the schedule never reads a pixel), 1 one after the
  // other; 0 (default) 2 where the machine has two hardware threads. Same report either way
  // (tested).
  int threads = 0;
  // Test hook: the source stops after this many pixels (a frame that never completes).
  int64_t truncate_input_px = -1;
  // VCD trace of FIFO occupancies and stage valid/stall signals for cycles [vcd_from, vcd_to).
  std::string vcd_path;
  int64_t vcd_from = 0, vcd_to = 0;
};

struct StageReport {
  std::string name;
  int ii_cycles = 0;
  int latency_cycles = 0;
  int64_t fires = 0;
  int64_t busy_cycles = 0;          // fires x II
  int64_t input_stall_cycles = 0;   // waiting for an input token to become visible
  int64_t output_stall_cycles = 0;  // waiting for space in an output FIFO
  int64_t first_fire_cycle = -1;
  int64_t last_fire_cycle = -1;
};

struct FifoReport {
  std::string name;
  std::string producer, consumer;
  int64_t depth = 0;       // 0 = unbounded
  int64_t tokens = 0;      // written during the frame
  int64_t high_water = 0;  // most tokens held at once (over time)
};

struct CycleReport {
  DisparityCodes codes;
  bool deadlock = false;
  std::string deadlock_message;  // names the stage(s) and FIFO(s) and the cycle
  int64_t deadlock_cycle = -1;
  int64_t first_input_cycle = 0;
  int64_t first_pixel_cycle = -1;  // first output pixel leaves the pipeline
  int64_t last_pixel_cycle = -1;   // last output pixel leaves the pipeline
  // Cycles between frames in steady state: the busiest stage's occupancy per frame (stages
  // overlap consecutive frames), or the input's frame period if that is longer.
  int64_t cycles_per_frame = 0;
  std::string bottleneck;
  std::vector<StageReport> stages;
  std::vector<FifoReport> fifos;
  int64_t input_period_cycles = 0;  // cycles the input needs to deliver one frame
  // Camera input only: the first pixel that found no room (a camera cannot wait).
  std::string input_overrun;
  int64_t rectify_window_misses = 0;  // map taps outside the rectify line buffers (both cameras)
  int64_t rows_fast_forwarded = 0;    // output rows the schedule applied at once (CycleOptions::fast_forward)
  // Two-pass designs: rows of pass 1 (to the frame buffer) applied at once.
  int64_t first_pass_rows_fast_forwarded = 0;
  // Two-pass designs: the DDR traffic of one frame (kernels/frame_buffer.hpp). Pass 1 writes and
  // pass 2 reads every word of the frame buffer once (words of ddr_word_bits, the packed pair's
  // next power of two); the map writer writes one 16-bit code per pixel. 0 for one pass.
  int ddr_word_bits = 0;
  int64_t ddr_bytes_written = 0;  // frame buffer, pass 1
  int64_t ddr_bytes_read = 0;     // frame buffer, pass 2
  int64_t map_bytes_written = 0;  // disparity map, pass 2
  // What the engine configured each SGM and WTA stage with, in configure() order (tests hold it
  // to kern::stage_setup(), the pipeline description).
  std::vector<std::pair<std::string, kern::StageSetup>> stage_setups;
};

// Extra cycles a firing of chunk `chunk` needs beyond II because the path-cost row memories'
// accesses (per row path: read the next firing's chunk, write lanes [lo, lo+PU-1]) exceed two ports
// per memory within II cycles: max over memories of ceil(accesses / 2) - II, at least 0.

// Runs one frame through the cycle model with the design's PU. The codes are bit-identical to the
// func run and the golden model (tested in both modes, see CycleOptions::coupled).
CycleReport run_cycle(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                      const CycleOptions& opt);

// The timing of run_cycle alone (the control-path schedule, whatever opt.coupled says): the same
// report with empty codes. Plans never depend on pixel values, so this is every frame's timing.
CycleReport run_timing(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                       const CycleOptions& opt);

// The same frame with every FIFO unbounded: the high-water marks are the smallest depths with
// which no stage ever waits for FIFO space (tested: sizing FIFOs so removes all output stalls).
// Behind a producer faster than its consumer that depth is the whole backlog; compare
// last_pixel_cycle with the bounded run's to see whether the back-pressure costs anything.
struct FifoSizing {
  std::map<std::string, int64_t> depths;
  int64_t last_pixel_cycle = -1;
};
FifoSizing stall_free_depths(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                             const CycleOptions& opt);

}  // namespace parallax::sim
