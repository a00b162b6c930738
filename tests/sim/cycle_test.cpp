// equiv + timing + reject: the cycle model runs the kernels bit-identically to the func run and
// the golden model, matches closed forms where they are exact, sizes FIFOs, writes VCD, and
// reports deadlocks naming the FIFO or stage and the cycle.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>

#include "../kernels/equiv_util.hpp"
#include "parallax/kernels/frame_buffer.hpp"
#include "parallax/reference/stereo.hpp"
#include "parallax/sim/cycle.hpp"
#include "parallax/sim/func.hpp"
#include "scheduler.hpp"

namespace parallax::test {
namespace {

using kern::StereoParams;

StereoParams params(int w, int h, int d, int pu, unsigned paths) {
  return test_params(w, h, d, pu, paths);
}

sim::CycleOptions one_pair_per_cycle() {
  sim::CycleOptions o;
  o.clock_hz = 200e6;
  o.input_bytes_per_s = 2.0 * o.clock_hz;  // exactly one left+right pixel pair per cycle
  return o;
}

const sim::StageReport& stage(const sim::CycleReport& r, const std::string& name) {
  for (const auto& s : r.stages)
    if (s.name == name) return s;
  ADD_FAILURE() << "no stage " << name;
  static sim::StageReport none;
  return none;
}

// --- equiv ---------------------------------------------------------------------------------

// Every figure of two cycle reports, field by field (codes apart).
void expect_same_report(const sim::CycleReport& a, const sim::CycleReport& b, const std::string& what) {
  EXPECT_EQ(a.deadlock, b.deadlock) << what;
  EXPECT_EQ(a.deadlock_message, b.deadlock_message) << what;
  EXPECT_EQ(a.deadlock_cycle, b.deadlock_cycle) << what;
  EXPECT_EQ(a.first_pixel_cycle, b.first_pixel_cycle) << what;
  EXPECT_EQ(a.last_pixel_cycle, b.last_pixel_cycle) << what;
  EXPECT_EQ(a.cycles_per_frame, b.cycles_per_frame) << what;
  EXPECT_EQ(a.bottleneck, b.bottleneck) << what;
  EXPECT_EQ(a.input_period_cycles, b.input_period_cycles) << what;
  EXPECT_EQ(a.input_overrun, b.input_overrun) << what;
  EXPECT_EQ(a.rectify_window_misses, b.rectify_window_misses) << what;
  EXPECT_EQ(a.ddr_word_bits, b.ddr_word_bits) << what;
  EXPECT_EQ(a.ddr_bytes_written, b.ddr_bytes_written) << what;
  EXPECT_EQ(a.ddr_bytes_read, b.ddr_bytes_read) << what;
  EXPECT_EQ(a.map_bytes_written, b.map_bytes_written) << what;
  ASSERT_EQ(a.stages.size(), b.stages.size()) << what;
  for (std::size_t i = 0; i < a.stages.size(); ++i) {
    const sim::StageReport &x = a.stages[i], &y = b.stages[i];
    const std::string at = what + ", stage " + x.name;
    EXPECT_EQ(x.name, y.name) << at;
    EXPECT_EQ(x.fires, y.fires) << at;
    EXPECT_EQ(x.busy_cycles, y.busy_cycles) << at;
    EXPECT_EQ(x.input_stall_cycles, y.input_stall_cycles) << at;
    EXPECT_EQ(x.output_stall_cycles, y.output_stall_cycles) << at;
    EXPECT_EQ(x.first_fire_cycle, y.first_fire_cycle) << at;
    EXPECT_EQ(x.last_fire_cycle, y.last_fire_cycle) << at;
  }
  ASSERT_EQ(a.fifos.size(), b.fifos.size()) << what;
  for (std::size_t i = 0; i < a.fifos.size(); ++i) {
    const sim::FifoReport &x = a.fifos[i], &y = b.fifos[i];
    EXPECT_EQ(x.name, y.name) << what;
    EXPECT_EQ(x.depth, y.depth) << what << ", FIFO " << x.name;
    EXPECT_EQ(x.tokens, y.tokens) << what << ", FIFO " << x.name;
    EXPECT_EQ(x.high_water, y.high_water) << what << ", FIFO " << x.name;
  }
}

// The default cycle run (control-path schedule + func data) against the coupled run, where the
// kernels' datapath fires inside the schedule at the design's PU: same report, same codes.
// Returns the coupled report.
sim::CycleReport run_both_modes(const sim::GreyImage& l, const sim::GreyImage& r, const StereoParams& p,
                                sim::CycleOptions o, const std::string& what) {
  o.coupled = false;
  const sim::CycleReport fast = sim::run_cycle(l, r, p, o);
  o.coupled = true;
  const sim::CycleReport coupled = sim::run_cycle(l, r, p, o);
  expect_same_report(fast, coupled, what);
  if (!coupled.deadlock) {
    const Comparison c = compare_maps(fast.codes.code, coupled.codes.code, p.width_px);
    EXPECT_TRUE(c.sizes_equal && c.mismatches == 0)
        << what << ": default vs coupled codes: " << c.mismatches << " mismatches, first at " << c.first;
  }
  return coupled;
}

void expect_cycle_equivalent(const StereoParams& p, const sim::CycleOptions& o, uint32_t seed) {
  const StereoPair sp = make_pair(Pattern::kShiftedTexture, p.width_px, p.height_px, seed, 3 + int(seed % 7));
  const sim::CycleReport c = run_both_modes(sp.left, sp.right, p, o, describe(p) + " seed " + std::to_string(seed));
  ASSERT_FALSE(c.deadlock) << describe(p) << ": " << c.deadlock_message;
  sim::FuncOptions design;
  design.use_design_pu = true;
  const sim::DisparityCodes f = sim::run_func(sp.left, sp.right, p, design);
  const std::vector<uint16_t> r = ref::compute_disparity(to_ref(sp.left), to_ref(sp.right), p);
  const Comparison cf = compare_maps(c.codes.code, f.code, p.width_px);
  const Comparison cr = compare_maps(c.codes.code, r, p.width_px);
  EXPECT_TRUE(cf.sizes_equal && cf.mismatches == 0)
      << describe(p) << " seed " << seed << " vs func: " << cf.mismatches << " mismatches, first at " << cf.first;
  EXPECT_TRUE(cr.sizes_equal && cr.mismatches == 0)
      << describe(p) << " seed " << seed << " vs golden: " << cr.mismatches << " mismatches, first at " << cr.first;
}

TEST(CycleEquiv, TableOfConfigurations) {
  const struct { int d, pu; } rows[] = {{16, 1}, {16, 16}, {60, 6}, {60, 60}, {64, 8}, {128, 16}};
  const unsigned path_sets[] = {
      kern::kPath0,        kern::kPath0 | kern::kPath90,         kern::kPath0 | kern::kPath45 | kern::kPath90,
      kern::kForwardPaths, kern::kForwardPaths | kern::kPath180, kern::kAllPaths};
  uint32_t seed = 7000;
  for (const auto& row : rows)
    for (unsigned paths : path_sets)
      for (int cost : {int(kern::kCostCensus), int(kern::kCostSad)}) {
        StereoParams p = params(row.d < 100 ? 45 : 133, 11, row.d, row.pu, paths);
        p.cost = cost;
        if (cost == kern::kCostSad) {
          p.p1 = 200;
          p.p2 = 800;
        }
        p.median = int(seed % 4) * 2 + 1 == 1 ? 0 : int(seed % 4) * 2 + 1;
        p.lr_check = seed % 3 != 0;
        expect_cycle_equivalent(p, one_pair_per_cycle(), ++seed);
      }
}

// A minimum disparity changes which right columns the costs read, never when; adaptive P2 adds
// an intensity row (one read and one write per pixel) and registers, no firing: the cycle run
// gives the golden codes, and every timing figure equals that of the same design without them.
TEST(CycleEquiv, MinDisparityAndAdaptiveP2KeepTheTiming) {
  uint32_t seed = 7500;
  for (unsigned paths : {kern::kForwardPaths, kern::kForwardPaths | kern::kPath180, kern::kAllPaths})
    for (int cost : {int(kern::kCostCensus), int(kern::kCostSad)}) {
      StereoParams p = params(45, 11, 16, 4, paths);
      p.cost = cost;
      if (cost == kern::kCostSad) {
        p.p1 = 200;
        p.p2 = 800;
      }
      StereoParams shifted = p;
      shifted.min_disparity = 9;
      if (!kern::two_pass_paths(paths)) shifted.p2_adaptive = 40;
      expect_cycle_equivalent(shifted, one_pair_per_cycle(), ++seed);
      const StereoPair sp = make_pair(Pattern::kShiftedTexture, p.width_px, p.height_px, seed, 12);
      expect_same_report(sim::run_timing(sp.left, sp.right, shifted, one_pair_per_cycle()),
                         sim::run_timing(sp.left, sp.right, p, one_pair_per_cycle()), describe(shifted));
    }
}

// MGM runs in the same passes with the golden codes (its II is the schedule's: the cycle model
// takes it from the kernel's declaration like every other stage's).
TEST(CycleEquiv, MgmGivesTheGoldenCodes) {
  uint32_t seed = 7700;
  for (unsigned paths :
       {unsigned(kern::kPath0 | kern::kPath45), unsigned(kern::kForwardPaths), unsigned(kern::kAllPaths)})
    for (int pu : {4, 16}) {
      StereoParams p = params(37, 9, 16, pu, paths);
      p.aggregation = kern::kAggregationMgm;
      expect_cycle_equivalent(p, one_pair_per_cycle(), ++seed);
    }
}

// Sub-pixel codes: the cycle run gives the golden codes (f = 3, one and two passes, 5 paths).
TEST(CycleEquiv, SubpixelGivesTheGoldenCodes) {
  uint32_t seed = 7800;
  for (unsigned paths :
       {unsigned(kern::kForwardPaths), unsigned(kern::kForwardPaths | kern::kPath180), unsigned(kern::kAllPaths)}) {
    StereoParams p = params(37, 9, 16, 4, paths);
    p.subpixel_bits = 3;
    p.median = 3;
    expect_cycle_equivalent(p, one_pair_per_cycle(), ++seed);
  }
}

TEST(CycleEquiv, AwkwardSizesFifoDepthsAndCameraInput) {
  uint32_t seed = 8000;
  const int sizes[][2] = {{1, 1}, {3, 2}, {17, 5}, {33, 3}};
  for (const auto& sz : sizes)
    for (std::size_t depth : {std::size_t(1), std::size_t(2), std::size_t(7)}) {
      sim::CycleOptions o = one_pair_per_cycle();
      o.fifo_depth = depth;
      if (seed % 2) {
        o.input = sim::InputKind::camera;
        o.camera_pixel_hz = 50e6;
        o.camera_h_blank_px = 3;
        o.fifo_depths["left_px"] = o.fifo_depths["right_px"] = 4096;
      }
      const unsigned paths = seed % 3 == 0   ? kern::kAllPaths
                             : seed % 3 == 1 ? kern::kForwardPaths
                                             : kern::kForwardPaths | kern::kPath180;
      const StereoParams p = params(sz[0], sz[1], 16, 8, paths);
      expect_cycle_equivalent(p, o, ++seed);
    }
}

// --- timing: closed forms ------------------------------------------------------------------

// With the aggregation as the only bottleneck it fires every II cycles without a gap:
// busy = pixels x D/PU x II, and the frame takes exactly that many cycles per frame. (The LR
// check's end-of-row flush would back-pressure it through a shallow FIFO, so it is off here.)
TEST(Timing, AggregationClosedForm) {
  for (const auto& c : {std::make_pair(16, 4), std::make_pair(60, 6), std::make_pair(64, 32)}) {
    StereoParams p = params(80, 20, c.first, c.second, kern::kForwardPaths);
    p.lr_check = false;
    p.median = 0;
    const StereoPair sp = make_pair(Pattern::kRandom, p.width_px, p.height_px, 1);
    const sim::CycleReport r = sim::run_cycle(sp.left, sp.right, p, one_pair_per_cycle());
    const int64_t fires = int64_t(p.width_px) * p.height_px * (c.first / c.second);
    const auto& agg = stage(r, "aggregate");
    EXPECT_EQ(agg.fires, fires);
    EXPECT_EQ(agg.busy_cycles, fires * 2);
    if (c.first / c.second >= 1 && fires * 2 > int64_t(p.width_px) * p.height_px) {
      EXPECT_EQ(r.bottleneck, "aggregate");
      EXPECT_EQ(r.cycles_per_frame, fires * 2);
      EXPECT_EQ(agg.last_fire_cycle - agg.first_fire_cycle, (fires - 1) * 2) << "the aggregation starved";
    }
  }
}

// The cost stage's line buffer must hold rh rows and rw pixels of the next row before its first
// token: with one pair per cycle the aggregation fires first at (rh * W + rw) + 2 + L_cost + rw
// (pixel i arrives at cycle i, is visible one cycle later, is read by the cost stage at that
// cycle, whose next firing writes the token, visible L_cost cycles later; the row's rw prologue
// steps of the window registers read no input, so the reads fall rw cycles behind the arrivals).
TEST(Timing, LineBufferFillLatency) {
  for (const auto& win : {std::make_pair(3, 3), std::make_pair(5, 5), std::make_pair(7, 5), std::make_pair(9, 7)})
    for (int w : {40, 97}) {
      StereoParams p = params(w, 12, 16, 16, kern::kPath0);
      p.window_w = win.first;
      p.window_h = win.second;
      const StereoPair sp = make_pair(Pattern::kRandom, p.width_px, p.height_px, 2);
      const sim::CycleReport r = sim::run_cycle(sp.left, sp.right, p, one_pair_per_cycle());
      const int rh = win.second / 2, rw = win.first / 2;
      const int cost_latency = sim::default_timing(p).at("cost").latency_cycles;
      EXPECT_EQ(stage(r, "aggregate").first_fire_cycle, int64_t(rh) * w + rw + 2 + cost_latency + rw)
          << win.first << "x" << win.second << " W=" << w;
    }
}

// Two passes: the DDR traffic is the frame buffer's packed power-of-two words (kernels/
// frame_buffer.hpp), each written once by pass 1 and read once by pass 2: pixels x chunks x beats
// x word bytes, not the tokens' bytes; the map adds 2 bytes per pixel. The writers' loops are the
// exported ones: ddr_write takes the first segment in before its first write and drains the last
// segment after the last pair; pass 2 reads one word per firing, at the DDR rate, from the last
// write + the DDR latency on; the map writer drains its last segment after the last code.
TEST(Timing, TwoPassDdrTrafficIsThePackedWords) {
  struct Case {
    int cost, d, pu, word_bits, beats;
  } cases[] = {{kern::kCostCensus, 32, 8, 128, 1},  // 8 x (5 + 10) = 120 bits
               {kern::kCostCensus, 16, 1, 32, 1},   // 15 bits
               {kern::kCostSad, 64, 64, 1024, 2}};  // 64 x (13 + 16) = 1856 bits: two beats
  for (const Case& c : cases) {
    StereoParams p = params(37, 9, c.d, c.pu, kern::kAllPaths);
    p.cost = c.cost;
    const std::string what = describe(p);
    const int64_t pixels = int64_t(p.width_px) * p.height_px, chunks = c.d / c.pu;
    ASSERT_EQ(kern::frame_word_bits(p), c.word_bits) << what;
    ASSERT_EQ(kern::frame_beats(p), c.beats) << what;
    sim::CycleOptions o = one_pair_per_cycle();
    o.ddr_bytes_per_s = double(c.word_bits / 8) * o.clock_hz / 4.0;  // one word every 4 cycles
    const StereoPair sp = make_pair(Pattern::kRandom, p.width_px, p.height_px, 21);
    const sim::CycleReport r = run_both_modes(sp.left, sp.right, p, o, what);
    ASSERT_FALSE(r.deadlock) << r.deadlock_message;
    const int64_t words = pixels * chunks * c.beats;
    EXPECT_EQ(r.ddr_word_bits, c.word_bits) << what;
    EXPECT_EQ(r.ddr_bytes_written, words * (c.word_bits / 8)) << what;
    EXPECT_EQ(r.ddr_bytes_read, r.ddr_bytes_written) << what;
    EXPECT_EQ(r.map_bytes_written, pixels * 2) << what;
    const int64_t seg_tokens = kern::frame_segment_pixels(p) * chunks, seg_words = seg_tokens * c.beats;
    const auto& wr = stage(r, "ddr_write");
    const auto& rd = stage(r, "ddr_read");
    EXPECT_EQ(wr.fires, seg_tokens + words) << what;
    EXPECT_EQ(rd.fires, words) << what;
    EXPECT_EQ(stage(r, "sink").fires, pixels + kern::map_segment_pixels(p)) << what;
    EXPECT_GE(wr.last_fire_cycle - stage(r, "aggregate").last_fire_cycle, seg_words) << what;
    EXPECT_GE(stage(r, "sink").last_fire_cycle - stage(r, "median").last_fire_cycle, kern::map_segment_pixels(p))
        << what;
    const int64_t ddr_latency = int64_t(std::ceil(o.ddr_latency_s * o.clock_hz));
    EXPECT_EQ(rd.first_fire_cycle, wr.last_fire_cycle + 1 + ddr_latency) << what;
    EXPECT_EQ(rd.last_fire_cycle - rd.first_fire_cycle, (words - 1) * 4) << what << ": pass 2 reads at the DDR rate";
  }
  const StereoParams one = params(37, 9, 32, 8, kern::kForwardPaths);
  const StereoPair sp = make_pair(Pattern::kRandom, one.width_px, one.height_px, 22);
  const sim::CycleReport r = sim::run_timing(sp.left, sp.right, one, one_pair_per_cycle());
  EXPECT_EQ(r.ddr_word_bits, 0);
  EXPECT_EQ(r.ddr_bytes_written + r.ddr_bytes_read + r.map_bytes_written, 0);
}

// Camera input: pixels at the pixel clock with blanking; a fast pipeline is input-bound and its
// frame period is (W + h_blank)(H + v_blank) pixel clocks.
TEST(Timing, CameraBoundFramePeriod) {
  StereoParams p = params(64, 16, 16, 16, kern::kForwardPaths);
  const StereoPair sp = make_pair(Pattern::kRandom, p.width_px, p.height_px, 3);
  sim::CycleOptions o = one_pair_per_cycle();
  o.input = sim::InputKind::camera;
  o.camera_pixel_hz = 25e6;  // 8 processing cycles per pixel
  o.camera_h_blank_px = 16;
  o.camera_v_blank_rows = 4;
  const sim::CycleReport r = sim::run_cycle(sp.left, sp.right, p, o);
  EXPECT_EQ(r.input_period_cycles, int64_t(64 + 16) * (16 + 4) * 8);
  EXPECT_EQ(r.cycles_per_frame, r.input_period_cycles);
  EXPECT_EQ(r.bottleneck, "input");
  EXPECT_TRUE(r.input_overrun.empty()) << r.input_overrun;
}

TEST(Timing, CameraOverrunIsReported) {
  StereoParams p = params(64, 16, 64, 1, kern::kForwardPaths);  // 128 cycles per pixel
  const StereoPair sp = make_pair(Pattern::kRandom, p.width_px, p.height_px, 4);
  sim::CycleOptions o = one_pair_per_cycle();
  o.input = sim::InputKind::camera;
  o.camera_pixel_hz = 100e6;  // 2 cycles per pixel: far faster than the pipeline
  const sim::CycleReport r = sim::run_cycle(sp.left, sp.right, p, o);
  EXPECT_NE(r.input_overrun.find("camera overrun"), std::string::npos);
  EXPECT_NE(r.input_overrun.find("left_px"), std::string::npos) << r.input_overrun;
}

// FIFOs sized from the unbounded run remove every wait for FIFO space.
TEST(Timing, StallFreeDepthsRemoveOutputStalls) {
  StereoParams p = params(48, 10, 16, 4, kern::kForwardPaths);
  const StereoPair sp = make_pair(Pattern::kShiftedTexture, p.width_px, p.height_px, 5);
  sim::CycleOptions o = one_pair_per_cycle();
  o.fifo_depth = 1;
  const sim::CycleReport tight = sim::run_cycle(sp.left, sp.right, p, o);
  int64_t stalls = 0;
  for (const auto& s : tight.stages) stalls += s.output_stall_cycles;
  EXPECT_GT(stalls, 0);
  const auto depths = sim::stall_free_depths(sp.left, sp.right, p, o);
  for (const auto& kv : depths.depths) o.fifo_depths[kv.first] = std::size_t(kv.second);
  const sim::CycleReport sized = sim::run_cycle(sp.left, sp.right, p, o);
  for (const auto& s : sized.stages) EXPECT_EQ(s.output_stall_cycles, 0) << s.name;
  for (const auto& f : sized.fifos) EXPECT_LE(f.high_water, f.depth) << f.name;
  EXPECT_LE(sized.last_pixel_cycle, tight.last_pixel_cycle);
  EXPECT_EQ(sized.last_pixel_cycle, depths.last_pixel_cycle);
}

TEST(Timing, HighWaterNeverExceedsDepth) {
  StereoParams p = params(40, 9, 32, 8, kern::kAllPaths);
  const StereoPair sp = make_pair(Pattern::kRandom, p.width_px, p.height_px, 6);
  for (std::size_t depth : {std::size_t(1), std::size_t(3), std::size_t(16)}) {
    sim::CycleOptions o = one_pair_per_cycle();
    o.fifo_depth = depth;
    const sim::CycleReport r = sim::run_cycle(sp.left, sp.right, p, o);
    for (const auto& f : r.fifos) {
      EXPECT_LE(f.high_water, int64_t(depth)) << f.name;
      EXPECT_GE(f.high_water, 1) << f.name;
    }
  }
}

// --- deadlock --------------------------------------------------------------------------------

// A frame whose input ends early can never complete: the cost stage's plan waits for a pixel
// that will not come. Reported, naming the FIFO, the finished producer and the cycle.
TEST(Deadlock, StageWhosePlanCanNeverBeMet) {
  StereoParams p = params(32, 8, 16, 4, kern::kForwardPaths);
  const StereoPair sp = make_pair(Pattern::kRandom, p.width_px, p.height_px, 7);
  sim::CycleOptions o = one_pair_per_cycle();
  o.truncate_input_px = 100;
  const sim::CycleReport r = run_both_modes(sp.left, sp.right, p, o, "truncated input");
  ASSERT_TRUE(r.deadlock);
  EXPECT_NE(r.deadlock_message.find("stage 'cost' waits for a token on FIFO 'left_px'"), std::string::npos)
      << r.deadlock_message;
  EXPECT_NE(r.deadlock_message.find("producer 'source' has finished"), std::string::npos) << r.deadlock_message;
  EXPECT_GT(r.deadlock_cycle, 99);
  EXPECT_NE(r.deadlock_message.find("at cycle " + std::to_string(r.deadlock_cycle)), std::string::npos);
}

// A split that reconverges: branch B holds 8 tokens before it emits, so branch A must buffer 8.
// With A 4 deep the graph deadlocks, and the diagnosis names A as too shallow.
struct SplitJoin {
  int64_t run(std::size_t depth_a, std::string* message) {
    using namespace sim;
    using namespace sim::detail;
    Graph<true> g(nullptr);
    Fifo<int> a("A", depth_a, true), b("B", 64, true), b2("B2", 64, true);
    g.add_fifo(&a, "split", "join");
    g.add_fifo(&b, "split", "delay");
    g.add_fifo(&b2, "delay", "join");
    auto& split = g.add_node("split", {1, 1, 0});
    auto& delay = g.add_node("delay", {1, 1, 0});
    auto& join = g.add_node("join", {1, 1, 0});
    const int n = 40;
    int sent = 0, held = 0, passed = 0, joined = 0;
    std::vector<std::function<bool()>> pumps = {
        [&] {
          bool f = false;
          while (sent < n && split.attempt({}, {Port{&a, true}, Port{&b, true}}, [&] {
            a.write(sent);
            b.write(sent);
          })) {
            ++sent;
            f = true;
          }
          return f;
        },
        [&] {
          bool f = false;
          while (passed < n) {
            const bool rd = held < 8 && sent > passed + held, wr = held == 8 || (sent == n && held > 0);
            const bool reading = held < 8 && passed + held < n;
            if (!delay.attempt({Port{&b, reading}}, {Port{&b2, !reading || held == 8}}, [&] {
                  if (reading) {
                    b.read();
                    ++held;
                  } else {
                    b2.write(passed++);
                    --held;
                  }
                }))
              break;
            (void)rd;
            (void)wr;
            f = true;
          }
          return f;
        },
        [&] {
          bool f = false;
          while (joined < n && join.attempt({Port{&a, true}, Port{&b2, true}}, {}, [&] {
            a.read();
            b2.read();
          })) {
            ++joined;
            f = true;
          }
          return f;
        }};
    if (!g.schedule(pumps, [&] { return joined >= n; })) {
      *message = g.deadlock_message();
      return -1;
    }
    return join.report().last_fire_cycle;
  }
};

TEST(Deadlock, UndersizedFifoIsNamed) {
  SplitJoin sj;
  std::string msg;
  EXPECT_EQ(sj.run(4, &msg), -1);
  EXPECT_NE(msg.find("FIFO 'A' is too shallow"), std::string::npos) << msg;
  EXPECT_NE(msg.find("deadlock at cycle"), std::string::npos) << msg;
  EXPECT_GT(sj.run(16, &msg), 0) << msg;
}

// --- VCD -------------------------------------------------------------------------------------

TEST(Vcd, WindowOfFifoOccupanciesAndStageSignals) {
  StereoParams p = params(32, 8, 16, 4, kern::kForwardPaths);
  const StereoPair sp = make_pair(Pattern::kRandom, p.width_px, p.height_px, 8);
  sim::CycleOptions o = one_pair_per_cycle();
  o.fifo_depth = 3;
  o.vcd_path = ::testing::TempDir() + "parallax_cycle_test.vcd";
  o.vcd_from = 100;
  o.vcd_to = 900;
  const sim::CycleReport r = sim::run_cycle(sp.left, sp.right, p, o);
  std::ifstream in(o.vcd_path);
  ASSERT_TRUE(in.good());
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string vcd = ss.str();
  for (const char* sig :
       {"$enddefinitions", "aggregate_valid", "aggregate_stall", "cost_valid", "fifo_cost", "fifo_sum", "$dumpvars"})
    EXPECT_NE(vcd.find(sig), std::string::npos) << sig;
  // Timestamps stay inside the window and are increasing.
  std::istringstream lines(vcd);
  std::string line;
  int64_t last = -1, stamps = 0;
  while (std::getline(lines, line))
    if (!line.empty() && line[0] == '#') {
      const int64_t t = std::stoll(line.substr(1));
      EXPECT_GE(t, 100);
      EXPECT_LE(t, 900);
      EXPECT_GT(t, last);
      last = t;
      ++stamps;
    }
  EXPECT_GT(stamps, 50);
  EXPECT_FALSE(r.deadlock);
  // The coupled run writes the same trace.
  sim::CycleOptions oc = o;
  oc.coupled = true;
  oc.vcd_path = ::testing::TempDir() + "parallax_cycle_test_coupled.vcd";
  (void)sim::run_cycle(sp.left, sp.right, p, oc);
  std::ifstream in_c(oc.vcd_path);
  std::stringstream sc;
  sc << in_c.rdbuf();
  EXPECT_EQ(sc.str(), vcd);
}

// The periodic fast-forward applies whole rows at once; on frames tall enough for it to engage,
// over designs of every pacing (aggregation-bound, memory-input-bound, camera-bound with and
// without overruns, back-pressured through depth-1 FIFOs, memory-port conflicts, LR flushes,
// no median), the report equals the one that simulates every firing and the coupled run's.
TEST(CycleEquiv, FastForwardEqualsEveryFiring) {
  uint32_t seed = 9300;
  int engaged = 0, cases = 0;
  for (int variant = 0; variant < 12; ++variant) {
    const int d = variant % 3 == 0 ? 16 : 32;
    const int pu = variant % 4 == 0 ? 16 : variant % 4 == 1 ? 4 : 8;
    StereoParams p = params(variant % 2 ? 24 : 41, 40 + variant, d, pu,
                            variant % 5 == 3 ? kern::kForwardPaths | kern::kPath180 : kern::kForwardPaths);
    p.cost = variant % 5 == 2 ? int(kern::kCostSad) : int(kern::kCostCensus);
    p.median = variant % 3 == 1 ? 0 : (variant % 2 ? 3 : 5);
    p.lr_check = variant % 4 != 3;
    const StereoPair sp = make_pair(Pattern::kShiftedTexture, p.width_px, p.height_px, seed, 4);
    sim::CycleOptions o = one_pair_per_cycle();
    o.fifo_depth = std::size_t(1 + variant % 3);
    if (variant % 4 == 2) {  // a camera: slower than the pipeline (variant 2), or faster (6, 10: overruns)
      o.input = sim::InputKind::camera;
      o.camera_pixel_hz = variant == 2 ? 5e6 : 150e6;
      o.camera_h_blank_px = 7;
      o.camera_v_blank_rows = 2;
    }
    if (variant == 9) o.input_bytes_per_s = 0.05e9;  // memory input slower than the pipeline
    const std::string what = describe(p) + " variant " + std::to_string(variant);
    sim::CycleOptions every = o;
    every.fast_forward = false;
    const sim::CycleReport fast = sim::run_timing(sp.left, sp.right, p, o);
    const sim::CycleReport slow = sim::run_timing(sp.left, sp.right, p, every);
    expect_same_report(fast, slow, what + " (fast-forward vs every firing)");
    EXPECT_EQ(slow.rows_fast_forwarded, 0);
    const sim::CycleReport coupled = run_both_modes(sp.left, sp.right, p, o, what);
    expect_same_report(fast, coupled, what + " (fast-forward vs coupled)");
    engaged += fast.rows_fast_forwarded > 0 ? 1 : 0;
    ++cases;
    ++seed;
  }
  EXPECT_GE(engaged, cases * 2 / 3) << "the fast-forward engaged in too few designs to test it";
}

// The two passes of the 8-path design fast-forward each on its own (pass 1 to the frame-buffer
// writer, rows of words, under the memory's write rate; pass 2 from the reader to the map
// writer): over designs of every pacing (aggregation-bound, input-bound, camera-bound with and
// without overruns, depth-1 FIFOs, a frame buffer slow enough to bind both passes (whole cycles
// per word: the passes still skip), another binding at a fraction of a cycle per word (the rows'
// words do not repeat with one period: no skip), no median, no LR check), the report equals the
// one that simulates every firing and the coupled run's.
TEST(CycleEquiv, TwoPassFastForwardEqualsEveryFiring) {
  uint32_t seed = 9400;
  int engaged1 = 0, engaged2 = 0, cases = 0;
  for (int variant = 0; variant < 12; ++variant) {
    const int d = variant % 3 == 0 ? 16 : 32;
    const int pu = variant % 4 == 0 ? 16 : variant % 4 == 1 ? 4 : 8;
    StereoParams p = params(variant % 2 ? 24 : 41, 44 + variant, d, pu, kern::kAllPaths);
    p.cost = variant % 5 == 2 ? int(kern::kCostSad) : int(kern::kCostCensus);
    p.median = variant % 3 == 1 ? 0 : (variant % 2 ? 3 : 5);
    p.lr_check = variant % 4 != 3;
    const StereoPair sp = make_pair(Pattern::kShiftedTexture, p.width_px, p.height_px, seed, 4);
    sim::CycleOptions o = one_pair_per_cycle();
    o.fifo_depth = std::size_t(1 + variant % 3);
    if (variant % 4 == 2) {  // a camera: slower than the pipeline (variant 2), or faster (6, 10: overruns)
      o.input = sim::InputKind::camera;
      o.camera_pixel_hz = variant == 2 ? 5e6 : 150e6;
      o.camera_h_blank_px = 7;
      o.camera_v_blank_rows = 2;
    }
    if (variant == 9) o.input_bytes_per_s = 0.05e9;                // memory input slower than the pipeline
    if (variant == 5 || variant == 7) o.ddr_bytes_per_s = 0.02e9;  // the frame buffer binds both passes
    if (variant == 11) o.ddr_bytes_per_s = 0.9e9;                  // binding at a fraction of a cycle per word: no skip
    const std::string what = describe(p) + " two-pass variant " + std::to_string(variant);
    sim::CycleOptions every = o;
    every.fast_forward = false;
    const sim::CycleReport fast = sim::run_timing(sp.left, sp.right, p, o);
    const sim::CycleReport slow = sim::run_timing(sp.left, sp.right, p, every);
    expect_same_report(fast, slow, what + " (fast-forward vs every firing)");
    EXPECT_EQ(slow.rows_fast_forwarded + slow.first_pass_rows_fast_forwarded, 0);
    const sim::CycleReport coupled = run_both_modes(sp.left, sp.right, p, o, what);
    expect_same_report(fast, coupled, what + " (fast-forward vs coupled)");
    engaged1 += fast.first_pass_rows_fast_forwarded > 0 ? 1 : 0;
    engaged2 += fast.rows_fast_forwarded > 0 ? 1 : 0;
    ++cases;
    ++seed;
  }
  EXPECT_GE(engaged1, cases * 2 / 3) << "pass 1's fast-forward engaged in too few designs to test it";
  EXPECT_GE(engaged2, cases * 2 / 3) << "pass 2's fast-forward engaged in too few designs to test it";
}

// An input-bound design whose rows arrive 72 cycles apart except one row in a hundred (73: the
// memory delivers a pixel every 3 + 0.01/24 cycles). The schedule repeats for long runs of rows;
// the fast-forward checks the arrivals of the rows it skips, stops before the longer row,
// simulates it, and skips again after it.
TEST(CycleEquiv, FastForwardStopsAtAnIrregularInputRow) {
  StereoParams p = params(24, 260, 16, 16, kern::kForwardPaths);
  const StereoPair sp = make_pair(Pattern::kShiftedTexture, p.width_px, p.height_px, 23, 4);
  sim::CycleOptions o = one_pair_per_cycle();
  const double cycles_per_pixel = 3.0 + 0.01 / 24.0;
  o.input_bytes_per_s = 2.0 * o.clock_hz / cycles_per_pixel;
  sim::CycleOptions every = o;
  every.fast_forward = false;
  const sim::CycleReport fast = sim::run_timing(sp.left, sp.right, p, o);
  const sim::CycleReport slow = sim::run_timing(sp.left, sp.right, p, every);
  EXPECT_GT(fast.rows_fast_forwarded, 200);
  EXPECT_EQ(slow.bottleneck, "input");
  expect_same_report(fast, slow, "irregular input rows");
}

// Work sharing: one recording of the cost stage replayed into designs that differ in every later
// stage gives each the codes of its own func run, with either engine; with the fast engine the
// designs of one aggregate (the last three: WTA, LR, uniqueness, sub-pixel and median differ)
// reuse it, and the eight-path variant replays too.
TEST(FuncSharing, ReplayedCostsGiveTheCodesOfTheRun) {
  uint32_t seed = 9500;
  for (sim::FuncEngine engine : {sim::FuncEngine::kernels, sim::FuncEngine::fast})
    for (int cost : {int(kern::kCostCensus), int(kern::kCostSad)}) {
      StereoParams base = params(53, 17, 32, 8, kern::kForwardPaths);
      base.cost = cost;
      const StereoPair sp = make_pair(Pattern::kShiftedTexture, base.width_px, base.height_px, seed++, 5);
      sim::FuncPipeline pipe;
      sim::CostRecording rec;
      sim::FuncOptions opt;
      opt.engine = engine;
      pipe.record_costs(sp.left, sp.right, base, rec, opt);
      const struct {
        int p1, p2, median;
        unsigned paths;
        bool lr;
        int uniqueness, subpixel;
      } variants[] = {{8, 32, 5, kern::kForwardPaths, true, 0, 0},
                      {4, 96, 0, kern::kPath0, false, 0, 0},
                      {20, 400, 3, kern::kPath0 | kern::kPath90, true, 0, 0},
                      {2, 3, 7, kern::kPath45 | kern::kPath135, true, 0, 0},
                      {6, 48, 5, kern::kForwardPaths | kern::kPath180, true, 0, 0},
                      {6, 48, 0, kern::kForwardPaths | kern::kPath180, false, 10, 0},
                      {6, 48, 3, kern::kForwardPaths | kern::kPath180, true, 0, 3},
                      {6, 48, 5, kern::kAllPaths, true, 5, 2}};
      for (std::size_t i = 0; i < std::size(variants); ++i) {
        const auto& v = variants[i];
        StereoParams p = base;
        p.p1 = cost == kern::kCostSad ? v.p1 * 25 : v.p1;
        p.p2 = cost == kern::kCostSad ? v.p2 * 25 : v.p2;
        p.median = v.median;
        p.path_mask = v.paths;
        p.lr_check = v.lr;
        p.uniqueness_pct = v.uniqueness;
        p.subpixel_bits = v.subpixel;
        p.parallel_units = 4;  // the design's PU does not matter to the func run's lanes
        if (sim::cost_sharing_key(p, engine).empty()) continue;  // the kernels' two passes
        ASSERT_EQ(sim::cost_sharing_key(p, engine), sim::cost_sharing_key(base, engine));
        const bool keep = i + 1 < std::size(variants) && variants[i + 1].paths == v.paths && variants[i + 1].p1 == v.p1;
        const sim::DisparityCodes replayed = pipe.run_from_costs(rec, p, keep);
        sim::FuncOptions kernels;
        kernels.engine = sim::FuncEngine::kernels;
        const sim::DisparityCodes direct = sim::run_func(sp.left, sp.right, p, kernels);
        const Comparison c = compare_maps(replayed.code, direct.code, p.width_px);
        EXPECT_TRUE(c.sizes_equal && c.mismatches == 0)
            << sim::to_string(engine) << " " << describe(p) << ": " << c.mismatches << " at " << c.first;
      }
    }
  StereoParams eight = params(20, 9, 16, 4, kern::kAllPaths);
  EXPECT_EQ(sim::cost_sharing_key(eight, sim::FuncEngine::kernels), "");
  EXPECT_NE(sim::cost_sharing_key(eight, sim::FuncEngine::fast), "");
  StereoParams sparse = params(20, 9, 16, 4, kern::kForwardPaths);
  StereoParams full = sparse;
  sparse.census = kern::kCensusSparse;
  EXPECT_NE(sim::cost_sharing_key(sparse), sim::cost_sharing_key(full));  // other taps, other costs
  StereoParams five = sparse;  // the stages after the costs do not matter to the key
  five.path_mask = kern::kForwardPaths | kern::kPath180;
  five.uniqueness_pct = 5;
  EXPECT_EQ(sim::cost_sharing_key(five), sim::cost_sharing_key(sparse));
}

// A frame that never completes is diagnosed the same with the fast-forward: the skipped rows
// stay clear of the end of the (truncated) input.
TEST(Deadlock, FastForwardKeepsTheDiagnosis) {
  StereoParams p = params(20, 60, 16, 4, kern::kForwardPaths);
  const StereoPair sp = make_pair(Pattern::kRandom, p.width_px, p.height_px, 17);
  sim::CycleOptions o = one_pair_per_cycle();
  o.truncate_input_px = 20 * 45 + 7;
  sim::CycleOptions every = o;
  every.fast_forward = false;
  const sim::CycleReport fast = sim::run_timing(sp.left, sp.right, p, o);
  const sim::CycleReport slow = sim::run_timing(sp.left, sp.right, p, every);
  ASSERT_TRUE(fast.deadlock);
  EXPECT_GT(fast.rows_fast_forwarded, 0);
  expect_same_report(fast, slow, "truncated input");
}

// The control-path schedule and the func run of the codes side by side (CycleOptions::threads
// 2) give the report and the codes of one thread, for a one-pass, a two-pass and a deadlocked
// design.
TEST(CycleEquiv, TwoThreadsGiveTheOneThreadRun) {
  for (int variant = 0; variant < 3; ++variant) {
    StereoParams p = params(33, 24, 32, 8, variant == 1 ? kern::kAllPaths : kern::kForwardPaths);
    const StereoPair sp = make_pair(Pattern::kShiftedTexture, p.width_px, p.height_px, 4100u + unsigned(variant), 5);
    sim::CycleOptions one = one_pair_per_cycle();
    if (variant == 2) one.truncate_input_px = 33 * 10 + 3;
    one.threads = 1;
    sim::CycleOptions two = one;
    two.threads = 2;
    const sim::CycleReport a = sim::run_cycle(sp.left, sp.right, p, one);
    const sim::CycleReport b = sim::run_cycle(sp.left, sp.right, p, two);
    const std::string what = describe(p) + " variant " + std::to_string(variant);
    EXPECT_EQ(a.deadlock, variant == 2) << what;
    expect_same_report(a, b, what + " (1 vs 2 threads)");
    EXPECT_EQ(a.codes.code, b.codes.code) << what;
    EXPECT_EQ(a.codes.width_px, b.codes.width_px) << what;
    EXPECT_EQ(a.codes.code.size(), std::size_t(p.width_px) * std::size_t(p.height_px)) << what;
  }
}

// run_timing is the report of run_cycle without the codes, in both modes; and on designs of
// every shape (two passes, SAD, camera input, shallow FIFOs, port conflicts) the control-path
// schedule and the coupled run agree on every figure.
TEST(CycleEquiv, ControlPathScheduleEqualsCoupledRun) {
  uint32_t seed = 9100;
  for (unsigned paths :
       {kern::kForwardPaths, kern::kAllPaths, kern::kPath0 | kern::kPath45, kern::kForwardPaths | kern::kPath180})
    for (std::size_t depth : {std::size_t(1), std::size_t(2), std::size_t(5)}) {
      StereoParams p = params(37, 9, 32, seed % 2 ? 4 : 8, paths);
      p.cost = seed % 3 ? int(kern::kCostCensus) : int(kern::kCostSad);
      const StereoPair sp = make_pair(Pattern::kShiftedTexture, p.width_px, p.height_px, seed, 5);
      sim::CycleOptions o = one_pair_per_cycle();
      o.fifo_depth = depth;
      if (seed % 4 == 1) {
        o.input = sim::InputKind::camera;
        o.camera_pixel_hz = 40e6;
        o.camera_h_blank_px = 5;
      }
      const std::string what = describe(p) + " depth " + std::to_string(depth);
      const sim::CycleReport coupled = run_both_modes(sp.left, sp.right, p, o, what);
      const sim::CycleReport timing = sim::run_timing(sp.left, sp.right, p, o);
      expect_same_report(timing, coupled, what + " (run_timing)");
      EXPECT_TRUE(timing.codes.code.empty());
      ++seed;
    }
}

}  // namespace
}  // namespace parallax::test

