// The exported DATAFLOW regions, generated from the tables the simulator runs: the calls, one per
// stage of the design's variant in the pipeline table's order (kernels/pipeline.hpp), each given
// the FIFOs it consumes and then those it produces (table order) and the run-time registers its
// parameter reader reads (params.hpp: for_each_param's register fields); and the registers' way
// from the top's AXI4-Lite ports to those stages. The C++ of each call is a fragment of
// hls/templates/fragments.in ("call_<stage>" where a stage talks to the top's ports, else
// "call_stage": <stage>_stage(...)); this file only lists names.
#include <algorithm>
#include <string>
#include <vector>

#include "export_parts.hpp"
#include "parallax/kernels/params.hpp"
#include "parallax/kernels/pipeline.hpp"

namespace parallax::hlsx::detail {
namespace {

struct Register {
  std::string name;  // the StereoParams field, the top's port and (with "_value") the value's name
  unsigned readers;
};

// The design's run-time registers, in the parameter table's order.
std::vector<Register> registers_of(const kern::StereoParams& p) {
  std::vector<Register> out;
  kern::for_each_param(p, [&](const kern::ParamField& f) {
    if (f.is_register) out.push_back(Register{f.name, f.readers});
  });
  return out;
}

// The items, each through `piece` (a fragment with @NAME@, or none: the item itself), comma-separated.
std::string joined(const std::vector<std::string>& items, const char* piece = nullptr) {
  std::string s;
  for (const std::string& item : items)
    s += (s.empty() ? "" : ", ") + (piece ? fragment(piece, {{"NAME", item}}) : item);
  return s;
}

// The pass a stage runs in: that of its FIFOs (2 for the second pass of a two-pass design).
int stage_pass(const kern::PipelineStage& st, unsigned cond) {
  int pass = 1;
  for (const kern::PipelineFifo& f : kern::kPipelineFifos)
    if (kern::pipeline_has(f.when, cond) &&
        (kern::pipeline_same_name(f.producer, st.name) || kern::pipeline_same_name(f.consumer, st.name)))
      pass = std::max(pass, f.pass);
  return pass;
}

// The registers the stage's reader reads, by name.
std::vector<std::string> stage_registers(const kern::PipelineStage& st, const std::vector<Register>& regs) {
  std::vector<std::string> names;
  for (const Register& r : regs)
    if ((r.readers & st.reads) != 0) names.push_back(r.name);
  return names;
}

// One stage's call: its input FIFOs, its output FIFOs, then its registers' values.
std::string stage_call(const kern::PipelineStage& st, unsigned cond, bool two_pass, const std::vector<Register>& regs) {
  std::vector<std::string> ins, outs;
  for (const kern::PipelineFifo& f : kern::kPipelineFifos) {
    if (!kern::pipeline_has(f.when, cond)) continue;
    if (kern::pipeline_same_name(f.consumer, st.name)) ins.push_back(f.name);
    if (kern::pipeline_same_name(f.producer, st.name)) outs.push_back(f.name);
  }
  std::vector<std::string> fifos = ins;
  fifos.insert(fifos.end(), outs.begin(), outs.end());
  const std::vector<std::string> registers = stage_registers(st, regs);
  std::string args = joined(fifos);
  if (!registers.empty()) args += (args.empty() ? "" : ", ") + joined(registers, "register_value");
  Values fv = {{"STAGE", st.name}, {"ARGS", args}};
  for (std::size_t i = 0; i < outs.size(); ++i) fv["OUT" + std::to_string(i)] = outs[i];
  const std::string own = std::string("call_") + st.name;
  const std::string by_pass = own + (two_pass ? "_two_pass" : "_one_pass");
  return has_fragment(by_pass) ? fragment(by_pass, fv)
         : has_fragment(own)   ? fragment(own, fv)
                               : fragment("call_stage", fv);
}

}  // namespace

void dataflow_values(const config::PipelineConfig& c, const kern::StereoParams& p, Values& v) {
  const bool two_pass = is_two_pass(c);
  const unsigned cond = kern::pipeline_conditions(p, c.rectify != "none");
  const std::vector<Register> regs = registers_of(p);
  // The calls of each pass (a one-pass design has only the first) and the registers each reads.
  std::string calls[2];
  std::vector<std::string> pass_registers[2];
  for (const kern::PipelineStage& st : kern::kPipelineStages) {
    if (!kern::pipeline_has(st.when, cond)) continue;
    const int pass = stage_pass(st, cond) - 1;
    calls[pass] += stage_call(st, cond, two_pass, regs);
    for (const std::string& r : stage_registers(st, regs))
      if (std::find(pass_registers[pass].begin(), pass_registers[pass].end(), r) == pass_registers[pass].end())
        pass_registers[pass].push_back(r);
  }
  v["DATAFLOW_CALLS"] = calls[0];
  v["PASS1_CALLS"] = calls[0];
  v["PASS2_CALLS"] = calls[1];
  std::vector<std::string> names;
  std::string pragmas, reads;
  for (const Register& r : regs) {
    names.push_back(r.name);
    pragmas += fragment("register_pragma", {{"NAME", r.name}});
    reads += fragment("register_read", {{"NAME", r.name}});
  }
  v["REGISTER_PRAGMAS"] = pragmas;
  v["REGISTER_READS"] = reads;
  v["REGISTER_PARAMS"] = joined(names, "register_value_param");
  v["REGISTER_ARGS"] = joined(names, "register_value");
  for (int pass = 0; pass < 2; ++pass) {
    const std::string n = std::to_string(pass + 1);
    v["PASS" + n + "_REGISTER_PARAMS"] = joined(pass_registers[pass], "register_value_param");
    v["PASS" + n + "_REGISTER_ARGS"] = joined(pass_registers[pass], "register_value");
  }
}

}  // namespace parallax::hlsx::detail
