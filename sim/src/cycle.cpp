// The cycle model: the engine of engine.hpp in timed mode, default timing derived from the kernel
// structure, and FIFO sizing.
#include "parallax/sim/cycle.hpp"

#include <algorithm>
#include <future>
#include <map>
#include <memory>
#include <system_error>
#include <thread>

#include "design_dispatch.hpp"
#include "engine.hpp"
#include "parallax/sim/schedule.hpp"

namespace parallax::sim {

TimingModel default_timing(const kern::StereoParams& p, double clock_hz) {
  // Every stage of the pipeline table (kernels/pipeline.hpp) at its latency rule; the II comes
  // from the kernels' own schedule declarations (a counting run, stage_schedules), 1 where none.
  TimingModel t;
  for (const kern::PipelineStage& st : kern::kPipelineStages) t[st.name] = {1, kern::stage_latency_cycles(st, p)};
  // The backward pass has the same kinds of work as the forward one (the same kernel on the
  // reversed stream): with no backward paths it is not in the graph, so its II is the forward's.
  const kern::RectifyParams no_rectify{p.width_px, p.height_px, kern::kRectifyNone, 0, 1};
  for (const StageSchedule& s : stage_schedules(p, no_rectify, clock_hz)) t[s.stage].ii_cycles = s.ii;
  if (!kern::two_pass_paths(p.path_mask)) t["aggregate_back"].ii_cycles = t["aggregate"].ii_cycles;
  return t;
}

namespace {

void require_valid(const kern::StereoParams& p) {
  const auto errors = func_param_errors(p);
  if (!errors.empty()) detail::internal_error("invalid parameters reached the cycle run: " + errors.front());
}

template <class Caps, class Word, bool kData>
void run_timed(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
               const detail::RunSetup& setup, CycleReport& rep) {
  using E = detail::Engine<Caps, Word, true, kData>;
  // The control path alone (kData false) never reads the kernels' data memories, so the engine
  // is default-initialised: value-initialising it (make_unique) zeroed tens of MiB of line
  // buffers sized for the largest design on every run, most of the timing run's time
  // (valgrind's memcheck finds no read of uninitialised memory on this path).
  std::unique_ptr<E> engine(kData ? new E() : new E);
  engine->run(left, right, p, setup, rep.codes, &rep);
}

// The kernels' datapath inside the schedule, at the design's PU.
void run_coupled(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                 const detail::RunSetup& setup, CycleReport& rep) {
  require_valid(p);
  // Tokens no longer than the design's PU needs: every firing copies one through a FIFO.
  detail::dispatch_design<detail::TinyCaps, detail::NarrowCaps, detail::WideCaps>(
      p.parallel_units, kern::aggregate_bits(p), [&](auto design) {
        using D = decltype(design);
        run_timed<typename D::Caps, typename D::Word, true>(left, right, p, setup, rep);
      });
}

// The schedule of the kernels' control path at the design's PU.
void run_control(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                 const detail::RunSetup& setup, CycleReport& rep) {
  require_valid(p);
  run_timed<detail::ControlCaps, uint16_t, false>(left, right, p, setup, rep);
}

}  // namespace

CycleReport run_cycle(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                      const CycleOptions& opt) {
  CycleReport rep;
  detail::RunSetup setup;
  setup.opt = &opt;
  if (opt.coupled) {
    run_coupled(left, right, p, setup, rep);
    return rep;
  }
  // The codes: the func run of the same kernels (on the rectified frames when the design
  // rectifies); independent of the schedule, so it may run beside it.
  const bool rectify =
      opt.rectify.mode != kern::kRectifyNone && opt.rectify_map_left != nullptr && opt.rectify_map_right != nullptr;
  auto codes_of_frame = [&]() -> DisparityCodes {
    if (!rectify) return run_func(left, right, p);
    const RectifyOutput rl = run_rectify_func(left, *opt.rectify_map_left, opt.rectify);
    const RectifyOutput rr = run_rectify_func(right, *opt.rectify_map_right, opt.rectify);
    return run_func(rl.image, rr.image, p);
  };
  const int threads = opt.threads > 0 ? opt.threads : (std::thread::hardware_concurrency() >= 2 ? 2 : 1);
  DisparityCodes codes;
  std::future<DisparityCodes> func;
  if (threads >= 2) {
    require_valid(p);  // before the second thread starts: an invalid design aborts on this one
    try {
      func = std::async(std::launch::async, codes_of_frame);
    } catch (const std::system_error&) {  // no thread to be had: one after the other
    }
  }
  if (func.valid()) {
    run_control(left, right, p, setup, rep);
    codes = func.get();
  } else {
    run_control(left, right, p, setup, rep);
    if (!rep.deadlock) codes = codes_of_frame();
  }
  if (rep.deadlock) {  // no frame leaves a deadlocked pipeline
    codes = DisparityCodes{p.width_px, p.height_px, p.disparities, p.min_disparity, p.subpixel_bits, {}};
    codes.code.assign(std::size_t(p.width_px) * std::size_t(p.height_px), 0);
  }
  rep.codes = std::move(codes);
  return rep;
}

CycleReport run_timing(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                       const CycleOptions& opt) {
  CycleReport rep;
  detail::RunSetup setup;
  setup.opt = &opt;
  run_control(left, right, p, setup, rep);
  rep.codes = DisparityCodes{p.width_px, p.height_px, p.disparities, p.min_disparity, p.subpixel_bits, {}};
  return rep;
}

FifoSizing stall_free_depths(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                             const CycleOptions& opt) {
  CycleOptions o = opt;
  o.vcd_path.clear();
  CycleReport rep;
  detail::RunSetup setup;
  setup.opt = &o;
  setup.unbounded = true;
  if (o.coupled)
    run_coupled(left, right, p, setup, rep);
  else
    run_control(left, right, p, setup, rep);
  FifoSizing sizing;
  for (const auto& f : rep.fifos) sizing.depths[f.name] = std::max<int64_t>(1, f.high_water);
  sizing.last_pixel_cycle = rep.last_pixel_cycle;
  return sizing;
}

}  // namespace parallax::sim
