// The HLS export: fills the templates of hls/templates/ for one design and copies the kernels.
#include "parallax/hls/export.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "embedded.hpp"
#include "export_loops.hpp"
#include "parallax/kernels/frame_buffer.hpp"
#include "parallax/kernels/params.hpp"
#include "parallax/kernels/pipeline.hpp"
#include "parallax/kernels/sgm.hpp"
#include "parallax/resources/model.hpp"

namespace parallax::hlsx {
namespace {

namespace fs = std::filesystem;

constexpr int kTestbenchFrames = 2;
constexpr int kReducedRows = 16;  // rows of the reduced frame of C/RTL co-simulation
constexpr const char* kMarker = ".parallax-export";

// Replaces every @KEY@ (KEY: upper-case letters, digits, '_', starting with a letter) by its
// value. A key without a value is a defect of the generator, reported with the template's name.
std::string fill(const std::string& name, const std::string& text, const std::map<std::string, std::string>& values) {
  std::string out;
  out.reserve(text.size() + 1024);
  std::size_t i = 0;
  while (i < text.size()) {
    if (text[i] == '@' && i + 1 < text.size() && std::isupper(static_cast<unsigned char>(text[i + 1]))) {
      std::size_t j = i + 1;
      while (j < text.size() && (std::isupper(static_cast<unsigned char>(text[j])) ||
                                 std::isdigit(static_cast<unsigned char>(text[j])) || text[j] == '_'))
        ++j;
      if (j < text.size() && text[j] == '@') {
        const std::string key = text.substr(i + 1, j - i - 1);
        const auto it = values.find(key);
        if (it == values.end())
          throw std::logic_error("hls export: template " + name + " uses @" + key + "@, which has no value");
        out += it->second;
        i = j + 1;
        continue;
      }
    }
    out += text[i++];
  }
  return out;
}

// The text of an embedded template (a handful of small files: a linear search).
std::string template_text(const std::string& name) {
  for (const auto& t : detail::templates())
    if (name == t.name) return *t.text;
  throw std::logic_error("hls export: no template " + name);
}

std::string identifier(const std::string& s) {
  std::string out;
  for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  if (out.empty() || std::isdigit(static_cast<unsigned char>(out[0]))) out = "d_" + out;
  return out;
}

// left_px -> kDepthLeftPx
std::string depth_constant(const std::string& fifo) {
  std::string out = "kDepth";
  bool upper = true;
  for (char c : fifo) {
    if (c == '_') {
      upper = true;
      continue;
    }
    out += upper ? char(std::toupper(static_cast<unsigned char>(c))) : c;
    upper = false;
  }
  return out;
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

// The storage a memory of the resource model maps to, as a BIND_STORAGE impl of a RAM / a FIFO.
std::string ram_impl(res::Storage s) {
  return s == res::Storage::bram ? "bram" : "lutram";
}
std::string fifo_impl(res::Storage s) {
  switch (s) {
    case res::Storage::bram:
      return "bram";
    case res::Storage::lutram:
      return "lutram";
    default:
      return "srl";
  }
}

const res::MemoryItem* find_memory(const res::Inventory& inv, const std::string& stage, const std::string& name) {
  for (const auto& m : inv.memories)
    if (m.stage == stage && m.name == name) return &m;
  return nullptr;
}

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

void check_request(const ExportRequest& r) {
  const auto errors = config::validate(r.config);
  if (!errors.empty())
    throw ExportError("design '" + r.config.name + "': field '" + errors.front().field +
                      "': " + errors.front().message);
  const std::size_t n = std::size_t(r.width_px) * std::size_t(r.height_px);
  if (r.width_px < 1 || r.height_px < 1) throw ExportError("export: the design's size is empty");
  if (r.left.size() != n || r.right.size() != n || r.golden.size() != n)
    throw ExportError("export: the testbench pair and golden output must all be " + std::to_string(r.width_px) + "x" +
                      std::to_string(r.height_px));
  std::set<std::string> names;
  for (const auto& f : r.fifos) {
    if (f.depth < 1) throw ExportError("export: FIFO " + f.name + " needs a depth of at least 1");
    names.insert(f.name);
  }
  const auto want = export_fifo_names(r.config);
  if (names != std::set<std::string>(want.begin(), want.end()) || r.fifos.size() != want.size())
    throw ExportError("export: one depth per FIFO of the top is needed, no more");
  const bool rectify = r.config.rectify != "none";
  if (rectify != (r.map_left.size() == n) || rectify != (r.map_right.size() == n))
    throw ExportError(rectify ? "export: a rectifying design needs both remap tables at the pair's size"
                              : "export: remap tables given for a design without rectification");
  if (!(r.clock_mhz > 0)) throw ExportError("export: the clock must be positive");
  if (r.reduced_height_px != reduced_frame_rows(r.height_px) ||
      r.reduced_golden.size() != std::size_t(r.width_px) * std::size_t(r.reduced_height_px))
    throw ExportError("export: the reduced frame's golden output must be " + std::to_string(r.width_px) + "x" +
                      std::to_string(reduced_frame_rows(r.height_px)));
  const int invalid = r.config.disparities << r.config.subpixel_bits;  // D * 2^f
  for (const std::vector<uint16_t>* g : {&r.golden, &r.reduced_golden})
    if (std::any_of(g->begin(), g->end(), [&](uint16_t c) { return c > invalid; }))
      throw ExportError("export: a golden code exceeds the invalid code D * 2^subpixel_bits");
}

}  // namespace

int reduced_frame_rows(int height_px) {
  return std::min(height_px, kReducedRows);
}

// The FIFOs of the design's variant, in the pipeline table's order (kernels/pipeline.hpp).
std::vector<const kern::PipelineFifo*> export_fifos(const config::PipelineConfig& c) {
  kern::StereoParams p{};
  p.path_mask = c.path_mask;
  const unsigned conditions = kern::pipeline_conditions(p, c.rectify != "none");
  std::vector<const kern::PipelineFifo*> fifos;
  for (const kern::PipelineFifo& f : kern::kPipelineFifos)
    if (kern::pipeline_has(f.when, conditions)) fifos.push_back(&f);
  return fifos;
}

std::vector<std::string> export_fifo_names(const config::PipelineConfig& c) {
  std::vector<std::string> names;
  for (const kern::PipelineFifo* f : export_fifos(c)) names.push_back(f->name);
  return names;
}

std::string clock_period_ns(double clock_mhz) {
  return fixed(1000.0 / clock_mhz, 3);
}

namespace {

using Values = std::map<std::string, std::string>;

bool is_two_pass(const config::PipelineConfig& c) {
  return kern::two_pass_paths(c.path_mask);
}

// The design's name, clock, sizes, structure constants, bit widths and register values.
void design_values(const ExportRequest& r, const kern::StereoParams& p, Values& v) {
  const config::PipelineConfig& c = r.config;
  v["NAME"] = c.name;
  v["NAME_ID"] = identifier(c.name);
  v["ORIGIN"] = r.origin;
  v["PART"] = r.part;
  v["CLOCK_MHZ"] = fixed(r.clock_mhz, r.clock_mhz == std::floor(r.clock_mhz) ? 0 : 3);
  v["PERIOD_NS"] = clock_period_ns(r.clock_mhz);
  v["WIDTH"] = std::to_string(r.width_px);
  v["HEIGHT"] = std::to_string(r.height_px);
  v["REDUCED_HEIGHT"] = std::to_string(r.reduced_height_px);
  const bool census = p.cost == kern::kCostCensus;
  v["COST_ENUM"] = census ? "kCostCensus" : "kCostSad";
  v["COST_HEADER"] = census ? "census.hpp" : "sad.hpp";
  v["COST_STAGE"] = census ? "CensusCostStage" : "SadCostStage";
  v["COST_NAME"] = !census                              ? "SAD"
                   : p.census == kern::kCensusSparse    ? "sparse Census"
                   : p.census == kern::kCensusSymmetric ? "centre-symmetric Census"
                                                        : "Census";
  const char* census_enums[] = {"kCensusFull", "kCensusSparse", "kCensusSymmetric"};
  v["CENSUS_ENUM"] = census_enums[p.census == kern::kCensusSparse ? 1 : p.census == kern::kCensusSymmetric ? 2 : 0];
  v["WINDOW_W"] = std::to_string(p.window_w);
  v["WINDOW_H"] = std::to_string(p.window_h);
  v["DISPARITIES"] = std::to_string(p.disparities);
  v["DISPARITIES_MINUS_1"] = std::to_string(p.disparities - 1);
  v["MIN_DISPARITY"] = std::to_string(p.min_disparity);
  v["P2_ADAPTIVE"] = std::to_string(p.p2_adaptive);
  v["P2_ADAPTIVE_01"] = p.p2_adaptive > 0 ? "1" : "0";
  v["SUBPIXEL_BITS"] = std::to_string(p.subpixel_bits);
  v["MEDIAN_WIDE_KEYS"] = kern::disparity_bits(p) + 6 > 16 ? "1" : "0";  // 6: median.hpp kKeyIndexBits
  v["AGGREGATION_ENUM"] = p.aggregation == kern::kAggregationMgm ? "kAggregationMgm" : "kAggregationSgm";
  v["STRUCTURE_KNOBS_TEXT"] = std::string(p.aggregation == kern::kAggregationMgm ? ", MGM aggregation" : "") +
                              (p.p2_adaptive > 0 ? ", adaptive P2 (a = " + std::to_string(p.p2_adaptive) + ")" : "");
  v["MIN_DISPARITY_TEXT"] =
      p.min_disparity == 0 ? "" : " from m = " + std::to_string(p.min_disparity) + " (code d is the disparity m + d)";
  v["PARALLEL_UNITS"] = std::to_string(p.parallel_units);
  v["PATH_MASK"] = std::to_string(p.path_mask);
  v["PATHS"] = config::paths_to_string(p.path_mask);
  v["LR_CHECK"] = p.lr_check ? "true" : "false";
  v["LR_CHECK_TEXT"] = p.lr_check ? "on" : "off";
  v["MEDIAN"] = std::to_string(p.median >= 3 ? p.median : 0);
  v["MEDIAN_ROWS"] = std::to_string(p.median >= 3 ? p.median : 1);
  // Stream path kinds of the forward and, for two passes, the backward pass (one kernel type serves both).
  v["KIND_MASK"] = std::to_string(kern::datapath_kinds(kern::stream_kinds(p.path_mask, false), p.aggregation) |
                                  kern::datapath_kinds(kern::stream_kinds(p.path_mask, true), p.aggregation));
  v["MEDIAN_TEXT"] = p.median >= 3 ? std::to_string(p.median) + "x" + std::to_string(p.median) : "off";
  v["COST_MAX"] = std::to_string(kern::cost_max(p));
  v["COST_BITS"] = std::to_string(kern::cost_bits(p));
  v["PENALTY_BITS"] = std::to_string(kern::penalty_bits(p));
  v["PATH_BITS"] = std::to_string(kern::path_bits(p));
  v["CENSUS_BITS"] =
      std::to_string(p.cost == kern::kCostCensus ? kern::census_bits(p.census, p.window_w, p.window_h) : 1);
  v["AGGREGATE_BITS"] = std::to_string(kern::aggregate_bits(p));
  v["DISPARITY_BITS"] = std::to_string(kern::disparity_bits(p));
  v["OUT_BITS"] = std::to_string(((kern::disparity_bits(p) + 7) / 8) * 8);
  v["AGG_WORD"] = kern::aggregate_bits(p) <= 16 ? "uint16_t" : "uint32_t";
  // The runtime registers: AXI4-Lite ports of the top; these values are the testbench's.
  const kern::StereoRegisters regs = c.registers();
  v["P1"] = std::to_string(regs.p1);
  v["P2"] = std::to_string(regs.p2);
  v["LR_TOLERANCE"] = std::to_string(regs.lr_tolerance);
  v["UNIQUENESS_PCT"] = std::to_string(regs.uniqueness_pct);
  v["UNIQUENESS_BITS"] = std::to_string(kern::kUniquenessBits);
  v["UNIQUENESS"] = regs.uniqueness_pct > 0 ? "true" : "false";
  v["UNIQUENESS_TEXT"] =
      regs.uniqueness_pct > 0 ? "built with the check; 0 turns it off" : "built without the check: ignored";
  v["FRAMES"] = std::to_string(kTestbenchFrames);
}

// Storage directives of the line buffers and the path-cost rows, from the resource model's mapping.
void storage_values(const config::PipelineConfig&, const res::Inventory& inv, Values& v) {
  // The row reversals' memories (5 paths, kernels/row_reverse.hpp), bound as the model maps them.
  std::string reverse;
  const struct {
    const char *stage, *memory, *macro, *member;
  } reversals[] = {{"row_reverse", "row_reverse_cost", "COST", "cost_"},
                   {"row_reverse", "row_reverse_sum", "SUM", "sum_"},
                   {"row_unreverse", "row_reverse_codes", "CODES", "codes_"}};
  for (const auto& m : reversals)
    if (const res::MemoryItem* item = find_memory(inv, m.stage, m.memory))
      reverse += std::string("#define PX_HLS_ROW_REVERSE_") + m.macro +
                 "_STORAGE \"HLS BIND_STORAGE variable=" + m.member +
                 " type=ram_s2p impl=" + ram_impl(item->per_copy.storage) + "\"\n";
  v["ROW_REVERSE_STORAGE"] = reverse;
  const res::MemoryItem* lb = find_memory(inv, "cost", "left_line_buffer");
  v["LINE_BUFFER_IMPL"] = lb ? ram_impl(lb->per_copy.storage) : "bram";
  const res::MemoryItem* row = nullptr;
  for (const char* n : {"row_path_up", "row_path_left", "row_path_right"})
    if (!row) row = find_memory(inv, "aggregate", n);
  v["ROW_IMPL"] = row ? ram_impl(row->per_copy.storage) : "bram";
}

// Rectification: two more AXI4-Stream inputs (the remap tables), a stage per camera. Its row
// memories: true dual port for bilinear (a tap pair per row and firing), else simple dual port.
void rectify_values(const config::PipelineConfig& c, const res::Inventory& inv, Values& v) {
  const bool rectify = c.rectify != "none";
  const res::MemoryItem* rlb = find_memory(inv, "rectify_left", "rectify_line_buffer");
  v["RECTIFY_STORAGE"] = rectify ? "#define PX_HLS_RECTIFY_STORAGE \"HLS BIND_STORAGE variable=lb_ type=" +
                                       std::string(c.rectify == "bilinear" ? "ram_t2p" : "ram_s2p") +
                                       " impl=" + (rlb ? ram_impl(rlb->per_copy.storage) : std::string("bram")) + "\"\n"
                                 : "";
  v["MAP_TYPEDEF"] =
      rectify ? "\n// One remap-table entry: the source position of an output pixel in the kernels' fixed point\n"
                "// (kRectifyFracBits fraction bits); x in TDATA[31:0], y in TDATA[63:32], both signed.\n"
                "typedef ap_axiu<64, 1, 1, 1> map_beat_t;\n"
              : "";
  v["MAP_PORTS"] =
      rectify ? "\n                  hls::stream<map_beat_t>& map_left_in, hls::stream<map_beat_t>& map_right_in," : "";
  v["RECTIFY_INCLUDE"] = rectify ? "#include \"parallax/kernels/rectify.hpp\"\n" : "";
  v["MAP_INTERFACE_PRAGMAS"] =
      rectify ? "#pragma HLS INTERFACE mode=axis port=map_left_in\n#pragma HLS INTERFACE mode=axis port=map_right_in\n"
              : "";
  v["RECTIFY_CONSTANTS"] =
      rectify ? "// Rectification (docs/algorithm.md §1): mode, fraction bits of the map entries, line-buffer rows.\n"
                "constexpr int kRectifyMode = parallax::kern::" +
                    std::string(c.rectify == "bilinear" ? "kRectifyBilinear" : "kRectifyNearest") +
                    ";\nconstexpr int kRectifyFracBits = " +
                    std::to_string(c.rectify == "bilinear" ? c.rectify_frac_bits : 0) +
                    ";\nconstexpr int kRectifyRows = " + std::to_string(c.rectify_rows) +
                    ";\n\ninline parallax::kern::RectifyParams rectify_params() {\n"
                    "  parallax::kern::RectifyParams p;\n  p.width_px = kWidthPx;\n  p.height_px = kHeightPx;\n"
                    "  p.mode = kRectifyMode;\n  p.frac_bits = kRectifyFracBits;\n  p.buffer_rows = kRectifyRows;\n  "
                    "return p;\n}\n\n"
              : "";
  v["FRONT_END"] = rectify ? "  read_pixels(left_in, raw_left_px);\n  read_pixels(right_in, raw_right_px);\n"
                             "  read_maps(map_left_in, map_left);\n  read_maps(map_right_in, map_right);\n"
                             "  rectify_stage<0>(raw_left_px, map_left, left_px);\n  rectify_stage<1>(raw_right_px, "
                             "map_right, right_px);\n"
                           : "  read_pixels(left_in, left_px);\n  read_pixels(right_in, right_px);\n";
  v["TB_MAP_FUNCTIONS"] = rectify ? template_text("tb_map_functions.cpp") : "";
  v["TB_MAP_LOAD"] = rectify ? "  std::vector<uint64_t> map_left, map_right;\n"
                               "  if (!read_map(dir + \"/map_left.bin\", map_left) || !read_map(dir + "
                               "\"/map_right.bin\", map_right)) return 1;\n"
                             : "";
  v["TB_MAP_FEED"] = rectify
                         ? "    hls::stream<map_beat_t> map_left_in(\"map_left_in\"), map_right_in(\"map_right_in\");\n"
                           "    feed_map(map_left_in, map_left);\n    feed_map(map_right_in, map_right);\n"
                         : "";
  v["TB_MAP_ARGS"] = rectify ? " map_left_in, map_right_in," : "";

  v["CFG_MAP_FILES"] = rectify ? "tb.file=tb/map_left.bin\ntb.file=tb/map_right.bin\n" : "";
  v["TCL_MAP_FILES"] = rectify ? "  add_files -tb tb/map_left.bin\n  add_files -tb tb/map_right.bin\n" : "";
  v["README_MAP_PORTS"] = rectify ? "| `map_left_in`, `map_right_in` | AXI4-Stream | 64 | remap tables, one entry per "
                                    "output pixel: source x in TDATA[31:0], y in [63:32], signed, " +
                                        std::to_string(c.rectify == "bilinear" ? c.rectify_frac_bits : 0) +
                                        " fraction bits |\n"
                                  : "";
  v["README_RECTIFY"] =
      rectify ? "\nThe design rectifies (" + c.rectify + ", " + std::to_string(c.rectify_rows) +
                    " line-buffer rows): the pair is the raw camera images, and `tb/map_left.bin`, `tb/map_right.bin` "
                    "hold the remap tables (one entry per pixel, two little-endian int32: x, y in the kernels' fixed "
                    "point), "
                    "fed through `map_left_in` / `map_right_in`.\n"
              : "";
}

// FIFOs: depth constants, stream declarations (per pass for two-pass designs), README rows.
void fifo_values(const ExportRequest& r, const res::Inventory& inv, Values& v) {
  const config::PipelineConfig& c = r.config;
  const bool two_pass = is_two_pass(c);
  std::string depths, streams, pass2_streams, fifo_rows;
  for (const kern::PipelineFifo* d : export_fifos(c)) {
    const std::string name = d->name;
    const ExportFifo& f =
        *std::find_if(r.fifos.begin(), r.fifos.end(), [&](const ExportFifo& x) { return x.name == name; });
    const std::string k = depth_constant(name);
    depths += "constexpr int " + k + " = " + std::to_string(f.depth) + ";\n";
    // The stream's type by its token (the design's widths, see the beats in parallax_top.cpp).
    const std::string type = d->token == kern::kTokenMapEntry ? "kern::MapEntry"
                             : d->token == kern::kTokenPixel  ? "uint8_t"
                             : d->token == kern::kTokenCost   ? "CostBeat"
                             : d->token == kern::kTokenSum    ? "SumBeat"
                                                              : "CodeBeat";
    const res::MemoryItem* m = find_memory(inv, "fifos", name);
    const res::MemoryMapping mapping = res::map_memory(res::MemoryKind::fifo, f.depth, m ? m->width_bits : 8, false);
    const bool second = two_pass && d->pass == 2;
    std::string& s = second ? pass2_streams : streams;
    s += "  hls::stream<" + type + "> " + name + "(\"" + name + "\");\n";
    s += "#pragma HLS STREAM variable=" + name + " depth=" + std::to_string(f.depth) + "\n";
    s += "#pragma HLS BIND_STORAGE variable=" + name + " type=fifo impl=" + fifo_impl(mapping.storage) + "\n";
    fifo_rows += "| `" + name + "` | " + std::to_string(f.depth) + " | " +
                 (f.stall_free >= 0 ? std::to_string(f.stall_free) : std::string("not sized")) + " | " + f.why + " |\n";
  }
  v["FIFO_DEPTHS"] = depths;
  v["STREAM_DECLARATIONS"] = streams;
  v["PASS1_STREAMS"] = streams;
  v["PASS2_STREAMS"] = pass2_streams;
  v["FIFO_ROWS"] = fifo_rows;
}

// The top's interface: one pass streams the codes out; two passes go through a DDR frame buffer
// and write the map to memory (the second pass runs in reverse order). Needs rectify_values'.
void interface_values(const ExportRequest& r, const kern::StereoParams& p, const res::Inventory& inv, Values& v) {
  const config::PipelineConfig& c = r.config;
  const bool two_pass = is_two_pass(c);
  const bool rectify = c.rectify != "none";
  v["TWO_PASS"] = two_pass ? "true" : "false";
  v["TWO_PASS_01"] = two_pass ? "1" : "0";
  v["ROW_REVERSE"] = kern::row_reverse_paths(c.path_mask) ? "true" : "false";
  v["PIXELS"] = std::to_string(int64_t(r.width_px) * r.height_px);
  // The frame buffer's layout (kernels/frame_buffer.hpp), of the full and the reduced frame: the
  // config's constants come from the same functions at compile time, checked against these.
  kern::StereoParams reduced_p = p;
  reduced_p.height_px = r.reduced_height_px;
  const std::string frame_check =
      two_pass
          ? "#ifndef PARALLAX_REDUCED_FRAME\nstatic_assert(kFrameWords == " + std::to_string(kern::frame_words(p)) +
                " && kFrameSegmentPixels == " + std::to_string(kern::frame_segment_pixels(p)) +
                " && kMapSegmentPixels == " + std::to_string(kern::map_segment_pixels(p)) +
                ",\n              \"the export's frame-buffer layout (m_axi depths, "
                "README)\");\n#else\nstatic_assert(kFrameWords == " +
                std::to_string(kern::frame_words(reduced_p)) +
                " && kFrameSegmentPixels == " + std::to_string(kern::frame_segment_pixels(reduced_p)) +
                " && kMapSegmentPixels == " + std::to_string(kern::map_segment_pixels(reduced_p)) +
                ",\n              \"the export's frame-buffer layout (m_axi depths, README)\");\n#endif\n"
          : "";
  v["TWO_PASS_TYPES"] =
      two_pass
          ? "\n#include \"parallax/kernels/frame_buffer.hpp\"\n\n"
            "// The frame buffer between the passes (DDR, m_axi; layout in parallax/kernels/frame_buffer.hpp):\n"
            "// per firing of pass 1 one pair of PU costs and PU forward sums (" +
                std::to_string(kern::frame_pair_bits(p)) +
                " bits), packed into kFrameBeats\n"
                "// word(s) of kFrameWordBits bits, the pixels in reverse raster order. Pass 1 reverses them on chip\n"
                "// in segments of kFrameSegmentPixels pixels (one burst each); pass 2 reads words 0 .. "
                "kFrameWords-1.\n"
                "// The map writer reverses the codes the same way, in segments of kMapSegmentPixels.\n"
                "namespace parallax_design {\n"
                "constexpr int kFramePairBits = parallax::kern::frame_pair_bits_of(kParallelUnits, kCostBits, "
                "kAggregateBits);\n"
                "constexpr int kFrameWordBits = parallax::kern::frame_word_bits_of(kFramePairBits);  // " +
                std::to_string(kern::frame_word_bits(p)) +
                "\n"
                "constexpr int kFrameBeats = parallax::kern::frame_beats_of(kFramePairBits);  // words per pair: " +
                std::to_string(kern::frame_beats(p)) +
                "\n"
                "constexpr int kFrameWordLimbs = kFrameWordBits / 32;\n"
                "constexpr int kFramePairLimbs = parallax::kern::frame_limbs_of(kFramePairBits);\n"
                "constexpr int kFramePixelWords = kChunks * kFrameBeats;\n"
                "constexpr int kFrameWords = kPixels * kFramePixelWords;\n"
                "constexpr int kFrameSegmentPixels = int(parallax::kern::segment_units_of(\n"
                "    kPixels, kFramePixelWords, parallax::kern::burst_elements_of(kFrameWordBits / 8)));\n"
                "constexpr int kFrameSegmentTokens = kFrameSegmentPixels * kChunks;\n"
                "constexpr int kFrameSegmentWords = kFrameSegmentTokens * kFrameBeats;\n"
                "constexpr int kFrameSegments = kPixels / kFrameSegmentPixels;\n"
                "constexpr int kMapSegmentPixels = int(parallax::kern::segment_units_of(\n"
                "    kPixels, 1, parallax::kern::burst_elements_of(parallax::kern::kMapCodeBytes)));\n"
                "constexpr int kMapSegments = kPixels / kMapSegmentPixels;\n" +
                frame_check +
                "static_assert(int64_t(kPixels) * kFramePixelWords < (int64_t(1) << 31), \"word addresses fit an "
                "int\");\n"
                "}  // namespace parallax_design\n"
                "// One DDR word: kFrameWordBits bits as 32-bit limbs (one bus word of the m_axi port).\n"
                "typedef parallax::kern::FrameWord<parallax_design::kFrameWordLimbs> frame_word_t;\n"
          : "";
  const std::string input_kind = rectify ? "raw (unrectified)" : "rectified";
  v["INPUT_KIND"] = input_kind;
  v["TOP_CONTRACT"] =
      two_pass
          ? "// Computes the disparity of " + input_kind +
                " stereo pairs in two passes, one frame behind. Contract:\n"
                "// each input stream carries exactly kWidthPx x kHeightPx beats in raster order; call k runs pass 1\n"
                "// of its frame into `frame_write` and pass 2 of the previous frame from `frame_read` (the buffer\n"
                "// call k - 1 wrote; kFrameWords words each; the host swaps them), writing that frame's map to\n"
                "// `disparity` (kPixels codes, raster order). The registers hold P1 < P2 (the SGM penalties, read\n"
                "// by the aggregation only), the left-right tolerance in pixels and the uniqueness margin in\n"
                "// percent (read by the WTA / LR check only)."
          : "// Computes the disparity of one " + input_kind +
                " stereo pair. Contract: each input stream carries exactly\n"
                "// kWidthPx x kHeightPx beats in raster order; the output carries as many, in raster order. The\n"
                "// registers hold P1 < P2 (the SGM penalties, read by the aggregation only), the left-right\n"
                "// tolerance in pixels and the uniqueness margin in percent (read by the WTA / LR check only).";
  const std::string ports =
      "void parallax_top(hls::stream<pixel_beat_t>& left_in, hls::stream<pixel_beat_t>& right_in," + v["MAP_PORTS"] +
      "\n";
  v["TOP_SIGNATURE"] =
      ports +
      (two_pass
           ? "                  parallax::kern::DispCode* disparity, frame_word_t* frame_write,\n"
             "                  const frame_word_t* frame_read,\n"
             "                  ap_uint<parallax_design::kPenaltyBits> p1, ap_uint<parallax_design::kPenaltyBits> p2,\n"
             "                  ap_uint<parallax_design::kDisparityBits> lr_tolerance,\n"
             "                  ap_uint<parallax::kern::kUniquenessBits> uniqueness_pct)"
           : "                  hls::stream<disparity_beat_t>& disparity_out, ap_uint<parallax_design::kPenaltyBits> "
             "p1,\n"
             "                  ap_uint<parallax_design::kPenaltyBits> p2, ap_uint<parallax_design::kDisparityBits> "
             "lr_tolerance,\n"
             "                  ap_uint<parallax::kern::kUniquenessBits> uniqueness_pct)");
  v["PASS_MAP_PARAMS"] =
      rectify ? "\n                  hls::stream<map_beat_t>& map_left_in, hls::stream<map_beat_t>& map_right_in," : "";
  v["DATAFLOW_MAP_PARAMS"] =
      rectify ? "\n                       hls::stream<map_beat_t>& map_left_in, hls::stream<map_beat_t>& map_right_in,"
              : "";
  v["PASS_MAP_ARGS"] = rectify ? " map_left_in, map_right_in," : "";
  // The m_axi ports: one bundle per direction of the frame buffer (gmem_wr: pass 1's writes,
  // gmem_rd: pass 2's reads), the map on its own (gmem_map: written by pass 2 while pass 1 writes
  // the other buffer). Bursts as long as a reversal segment (at most 256 beats and 4 KB), two
  // outstanding per direction used (hides ~150 ns of DDR latency with >= 2 x the segment in
  // flight), one for the direction a port never uses; depth= is the words C/RTL co-simulation
  // moves, of the full and of the reduced frame.
  {
    auto m_axi = [&](const kern::StereoParams& q) {
      const std::string words = std::to_string(kern::frame_words(q));
      const std::string burst = std::to_string(kern::burst_elements_of(kern::frame_word_bytes(q)));
      const std::string map_burst = std::to_string(kern::burst_elements_of(kern::kMapCodeBytes));
      return "#pragma HLS INTERFACE mode=m_axi port=frame_write offset=slave bundle=gmem_wr depth=" + words +
             " max_write_burst_length=" + burst +
             " num_write_outstanding=2 max_read_burst_length=2 num_read_outstanding=1\n"
             "#pragma HLS INTERFACE mode=m_axi port=frame_read offset=slave bundle=gmem_rd depth=" +
             words + " max_read_burst_length=" + burst +
             " num_read_outstanding=2 max_write_burst_length=2 num_write_outstanding=1\n"
             "#pragma HLS INTERFACE mode=m_axi port=disparity offset=slave bundle=gmem_map depth=" +
             std::to_string(kern::frame_pixels(q)) + " max_write_burst_length=" + map_burst +
             " num_write_outstanding=2 max_read_burst_length=2 num_read_outstanding=1 max_widen_bitwidth=128\n";
    };
    v["M_AXI_PRAGMAS"] = "#ifndef PARALLAX_REDUCED_FRAME\n" + m_axi(p) + "#else\n" + m_axi(reduced_p) + "#endif\n";
  }
  // The on-chip reversal buffers' RAM, as the resource model maps them.
  const res::MemoryItem* seg_mem = find_memory(inv, "ddr_write", "segment_buffer");
  v["FRAME_SEGMENT_IMPL"] = seg_mem ? ram_impl(seg_mem->per_copy.storage) : "bram";
  const res::MemoryItem* map_mem = find_memory(inv, "sink", "map_segment_buffer");
  v["MAP_SEGMENT_IMPL"] = map_mem ? ram_impl(map_mem->per_copy.storage) : "bram";
}

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

// The project's files: the templates filled with v (the two configurations of the unified flow
// set their own values), stages.json, design.yaml, the kernels' copies and the testbench's data.
std::vector<GeneratedFile> project_files(const ExportRequest& r, Values& v) {
  const config::PipelineConfig& c = r.config;
  const bool rectify = c.rectify != "none";
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
  files.push_back({"tb/left.pgm", pgm(r.width_px, r.height_px, 255, nullptr, r.left.data()), true});
  files.push_back({"tb/right.pgm", pgm(r.width_px, r.height_px, 255, nullptr, r.right.data()), true});
  files.push_back({"tb/golden_disparity.pgm",
                   pgm(r.width_px, r.height_px, c.disparities << c.subpixel_bits, r.golden.data(), nullptr), true});
  files.push_back(
      {"tb/golden_disparity_reduced.pgm",
       pgm(r.width_px, r.reduced_height_px, c.disparities << c.subpixel_bits, r.reduced_golden.data(), nullptr), true});
  if (rectify) {
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

}  // namespace

std::vector<GeneratedFile> generate_project(const ExportRequest& r) {
  check_request(r);
  const config::PipelineConfig& c = r.config;
  const kern::StereoParams p = c.stereo_params(r.width_px, r.height_px);
  const res::Inventory inv = res::design_inventory(c, r.width_px, r.height_px);
  Values v;
  design_values(r, p, v);
  storage_values(c, inv, v);
  rectify_values(c, inv, v);
  fifo_values(r, inv, v);
  interface_values(r, p, inv, v);
  detail::loop_values(r, v);
  detail::priced_width_values(inv, v);
  readme_values(r, p, v);
  // The functions filled from templates, once every value above is set.
  const bool two_pass = is_two_pass(c);
  v["RECTIFY_FUNCTIONS"] =
      c.rectify != "none" ? fill("rectify_functions.cpp", template_text("rectify_functions.cpp"), v) : "";
  const char* top = two_pass                               ? "top_two_pass.cpp"
                    : kern::row_reverse_paths(c.path_mask) ? "top_row_reverse.cpp"
                                                           : "top_one_pass.cpp";
  v["TOP_FUNCTIONS"] = fill(top, template_text(top), v);
  return project_files(r, v);
}

void check_project_dir(const std::string& dir) {
  std::error_code ec;
  const fs::path root(dir);
  if (!fs::exists(root, ec)) return;
  if (!fs::is_directory(root, ec)) throw ExportError(dir + ": exists and is not a folder");
  const bool empty = fs::directory_iterator(root, ec) == fs::directory_iterator();
  if (!empty && !fs::exists(root / kMarker, ec))
    throw ExportError(dir + ": folder is not empty and was not written by parallax export-hls; choose another --out");
}

void write_project(const std::vector<GeneratedFile>& files, const std::string& dir) {
  check_project_dir(dir);
  std::error_code ec;
  const fs::path root(dir);
  for (const auto& f : files) {
    const fs::path path = root / f.path;
    fs::create_directories(path.parent_path(), ec);
    if (ec) throw ExportError(path.parent_path().string() + ": cannot create folder: " + ec.message());
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(f.content.data(), std::streamsize(f.content.size()));
    out.close();
    if (!out) throw ExportError(path.string() + ": cannot write: " + std::strerror(errno));
  }
  std::ofstream marker(root / kMarker, std::ios::trunc);
  marker << "Written by parallax export-hls; a later export may overwrite this folder.\n";
  if (!marker) throw ExportError((root / kMarker).string() + ": cannot write");
}

}  // namespace parallax::hlsx
