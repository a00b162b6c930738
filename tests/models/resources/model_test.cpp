// unit + golden: the resource model on the published points (BRAM exact for the Vitis kernels,
// the seed design within 10 %), the compiled-in coefficients equal a fresh fit, the per-stage
// breakdown of both paper presets against golden JSON, utilisation and power.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "parallax/resources/fit.hpp"
#include "parallax/resources/model.hpp"

namespace parallax::test {
namespace {

const std::string kRoot = PARALLAX_SOURCE_DIR;

const std::vector<res::PublishedPoint>& points() {
  static const auto p = res::load_points(kRoot + "/models/data/published_points.yaml", kRoot);
  return p;
}
const res::PublishedPoint& point(const std::string& name) {
  for (const auto& p : points())
    if (p.name == name) return p;
  throw std::runtime_error("no point " + name);
}

TEST(ResourcesPublished, BramExactForTheVitisKernels) {
  for (const char* name :
       {"vitis-sgbm-1080p", "vitis-medianblur-5x5", "vitis-medianblur-3x3", "vitis-remap-64-bilinear"}) {
    const auto& p = point(name);
    EXPECT_EQ(res::estimate(p.inventory).total.bram18k, p.published.bram18k) << name;
  }
}

TEST(ResourcesPublished, SeedDesignBramWithinTenPercent) {
  const auto& p = point("ruf2018-census");
  const double bram = double(res::estimate(p.inventory).total.bram18k);
  EXPECT_NEAR(bram, 132.0, 13.2);
  // The inference behind it: 3 disparities per path-cost word. Other packings miss the band.
  config::PipelineConfig cfg = config::load_config(kRoot + "/configs/ruf2018-census.yaml");
  EXPECT_EQ(cfg.row_packing, 3);
  for (int packing : {1, 2, 4}) {
    cfg.row_packing = packing;
    const double b = double(res::estimate(res::design_inventory(cfg, 640, 360)).total.bram18k);
    EXPECT_GT(std::fabs(b - 132.0), 13.2) << "packing " << packing << " gives " << b;
  }
}

TEST(ResourcesPublished, MediansNeedNoDsp) {
  EXPECT_EQ(res::estimate(point("vitis-medianblur-5x5").inventory).total.dsp, 0);
  EXPECT_EQ(res::estimate(point("vitis-medianblur-3x3").inventory).total.dsp, 0);
}

// The coefficients compiled in are the fit of the published points (refit with
// `parallax fit-resources --write models/data/resource_model.yaml` after changing a kernel's
// declarations), and the leave-one-out LUT error stays where docs/resources.md reports it.
TEST(ResourcesFit, CompiledCoefficientsAreTheFit) {
  const res::Coefficients& c = res::default_coefficients();
  const res::FitResult f = res::fit(points(), c);
  auto near = [](double a, double b) { return std::fabs(a - b) <= 1e-3 * std::max(1.0, std::fabs(b)); };
  EXPECT_TRUE(near(c.lut_scale, f.coefficients.lut_scale)) << c.lut_scale << " vs " << f.coefficients.lut_scale;
  EXPECT_TRUE(near(c.lut_per_stage, f.coefficients.lut_per_stage)) << c.lut_per_stage;
  EXPECT_TRUE(near(c.lut_per_memory, f.coefficients.lut_per_memory)) << c.lut_per_memory;
  EXPECT_TRUE(near(c.ff_per_op_bit, f.coefficients.ff_per_op_bit)) << c.ff_per_op_bit;
  EXPECT_TRUE(near(c.ff_per_stage, f.coefficients.ff_per_stage)) << c.ff_per_stage;
  EXPECT_LE(f.lut_loo_mean_pct, 25.0);
  EXPECT_EQ(f.rows.size(), points().size());
}

TEST(ResourcesFit, RecoversKnownCoefficients) {
  // Synthetic points made with known coefficients are fitted back.
  res::Coefficients truth = res::default_coefficients();
  truth.lut_scale = 1.3;
  truth.lut_per_stage = 250;
  truth.lut_per_memory = 12;
  truth.ff_per_op_bit = 0.7;
  truth.ff_per_stage = 300;
  std::vector<res::PublishedPoint> synthetic = points();
  for (auto& p : synthetic) p.published = res::estimate(p.inventory, truth).total;
  res::Coefficients start = truth;
  start.lut_scale = 1;
  start.lut_per_stage = 100;
  start.lut_per_memory = 1;
  start.ff_per_op_bit = 0.1;
  start.ff_per_stage = 50;
  const res::FitResult f = res::fit(synthetic, start);
  EXPECT_NEAR(f.coefficients.lut_scale, 1.3, 0.01);
  EXPECT_NEAR(f.coefficients.lut_per_stage, 250, 5);
  EXPECT_NEAR(f.coefficients.ff_per_op_bit, 0.7, 0.01);
  EXPECT_LT(f.lut_loo_max_pct, 1.0);
}

TEST(ResourcesModel, StorageFollowsTheDefaultRules) {
  config::PipelineConfig cfg = config::load_config(kRoot + "/configs/ruf2018-census.yaml");
  const res::Inventory inv = res::design_inventory(cfg, 640, 360);
  for (const auto& m : inv.memories) {
    if (m.kind == res::MemoryKind::fifo) {
      EXPECT_NE(m.per_copy.storage, res::Storage::bram) << m.name;
    }
    if (m.name == "left_line_buffer") {
      EXPECT_EQ(m.copies, 5);  // the window's rows
      EXPECT_EQ(m.per_copy.bram18k, 1);
    }
  }
  // FIFO names are the cycle model's.
  std::vector<std::string> fifos;
  for (const auto& m : inv.memories)
    if (m.kind == res::MemoryKind::fifo) fifos.push_back(m.name);
  EXPECT_EQ(fifos, (std::vector<std::string>{"left_px", "right_px", "cost", "sum", "disp_lr", "disp_out"}));
}

TEST(ResourcesModel, UtilisationAndPower) {
  const res::Device* zu3 = res::find_device("XCZU3EG");
  ASSERT_NE(zu3, nullptr);
  res::Usage u;
  u.bram18k = 432;
  u.lut = 70560;
  EXPECT_TRUE(res::utilisation(u, *zu3).fits);
  u.bram18k = 433;
  EXPECT_FALSE(res::utilisation(u, *zu3).fits);
  EXPECT_NEAR(res::utilisation(u, *zu3).lut_pct, 100.0, 1e-9);
  const res::Power p100 = res::power(u, 100, 50), p200 = res::power(u, 200, 50);
  EXPECT_NEAR(p200.dynamic_w, 2 * p100.dynamic_w, 1e-12);  // dynamic power scales with the clock
  EXPECT_NEAR(p200.static_w, p100.static_w, 1e-12);
  EXPECT_NEAR(p200.energy_mj_per_frame, p200.total_w * 50, 1e-9);
}

// --- golden: the per-stage breakdown of both paper presets --------------------------------------

std::string breakdown_json(const std::string& config_name) {
  const config::PipelineConfig cfg = config::load_config(kRoot + "/configs/" + config_name + ".yaml");
  const res::Estimate e = res::estimate(res::design_inventory(cfg, 640, 360));
  nlohmann::json j;
  j["config"] = config_name;
  j["total"] = {
      {"bram18k", e.total.bram18k},         {"lut", e.total.lut},          {"ff", e.total.ff}, {"dsp", e.total.dsp},
      {"lutram_luts", e.total.lutram_luts}, {"srl_luts", e.total.srl_luts}};
  j["stages"] = nlohmann::json::array();
  for (const auto& s : e.stages)
    j["stages"].push_back({{"stage", s.stage},
                           {"bram18k", s.usage.bram18k},
                           {"lut", s.usage.lut},
                           {"ff", s.usage.ff},
                           {"dsp", s.usage.dsp}});
  return j.dump(2) + "\n";
}

void expect_golden(const std::string& config_name) {
  const std::string path = kRoot + "/tests/models/resources/golden/" + config_name + ".json";
  const std::string now = breakdown_json(config_name);
  if (std::getenv("PARALLAX_UPDATE_GOLDEN")) {
    std::ofstream(path) << now;
    GTEST_SKIP() << "rewrote " << path;
  }
  std::ifstream in(path);
  ASSERT_TRUE(in.good()) << path << " missing: run with PARALLAX_UPDATE_GOLDEN=1";
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_EQ(now, ss.str()) << "the breakdown of " << config_name << " changed; if intended, rerun with "
                           << "PARALLAX_UPDATE_GOLDEN=1 and review the diff";
}

TEST(ResourcesGolden, Ruf2018Census) {
  expect_golden("ruf2018-census");
}
TEST(ResourcesGolden, Ruf2018Sad) {
  expect_golden("ruf2018-sad");
}

}  // namespace
}  // namespace parallax::test
