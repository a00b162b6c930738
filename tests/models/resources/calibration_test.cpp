// validation: the resource model against the published rows of models/data/vitis_vision_points.csv
// (AMD Vitis Vision, HLS C-synthesis estimates) described by models/data/functions: every row
// listed, the compiled-in coefficients equal to a fresh fit, the fit recovering known
// coefficients and DSP thresholds, and the leave-one-family-out accuracy it reaches
// (docs/resources.md, section 6).
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "parallax/resources/fit.hpp"

namespace parallax::test {
namespace {

const std::string kRoot = PARALLAX_SOURCE_DIR;
const std::string kPoints = kRoot + "/models/data/vitis_vision_points.csv";

std::vector<res::FitRow> rows() {
  std::vector<res::FitRow> r = res::describe_rows(res::load_points_csv(kPoints), res::default_functions(), kPoints);
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

// What the model reaches on the published rows today (docs/resources.md, section 6), held as
// regression guards a little below the measured figures (2026-12-01: BRAM exact 75.7 %, DSP exact
// 50.4 %, LUT leave-one-family-out median 34.9 % / p90 81.0 %, FF 25.3 % / 80.6 %). The issue's
// targets (BRAM >= 90 %, DSP >= 80 %, LUT/FF median <= 20 %, p90 <= 40 %) are NOT met yet;
// `parallax fit-resources` prints them with "met" / "NOT met".
TEST(Calibration, HoldsTheMeasuredAccuracy) {
  const auto& s = fitted().stats;
  EXPECT_GE(s[res::kResBram].lofo.exact_share(), 0.75);
  EXPECT_GE(s[res::kResDsp].lofo.exact_share(), 0.49);
  EXPECT_LE(s[res::kResLut].lofo.median_pct, 36.0);
  EXPECT_LE(s[res::kResLut].lofo.p90_pct, 85.0);
  EXPECT_LE(s[res::kResFf].lofo.median_pct, 27.0);
  EXPECT_LE(s[res::kResFf].lofo.p90_pct, 85.0);
}

}  // namespace
}  // namespace parallax::test
