// Published library functions described as data (models/data/functions/*.yaml), in the same
// vocabulary the kernels declare: line buffers, window registers, adders, comparators, adder and
// min trees, popcounts, XORs, muxes, multipliers by variables and by constants, FIFOs and
// interface adapters. A description is one YAML file per function, its sizes expressions over
// the variables of a published row (points_csv.hpp); instantiate() turns a description and a row
// into an Inventory the resource model prices like any design's.
//
// File format (docs/resources.md, section 6):
//   function: NAME            family: NAME (the leave-one-family-out unit)
//   group: stereo | filter | geometric | pixelwise | flow
//   matches: REGEX            ECMAScript, searched in the row's `kernel` column
//   source: TEXT              where the structure was read (library file and facts)
//   flags: {NAME: REGEX}      1 when REGEX is found in the row's kernel, design and notes, else 0
//   let: {NAME: EXPR}         derived variables, evaluated in order
//   stages: [{stage: NAME, when: EXPR, items: [ITEM...]}]
// ITEM is a map with `kind` and expression fields (an item whose `when` or count is 0 is left out):
//   line_buffer {rows, depth, width_bits, uram, lutram}  rows memories of depth x width_bits
//   memory {depth, width_bits, copies, true_dual_port, uram, lutram}   (uram / lutram: bound there)
//   fifo {depth, width_bits, count}                 stream FIFOs (SRL or BRAM by the default mapping)
//   window {rows, cols, width_bits, count}          window registers
//   registers {width_bits, count}
//   add | compare | mux | popcount | xor {width_bits, count}   (add: dsp 1 when the source binds it
//                                                   to a DSP slice, core=AddSub_DSP; mux: fan_in N,
//                                                   count N:1 muxes, 2 by default)
//   adder_tree {inputs, width_bits, count}          inputs - 1 adders, one bit wider per level
//   min_tree | max_tree {inputs, width_bits, index_bits, count}   inputs - 1 compare-selects
//   mul | mul_const {a_bits, b_bits, count, unsigned}   by a variable | by a synthesis-time constant
//   fmul | fadd | fdiv | fexp | fconv {count}        single-precision floating-point cores
//   divider {width_bits, divisor_bits, count, sequential}   quotient bits x (subtract + select);
//                                                   sequential 1: outside a pipelined loop, an
//                                                   iterative core (one subtract + select, its state)
//   axis | m_axi | s_axilite {width_bits, count}    interface adapters
// Expressions (muparser): + - * / ^, comparisons, && ||, c ? a : b, min, max, abs, rint and
// ceil(x), floor(x), ceil_div(a, b), bits(n) (bits to hold 0..n), log2c(n) (ceil log2).
// A row on a Versal device (variable versal = 1) has DSP58 slices (27 x 24).
#pragma once

#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "parallax/resources/model.hpp"

namespace parallax::res {

struct FunctionDescription {
  std::string function, family, group, matches, source, file;
  YAML::Node flags, let, stages;
};

// The variables of one published row, and the names the row leaves unstated.
struct RowVariables {
  std::map<std::string, double> values;
  std::set<std::string> unstated;  // e.g. width when the row says "not stated"
  std::string text;                // kernel, design and notes: what flags are matched in
};

// Thrown when a row lacks what its description needs (an unstated variable): the row is listed
// as not described, with this reason.
struct NotDescribable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The compiled-in descriptions (models/data/functions), or those of a directory. Throws
// ConfigError naming the file and field for a malformed description.
const std::vector<FunctionDescription>& default_functions();
std::vector<FunctionDescription> load_functions(const std::string& directory);
FunctionDescription parse_function(const std::string& yaml_text, const std::string& file);

// The description whose `matches` finds the kernel name (the first in file order), or nullptr.
const FunctionDescription* find_function(const std::vector<FunctionDescription>& fns, const std::string& kernel);

// The inventory of a described function for one row. Throws NotDescribable when an expression
// needs a variable the row leaves unstated, ConfigError for a defect of the description (naming
// file, stage, item and field).
Inventory instantiate(const FunctionDescription& fn, const RowVariables& row);

}  // namespace parallax::res
