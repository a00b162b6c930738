// validation: the resource model against the published rows of models/data/vitis_vision_points.csv
// (AMD Vitis Vision, HLS C-synthesis estimates) described by models/data/functions: every row
// listed, the compiled-in coefficients equal to a fresh fit, the fit recovering known
// coefficients and DSP thresholds, and the leave-one-family-out accuracy it reaches
// (docs/resources.md, section 6).
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "parallax/config/config.hpp"
#include "parallax/resources/fit.hpp"

namespace parallax::test {
namespace {

const std::string kRoot = PARALLAX_SOURCE_DIR;
const std::string kPoints = kRoot + "/models/data/vitis_vision_points.csv";

std::vector<res::FitRow> rows() {
  std::vector<res::FitRow> r = res::describe_rows(res::load_points_csv(kPoints), res::default_functions(), kPoints);
  res::apply_exclusions(r, res::default_exclusions());
  for (auto& d : res::load_design_points(kRoot + "/models/data/published_points.yaml", kRoot)) r.push_back(d);
  return r;
}

const res::FitResult& fitted() {
  static const res::FitResult f = res::fit(rows(), res::default_coefficients());
  return f;
}

TEST(Calibration, EveryRowIsListedAndTheUndescribedSayWhy) {
  const auto& f = fitted();
  EXPECT_EQ(f.rows.size(), res::load_points_csv(kPoints).size() + 2);
  std::set<std::string> groups;
  for (const auto& r : f.rows) {
    if (!r.described) {
      EXPECT_FALSE(r.not_described.empty()) << r.source;
    }
    if (r.described && !r.validation_only) groups.insert(r.group);
  }
  for (const char* g : {"stereo", "filter", "geometric"}) EXPECT_TRUE(groups.count(g)) << g;
  EXPECT_GE(f.fitted_rows, 100);
}

TEST(Calibration, CompiledCoefficientsAreTheFit) {
  // `parallax fit-resources --write models/data/resource_model.yaml` after changing a description
  // or a kernel's declarations keeps this true.
  const res::Coefficients& c = res::default_coefficients();
  const res::Coefficients& k = fitted().coefficients;
  EXPECT_EQ(c.dsp_min_bits_var, k.dsp_min_bits_var);
  EXPECT_EQ(c.dsp_min_bits_const, k.dsp_min_bits_const);
  EXPECT_EQ(c.dsp_per_fmul, k.dsp_per_fmul);
  EXPECT_EQ(c.dsp_per_fadd, k.dsp_per_fadd);
  EXPECT_EQ(c.dsp_per_fexp, k.dsp_per_fexp);
  for (int i = 0; i < res::kFeatureCount; ++i) {
    EXPECT_NEAR(c.lut[i], k.lut[i], 2e-3 * std::max(1.0, k.lut[i])) << res::feature_name(i);
    EXPECT_NEAR(c.ff[i], k.ff[i], 2e-3 * std::max(1.0, k.ff[i])) << res::feature_name(i);
  }
}

TEST(Calibration, RecoversKnownCoefficientsAndDspThresholds) {
  std::vector<res::FitRow> synthetic;
  for (auto& r : rows())
    if (r.described && !r.validation_only) synthetic.push_back(r);
  res::Coefficients truth = res::default_coefficients();
  truth.dsp_min_bits_var = 12;
  truth.dsp_min_bits_const = 99;
  for (int i = 0; i < res::kFeatureCount; ++i) {
    truth.lut[i] = truth.lut_prior[i] * 1.5 + 0.1;
    truth.ff[i] = truth.ff_prior[i] * 0.7 + 0.1;
  }
  for (auto& r : synthetic) {
    const res::Usage u = res::estimate(r.inventory, truth).total;
    r.published = {u.bram18k, u.uram, u.dsp, u.ff, u.lut};
  }
  const res::Coefficients k =
      res::fit_coefficients(synthetic, std::vector<bool>(synthetic.size(), true), res::default_coefficients());
  int exact_dsp = 0;
  for (const auto& r : synthetic) exact_dsp += res::estimate(r.inventory, k).total.dsp == r.published.dsp;
  EXPECT_EQ(exact_dsp, int(synthetic.size())) << "learned " << k.dsp_min_bits_var << "/" << k.dsp_min_bits_const;
  for (const auto& r : synthetic) {
    const res::Usage u = res::estimate(r.inventory, k).total;
    EXPECT_NEAR(double(u.lut), double(r.published.lut), 0.05 * double(r.published.lut) + 2) << r.kernel;
    EXPECT_NEAR(double(u.ff), double(r.published.ff), 0.05 * double(r.published.ff) + 2) << r.kernel;
  }
}

// What the model reaches on the kept published rows today (docs/resources.md, section 6), held
// as regression guards a little above the measured leave-one-family-out figures (2026-12-06, the
// datapath priced from the operator table, only the Vitis overheads fitted, resize's once-per-frame
// dividers iterative: BRAM exact 80.6 %, DSP exact 52.3 %, LUT median 29.0 % / p90 106.6 %, FF
// 32.2 % / 114.3 %). Issue 42's targets (BRAM
// >= 90 %, DSP >= 70 %, LUT/FF median <= 20 %, p90 <= 45 %) are NOT met; `parallax fit-resources`
// prints them with "met" / "NOT met".
TEST(Calibration, HoldsTheMeasuredAccuracy) {
  const auto& s = fitted().stats;
  EXPECT_GE(s[res::kResBram].lofo.exact_share(), 0.80);
  EXPECT_GE(s[res::kResDsp].lofo.exact_share(), 0.52);
  EXPECT_LE(s[res::kResLut].lofo.median_pct, 31.0);
  EXPECT_LE(s[res::kResLut].lofo.p90_pct, 112.0);
  EXPECT_LE(s[res::kResFf].lofo.median_pct, 34.0);
  EXPECT_LE(s[res::kResFf].lofo.p90_pct, 120.0);
}

// The exclusions are few, each with evidence, and each names a row that exists (kernel and
// design exact): a renamed row would otherwise silently come back into the fit.
TEST(Calibration, ExclusionsAreFewAndEachMatchesARow) {
  const auto& ex = res::default_exclusions();
  const auto points = res::load_points_csv(kPoints);
  EXPECT_LE(double(ex.size()), 0.15 * double(points.size()));
  for (const auto& e : ex) {
    EXPECT_GT(e.evidence.size(), 80u) << e.kernel;
    EXPECT_NE(e.resources, 0u) << e.kernel;
    int matches = 0;
    for (const auto& p : points) matches += p.kernel == e.kernel && p.design == e.design;
    EXPECT_GE(matches, 1) << e.kernel << " / " << e.design;
  }
  EXPECT_EQ(fitted().excluded_rows, int(ex.size()));
  EXPECT_THROW(res::parse_exclusions("rows: [{kernel: a, design: b, evidence: c, resources: [luts]}]", "x.yaml"),
               config::ConfigError);
}

}  // namespace
}  // namespace parallax::test
