#include "parallax/hls_flow/hls_export.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "parallax/design/result.hpp"
#include "parallax/eval/evaluate.hpp"
#include "parallax/eval/simulate.hpp"
#include "parallax/resources/devices.hpp"
#include "parallax/resources/model.hpp"
#include "parallax/sim/accesses.hpp"

namespace parallax::hls_flow {

// The names this file takes from the other rooms (one namespace per room).
using design::resource_figures;
using design::ResourceFigures;
using eval::cycle_options;
using eval::load_rectify_maps;
using eval::maps_of_size;
using eval::RectifyMaps;
using eval::simulate;
using eval::SimulateOptions;
using eval::SimulationResult;
using eval::to_grey_image;

std::string device_for_part(const std::string& part) {
  std::string upper;
  for (char c : part) upper += char(std::toupper(static_cast<unsigned char>(c)));
  std::string best;
  for (const auto& d : res::devices())
    if (upper.rfind(d.name, 0) == 0 && d.name.size() > best.size()) best = d.name;
  return best;
}

namespace {

// The cycles of one call of the IP, which takes one call per frame (ap_ctrl_hs: the next call
// starts when this one is done). A one-pass call lasts the frame's latency; a two-pass call runs
// pass 1 of its frame beside pass 2 of the previous one, so it lasts the longer pass.
int64_t call_cycles(const config::PipelineConfig& cfg, const sim::CycleReport& cycle) {
  const int64_t latency = cycle.last_pixel_cycle - cycle.first_input_cycle;
  if (!kern::two_pass_paths(cfg.path_mask)) return latency;
  int64_t pass1_end = -1, pass2_start = -1;
  for (const auto& s : cycle.stages) {
    if (s.name == "ddr_write") pass1_end = s.last_fire_cycle + 1;
    if (s.name == "ddr_read") pass2_start = s.first_fire_cycle;
  }
  if (pass1_end <= 0 || pass2_start < 0) return latency;
  return std::max(pass1_end - cycle.first_input_cycle, cycle.last_pixel_cycle - pass2_start);
}

}  // namespace

hlsx::ExportRequest prepare_export(const config::PipelineConfig& cfg_in, const cv::Mat& left, const cv::Mat& right,
                                   const std::string& origin, const std::string& pair_source,
                                   const ExportOptions& opt) {
  hlsx::ExportRequest r;
  r.config = cfg_in;
  r.origin = origin;
  r.part = opt.part;
  r.clock_mhz = opt.clock_mhz > 0 ? opt.clock_mhz : double(cfg_in.clock_mhz);
  const int sim_clock = int(std::lround(r.clock_mhz));
  // The export's clock is the synthesis clock: the stages' II are derived at it.
  config::PipelineConfig base = cfg_in;
  base.clock_mhz = sim_clock;
  r.width_px = left.cols;
  r.height_px = left.rows;

  // 1. Size the FIFOs: the configured depths, then unbounded.
  SimulateOptions so;
  so.clock_mhz = sim_clock;
  so.size_fifos = true;
  const SimulationResult sized = simulate(base, left, right, so);
  if (sized.cycle.deadlock)
    throw hlsx::ExportError("design '" + cfg_in.name +
                            "' deadlocks with its configured FIFO depths: " + sized.cycle.deadlock_message);
  config::PipelineConfig cfg = base;
  for (const std::string& name : hlsx::export_fifo_names(cfg_in)) {
    hlsx::ExportFifo f;
    f.name = name;
    const auto conf = cfg_in.fifo_depths.find(name);
    const int64_t configured = conf != cfg_in.fifo_depths.end() ? conf->second : cfg_in.fifo_depth;
    const auto sf = sized.stall_free_depths.find(name);
    f.stall_free = sf != sized.stall_free_depths.end() ? sf->second : -1;
    if (f.stall_free >= 0 && f.stall_free <= opt.max_fifo_depth) {
      f.depth = std::max<int64_t>(2, f.stall_free);
      f.why = f.depth == f.stall_free ? "stall-free depth"
                                      : "stall-free depth " + std::to_string(f.stall_free) + ", at least 2";
    } else {
      f.depth = std::max<int64_t>(2, configured);
      f.why =
          f.stall_free < 0 ? "not sized; configured depth" : "backlog behind a faster producer; configured depth kept";
    }
    cfg.fifo_depths[name] = int(f.depth);
    r.fifos.push_back(f);
  }

  // 2. The design with those depths: timing and the golden output.
  so.size_fifos = false;
  const SimulationResult res = simulate(cfg, left, right, so);
  if (res.cycle.deadlock)
    throw hlsx::ExportError("design '" + cfg.name +
                            "' deadlocks with the sized FIFO depths: " + res.cycle.deadlock_message);
  auto& pr = r.prediction;
  pr.clock_mhz = r.clock_mhz;
  pr.first_pixel_cycle = res.cycle.first_pixel_cycle - res.cycle.first_input_cycle;
  pr.last_pixel_cycle = res.cycle.last_pixel_cycle - res.cycle.first_input_cycle;
  pr.unbounded_last_pixel_cycle = sized.unbounded_last_pixel_cycle;
  pr.cycles_per_frame = res.cycle.cycles_per_frame;
  pr.bottleneck = res.cycle.bottleneck;
  pr.fpga_latency_ms = double(pr.last_pixel_cycle) / (r.clock_mhz * 1e3);
  // Never shorter than the busiest stage.
  const int64_t interval = std::max(pr.cycles_per_frame, call_cycles(cfg, res.cycle));
  pr.fps = interval > 0 ? r.clock_mhz * 1e6 / double(interval) : 0.0;
  const int64_t extra = pr.last_pixel_cycle - (sized.unbounded_last_pixel_cycle - sized.cycle.first_input_cycle);
  for (auto& f : r.fifos)
    if (f.why.rfind("backlog", 0) == 0)
      f.why += " (the whole design: " + std::to_string(extra) + " cycles later than with unbounded FIFOs)";
  r.golden = res.cycle.codes.code;
  for (const auto& s : res.cycle.stages) {
    r.stage_fires[s.name] = s.fires;
    r.stage_timing.push_back({s.name, s.ii_cycles, s.latency_cycles});
  }
  r.access_stages = sim::access_stages(cfg.stereo_params(left.cols, left.rows),
                                       cfg.rectify_params(left.cols, left.rows), sim_clock * 1e6);

  // 2b. The reduced frame of C/RTL co-simulation: the pair's first rows, the same depths; the
  // remap tables (rectifying designs) cut to those rows as the images are.
  r.reduced_height_px = hlsx::reduced_frame_rows(r.height_px);
  {
    const cv::Mat lr = left.rowRange(0, r.reduced_height_px).clone(),
                  rr = right.rowRange(0, r.reduced_height_px).clone();
    sim::CycleOptions o = cycle_options(cfg, sim_clock);
    RectifyMaps maps;
    if (cfg.rectify != "none") {
      maps = maps_of_size(load_rectify_maps(cfg), cfg, left.cols, left.rows);
      const std::size_t n = std::size_t(lr.cols) * std::size_t(lr.rows);
      maps.left.resize(n);
      maps.right.resize(n);
      o.rectify = cfg.rectify_params(lr.cols, lr.rows);
      o.rectify_map_left = &maps.left;
      o.rectify_map_right = &maps.right;
    }
    const sim::CycleReport reduced =
        sim::run_cycle(to_grey_image(lr), to_grey_image(rr), cfg.stereo_params(lr.cols, lr.rows), o);
    if (reduced.deadlock)
      throw hlsx::ExportError("design '" + cfg.name + "' deadlocks on the reduced frame of " +
                              std::to_string(r.reduced_height_px) + " rows: " + reduced.deadlock_message);
    r.reduced_golden = reduced.codes.code;
    for (const auto& s : reduced.stages) r.reduced_stage_fires[s.name] = s.fires;
  }
  r.golden_source =
      "the Parallax cycle model (`parallax sim`), which is bit-identical to its func run and golden model";
  r.pair_source = pair_source;
  if (cfg_in.rectify != "none") {
    // The simulation above checked their size.
    const RectifyMaps maps = maps_of_size(load_rectify_maps(cfg_in), cfg_in, left.cols, left.rows);
    r.map_left = maps.left;
    r.map_right = maps.right;
  }
  r.left.assign(left.datastart, left.dataend);
  r.right.assign(right.datastart, right.dataend);
  if (!left.isContinuous() || !right.isContinuous() || r.left.size() != std::size_t(left.total()))
    throw hlsx::ExportError("export: the pair must be continuous 8-bit images");

  // 3. Resources on the part's device (the resource part of evaluate_point).
  pr.device = device_for_part(r.part);
  const res::Device* dev = pr.device.empty() ? nullptr : res::find_device(pr.device);
  const ResourceFigures figures =
      resource_figures(cfg, r.width_px, r.height_px, dev, cfg.clock_mhz, 1e3 / std::max(pr.fps, 1e-9));
  const res::Estimate& est = figures.estimate;
  pr.bram18k = est.total.bram18k;
  pr.lut = est.total.lut;
  pr.ff = est.total.ff;
  pr.dsp = est.total.dsp;
  pr.uram = est.total.uram;
  for (const auto& s : est.stages)
    pr.stages.push_back({s.stage, s.usage.bram18k, s.usage.lut, s.usage.ff, s.usage.dsp});
  if (dev != nullptr) {
    const res::Utilisation& u = figures.utilisation;
    pr.bram18k_pct = u.bram18k_pct;
    pr.lut_pct = u.lut_pct;
    pr.ff_pct = u.ff_pct;
    pr.dsp_pct = u.dsp_pct;
    pr.fits = u.fits;
  } else {
    pr.device = r.part + " (not in the device table: no utilisation)";
  }
  // The exported configuration carries the sized depths and the synthesis clock.
  r.config = cfg;
  r.config.clock_mhz = sim_clock;
  return r;
}

}  // namespace parallax::hls_flow
