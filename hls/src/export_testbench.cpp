// The exported testbench's values and data (export_parts.hpp): the remap tables' loading and
// feeding when the design rectifies, the pair, the golden maps and the tables as files.
#include <string>

#include "export_parts.hpp"

namespace parallax::hlsx::detail {

namespace {

std::string pgm(int width_px, int height_px, int maxval, const uint16_t* px16, const uint8_t* px8) {
  std::string out =
      "P5\n" + std::to_string(width_px) + " " + std::to_string(height_px) + "\n" + std::to_string(maxval) + "\n";
  const std::size_t n = std::size_t(width_px) * std::size_t(height_px);
  out.reserve(out.size() + n * (maxval >= 256 ? 2 : 1));
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned v = px16 ? px16[i] : px8[i];
    if (maxval >= 256) out += char((v >> 8) & 0xFFu);
    out += char(v & 0xFFu);
  }
  return out;
}

}  // namespace

void testbench_values(const config::PipelineConfig& c, Values& v) {
  const bool rectify = c.rectify != "none";
  v["TB_MAP_FUNCTIONS"] = rectify ? template_text("tb_map_functions.cpp") : "";
  v["TB_MAP_LOAD"] = rectify ? fragment("tb_map_load", {}) : "";
  v["TB_MAP_FEED"] = rectify ? fragment("tb_map_feed", {}) : "";
  v["TB_MAP_ARGS"] = rectify ? fragment("map_args", {}) : "";
  v["CFG_MAP_FILES"] = rectify ? "tb.file=tb/map_left.bin\ntb.file=tb/map_right.bin\n" : "";
  v["TCL_MAP_FILES"] = rectify ? "  add_files -tb tb/map_left.bin\n  add_files -tb tb/map_right.bin\n" : "";
}

std::vector<GeneratedFile> testbench_files(const ExportRequest& r) {
  const config::PipelineConfig& c = r.config;
  std::vector<GeneratedFile> files;
  files.push_back({"tb/left.pgm", pgm(r.width_px, r.height_px, 255, nullptr, r.left.data()), true});
  files.push_back({"tb/right.pgm", pgm(r.width_px, r.height_px, 255, nullptr, r.right.data()), true});
  files.push_back({"tb/golden_disparity.pgm",
                   pgm(r.width_px, r.height_px, c.disparities << c.subpixel_bits, r.golden.data(), nullptr), true});
  files.push_back(
      {"tb/golden_disparity_reduced.pgm",
       pgm(r.width_px, r.reduced_height_px, c.disparities << c.subpixel_bits, r.reduced_golden.data(), nullptr), true});
  if (c.rectify != "none") {
    auto table = [](const std::vector<kern::MapEntry>& m) {
      std::string out;
      out.reserve(m.size() * 8);
      for (const auto& e : m)
        for (int32_t v32 : {e.x, e.y})
          for (int b = 0; b < 4; ++b) out += char((uint32_t(v32) >> (8 * b)) & 0xFFu);
      return out;
    };
    files.push_back({"tb/map_left.bin", table(r.map_left), true});
    files.push_back({"tb/map_right.bin", table(r.map_right), true});
  }
  return files;
}

}  // namespace parallax::hlsx::detail
