// The configuration table: the rows of PipelineConfig's fields and the rules between them.
#include "field_table.hpp"

#include <algorithm>
#include <cctype>
#include <sstream>
#include <stdexcept>

#include "parallax/kernels/param_table.hpp"
#include "parallax/kernels/pipeline.hpp"

namespace parallax::config {
namespace detail {

std::string trim(std::string s) {
  auto sp = [](unsigned char ch) { return std::isspace(ch) != 0; };
  while (!s.empty() && sp(s.back())) s.pop_back();
  std::size_t i = 0;
  while (i < s.size() && sp(s[i])) ++i;
  return s.substr(i);
}

// "a", "a or b", "a, b or c".
std::string either(const std::vector<std::string>& items) {
  std::string s;
  for (std::size_t i = 0; i < items.size(); ++i) s += (i == 0 ? "" : i + 1 == items.size() ? " or " : ", ") + items[i];
  return s;
}

bool Bound::holds(double v) const {
  switch (kind) {
    case Kind::range:
      return v >= lo && v <= hi;
    case Kind::at_least:
      return v >= lo;
    case Kind::above:
      return v > lo;
    case Kind::at_most:
      return v <= hi;
    case Kind::one_of:
      return std::find(values.begin(), values.end(), v) != values.end();
    case Kind::any:
      break;
  }
  return true;
}

std::string Bound::values_text() const {
  switch (kind) {
    case Kind::range:
      return "in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    case Kind::at_least:
      return ">= " + std::to_string(lo);
    case Kind::above:
      return "> " + std::to_string(lo);
    case Kind::at_most:
      return "<= " + std::to_string(hi);
    case Kind::one_of: {
      std::vector<std::string> items;
      for (int v : values) items.push_back(v == 0 && !zero_word.empty() ? zero_word + " (0)" : std::to_string(v));
      return either(items);
    }
    case Kind::any:
      break;
  }
  return "";
}

std::string Bound::described() const {
  return note.empty() ? values_text() : values_text() + " (" + note + ")";
}

std::string Bound::message(double v) const {
  std::string m = "must be " + described();
  if (show_value) m += " (got " + std::to_string(static_cast<long long>(v)) + ")";
  return m;
}

Bound Bound::with_value() const {
  Bound b = *this;
  b.show_value = true;
  return b;
}

Bound Bound::with_note(std::string text) const {
  Bound b = *this;
  b.note = std::move(text);
  return b;
}

namespace {

Bound bound(Bound::Kind kind, int lo, int hi) {
  Bound b;
  b.kind = kind;
  b.lo = lo;
  b.hi = hi;
  return b;
}

}  // namespace

Bound in_range(int lo, int hi) {
  return bound(Bound::Kind::range, lo, hi);
}
Bound at_least(int lo) {
  return bound(Bound::Kind::at_least, lo, 0);
}
Bound above(int lo) {
  return bound(Bound::Kind::above, lo, 0);
}
Bound at_most(int hi) {
  return bound(Bound::Kind::at_most, 0, hi);
}

Bound one_of(std::vector<int> values, std::string zero_word) {
  Bound b = bound(Bound::Kind::one_of, 0, 0);
  b.values = std::move(values);
  b.zero_word = std::move(zero_word);
  return b;
}

Bound param_range(const char* param) {
  const kern::ParamLimits l = kern::param_limits(param);
  if (l.lo > l.hi) throw std::logic_error(std::string("no field of kern::StereoParams is named ") + param);
  return in_range(int(l.lo), int(l.hi));
}

}  // namespace detail

namespace {

using detail::above;
using detail::at_least;
using detail::Bound;
using detail::CrossRule;
using detail::either;
using detail::FieldRow;
using detail::in_range;
using detail::one_of;
using detail::param_range;
using detail::trim;
using Errors = std::vector<FieldError>;

const int kAngles[8] = {0, 45, 90, 135, 180, 225, 270, 315};

// --- text into values; each error names the field's key ---

// v as a number of field `key`: whole and within +-1e9 (an integer field), or finite and within
// +-1e12 (a number field); otherwise ConfigError "expected an integer" / "expected a number".
double parse_number(const std::string& key, const std::string& v, bool whole) {
  const std::string bad = "field '" + key + "': expected " + (whole ? "an integer" : "a number") + ", got '" + v + "'";
  std::size_t used = 0;
  double x = 0;
  try {
    x = whole ? double(std::stol(v, &used)) : std::stod(v, &used);
  } catch (const std::exception&) {
    throw ConfigError(bad);
  }
  const bool in_limits = whole ? (x >= -1e9 && x <= 1e9) : (x > -1e12 && x < 1e12);
  if (used != v.size() || !in_limits) throw ConfigError(bad);
  return x;
}

int parse_int(const std::string& key, const std::string& v) {
  return int(parse_number(key, v, true));
}
double parse_double(const std::string& key, const std::string& v) {
  return parse_number(key, v, false);
}

bool parse_bool(const std::string& key, const std::string& v) {
  std::string l = v;
  std::transform(l.begin(), l.end(), l.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  if (l == "true" || l == "on" || l == "yes" || l == "1") return true;
  if (l == "false" || l == "off" || l == "no" || l == "0") return false;
  throw ConfigError("field '" + key + "': expected true or false, got '" + v + "'");
}

// "5" -> 5x5, "5x3" -> 5 wide, 3 high. Assigns w before parsing h (a bad height leaves w set).
void parse_size(const std::string& key, const std::string& v, int& w, int& h) {
  const auto xpos = v.find_first_of("xX");
  if (xpos == std::string::npos) {
    w = h = parse_int(key, v);
  } else {
    w = parse_int(key, trim(v.substr(0, xpos)));
    h = parse_int(key, trim(v.substr(xpos + 1)));
  }
}

std::string join(const std::vector<std::string>& items, const char* sep) {
  std::string s;
  for (const auto& i : items) s += (s.empty() ? "" : sep) + i;
  return s;
}

// --- row builders: a field of one member, parsed, checked and written by its kind ---

using Check = std::function<void(const PipelineConfig&, Errors&)>;
using Write = std::function<void(const PipelineConfig&, std::ostream&)>;

FieldRow row(std::string name, std::string doc, std::string values) {
  FieldRow r;
  r.name = std::move(name);
  r.doc = std::move(doc);
  r.values = std::move(values);
  return r;
}

// Writes "name: value(c)\n".
template <class Value>
Write line(const std::string& name, Value value) {
  return [name, value](const PipelineConfig& c, std::ostream& o) { o << name << ": " << value(c) << "\n"; };
}

// The check of a number against b (none for Kind::any).
template <class T>
Check bounded(const std::string& name, T PipelineConfig::*m, const Bound& b) {
  if (b.kind == Bound::Kind::any) return nullptr;
  return [name, m, b](const PipelineConfig& c, Errors& e) {
    if (!b.holds(double(c.*m))) e.push_back({name, b.message(double(c.*m))});
  };
}

using ParamMember = int kern::StereoParams::*;

// A row that also sets kern::StereoParams::*param to the config's member m.
template <class T, class U>
FieldRow setting(FieldRow r, T PipelineConfig::*m, U kern::StereoParams::*param) {
  if (param != nullptr) r.to_params = [m, param](const PipelineConfig& c, kern::StereoParams& p) { p.*param = c.*m; };
  return r;
}

FieldRow integer(const char* name, int PipelineConfig::*m, const Bound& b, const char* doc,
                 ParamMember param = nullptr) {
  FieldRow r = row(name, doc, b.described());
  const std::string zero = b.zero_word;
  r.parse = [m, zero](PipelineConfig& c, const std::string& key, const std::string& v) {
    c.*m = (!zero.empty() && v == zero) ? 0 : parse_int(key, v);
  };
  r.check = bounded(name, m, b);
  r.write = line(name, [m](const PipelineConfig& c) { return c.*m; });
  return setting(r, m, param);
}

// An integer of Registers: a runtime register.
FieldRow register_int(const char* name, int Registers::*m, const Bound& b, const char* doc, ParamMember param) {
  FieldRow r = integer(name, static_cast<int PipelineConfig::*>(m), b, doc, param);
  r.is_register = true;
  return r;
}

FieldRow number(const char* name, double PipelineConfig::*m, const Bound& b, const char* doc) {
  FieldRow r = row(name, doc, b.described());
  r.parse = [m](PipelineConfig& c, const std::string& key, const std::string& v) { c.*m = parse_double(key, v); };
  r.check = bounded(name, m, b);
  r.write = line(name, [m](const PipelineConfig& c) { return c.*m; });
  return r;
}

FieldRow flag(const char* name, bool PipelineConfig::*m, const char* doc, bool kern::StereoParams::*param) {
  FieldRow r = row(name, doc, "true | false");
  r.parse = [m](PipelineConfig& c, const std::string& key, const std::string& v) { c.*m = parse_bool(key, v); };
  r.write = line(name, [m](const PipelineConfig& c) { return c.*m ? "true" : "false"; });
  return setting(r, m, param);
}

// Free text; an optional field is not written while empty.
FieldRow text(const char* name, std::string PipelineConfig::*m, bool optional, const char* doc) {
  FieldRow r = row(name, doc, optional ? "text, may be absent" : "text");
  r.parse = [m](PipelineConfig& c, const std::string&, const std::string& v) { c.*m = v; };
  const std::string n = name;
  r.write = [n, m, optional](const PipelineConfig& c, std::ostream& o) {
    if (!optional || !(c.*m).empty()) o << n << ": " << c.*m << "\n";
  };
  return r;
}

// One word of `choices`, refused when parsed otherwise.
// A choice whose index in `choices` is the kern::StereoParams enum value of *param (when given).
FieldRow choice(const char* name, std::string PipelineConfig::*m, const std::vector<std::string>& choices,
                const char* doc, ParamMember param = nullptr) {
  FieldRow r = row(name, doc, join(choices, " | "));
  if (param != nullptr)
    r.to_params = [m, choices, param](const PipelineConfig& c, kern::StereoParams& p) {
      const auto at = std::find(choices.begin(), choices.end(), c.*m);
      p.*param = at == choices.end() ? 0 : int(at - choices.begin());  // unparsed text: the first
    };
  r.parse = [m, choices](PipelineConfig& c, const std::string& key, const std::string& v) {
    if (std::find(choices.begin(), choices.end(), v) == choices.end())
      throw ConfigError("field '" + key + "': expected " + either(choices) + ", got '" + v + "'");
    c.*m = v;
  };
  r.write = line(name, [m](const PipelineConfig& c) { return c.*m; });
  return r;
}

// A row of the rectification: its value changes the images the cost stage reads.
FieldRow rectifying(FieldRow r) {
  r.readers = detail::kReadByRectify;
  return r;
}

// The names a pattern row's keys end in: what they are and which exist.
struct NameSet {
  const char* placeholder;  // in the row's name: "fifo" of "fifo_depth_<fifo>"
  const char* what;         // in messages: "FIFO"
  std::vector<std::string> names;
};

// The FIFOs and the stages of the pipeline (kernels/pipeline.hpp), each once, in its order.
NameSet fifo_names() {
  NameSet s{"fifo", "FIFO", {}};
  for (const kern::PipelineFifo& f : kern::kPipelineFifos)
    if (std::find(s.names.begin(), s.names.end(), f.name) == s.names.end()) s.names.emplace_back(f.name);
  return s;
}
NameSet stage_names() {
  NameSet s{"stage", "stage", {}};
  for (const kern::PipelineStage& st : kern::kPipelineStages)
    if (std::find(s.names.begin(), s.names.end(), st.name) == s.names.end()) s.names.emplace_back(st.name);
  return s;
}

// prefix<name>: an integer per name of `known`, kept in a map by name.
FieldRow pattern(const std::string& prefix, const NameSet& known, std::map<std::string, int> PipelineConfig::*m,
                 const Bound& b, const char* doc) {
  FieldRow r = row(prefix + "<" + known.placeholder + ">", doc,
                   "<" + std::string(known.placeholder) + ">: " + join(known.names, ", ") + "; value " + b.described());
  r.prefix = prefix;
  r.parse = [prefix, m](PipelineConfig& c, const std::string& key, const std::string& v) {
    (c.*m)[key.substr(prefix.size())] = parse_int(key, v);
  };
  r.check = [prefix, known, m, b](const PipelineConfig& c, Errors& e) {
    for (const auto& kv : c.*m) {
      const std::string field = prefix + kv.first;
      if (std::find(known.names.begin(), known.names.end(), kv.first) == known.names.end())
        e.push_back({field, "unknown " + std::string(known.what) + " '" + kv.first +
                                "' (known: " + join(known.names, ", ") + ")"});
      if (!b.holds(kv.second)) e.push_back({field, b.message(kv.second)});
    }
  };
  r.write = [prefix, m](const PipelineConfig& c, std::ostream& o) {
    for (const auto& kv : c.*m) o << prefix << kv.first << ": " << kv.second << "\n";
  };
  return r;
}

// --- the fields whose value is not one member ---

FieldRow roi_row() {
  static_assert(kern::kMaxWidthPx == kern::kMaxHeightPx, "one bound names both sides");
  const Bound side = param_range("width_px");
  FieldRow r = row("roi", "region of interest: the centred crop of the input the design processes (docs/evaluation.md)",
                   "WxH, each side " + side.values_text() + ", or full (the whole image)");
  r.parse = [](PipelineConfig& c, const std::string& key, const std::string& v) {
    if (v == "full") {
      c.roi_full = true;
    } else {
      c.roi_full = false;
      parse_size(key, v, c.roi_width_px, c.roi_height_px);
    }
  };
  r.check = [side](const PipelineConfig& c, Errors& e) {
    if (!c.roi_full && !(side.holds(c.roi_width_px) && side.holds(c.roi_height_px)))
      e.push_back({"roi", "each side must be " + side.values_text() + ", or 'full'"});
  };
  r.write = line("roi", [](const PipelineConfig& c) {
    return c.roi_full ? std::string("full") : std::to_string(c.roi_width_px) + "x" + std::to_string(c.roi_height_px);
  });
  return r;
}

FieldRow window_row() {
  const Bound side = param_range("window_w");
  FieldRow r = row("window", "matching window of the cost, WxH (W wide, H high) or N for NxN",
                   "both sides odd, " + side.values_text());
  r.parse = [](PipelineConfig& c, const std::string& key, const std::string& v) {
    parse_size(key, v, c.window_w, c.window_h);
  };
  r.check = [side](const PipelineConfig& c, Errors& e) {
    if (!(side.holds(c.window_w) && side.holds(c.window_h) && c.window_w % 2 == 1 && c.window_h % 2 == 1))
      e.push_back({"window", "both sides odd, " + side.values_text() + " (got " + std::to_string(c.window_w) + "x" +
                                 std::to_string(c.window_h) + ")"});
  };
  r.to_params = [](const PipelineConfig& c, kern::StereoParams& p) {
    p.window_w = c.window_w;
    p.window_h = c.window_h;
  };
  r.write = line("window",
                 [](const PipelineConfig& c) { return std::to_string(c.window_w) + "x" + std::to_string(c.window_h); });
  return r;
}

FieldRow paths_row() {
  FieldRow r = row("paths", "SGM path directions aggregated (docs/algorithm.md §3)",
                   "a count 1, 2, 3, 4, 5 (4 and 180, one pass) or 8 (two passes), or a list of angles of 0, 45, ..., "
                   "315 such as [0, 90, 180]");
  r.parse = [](PipelineConfig& c, const std::string&, const std::string& v) { c.path_mask = parse_paths(v); };
  r.check = [](const PipelineConfig& c, Errors& e) {
    if (!(c.path_mask != 0 && (c.path_mask & ~kern::kAllPaths) == 0))
      e.push_back({"paths", "at least one path of 0..315"});
  };
  r.to_params = [](const PipelineConfig& c, kern::StereoParams& p) { p.path_mask = c.path_mask; };
  r.write = line("paths", [](const PipelineConfig& c) { return paths_to_string(c.path_mask); });
  return r;
}

using P = PipelineConfig;
using K = kern::StereoParams;

std::vector<FieldRow> make_table() {
  return {
      text("name", &P::name, false, "the design's name (reports, the exported project)"),
      roi_row(),
      choice("cost", &P::cost, {"census", "sad"}, "matching cost", &K::cost),
      choice("census", &P::census, {"full", "sparse", "symmetric"},
             "census taps: every tap against the centre, every second tap, or centre-symmetric pairs", &K::census),
      window_row(),
      integer("disparities", &P::disparities, param_range("disparities").with_value(),
              "D: how many disparities are searched, [min_disparity, min_disparity + D)", &K::disparities),
      integer("min_disparity", &P::min_disparity, param_range("min_disparity"),
              "m: the smallest disparity searched, in pixels (far limit f*B/m; 0 = infinity)", &K::min_disparity),
      integer("parallel_units", &P::parallel_units, Bound{}, "PU: disparities computed per firing; >= 1, divides D",
              &K::parallel_units),
      paths_row(),
      register_int("p1", &Registers::p1, param_range("p1").with_value(), "SGM penalty of a disparity step of 1",
                   &K::p1),
      register_int("p2", &Registers::p2, param_range("p2"), "SGM penalty of larger steps, greater than p1", &K::p2),
      integer("p2_adaptive", &P::p2_adaptive, param_range("p2_adaptive"),
              "intensity-adaptive P2 gain a: along a path P2 drops by (a |I(p) - I(q)|) >> 4, never below p1 + 1; "
              "0 = off (no hardware); one-pass designs (paths up to 5)",
              &K::p2_adaptive),
      choice("aggregation", &P::aggregation, {"sgm", "mgm"},
             "path recursion: SGM steps from the path's predecessor; MGM averages the steps from it and the "
             "neighbour across the path (more memory; forward paths or eight)",
             &K::aggregation),
      integer("subpixel_bits", &P::subpixel_bits, param_range("subpixel_bits"),
              "fraction bits of the disparity codes: a parabola through the aggregates at d-1, d, d+1 refines "
              "the winner (0 = integer disparities, no hardware)",
              &K::subpixel_bits),
      flag("lr_check", &P::lr_check, "left-right consistency check", &K::lr_check),
      register_int("lr_tolerance", &Registers::lr_tolerance, param_range("lr_tolerance"),
                   "largest left-right disagreement in pixels that the check accepts", &K::lr_tolerance),
      register_int("uniqueness_pct", &Registers::uniqueness_pct, param_range("uniqueness_pct"),
                   "uniqueness margin in percent: invalid when a disparity 2+ steps from the best costs less "
                   "than (100 + u)% of it; 0 = off (no hardware)",
                   &K::uniqueness_pct),
      integer("median", &P::median, one_of({0, 3, 5, 7}, "off"), "k x k median filter of the disparity codes",
              &K::median),
      integer("clock_mhz", &P::clock_mhz, in_range(1, 1000), "processing clock in MHz (timing model)"),
      rectifying(choice("rectify", &P::rectify, {"none", "nearest", "bilinear"},
                        "rectification by remap tables before the ROI crop")),
      rectifying(
          integer("rectify_rows", &P::rectify_rows, in_range(1, 256), "line-buffer rows of the rectification stage")),
      rectifying(integer("rectify_frac_bits", &P::rectify_frac_bits, in_range(0, 10),
                         "fixed-point fraction bits of bilinear maps")),
      rectifying(text("rectify_maps_left", &P::rectify_maps_left, true,
                      "left remap table (OpenCV FileStorage, float map_x, map_y; relative to the file's folder)")),
      rectifying(text("rectify_maps_right", &P::rectify_maps_right, true, "right remap table, as rectify_maps_left")),
      choice("input", &P::input, {"memory", "camera"},
             "how pairs arrive: streamed from DDR, or a camera's pixel clock"),
      number("input_gbps", &P::input_gbps, above(0), "memory input bandwidth, GB/s (left + right bytes)"),
      number("camera_pixel_mhz", &P::camera_pixel_mhz, above(0), "camera pixel clock, MHz"),
      integer("camera_h_blank_px", &P::camera_h_blank_px, at_least(0), "camera horizontal blanking, pixels per row"),
      integer("camera_v_blank_rows", &P::camera_v_blank_rows, at_least(0), "camera vertical blanking, rows per frame"),
      number("ddr_gbps", &P::ddr_gbps, above(0), "DDR bandwidth of the 8-path design's frame buffer, GB/s"),
      integer("ddr_latency_ns", &P::ddr_latency_ns, at_least(0), "DDR access latency, ns"),
      integer("fifo_depth", &P::fifo_depth, at_least(1), "default depth of every FIFO"),
      choice("estimate", &P::estimate, {"csynth", "routed"},
             "resource figures as Vitis HLS C synthesis reports them, or after place and route"),
      pattern("fifo_depth_", fifo_names(), &P::fifo_depths, at_least(1), "depth of one FIFO"),
      pattern("ii_", stage_names(), &P::stage_ii, at_least(1), "initiation interval of one stage (calibration)"),
      pattern("latency_", stage_names(), &P::stage_latency, at_least(0), "pipeline latency of one stage, cycles"),
      pattern("setup_", stage_names(), &P::stage_setup, at_least(0),
              "cycles of per-frame set-up before a stage's first firing"),
      number("host_copy_gbps", &P::host_copy_gbps, at_least(0).with_note("0 = no copies"),
             "the processor's copies of each pair in and map out, GB/s"),
      number("host_latency_ms", &P::host_latency_ms, at_least(0), "fixed host latency per frame, ms (calibration)"),
      number("host_frame_ms", &P::host_frame_ms, at_least(0), "lower bound of the frame interval, ms (calibration)"),
      number("avoid_ms", &P::avoid_ms, at_least(0),
             "the avoidance stage's time per frame on the processor, ms (a model: flights are repeatable)"),
  };
}

// Whether c keeps the kernels' rule r (kernels/param_table.hpp: the predicate is written there
// once, for validate(), the fast engine and the func run); the messages here name the values.
bool keeps(const P& c, kern::ParamRule r) {
  return kern::rule_holds(c.stereo_params(640, 360), r);
}

std::vector<CrossRule> make_rules() {
  return {
      {"census_bits", "window", "window", "census: at most 64 code bits",
       [](const P& c) -> std::string {
         return keeps(c, kern::kRuleCensusBits)
                    ? ""
                    : "a full census needs w*h - 1 <= 64 bits (9x7 is the largest 9-wide window; sparse and "
                      "symmetric take 9x9)";
       }},
      {"units_divide_disparities", "parallel_units", "parallel_units", "parallel_units >= 1 divides disparities",
       [](const P& c) -> std::string {
         return keeps(c, kern::kRuleUnitsDivide) && c.disparities >= 1
                    ? ""
                    : "must be >= 1 and divide disparities (" + std::to_string(c.parallel_units) + " does not divide " +
                          std::to_string(c.disparities) + ")";
       }},
      {"p2_adaptive_one_pass", "p2_adaptive", "p2_adaptive", "p2_adaptive: a one-pass design (paths up to 5)",
       [](const P& c) -> std::string {
         return keeps(c, kern::kRuleP2AdaptiveOnePass)
                    ? ""
                    : "needs a one-pass design (paths 0, 45, 90, 135 and 180): the two-pass frame buffer does not "
                      "carry the left image's intensities";
       }},
      {"mgm_paths", "aggregation", "aggregation", "aggregation: mgm with forward paths or eight paths",
       [](const P& c) -> std::string {
         return keeps(c, kern::kRuleMgmPaths)
                    ? ""
                    : "mgm needs forward paths (0, 45, 90, 135) or all eight: the one-pass 180-degree path's second "
                      "predecessor (x, y+1) is in the next row";
       }},
      {"p1_below_p2", "p2", "p1", "p1 < p2",
       [](const P& c) -> std::string {
         return c.p1 < c.p2  // p1 >= 0 is p1's own range
                    ? ""
                    : "must be greater than p1 (p1 = " + std::to_string(c.p1) + ", p2 = " + std::to_string(c.p2) + ")";
       }},
      {"bilinear_fraction", "rectify_frac_bits", "rectify_frac_bits", "rectify: bilinear needs rectify_frac_bits >= 1",
       [](const P& c) -> std::string {
         return c.rectify != "bilinear" || c.rectify_frac_bits >= 1 ? "" : "bilinear needs at least 1 fraction bit";
       }},
  };
}

}  // namespace

unsigned parse_paths(const std::string& text) {
  const std::string t = trim(text);
  if (t.find(',') == std::string::npos && t.find('[') == std::string::npos) {
    const int n = parse_int("paths", t);
    switch (n) {
      case 1:
        return kern::kPath0;
      case 2:
        return kern::kPath0 | kern::kPath90;
      case 3:
        return kern::kPath0 | kern::kPath45 | kern::kPath90;
      case 4:
        return kern::kForwardPaths;
      case 5:
        return kern::kForwardPaths | kern::kPath180;
      case 8:
        return kern::kAllPaths;
      default:
        throw ConfigError("field 'paths': " + t +
                          " is not a path count (1, 2, 3, 4, 5 or 8); give a list of angles such as 0,90 otherwise");
    }
  }
  std::string body = t;
  body.erase(std::remove(body.begin(), body.end(), '['), body.end());
  body.erase(std::remove(body.begin(), body.end(), ']'), body.end());
  unsigned mask = 0;
  std::stringstream ss(body);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const int a = parse_int("paths", trim(item));
    bool found = false;
    for (int i = 0; i < 8; ++i)
      if (kAngles[i] == a) {
        mask |= 1u << i;
        found = true;
      }
    if (!found) throw ConfigError("field 'paths': angle " + std::to_string(a) + " is not one of 0, 45, ..., 315");
  }
  return mask;
}

std::string paths_to_string(unsigned mask) {
  if (mask == kern::kForwardPaths) return "4";
  if (mask == (kern::kForwardPaths | kern::kPath180)) return "5";
  if (mask == kern::kAllPaths) return "8";
  std::string s;
  for (int i = 0; i < 8; ++i)
    if (mask & (1u << i)) s += (s.empty() ? "" : ",") + std::to_string(kAngles[i]);
  return "[" + s + "]";
}

namespace detail {

std::string readers_text(unsigned readers) {
  const struct {
    unsigned bit;
    const char* name;
  } stages[] = {{kern::kReadByCost, "cost"},     {kern::kReadByAggregate, "aggregate"}, {kern::kReadBySelect, "select"},
                {kern::kReadByMedian, "median"}, {kern::kReadBySystem, "system"},       {kReadByRectify, "rectify"}};
  std::vector<std::string> names;
  for (const auto& st : stages)
    if ((readers & st.bit) != 0) names.emplace_back(st.name);
  return join(names, ", ");
}

namespace {

// The kern::StereoParams fields (kernels/param_table.hpp names) that the row `name` sets.
std::vector<std::string> params_of_row(const std::string& name) {
  if (name == "roi") return {"width_px", "height_px"};
  if (name == "window") return {"window_w", "window_h"};
  if (name == "paths") return {"path_mask"};
  return {name};
}

// Each row's readers from the kernels' table, read on a Census design (so that the census kind
// shows its reader); a row that sets no field of it is read by the system model alone.
void set_readers(std::vector<FieldRow>& rows) {
  kern::StereoParams p{};
  p.cost = kern::kCostCensus;
  std::vector<std::string> uncovered;
  kern::for_each_param(p, [&](const kern::ParamField& f) { uncovered.emplace_back(f.name); });
  for (FieldRow& r : rows) {
    bool is_register = false;
    const unsigned preset = r.readers;  // a row of the rectification (rectifying())
    r.readers = 0;
    for (const std::string& param : params_of_row(r.name))
      kern::for_each_param(p, [&](const kern::ParamField& f) {
        if (param != f.name) return;
        r.readers |= f.readers;
        is_register = is_register || f.is_register;
        uncovered.erase(std::remove(uncovered.begin(), uncovered.end(), param), uncovered.end());
      });
    const bool sets_params = r.readers != 0 && r.name != "roi";  // the region's size is the caller's
    if (preset != 0 && r.readers != 0)
      throw std::logic_error("field " + r.name + ": preset readers on a kern::StereoParams field");
    if (r.readers == 0) r.readers = preset != 0 ? preset : kern::kReadBySystem;
    if (is_register != r.is_register)
      throw std::logic_error("field " + r.name + ": the register mark disagrees with kern::for_each_param");
    if (sets_params != bool(r.to_params))
      throw std::logic_error("field " + r.name + ": sets kern::StereoParams " + (sets_params ? "without" : "with") +
                             " a to_params");
  }
  if (!uncovered.empty())
    throw std::logic_error("no configuration field sets kern::StereoParams::" + uncovered.front());
}

}  // namespace

const std::vector<FieldRow>& field_table() {
  static const std::vector<FieldRow> rows = [] {
    std::vector<FieldRow> t = make_table();
    set_readers(t);
    return t;
  }();
  return rows;
}

const std::vector<CrossRule>& cross_rules() {
  static const std::vector<CrossRule> rules = [] {
    std::vector<CrossRule> r = make_rules();
    for (const CrossRule& rule : r) {
      const auto& rows = field_table();
      if (std::none_of(rows.begin(), rows.end(), [&](const FieldRow& f) { return f.name == rule.after; }))
        throw std::logic_error(std::string("configuration rule ") + rule.name + " runs after no field");
    }
    return r;
  }();
  return rules;
}

const std::vector<CrossRule>& whole_design_rules() {
  static const std::vector<CrossRule> rules = {
      {"aggregate_width", "p2", nullptr, "the aggregation's sums fit 31 bits (path count x (cost_max + P2 register))",
       [](const PipelineConfig& c) -> std::string {
         const auto p = c.stereo_params(c.roi_full ? 640 : c.roi_width_px, c.roi_full ? 360 : c.roi_height_px);
         return kern::rule_holds(p, kern::kRuleAggregateWidth) ? "" : "aggregate would need more than 31 bits";
       }},
      // The net under the rows and rules above: a design validate() accepts is one every engine
      // runs (kern::for_each_param_violation, the fast engine's and the func run's own check).
      {"kernel_contract", "name", nullptr, "every engine runs the design (kernels/param_table.hpp)",
       [](const PipelineConfig& c) -> std::string {
         const auto p = c.stereo_params(c.roi_full ? 640 : c.roi_width_px, c.roi_full ? 360 : c.roi_height_px);
         std::string broken;
         kern::for_each_param_violation(p, [&](const kern::ParamViolation& v) {
           if (broken.empty())
             broken = std::string("the kernels refuse the design: ") + v.field.name + " " + v.requires_text;
         });
         return broken;
       }},
  };
  return rules;
}

}  // namespace detail
}  // namespace parallax::config
