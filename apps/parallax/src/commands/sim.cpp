// parallax sim: one frame through the cycle model: latency, frame rate, stalls, FIFO depths,
// resources and power; optionally calibrated to measured figures, a VCD trace and an HTML page.
// A deadlock of the cycle model exits with kExitDeadlock (3).
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "parallax/design/json.hpp"
#include "parallax/design/result.hpp"
#include "parallax/eval/disparity_io.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/eval/simulate.hpp"
#include "parallax/reports/report.hpp"
#include "parallax/eval/evaluate.hpp"
#include "parallax/resources/model.hpp"
#include "parallax/sim/accesses.hpp"
#include "parallax/sim/schedule.hpp"

namespace parallax::cli {

namespace {

using nlohmann::json;
using namespace parallax::eval;
using namespace parallax::design;
using namespace parallax::search;
using namespace parallax::hls_flow;
using namespace parallax::reports;

struct SimOptions {
  ConfigArgs cfg;
  std::string left, right, out, vcd, vcd_cycles, write_config, html, accesses, device = "XCZU3EG";
  int clock_mhz = 0, threads = 0;
  bool json = false, no_sizing = false, coupled = false, every_firing = false;
  double cal_latency = 0, cal_fps = 0;
};

// Resources, utilisation and power of a design at its processed size: the resource part of the
// one evaluation (explore/design).
using ResourceReport = ResourceFigures;

// The resource report as a table on stdout: per stage, total, the device, utilisation, fit, power.
void print_resources(const ResourceReport& r) {
  const res::Usage& u = r.estimate.total;
  const res::Device& d = *r.utilisation.device;
  std::printf("\nresources (estimate: %-6s) %-8s %8s %8s %8s %8s\n", res::flavour_name(r.estimate.flavour), "BRAM_18K",
              "LUT", "FF", "DSP", "URAM");
  for (const auto& s : r.estimate.stages)
    std::printf("  %-19s %8lld %8lld %8lld %8lld %8lld\n", s.stage.c_str(), (long long)s.usage.bram18k,
                (long long)s.usage.lut, (long long)s.usage.ff, (long long)s.usage.dsp, (long long)s.usage.uram);
  std::printf("  %-19s %8lld %8lld %8lld %8lld %8lld\n", "total", (long long)u.bram18k, (long long)u.lut,
              (long long)u.ff, (long long)u.dsp, (long long)u.uram);
  std::printf("  %-19s %8lld %8lld %8lld %8lld %8lld\n", d.name.c_str(), (long long)d.bram18k, (long long)d.lut,
              (long long)d.ff, (long long)d.dsp, (long long)d.uram);
  std::printf("  %-19s %7.1f%% %7.1f%% %7.1f%% %7.1f%% %7.1f%%\n", "utilisation", r.utilisation.bram18k_pct,
              r.utilisation.lut_pct, r.utilisation.ff_pct, r.utilisation.dsp_pct, r.utilisation.uram_pct);
  std::printf("fits %s: %s\n", d.name.c_str(), r.utilisation.fits ? "yes" : "no");
  std::printf("power (estimate)     %.2f W static + %.2f W dynamic = %.2f W; %.1f mJ per frame\n", r.power.static_w,
              r.power.dynamic_w, r.power.total_w, r.power.energy_mj_per_frame);
}

// What sets each kernel stage's II (sim/schedule.hpp), at the design's own (synthesis) clock.
std::map<std::string, std::string> ii_reasons(const config::PipelineConfig& cfg, int w, int h) {
  std::map<std::string, std::string> out;
  const kern::RectifyParams rect = cfg.rectify_params(w, h);
  for (const auto& s : sim::stage_schedules(cfg.stereo_params(w, h), rect, double(cfg.clock_mhz) * 1e6))
    out[s.stage] = "II " + std::to_string(s.ii) + ": " + s.limit;
  return out;
}

// --vcd-cycles A:B into [from, to); the default window 0:20000 when empty. Throws InputError
// unless 0 <= A < B.
void parse_vcd_cycles(const std::string& text, int64_t& from, int64_t& to) {
  from = 0;
  to = 20000;
  if (text.empty()) return;
  const auto colon = text.find(':');
  try {
    if (colon == std::string::npos) throw std::invalid_argument("no colon");
    from = std::stoll(text.substr(0, colon));
    to = std::stoll(text.substr(colon + 1));
  } catch (const std::exception&) {
    throw InputError("--vcd-cycles '" + text + "': expected A:B, two cycle numbers");
  }
  if (from < 0 || to <= from) throw InputError("--vcd-cycles: need 0 <= A < B");
}

// The simulation of `cfg` on the pair `l` at `clock` MHz as one JSON object: the timing's and the
// resources' own forms (parallax/design/json.hpp) with the design, the size and what sets each II.
json sim_json(const config::PipelineConfig& cfg, int clock, const cv::Mat& l, const SimulationResult& result,
              const ResourceReport& rr) {
  json j = result;
  j.update(json(rr));
  j["config"] = cfg.name;
  j["clock_mhz"] = clock;
  j["width_px"] = l.cols;
  j["height_px"] = l.rows;
  j["host_latency_ms"] = cfg.host_latency_ms;
  if (cfg.rectify != "none") j["rectify_window_misses"] = result.cycle.rectify_window_misses;
  if (j.contains("ddr")) j["ddr"]["ddr_gbps"] = cfg.ddr_gbps;
  const std::map<std::string, std::string> why = ii_reasons(cfg, l.cols, l.rows);
  for (auto& sj : j["stages"])
    if (why.count(sj["name"].get<std::string>())) sj["ii_limit"] = why.at(sj["name"].get<std::string>());
  return j;
}

// The headline figures of a simulation: cycles, latency, frame interval, DDR traffic.
void print_sim_summary(const config::PipelineConfig& cfg, int clock, const cv::Mat& l, const SimulationResult& result) {
  const auto& c = result.cycle;
  std::printf("%s at %d MHz, %dx%d, D=%d, PU=%d\n", cfg.name.c_str(), clock, l.cols, l.rows, cfg.disparities,
              cfg.parallel_units);
  std::printf("cycles per frame   %lld (bottleneck: %s)\n", (long long)c.cycles_per_frame, c.bottleneck.c_str());
  std::printf("first pixel        cycle %lld (%.3f ms)\n", (long long)c.first_pixel_cycle, result.fpga_first_pixel_ms);
  std::printf("last pixel         cycle %lld (%.3f ms)\n", (long long)c.last_pixel_cycle, result.fpga_last_pixel_ms);
  std::printf("latency_ms         %.3f (host copies %.3f + %.3f, host %.3f)\n", result.latency_ms, result.copy_in_ms,
              result.copy_out_ms, cfg.host_latency_ms);
  std::printf("frame_interval_ms  %.3f (%s)\nfps                %.2f\n", result.frame_interval_ms,
              result.interval_limit.c_str(), result.fps);
  if (c.ddr_word_bits > 0)
    std::printf(
        "ddr per frame      %lld B written + %lld B read (frame buffer, %d-bit words), map %lld B; "
        "%.2f GB/s at %.2f fps (ddr_gbps %.2f)\n",
        (long long)c.ddr_bytes_written, (long long)c.ddr_bytes_read, c.ddr_word_bits, (long long)c.map_bytes_written,
        double(c.ddr_bytes_written + c.ddr_bytes_read + c.map_bytes_written) * result.fps / 1e9, result.fps,
        cfg.ddr_gbps);
}

// The simulation as text on stdout: the summary, the stages and what sets their II, the FIFOs,
// and the resource report.
void print_sim_text(const config::PipelineConfig& cfg, int clock, const cv::Mat& l, const SimulationResult& result,
                    const ResourceReport& rr) {
  const auto& c = result.cycle;
  print_sim_summary(cfg, clock, l, result);
  std::printf("\n");
  std::printf("%-15s %4s %4s %10s %12s %12s %12s %12s %12s\n", "stage", "II", "lat", "fires", "busy", "in_stall",
              "out_stall", "first_fire", "last_fire");
  for (const auto& s : c.stages)
    std::printf("%-15s %4d %4d %10lld %12lld %12lld %12lld %12lld %12lld\n", s.name.c_str(), s.ii_cycles,
                s.latency_cycles, (long long)s.fires, (long long)s.busy_cycles, (long long)s.input_stall_cycles,
                (long long)s.output_stall_cycles, (long long)s.first_fire_cycle, (long long)s.last_fire_cycle);
  std::printf(
      "\nII derived from the kernels' counted accesses and declared recurrences at the design's %d MHz "
      "(docs/hls.md):\n",
      cfg.clock_mhz);
  for (const auto& kv : ii_reasons(cfg, l.cols, l.rows))
    std::printf("  %-13s %s\n", kv.first.c_str(), kv.second.c_str());
  if (c.rows_fast_forwarded > 0)
    std::printf("\n%lld of %d output rows repeated the previous rows' schedule exactly and were applied at once\n",
                (long long)c.rows_fast_forwarded, l.rows);
  if (c.first_pass_rows_fast_forwarded > 0)
    std::printf("%lld of %d rows of the first pass (to the frame buffer) likewise\n",
                (long long)c.first_pass_rows_fast_forwarded, l.rows);
  if (result.unbounded_last_pixel_cycle >= 0)
    std::printf(
        "\nwith unbounded FIFOs the last pixel leaves at cycle %lld (%+lld cycles); stall_free = depth at which\n"
        "no producer ever waits (behind a faster producer: its whole backlog, harmless back-pressure)\n",
        (long long)result.unbounded_last_pixel_cycle,
        (long long)(result.unbounded_last_pixel_cycle - c.last_pixel_cycle));
  std::printf("\n%-15s %-15s %-15s %7s %10s %10s %12s\n", "fifo", "producer", "consumer", "depth", "tokens",
              "high_water", "stall_free");
  for (const auto& f : c.fifos) {
    const auto it = result.stall_free_depths.find(f.name);
    std::printf("%-15s %-15s %-15s %7lld %10lld %10lld %12s\n", f.name.c_str(), f.producer.c_str(), f.consumer.c_str(),
                (long long)f.depth, (long long)f.tokens, (long long)f.high_water,
                it == result.stall_free_depths.end() ? "-" : std::to_string(it->second).c_str());
  }
  print_resources(rr);
}

// The --html page: the design, the pair, its cycle-run disparity, timing, FIFOs and resources.
void write_sim_page(const SimOptions& o, const Invocation& inv, const config::PipelineConfig& cfg, int clock,
                    const cv::Mat& l, const SimulationResult& result, const ResourceReport& rr,
                    const res::Device* device) {
  DesignSection s;
  s.title = cfg.name + " at " + std::to_string(clock) + " MHz" + (o.left.empty() ? " (test pattern)" : " on " + o.left);
  s.config_yaml = config::to_yaml(cfg);
  s.command = command_line(inv);
  s.left_grey = l.clone();
  const DisparityMap d = to_disparity_map(result.cycle.codes);
  s.disparity_colour = colourize_disparity(d.disparity_px, d.valid_mask, double(cfg.disparity_end_px()));
  s.metrics = {{"latency_ms", result.latency_ms},
               {"frame_interval_ms", result.frame_interval_ms},
               {"fps", result.fps},
               {"cycles_per_frame", double(result.cycle.cycles_per_frame)},
               {"bram18k", double(rr.estimate.total.bram18k)},
               {"lut", double(rr.estimate.total.lut)},
               {"ff", double(rr.estimate.total.ff)},
               {"dsp", double(rr.estimate.total.dsp)},
               {"fits_device", rr.utilisation.fits ? 1.0 : 0.0},
               {"power_w", rr.power.total_w},
               {"energy_mj_per_frame", rr.power.energy_mj_per_frame}};
  s.cycle = result.cycle;
  s.resources = rr.estimate;
  s.device = device;
  write_text_file(o.html, standalone_page("Parallax: " + s.title, design_section_html(s)));
}

// After a run without deadlock: calibration, --write-config, --out, the notes, the page and the
// answer on stdout.
int finish_sim(const SimOptions& o, const Invocation& inv, config::PipelineConfig& cfg, int clock, const cv::Mat& l,
               SimulationResult& result, const res::Device* device, std::vector<std::string>& notes) {
  if (!result.cycle.input_overrun.empty()) notes.push_back(result.cycle.input_overrun);
  if (result.cycle.rectify_window_misses > 0)
    notes.push_back("rectification: " + std::to_string(result.cycle.rectify_window_misses) +
                    " map taps fell outside the line buffer's rows (read as 0); raise rectify_rows");
  std::string calibration;
  if (o.cal_latency > 0 || o.cal_fps > 0) {
    if (o.cal_latency <= 0) throw InputError("--calibrate-fps needs --calibrate-latency-ms too");
    calibration = calibrate(cfg, result, o.cal_latency, o.cal_fps);
    system_figures(cfg, result);  // the cycles do not change, only the host model
    notes.push_back("calibrated at " + std::to_string(clock) + " MHz: " + calibration);
  }
  if (!o.write_config.empty()) {
    cfg.clock_mhz = clock;
    std::ofstream(o.write_config) << "# written by parallax sim"
                                  << (calibration.empty() ? "" : " (calibrated: " + calibration + ")") << "\n"
                                  << config::to_yaml(cfg);
  }
  if (!o.out.empty()) {
    const DisparityMap d = to_disparity_map(result.cycle.codes);
    write_kitti_disparity(o.out, d.disparity_px, d.valid_mask);
  }
  print_notes(notes);
  const ResourceReport rr = resource_figures(cfg, l.cols, l.rows, device, clock, result.frame_interval_ms);
  if (!o.html.empty()) write_sim_page(o, inv, cfg, clock, l, result, rr, device);
  if (o.json)
    std::cout << sim_json(cfg, clock, l, result, rr).dump(2) << "\n";
  else
    print_sim_text(cfg, clock, l, result, rr);
  return 0;
}

// csim_accesses.json as Markdown (docs/hls.md's per-stage tables): per stage its declared II,
// then one row per counted memory and per recurrence.
std::string accesses_markdown(const std::string& text) {
  const json j = json::parse(text);
  std::string o = "Design `" + j.at("design").get<std::string>() + "`:\n\n" +
                  "| stage | II declared (forced) | firings | memory or recurrence | kind, banks, ports per bank | "
                  "largest reads + writes per bank and firing, or chain and delay | sites banked at run time | "
                  "II forced |\n|---|---|---|---|---|---|---|---|\n";
  char buf[256];
  for (const auto& s : j.at("stages")) {
    std::snprintf(buf, sizeof buf, "| %s | %d (%d) | %lld |", s.at("name").get<std::string>().c_str(),
                  s.at("ii_declared").get<int>(), s.at("ii_forced").get<int>(), s.at("firings").get<long long>());
    const std::string head = buf;
    bool first = true;
    for (const auto& m : s.at("memories")) {
      const int rp = m.at("read_ports").get<int>(), wp = m.at("write_ports").get<int>();
      std::snprintf(
          buf, sizeof buf, " %s | %s, %d, %s | %d + %d | %d (widest %d) | %d |\n",
          m.at("name").get<std::string>().c_str(), m.at("kind").get<std::string>().c_str(), m.at("banks").get<int>(),
          rp == 0 ? "any" : (std::to_string(rp) + "R " + std::to_string(wp) + "W").c_str(),
          m.at("max_reads_per_bank_per_firing").get<int>(), m.at("max_writes_per_bank_per_firing").get<int>(),
          m.at("runtime_banked_sites").get<int>(), m.at("max_banks_per_site").get<int>(), m.at("ii_forced").get<int>());
      o += (first ? head : std::string("| | | |")) + buf;
      first = false;
    }
    for (const auto& r : s.at("recurrences")) {
      std::string ops;
      for (const auto& op : r.at("operators")) ops += (ops.empty() ? "" : ", ") + op.get<std::string>();
      std::snprintf(buf, sizeof buf, " recurrence %s | distance %d | %.2f ns over %d firing(s) of %.2f ns: ",
                    r.at("name").get<std::string>().c_str(), r.at("distance").get<int>(),
                    r.at("delay_ns").get<double>(), r.at("distance").get<int>(), r.at("budget_ns").get<double>());
      o += (first ? head : std::string("| | | |")) + buf + ops + " | | " +
           std::to_string(r.at("ii_forced").get<int>()) + " |\n";
      first = false;
    }
    if (first) o += head + " (none counted) | | | | |\n";
  }
  return o;
}

// --accesses FILE: the counting run on the same pair (sim/accesses.hpp), csim_accesses.json, or
// its Markdown tables when FILE ends in .md.
void write_accesses(const std::string& path, const config::PipelineConfig& cfg, int clock, const cv::Mat& l,
                    const cv::Mat& r) {
  std::fprintf(stderr, "parallax: counting every kernel array's accesses per firing (%dx%d)...\n", l.cols, l.rows);
  sim::AccessRunOptions ao;
  ao.design = cfg.name;
  ao.clock_hz = clock * 1e6;
  ao.rectify = cfg.rectify_params(l.cols, l.rows);
  const std::string text =
      sim::count_accesses_json(to_grey_image(l), to_grey_image(r), cfg.stereo_params(l.cols, l.rows), ao);
  const bool markdown = path.size() > 3 && path.compare(path.size() - 3, 3, ".md") == 0;
  write_text_file(path, markdown ? accesses_markdown(text) : text);
}

int run_sim(const SimOptions& o, const Invocation& inv) {
  config::PipelineConfig cfg = load_config_args(o.cfg);
  const int clock = o.clock_mhz > 0 ? o.clock_mhz : cfg.clock_mhz;
  const res::Device* device = res::find_device(o.device);
  if (!device) throw InputError("--device '" + o.device + "': unknown device; known: " + res::device_names());
  cv::Mat l, r;
  std::vector<std::string> notes;
  std::string pair_what;
  load_pair_or_pattern(cfg, o.left, o.right, notes, l, r, pair_what);
  SimulateOptions so;
  parse_vcd_cycles(o.vcd_cycles, so.vcd_from, so.vcd_to);
  so.clock_mhz = clock;
  so.size_fifos = !o.no_sizing;
  so.coupled = o.coupled;
  so.fast_forward = !o.every_firing;
  so.threads = o.threads;
  so.vcd_path = o.vcd;
  SimulationResult result = simulate(cfg, l, r, so);
  if (!o.accesses.empty()) write_accesses(o.accesses, cfg, clock, l, r);
  if (result.cycle.deadlock) {
    std::fprintf(stderr, "parallax: error: %s\n", result.cycle.deadlock_message.c_str());
    return kExitDeadlock;
  }
  return finish_sim(o, inv, cfg, clock, l, result, device, notes);
}

}  // namespace

Command add_sim(CLI::App& app) {
  auto o = std::make_shared<SimOptions>();
  auto* simc =
      app.add_subcommand("sim", "Cycle-level simulation of one frame: latency, frame rate, stalls, FIFO depths");
  add_config_options(simc, o->cfg, true);
  add_engine_option(simc);
  simc->add_option("--left", o->left, "Left image (default: a generated test pattern of the ROI size)");
  simc->add_option("--right", o->right, "Right image");
  simc->add_option("--out", o->out, "Write the disparity (KITTI 16-bit PNG) of the cycle run")
      ->check(OutputFile(".png"));
  simc->add_option("--clock-mhz", o->clock_mhz, "Processing clock in MHz (default: the config's clock_mhz)")
      ->check(InRange(1, 2000));
  simc->add_flag("--json", o->json, "Print JSON");
  simc->add_option("--accesses", o->accesses,
                   "Also count every kernel array's reads and writes per bank and firing on the pair and write the "
                   "report (csim_accesses.json, docs/hls.md) here; a FILE ending in .md gets Markdown tables")
      ->check(OutputFile());
  simc->add_flag("--no-sizing", o->no_sizing, "Skip the second run that finds stall-free FIFO depths");
  simc->add_flag("--coupled", o->coupled,
                 "Fire the kernels' datapath inside the schedule at the design's PU (slower; same report and "
                 "output, which by default come from the control-path schedule and the func run)");
  simc->add_option("--html", o->html,
                   "Write a self-contained HTML page of this design (timing, FIFOs, resources, images)")
      ->check(OutputFile());
  simc->add_option("--device", o->device, "Device for utilisation and fit (" + res::device_names() + ")")
      ->capture_default_str();
  simc->add_option("--threads", o->threads,
                   "2: the schedule and the func run of the codes side by side, 1: one after the other (same "
                   "report; default 2 where the machine has two hardware threads)")
      ->check(InRange(1, 2));
  simc->add_flag("--every-firing", o->every_firing,
                 "Simulate every firing instead of applying rows that repeat exactly at once (same report, slower)");
  simc->add_option("--vcd", o->vcd, "Write FIFO occupancies and stage valid/stall signals as VCD (GTKWave)")
      ->check(OutputFile());
  simc->add_option("--vcd-cycles", o->vcd_cycles, "Cycle window A:B of the VCD (default 0:20000)");
  simc->add_option("--calibrate-latency-ms", o->cal_latency,
                   "Measured latency at this clock: set host_latency_ms to match")
      ->check(InRange(0.001, 1e6));
  simc->add_option("--calibrate-fps", o->cal_fps, "Measured frame rate at this clock: set host_frame_ms to match")
      ->check(InRange(0.001, 1e6));
  simc->add_option("--write-config", o->write_config, "Write the (calibrated) configuration here")->check(OutputFile());
  return bind_command(simc, o, run_sim);
}

}  // namespace parallax::cli