namespace parallax::test {
namespace {

// The kernels' plans depend on counters only, never on pixel values: timing is a property of the
// design, so a sweep needs one cycle run per design, not one per frame.
TEST(Timing, IndependentOfImageContent) {
  for (unsigned paths :
       {unsigned(kern::kForwardPaths), unsigned(kern::kAllPaths), unsigned(kern::kForwardPaths | kern::kPath180)}) {
    StereoParams p = params(50, 12, 24, 6, paths);
    const StereoPair a = make_pair(Pattern::kRandom, p.width_px, p.height_px, 11);
    const StereoPair b = make_pair(Pattern::kFlat, p.width_px, p.height_px, 12);
    const sim::CycleReport ra = sim::run_cycle(a.left, a.right, p, one_pair_per_cycle());
    const sim::CycleReport rb = sim::run_cycle(b.left, b.right, p, one_pair_per_cycle());
    EXPECT_EQ(ra.last_pixel_cycle, rb.last_pixel_cycle);
    ASSERT_EQ(ra.stages.size(), rb.stages.size());
    for (std::size_t i = 0; i < ra.stages.size(); ++i) {
      EXPECT_EQ(ra.stages[i].input_stall_cycles, rb.stages[i].input_stall_cycles) << ra.stages[i].name;
      EXPECT_EQ(ra.stages[i].output_stall_cycles, rb.stages[i].output_stall_cycles) << ra.stages[i].name;
    }
  }
}

}  // namespace
}  // namespace parallax::test

