// The JSON forms of the result types (json.hpp).
#include "parallax/design/json.hpp"

namespace parallax {
namespace res {

void to_json(nlohmann::json& j, const Usage& u) {
  j = {{"bram18k", u.bram18k}, {"uram", u.uram}, {"dsp", u.dsp}, {"ff", u.ff}, {"lut", u.lut}};
}

}  // namespace res

namespace design {

void to_json(nlohmann::json& j, const ResourceFigures& r) {
  j = r.estimate.total;
  if (r.utilisation.device != nullptr) j["device"] = r.utilisation.device->name;
  j["estimate"] = res::flavour_name(r.estimate.flavour);
  j["fits_device"] = r.utilisation.fits;
  j["utilisation_pct"] = {{"bram18k", r.utilisation.bram18k_pct},
                          {"uram", r.utilisation.uram_pct},
                          {"lut", r.utilisation.lut_pct},
                          {"ff", r.utilisation.ff_pct},
                          {"dsp", r.utilisation.dsp_pct}};
  j["resource_stages"] = nlohmann::json::array();
  for (const auto& s : r.estimate.stages)
    j["resource_stages"].push_back({{"stage", s.stage},
                                    {"bram18k", s.usage.bram18k},
                                    {"lut", s.usage.lut},
                                    {"ff", s.usage.ff},
                                    {"dsp", s.usage.dsp},
                                    {"lutram_luts", s.usage.lutram_luts},
                                    {"srl_luts", s.usage.srl_luts}});
  j["power_estimate_w"] = {{"static", r.power.static_w}, {"dynamic", r.power.dynamic_w}, {"total", r.power.total_w}};
  j["energy_estimate_mj_per_frame"] = r.power.energy_mj_per_frame;
}

}  // namespace design

namespace eval {

void to_json(nlohmann::json& j, const SimulationResult& t) {
  const sim::CycleReport& c = t.cycle;
  j = nlohmann::json::object();
  j["clock_mhz"] = t.clock_mhz;
  j["cycles_per_frame"] = c.cycles_per_frame;
  j["first_pixel_cycle"] = c.first_pixel_cycle;
  j["last_pixel_cycle"] = c.last_pixel_cycle;
  j["first_pixel_latency_ms"] = t.fpga_first_pixel_ms;
  j["last_pixel_latency_ms"] = t.fpga_last_pixel_ms;
  j["host_copy_in_ms"] = t.copy_in_ms;
  j["host_copy_out_ms"] = t.copy_out_ms;
  j["latency_ms"] = t.latency_ms;
  j["frame_interval_ms"] = t.frame_interval_ms;
  j["fps"] = t.fps;
  j["interval_limit"] = t.interval_limit;
  j["bottleneck"] = c.bottleneck;
  j["rows_fast_forwarded"] = c.rows_fast_forwarded;
  if (c.ddr_word_bits > 0) j["first_pass_rows_fast_forwarded"] = c.first_pass_rows_fast_forwarded;
  j["input_period_cycles"] = c.input_period_cycles;
  if (c.ddr_word_bits > 0)  // two passes: the frame buffer's and the map's traffic per frame
    j["ddr"] = {
        {"word_bits", c.ddr_word_bits},
        {"frame_bytes_written", c.ddr_bytes_written},
        {"frame_bytes_read", c.ddr_bytes_read},
        {"map_bytes_written", c.map_bytes_written},
        {"gbytes_per_s_at_fps", double(c.ddr_bytes_written + c.ddr_bytes_read + c.map_bytes_written) * t.fps / 1e9}};
  if (t.unbounded_last_pixel_cycle >= 0) j["unbounded_fifos_last_pixel_cycle"] = t.unbounded_last_pixel_cycle;
  j["stages"] = nlohmann::json::array();
  for (const auto& s : c.stages)
    j["stages"].push_back({{"name", s.name},
                           {"ii_cycles", s.ii_cycles},
                           {"latency_cycles", s.latency_cycles},
                           {"fires", s.fires},
                           {"busy_cycles", s.busy_cycles},
                           {"input_stall_cycles", s.input_stall_cycles},
                           {"output_stall_cycles", s.output_stall_cycles},
                           {"first_fire_cycle", s.first_fire_cycle},
                           {"last_fire_cycle", s.last_fire_cycle}});
  j["fifos"] = nlohmann::json::array();
  for (const auto& f : c.fifos) {
    nlohmann::json fj = {{"name", f.name},   {"producer", f.producer}, {"consumer", f.consumer},
                         {"depth", f.depth}, {"tokens", f.tokens},     {"high_water", f.high_water}};
    if (t.stall_free_depths.count(f.name)) fj["stall_free_depth"] = t.stall_free_depths.at(f.name);
    j["fifos"].push_back(fj);
  }
}

}  // namespace eval
}  // namespace parallax
