// The exported top's values (export_parts.hpp): rectification, the FIFOs between the stages and
// the top's interface (one pass: streams; two passes: the DDR frame buffer and the map in memory).
// The C++ is in hls/templates/fragments.in; this file chooses fragments and computes their values.
#include <algorithm>
#include <string>

#include "export_parts.hpp"
#include "parallax/kernels/frame_buffer.hpp"
#include "parallax/kernels/pipeline.hpp"

namespace parallax::hlsx::detail {

// Rectification: two more AXI4-Stream inputs (the remap tables), a stage per camera. Its row
// memories: true dual port for bilinear (a tap pair per row and firing), else simple dual port.
void rectify_values(const config::PipelineConfig& c, const res::Inventory& inv, Values& v) {
  const bool rectify = c.rectify != "none";
  const bool bilinear = c.rectify == "bilinear";
  const res::MemoryItem* rlb = find_memory(inv, "rectify_left", "rectify_line_buffer");
  const Values r = {{"RECTIFY_RAM", bilinear ? "ram_t2p" : "ram_s2p"},
                    {"RECTIFY_IMPL", rlb ? ram_impl(rlb->per_copy.storage) : std::string("bram")},
                    {"RECTIFY_MODE_ENUM", bilinear ? "kRectifyBilinear" : "kRectifyNearest"},
                    {"RECTIFY_FRAC_BITS", std::to_string(bilinear ? c.rectify_frac_bits : 0)},
                    {"RECTIFY_ROWS", std::to_string(c.rectify_rows)}};
  auto when = [&](const char* name) { return rectify ? fragment(name, r) : std::string(); };
  v["RECTIFY_STORAGE"] = when("rectify_storage");
  v["MAP_TYPEDEF"] = when("map_typedef");
  v["MAP_PORTS"] = when("map_ports");
  v["PASS_MAP_PARAMS"] = v["MAP_PORTS"];
  v["DATAFLOW_MAP_PARAMS"] = when("dataflow_map_params");
  v["PASS_MAP_ARGS"] = when("map_args");
  v["RECTIFY_INCLUDE"] = when("rectify_include");
  v["MAP_INTERFACE_PRAGMAS"] = when("map_interface_pragmas");
  v["RECTIFY_CONSTANTS"] = when("rectify_constants");
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
    // The stream's type by its token (the design's widths, see the beats in parallax_top.cpp).
    const std::string type = d->token == kern::kTokenMapEntry ? "kern::MapEntry"
                             : d->token == kern::kTokenPixel  ? "uint8_t"
                             : d->token == kern::kTokenCost   ? "CostBeat"
                             : d->token == kern::kTokenSum    ? "SumBeat"
                                                              : "CodeBeat";
    const res::MemoryItem* m = find_memory(inv, "fifos", name);
    const res::MemoryMapping mapping = res::map_memory(res::MemoryKind::fifo, f.depth, m ? m->width_bits : 8, false);
    const Values fv = {{"CONSTANT", depth_constant(name)},
                       {"NAME", name},
                       {"TYPE", type},
                       {"DEPTH", std::to_string(f.depth)},
                       {"IMPL", fifo_impl(mapping.storage)}};
    depths += fragment("fifo_depth", fv);
    (two_pass && d->pass == 2 ? pass2_streams : streams) += fragment("fifo_stream", fv);
    fifo_rows += "| `" + name + "` | " + std::to_string(f.depth) + " | " +
                 (f.stall_free >= 0 ? std::to_string(f.stall_free) : std::string("not sized")) + " | " + f.why + " |\n";
  }
  v["FIFO_DEPTHS"] = depths;
  v["STREAM_DECLARATIONS"] = streams;
  v["PASS1_STREAMS"] = streams;
  v["PASS2_STREAMS"] = pass2_streams;
  v["FIFO_ROWS"] = fifo_rows;
}

namespace {

// The frame buffer's layout check and the m_axi ports' pragmas of one frame size (the full frame,
// or the reduced frame of C/RTL co-simulation).
Values frame_values(const kern::StereoParams& q) {
  return {{"FRAME_WORDS", std::to_string(kern::frame_words(q))},
          {"FRAME_SEGMENT_PIXELS", std::to_string(kern::frame_segment_pixels(q))},
          {"MAP_SEGMENT_PIXELS", std::to_string(kern::map_segment_pixels(q))},
          {"WORDS", std::to_string(kern::frame_words(q))},
          {"BURST", std::to_string(kern::burst_elements_of(kern::frame_word_bytes(q)))},
          {"MAP_BURST", std::to_string(kern::burst_elements_of(kern::kMapCodeBytes))},
          {"PIXELS", std::to_string(kern::frame_pixels(q))}};
}

}  // namespace

// The top's interface: one pass streams the codes out; two passes go through a DDR frame buffer
// and write the map to memory (the second pass runs in reverse order).
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
  const Values full = frame_values(p), reduced = frame_values(reduced_p);
  const Values types = {{"FRAME_PAIR_BITS", std::to_string(kern::frame_pair_bits(p))},
                        {"FRAME_WORD_BITS", std::to_string(kern::frame_word_bits(p))},
                        {"FRAME_BEATS", std::to_string(kern::frame_beats(p))},
                        {"FULL_FRAME_CHECK", fragment("frame_layout_check", full)},
                        {"REDUCED_FRAME_CHECK", fragment("frame_layout_check", reduced)}};
  v["TWO_PASS_TYPES"] = two_pass ? fragment("two_pass_types", types) : "";
  const std::string input_kind = rectify ? "raw (unrectified)" : "rectified";
  v["INPUT_KIND"] = input_kind;
  v["TOP_CONTRACT"] = fragment(two_pass ? "top_contract_two_pass" : "top_contract_one_pass", v);
  v["TOP_SIGNATURE"] = fragment(two_pass ? "top_signature_two_pass" : "top_signature_one_pass", v);
  // The m_axi ports: one bundle per direction of the frame buffer (gmem_wr: pass 1's writes,
  // gmem_rd: pass 2's reads), the map on its own (gmem_map: written by pass 2 while pass 1 writes
  // the other buffer). Bursts as long as a reversal segment (at most 256 beats and 4 KB), two
  // outstanding per direction used (hides ~150 ns of DDR latency with >= 2 x the segment in
  // flight), one for the direction a port never uses; depth= is the words C/RTL co-simulation
  // moves, of the full and of the reduced frame.
  v["M_AXI_PRAGMAS"] = fragment("by_frame", {{"FULL_FRAME", fragment("m_axi_pragmas", full)},
                                             {"REDUCED_FRAME", fragment("m_axi_pragmas", reduced)}});
  // The on-chip reversal buffers' RAM, as the resource model maps them.
  const res::MemoryItem* seg_mem = find_memory(inv, "ddr_write", "segment_buffer");
  v["FRAME_SEGMENT_IMPL"] = seg_mem ? ram_impl(seg_mem->per_copy.storage) : "bram";
  const res::MemoryItem* map_mem = find_memory(inv, "sink", "map_segment_buffer");
  v["MAP_SEGMENT_IMPL"] = map_mem ? ram_impl(map_mem->per_copy.storage) : "bram";
}

}  // namespace parallax::hlsx::detail
