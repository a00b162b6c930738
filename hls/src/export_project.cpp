// The exported project's README values and its files (export_parts.hpp): the templates filled,
// the unified flow's two configurations, stages.json, design.yaml and the kernels' copies.
#include <cstring>
#include <string>
#include <utility>

#include "embedded.hpp"
#include "export_parts.hpp"
#include "parallax/kernels/frame_buffer.hpp"

namespace parallax::hlsx::detail {

// The README's output ports, kernel headers, provenance and predictions.
void readme_values(const ExportRequest& r, const kern::StereoParams& p, Values& v) {
  const ExportPrediction& pr = r.prediction;
  const bool two_pass = is_two_pass(r.config);
  v["README_OUTPUT_PORTS"] =
      two_pass
          ? "| `disparity` | AXI4 master (m_axi) | " + std::to_string(((kern::disparity_bits(p) + 15) / 16) * 16) +
                " | the map, " + std::to_string(r.width_px) + "x" + std::to_string(r.height_px) +
                " codes in raster order: 0.." + std::to_string(kern::invalid_code(p) - 1) + ", " +
                std::to_string(kern::invalid_code(p)) +
                " = invalid, of the previous call's frame (bundle `gmem_map`) |\n| `frame_write`, `frame_read` | AXI4 "
                "master (m_axi) | " +
                std::to_string(kern::frame_word_bits(p)) + " | two frame buffers of " +
                std::to_string(kern::frame_words(p)) + " words (" + std::to_string(kern::frame_bytes(p)) +
                " bytes) each, pass 1 writes one (bundle `gmem_wr`) while pass 2 reads the other (bundle `gmem_rd`); "
                "the host swaps them between calls; layout in `src/parallax/kernels/frame_buffer.hpp` |\n"
          : "| `disparity_out` | AXI4-Stream | " + v["OUT_BITS"] + " | disparity codes 0.." +
                std::to_string(kern::invalid_code(p) - 1) + ", " + std::to_string(kern::invalid_code(p)) +
                " = invalid; same framing |\n";

  const config::PipelineConfig& c = r.config;
  v["README_MAP_PORTS"] =
      c.rectify != "none" ? "| `map_left_in`, `map_right_in` | AXI4-Stream | 64 | remap tables, one entry per "
                            "output pixel: source x in TDATA[31:0], y in [63:32], signed, " +
                                std::to_string(c.rectify == "bilinear" ? c.rectify_frac_bits : 0) + " fraction bits |\n"
                          : "";
  v["README_RECTIFY"] =
      c.rectify != "none"
          ? "\nThe design rectifies (" + c.rectify + ", " + std::to_string(c.rectify_rows) +
                " line-buffer rows): the pair is the raw camera images, and `tb/map_left.bin`, `tb/map_right.bin` "
                "hold the remap tables (one entry per pixel, two little-endian int32: x, y in the kernels' fixed "
                "point), "
                "fed through `map_left_in` / `map_right_in`.\n"
          : "";
  std::string headers;
  for (const auto& f : detail::copied_files())
    if (std::strncmp(f.name, "src/", 4) == 0) headers += std::string(headers.empty() ? "" : " ") + f.name;
  v["KERNEL_HEADERS"] = headers;

  // README: provenance and predictions.
  v["PAIR_SOURCE"] = r.pair_source;
  v["GOLDEN_SOURCE"] = r.golden_source;
  v["FIRST_PIXEL_CYCLE"] = std::to_string(pr.first_pixel_cycle);
  v["LAST_PIXEL_CYCLE"] = std::to_string(pr.last_pixel_cycle);
  v["FPGA_LATENCY_MS"] = fixed(pr.fpga_latency_ms, 2);
  v["CYCLES_PER_FRAME"] = std::to_string(pr.cycles_per_frame);
  v["BOTTLENECK"] = pr.bottleneck.empty() ? "-" : pr.bottleneck;
  v["FPS"] = fixed(pr.fps, 1);
  v["DEVICE"] = pr.device;
  v["ESTIMATE"] = r.config.estimate;
  v["ESTIMATE_MEANING"] = r.config.estimate == "routed" ? "after place and route, csynth x documented ratios"
                                                        : "what Vitis HLS C synthesis reports";
  std::string rows;
  for (const auto& s : pr.stages)
    rows += "| " + s.name + " | " + std::to_string(s.bram18k) + " | " + std::to_string(s.lut) + " | " +
            std::to_string(s.ff) + " | " + std::to_string(s.dsp) + " |\n";
  v["RESOURCE_ROWS"] = rows;
  v["BRAM"] = std::to_string(pr.bram18k);
  v["LUT"] = std::to_string(pr.lut);
  v["FF"] = std::to_string(pr.ff);
  v["DSP"] = std::to_string(pr.dsp);
  v["BRAM_PCT"] = fixed(pr.bram18k_pct, 1);
  v["LUT_PCT"] = fixed(pr.lut_pct, 1);
  v["FF_PCT"] = fixed(pr.ff_pct, 1);
  v["DSP_PCT"] = fixed(pr.dsp_pct, 1);
  v["FITS"] = pr.fits ? "yes" : "no";
}

// The two configurations of the unified flow set their own values.
std::vector<GeneratedFile> project_files(const ExportRequest& r, Values& v) {
  const config::PipelineConfig& c = r.config;
  std::vector<GeneratedFile> files;
  auto add = [&](const std::string& path, const std::string& tmpl) {
    files.push_back({path, fill(tmpl, template_text(tmpl), v), false});
  };
  add("src/parallax_config.hpp", "parallax_config.hpp");
  add("src/parallax_top.hpp", "parallax_top.hpp");
  add("src/parallax_top.cpp", "parallax_top.cpp");
  add("tb/parallax_tb.cpp", "parallax_tb.cpp");
  add("Makefile", "Makefile");
  add("run_hls.tcl", "run_hls.tcl");
  // The unified flow's configurations: the full frame, and the reduced frame of C/RTL
  // co-simulation (a component of its own: the frame's size is compile-time).
  const std::string id = identifier(c.name);
  v["CFG_HEADER"] = "# Design " + c.name +
                    ", exported by `parallax export-hls`, for the Vitis unified flow (2023.2 and later;\n"
                    "# the only one from 2025.1), the full frame (`make vitis FLOW=vpp` runs these):\n"
                    "#   vitis-run --mode hls --csim --config hls_config.cfg --work_dir parallax_" +
                    id +
                    "\n"
                    "#   v++ -c --mode hls --config hls_config.cfg --work_dir parallax_" +
                    id +
                    "\n"
                    "#   vitis-run --mode hls --cosim --config hls_config.cfg --work_dir parallax_" +
                    id +
                    "   (COSIM_FULL=1 only)\n"
                    "#   vitis-run --mode hls --package --config hls_config.cfg --work_dir parallax_" +
                    id +
                    "\n"
                    "# C/RTL co-simulation runs by default on the reduced frame, a component of its own synthesised\n"
                    "# with -DPARALLAX_REDUCED_FRAME: hls_config_reduced.cfg.\n";
  v["CFG_DEFINES"] = "";
  v["CFG_GOLDEN"] = "golden_disparity.pgm";
  add("hls_config.cfg", "hls_config.cfg");
  v["CFG_HEADER"] = "# Design " + c.name +
                    ", exported by `parallax export-hls`: the reduced frame of C/RTL co-simulation,\n"
                    "# the pair's first " +
                    v["REDUCED_HEIGHT"] +
                    " rows at the full width (-DPARALLAX_REDUCED_FRAME; the frame's size is\n"
                    "# compile-time, so this is a component of its own), checked bit for bit against\n"
                    "# tb/golden_disparity_reduced.pgm (`make vitis FLOW=vpp` runs these):\n"
                    "#   v++ -c --mode hls --config hls_config_reduced.cfg --work_dir parallax_" +
                    id +
                    "_reduced\n"
                    "#   vitis-run --mode hls --cosim --config hls_config_reduced.cfg --work_dir parallax_" +
                    id + "_reduced\n";
  v["CFG_DEFINES"] = " -DPARALLAX_REDUCED_FRAME";
  v["CFG_GOLDEN"] = "golden_disparity_reduced.pgm";
  add("hls_config_reduced.cfg", "hls_config.cfg");
  add("README.md", "README.md");
  {
    // stages.json: one entry per stage of the cycle model, its II and pipeline depth at the
    // export's clock (the same as `parallax sim --json` stages[].ii_cycles / latency_cycles).
    std::string js = "[\n";
    for (std::size_t i = 0; i < r.stage_timing.size(); ++i) {
      const auto& t = r.stage_timing[i];
      js += "  {\"name\": \"" + t.name + "\", \"ii_cycles\": " + std::to_string(t.ii_cycles) +
            ", \"depth_cycles\": " + std::to_string(t.depth_cycles) + "}" +
            (i + 1 < r.stage_timing.size() ? ",\n" : "\n");
    }
    files.push_back({"stages.json", js + "]\n", false});
  }
  files.push_back(
      {"design.yaml", "# Exported by parallax export-hls from " + r.origin + "\n" + config::to_yaml(c), false});
  for (const auto& f : detail::copied_files()) files.push_back({f.name, *f.text, false});
  for (auto& f : testbench_files(r)) files.push_back(std::move(f));
  return files;
}

}  // namespace parallax::hlsx::detail
