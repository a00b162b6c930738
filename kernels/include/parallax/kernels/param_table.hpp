// The rules between the fields of StereoParams (whose table, kern::for_each_param, is in
// params.hpp beside the struct) and the one parameter check built on both: the fast engine, the
// func run and validate() all use it (docs/architecture.md, "Adding a knob"). C++14, no STL.
#pragma once

#include "parallax/kernels/params.hpp"

namespace parallax {
namespace kern {

// The rules between fields (and of one field beyond its range), each a name, the field it is
// reported on, and what it requires.
enum ParamRule : int {
  kRuleWindowOdd = 0,
  kRuleCensusBits,
  kRulePathsKnown,
  kRuleP1BelowP2,
  kRuleMedianSize,
  kRuleUnitsDivide,
  kRuleP2AdaptiveOnePass,
  kRuleMgmPaths,
  kRuleAggregateWidth,
  kParamRuleCount
};
struct ParamRuleInfo {
  const char* name;
  const char* field;
  const char* requires_text;
};
constexpr ParamRuleInfo kParamRules[kParamRuleCount] = {
    {"window_odd", "window_w", "window sides must be odd"},
    {"census_bits", "window_w", "census window needs at most 64 bits"},
    {"paths_known", "path_mask", "path set empty or unknown"},
    {"p1_below_p2", "p2", "need 0 <= p1 < p2"},
    {"median_size", "median", "median must be 0, 3, 5 or 7"},
    {"units_divide_disparities", "parallel_units", "parallel_units must divide disparities"},
    {"p2_adaptive_one_pass", "p2_adaptive", "p2_adaptive needs a one-pass design (paths <= 5)"},
    {"mgm_paths", "aggregation", "mgm needs forward paths or all eight"},
    {"aggregate_width", "p2", "aggregate wider than 31 bits"},
};

// Whether p keeps rule r. Rules whose inputs are out of their fields' ranges hold vacuously
// where evaluating them would not be meaningful (the range check reports those).
inline bool rule_holds(const StereoParams& p, int r) {
  switch (r) {
    case kRuleWindowOdd:
      return p.window_w % 2 == 1 && p.window_h % 2 == 1;
    case kRuleCensusBits:
      return p.cost != kCostCensus || census_bits(p.census, p.window_w, p.window_h) <= kMaxCensusBits;
    case kRulePathsKnown:
      return p.path_mask != 0 && (p.path_mask & ~kAllPaths) == 0;
    case kRuleP1BelowP2:
      return p.p1 >= 0 && p.p1 < p.p2;
    case kRuleMedianSize:
      return p.median == 0 || p.median == 1 || p.median == 3 || p.median == 5 || p.median == 7;
    case kRuleUnitsDivide:
      return p.parallel_units >= 1 && p.disparities % p.parallel_units == 0;
    case kRuleP2AdaptiveOnePass:
      return p.p2_adaptive == 0 || !two_pass_paths(p.path_mask);
    case kRuleMgmPaths:
      return p.aggregation != kAggregationMgm || mgm_paths_supported(p.path_mask);
    case kRuleAggregateWidth:
      return aggregate_bits(p) <= 31;
    default:
      return true;
  }
}

// One violation: a field outside its range (rule -1; the field's limits in `field`), or a rule
// broken (its index; `field` holds the field it is reported on and its value).
struct ParamViolation {
  int rule;
  ParamField field;
  const char* requires_text;  // "out of range" for a range
};

// Calls v(const ParamViolation&) for every violation of p: each field outside its range, then
// each rule broken, in table order; the rules only when every field is in range. Returns how
// many. The one parameter check of the fast engine, the func run and validate() (whose rows and
// rules take their limits and predicates from this table).
template <class Visitor>
int for_each_param_violation(const StereoParams& p, Visitor&& v) {
  int out_of_range = 0;
  for_each_param(p, [&](const ParamField& f) {
    if (f.value < f.lo || f.value > f.hi) {
      v(ParamViolation{-1, f, "out of range"});
      ++out_of_range;
    }
  });
  if (out_of_range > 0) return out_of_range;
  int broken = 0;
  for (int r = 0; r < kParamRuleCount; ++r)
    if (!rule_holds(p, r)) {
      ParamField reported{kParamRules[r].field, 0, 0u, false, 0, 0};
      for_each_param(p, [&](const ParamField& f) {
        if (same_name(f.name, kParamRules[r].field)) reported = f;
      });
      v(ParamViolation{r, reported, kParamRules[r].requires_text});
      ++broken;
    }
  return broken;
}

}  // namespace kern
}  // namespace parallax