namespace parallax::test {
namespace {

// Rectification in the cycle graph: the same bits as rectifying with the func run's rectify
// stage and then matching, the same window misses, and the rectify stages appear in the report.
TEST(CycleEquiv, RectifyInFrontOfTheCostStage) {
  for (int mode : {int(kern::kRectifyNearest), int(kern::kRectifyBilinear)})
    for (int rows : {2, 8}) {
      const int w = 48, h = 14, frac = mode == kern::kRectifyBilinear ? 5 : 0;
      StereoParams p = params(w, h, 16, 4, kern::kForwardPaths);
      const StereoPair sp = make_pair(Pattern::kShiftedTexture, w, h, 21, 4);
      std::vector<kern::MapEntry> map_l, map_r;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const double sx = x + 0.03 * (y - h / 2.0) + 0.4, sy = y - 0.02 * (x - w / 2.0) + 0.6;
          map_l.push_back({int32_t(std::lround(sx * (1 << frac))), int32_t(std::lround(sy * (1 << frac)))});
          map_r.push_back({int32_t(std::lround((sx - 0.3) * (1 << frac))), int32_t(std::lround(sy * (1 << frac)))});
        }
      sim::CycleOptions o = one_pair_per_cycle();
      o.rectify = kern::RectifyParams{w, h, mode, frac, rows};
      o.rectify_map_left = &map_l;
      o.rectify_map_right = &map_r;
      const sim::CycleReport c = run_both_modes(
          sp.left, sp.right, p, o, "rectify mode " + std::to_string(mode) + " rows " + std::to_string(rows));
      ASSERT_FALSE(c.deadlock) << c.deadlock_message;
      const sim::RectifyOutput rl = sim::run_rectify_func(sp.left, map_l, o.rectify);
      const sim::RectifyOutput rr = sim::run_rectify_func(sp.right, map_r, o.rectify);
      sim::FuncOptions design;
      design.use_design_pu = true;
      const sim::DisparityCodes f = sim::run_func(rl.image, rr.image, p, design);
      const Comparison cf = compare_maps(c.codes.code, f.code, w);
      EXPECT_EQ(cf.mismatches, 0) << "mode " << mode << " rows " << rows << ": first at " << cf.first;
      EXPECT_EQ(c.rectify_window_misses, rl.window_misses + rr.window_misses);
      EXPECT_GT(stage(c, "rectify_left").fires, 0);
      EXPECT_GT(stage(c, "map_right").fires, 0);
    }
}

}  // namespace
}  // namespace parallax::test

