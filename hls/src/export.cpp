// The HLS export: checks the request, fills the templates of hls/templates/ for one design
// (export_parts.hpp: the design constants, the top, the testbench, the project's files) and writes
// the project.
#include "parallax/hls/export.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>

#include "export_loops.hpp"
#include "export_parts.hpp"
#include "parallax/kernels/params.hpp"
#include "parallax/kernels/pipeline.hpp"
#include "parallax/resources/model.hpp"

namespace parallax::hlsx {
namespace {

namespace fs = std::filesystem;
using detail::Values;

constexpr int kReducedRows = 16;  // rows of the reduced frame of C/RTL co-simulation
constexpr const char* kMarker = ".parallax-export";

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
  return detail::fixed(1000.0 / clock_mhz, 3);
}

std::vector<GeneratedFile> generate_project(const ExportRequest& r) {
  check_request(r);
  const config::PipelineConfig& c = r.config;
  const kern::StereoParams p = c.stereo_params(r.width_px, r.height_px);
  const res::Inventory inv = res::design_inventory(c, r.width_px, r.height_px);
  Values v;
  detail::design_values(r, p, v);
  detail::storage_values(inv, v);
  detail::rectify_values(c, inv, v);
  detail::fifo_values(r, inv, v);
  detail::interface_values(r, p, inv, v);
  detail::dataflow_values(c, p, v);
  detail::testbench_values(c, v);
  detail::loop_values(r, v);
  detail::priced_width_values(inv, v);
  detail::readme_values(r, p, v);
  // The functions filled from templates, once every value above is set.
  const bool two_pass = detail::is_two_pass(c);
  v["RECTIFY_FUNCTIONS"] =
      c.rectify != "none" ? detail::fill("rectify_functions.cpp", detail::template_text("rectify_functions.cpp"), v)
                          : "";
  const char* top = two_pass                               ? "top_two_pass.cpp"
                    : kern::row_reverse_paths(c.path_mask) ? "top_row_reverse.cpp"
                                                           : "top_one_pass.cpp";
  v["TOP_FUNCTIONS"] = detail::fill(top, detail::template_text(top), v);
  return detail::project_files(r, v);
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
