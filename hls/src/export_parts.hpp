// The parts of the HLS export (export.cpp drives them): the text helpers that fill templates and
// fragments (export_text.cpp), the design constants (export_design.cpp), the top's interface,
// streams and rectification (export_top.cpp), the testbench's values and data (export_testbench.cpp)
// and the project's other files (export_project.cpp). Every generated line of C++ is in
// hls/templates: a template per file, and hls/templates/fragments.in for the pieces a design
// includes or repeats; the parts only choose fragments and compute their values.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "parallax/hls/export.hpp"
#include "parallax/kernels/params.hpp"
#include "parallax/kernels/pipeline.hpp"
#include "parallax/resources/model.hpp"

namespace parallax::hlsx {
// The FIFOs of the design's variant, in the pipeline table's order (export.cpp).
std::vector<const kern::PipelineFifo*> export_fifos(const config::PipelineConfig& c);
}  // namespace parallax::hlsx

namespace parallax::hlsx::detail {

using Values = std::map<std::string, std::string>;

constexpr int kTestbenchFrames = 2;

// Replaces every @KEY@ (KEY: upper-case letters, digits, '_', starting with a letter) by its
// value. A key without a value is a defect of the generator, reported with the template's name.
std::string fill(const std::string& name, const std::string& text, const Values& values);
// The text of an embedded template (hls/templates/NAME.in); std::logic_error when there is none.
std::string template_text(const std::string& name);
// A fragment of hls/templates/fragments.in, filled with `values`; std::logic_error when there is none.
std::string fragment(const std::string& name, const Values& values);
bool has_fragment(const std::string& name);

std::string identifier(const std::string& s);         // a C identifier from a design's name
std::string depth_constant(const std::string& fifo);  // left_px -> kDepthLeftPx
std::string fixed(double v, int decimals);
// The storage a memory of the resource model maps to, as a BIND_STORAGE impl of a RAM / a FIFO.
std::string ram_impl(res::Storage s);
std::string fifo_impl(res::Storage s);
const res::MemoryItem* find_memory(const res::Inventory& inv, const std::string& stage, const std::string& name);
bool is_two_pass(const config::PipelineConfig& c);

// The values of the templates, by part.
void design_values(const ExportRequest& r, const kern::StereoParams& p, Values& v);
void storage_values(const res::Inventory& inv, Values& v);
void rectify_values(const config::PipelineConfig& c, const res::Inventory& inv, Values& v);
void fifo_values(const ExportRequest& r, const res::Inventory& inv, Values& v);
// Needs rectify_values' MAP_PORTS.
void interface_values(const ExportRequest& r, const kern::StereoParams& p, const res::Inventory& inv, Values& v);
// The DATAFLOW regions' calls and the registers' routing, from the pipeline and parameter tables.
void dataflow_values(const config::PipelineConfig& c, const kern::StereoParams& p, Values& v);
void testbench_values(const config::PipelineConfig& c, Values& v);
void readme_values(const ExportRequest& r, const kern::StereoParams& p, Values& v);

// The testbench's data: the pair, the golden maps of the full and the reduced frame, the remap tables.
std::vector<GeneratedFile> testbench_files(const ExportRequest& r);
// The project's files: the templates filled with v, stages.json, design.yaml, the kernels' copies
// and the testbench's data.
std::vector<GeneratedFile> project_files(const ExportRequest& r, Values& v);

}  // namespace parallax::hlsx::detail