#include "parallax/config/config.hpp"

namespace parallax::test {
namespace {

// Every stage the cycle model times can be calibrated from a configuration, and nothing else.
TEST(Timing, ConfigurationKnowsEveryStage) {
  for (unsigned paths :
       {unsigned(kern::kForwardPaths), unsigned(kern::kAllPaths), unsigned(kern::kForwardPaths | kern::kPath180)}) {
    for (const auto& kv : sim::default_timing(params(8, 8, 16, 4, paths))) {
      config::PipelineConfig c;
      config::set_field(c, "ii_" + kv.first, "2");
      config::set_field(c, "latency_" + kv.first, "3");
      EXPECT_TRUE(config::validate(c).empty()) << kv.first;
    }
  }
  config::PipelineConfig c;
  config::set_field(c, "ii_agg", "2");
  const auto errors = config::validate(c);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].field, "ii_agg");
}

}  // namespace
}  // namespace parallax::test

namespace parallax::test {
namespace {

// The 180-degree path in one pass (kernels/row_reverse.hpp) keeps the frame rate: the stages it
// adds fire at the aggregation's rate. It costs latency: the last row's 180-degree path starts
// only when the row is complete, and the codes' reversal holds one more row.
TEST(Timing, RowReverseKeepsTheRateAndAddsTheLastRows) {
  for (const auto& c : {std::make_pair(16, 4), std::make_pair(32, 32)}) {
    StereoParams four = params(80, 20, c.first, c.second, kern::kForwardPaths);
    four.lr_check = false;
    four.median = 0;
    StereoParams five = four;
    five.path_mask = kern::kForwardPaths | kern::kPath180;
    const StereoPair sp = make_pair(Pattern::kRandom, four.width_px, four.height_px, 2);
    const sim::CycleReport r4 = sim::run_cycle(sp.left, sp.right, four, one_pair_per_cycle());
    const sim::CycleReport r5 = sim::run_cycle(sp.left, sp.right, five, one_pair_per_cycle());
    const int64_t row_tokens = int64_t(four.width_px) * (c.first / c.second);
    const int64_t ii = stage(r5, "aggregate_row").busy_cycles / stage(r5, "aggregate_row").fires;
    EXPECT_EQ(r5.cycles_per_frame, r4.cycles_per_frame);
    // The first row is only read in and the last only emitted: one row more than the frame.
    EXPECT_EQ(stage(r5, "row_reverse").fires, row_tokens * (four.height_px + 1));
    // The last row: its 180-degree path runs once its last token is in (a row of tokens at the
    // aggregation's II), then its codes leave the reversal W firings later; on top, the pipeline
    // latency of the three stages the variant adds.
    const sim::TimingModel t = sim::default_timing(five, 200e6);
    const int64_t added_latency = t.at("row_reverse").latency_cycles + t.at("aggregate_row").latency_cycles +
                                  t.at("row_unreverse").latency_cycles;
    EXPECT_EQ(r5.last_pixel_cycle - r4.last_pixel_cycle, ii * row_tokens + four.width_px + added_latency)
        << "D " << c.first << " PU " << c.second;
  }
}

}  // namespace
}  // namespace parallax::test
