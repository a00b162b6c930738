// The configuration table, internal to parallax_config: one row per field of PipelineConfig with
// everything the library does with it (parse, check, write, document), and the rules between
// fields. field_names(), set_field(), validate(), to_yaml(), parse_config() and
// field_documentation() (config.cpp) only iterate these; adding a field is adding a row.
#pragma once

#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "parallax/config/config.hpp"

namespace parallax::config::detail {

// A per-field constraint on a number: what validate() requires of the value, and the words its
// message and the documentation use for the values allowed.
struct Bound {
  enum class Kind { any, range, at_least, above, at_most, one_of };
  Kind kind = Kind::any;
  int lo = 0;               // range [lo, hi]; at_least (>= lo); above (> lo)
  int hi = 0;               // range; at_most (<= hi)
  std::vector<int> values;  // one_of
  std::string zero_word;    // one_of: a word that also means 0 ("off"), accepted by the parser
  std::string note;         // appended to the message in parentheses
  bool show_value = false;  // appended to the message: "(got V)"; integer fields only

  bool holds(double v) const;
  // The values allowed: "in [1, 256]", ">= 0", "off (0), 3, 5 or 7"; empty for any.
  std::string values_text() const;
  // values_text() and the note: ">= 0 (0 = no copies)".
  std::string described() const;
  // The message for the violating value v: "must be " + described(), then the value if shown.
  std::string message(double v) const;

  Bound with_value() const;                 // a copy that names the value in its message
  Bound with_note(std::string text) const;  // a copy with a note after its message
};
Bound in_range(int lo, int hi);
Bound at_least(int lo);
Bound above(int lo);
Bound at_most(int hi);
// One of `values`; zero_word (may be empty) is accepted for 0 and named "zero_word (0)".
Bound one_of(std::vector<int> values, std::string zero_word);

// One field as users write it, and all the library does with it.
struct FieldRow {
  std::string name;          // as written in files; a pattern row: "ii_<stage>"
  std::string prefix;        // a pattern row's key prefix ("ii_"); empty for a plain field
  std::string doc;           // one line: what the field means
  std::string values;        // the values it takes, for the documentation ("census | sad")
  bool is_register = false;  // a runtime register (Registers), not structure
  // The stages that read the field (kern::ParamReader bits): those of the kern::StereoParams
  // fields it sets (kernels/param_table.hpp), kReadBySystem for a field of the system around
  // the pipeline. Filled in by field_table(), which checks is_register against the same table.
  unsigned readers = 0;
  // Sets the kern::StereoParams fields of this field (PipelineConfig::stereo_params() runs every
  // row's); empty for a field of the system around the pipeline. The region's size is the
  // caller's, not the row's.
  std::function<void(const PipelineConfig&, kern::StereoParams&)> to_params;
  // Sets the field of `key` (a pattern row: the whole key, e.g. "ii_cost") from the trimmed text
  // `value`. Throws ConfigError naming `key`.
  std::function<void(PipelineConfig&, const std::string& key, const std::string& value)> parse;
  // Appends the field's own violations, under its name (a pattern row: one name per entry).
  // Empty for a field with no constraint of its own.
  std::function<void(const PipelineConfig&, std::vector<FieldError>&)> check;
  // Writes the field's canonical lines, "key: value\n": none for an unset optional field, one
  // per entry of a pattern row. Numbers go through the stream's precision (to_yaml's).
  std::function<void(const PipelineConfig&, std::ostream&)> write;
};

// A constraint between fields, reported under `field`. validate() checks it right after the own
// check of the row named `after`, so that a report lists the violations in the table's order.
struct CrossRule {
  const char* name;   // what the rule is called in the documentation
  const char* field;  // the field its message is reported under
  const char* after;  // the row after whose own check it runs
  const char* doc;    // one line: what it requires
  // "" when the rule holds for c, else the message.
  std::string (*violation)(const PipelineConfig& c);
};

// The rectification before the cost, a reader beside kern::ParamReader's: its fields are not
// kern::StereoParams fields (kern::RectifyParams), but they change the images the cost reads.
constexpr unsigned kReadByRectify = 1u << 5;

// "cost, aggregate": the stages of a readers bit set, in pipeline order ("system" for that bit).
std::string readers_text(unsigned readers);
// The rows, in documentation order (field_names()).
const std::vector<FieldRow>& field_table();
// The rules between fields; each `after` names a row (checked when the list is built).
const std::vector<CrossRule>& cross_rules();
// Rules that need a design satisfying every other constraint (the derived bit widths): checked
// only when nothing else is violated, last; their `after` is null.
const std::vector<CrossRule>& whole_design_rules();

// s without leading and trailing white space.
std::string trim(std::string s);
// "a", "a or b", "a, b or c".
std::string either(const std::vector<std::string>& items);

}  // namespace parallax::config::detail
