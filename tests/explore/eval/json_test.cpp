// unit: the scoring room's JSON forms (parallax/eval/json.hpp), what eval, score, baseline, run
// and bench print with --json.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <set>
#include <string>

#include "parallax/eval/json.hpp"

namespace {

namespace px = parallax::eval;
using nlohmann::json;

px::FrameCounts counts(std::int64_t roi, std::int64_t valid, std::int64_t correct) {
  px::FrameCounts c;
  c.roi_pixels = roi;
  c.valid_pixels = valid;
  c.gt_pixels = roi;
  c.valid_gt_pixels = valid;
  c.correct_3px = correct;
  c.abs_error_sum_px = 2.0 * double(valid);
  return c;
}

TEST(EvalJson, MetricsAreTheNamedMeasuresAndNanIsNull) {
  const json j = px::derive_metrics(px::FrameCounts{});  // nothing to divide by: every measure NaN
  std::set<std::string> keys;
  for (const auto& kv : j.items()) keys.insert(kv.key());
  std::set<std::string> named;
  for (const auto& kv : px::named_metrics(px::DerivedMetrics{})) named.insert(kv.first);
  EXPECT_EQ(keys, named);
  EXPECT_NE(j.dump().find("\"density_pct\":null"), std::string::npos) << j.dump();
}

TEST(EvalJson, EvaluationCarriesPooledMeasuresCountsAndFrameRows) {
  px::EvalResult r;
  r.frames = {px::make_frame_row("000001", counts(100, 80, 60)), px::make_frame_row("000005", counts(100, 40, 40))};
  r.pooled = px::pool_rows(r.frames);
  r.notes = {"a note, not part of the form"};
  r.seconds = 1.5;
  const json j = r;
  EXPECT_DOUBLE_EQ(j["density_pct"].get<double>(), 60.0);  // pooled: 120 valid of 200
  EXPECT_DOUBLE_EQ(j["correct_3px_pct"].get<double>(), 100.0 * 100 / 120);
  EXPECT_EQ(j["frames"].get<int>(), 2);
  EXPECT_EQ(j["counts"]["roi_pixels"].get<std::int64_t>(), 200);
  EXPECT_EQ(j["counts"]["valid_pixels"].get<std::int64_t>(), 120);
  EXPECT_FALSE(j["counts"].contains("abs_error_sum_px"));
  ASSERT_EQ(j["per_frame"].size(), 2u);
  EXPECT_EQ(j["per_frame"][1]["frame"].get<std::string>(), "000005");
  EXPECT_DOUBLE_EQ(j["per_frame"][1]["density_pct"].get<double>(), 40.0);
  EXPECT_FALSE(j["per_frame"][0].contains("counts"));
  EXPECT_DOUBLE_EQ(j["seconds"].get<double>(), 1.5);
  EXPECT_FALSE(j.contains("notes"));
}

TEST(EvalJson, EmptyEvaluationHasAnEmptyFrameList) {
  const json j = px::EvalResult{};
  EXPECT_TRUE(j["per_frame"].is_array());
  EXPECT_EQ(j["per_frame"].dump(), "[]");
  EXPECT_EQ(j["frames"].get<int>(), 0);
}

TEST(EvalJson, BenchRowNamesTheRatiosToHh4AndSgbm) {
  px::BenchRow row;
  row.method = "func";
  row.ratio_to_peer = 0.5;
  row.min_ratio_to_peer = 0.25;
  row.ratio_to_sgbm = 0.75;
  row.min_ratio_to_sgbm = 0.5;
  const json j = std::vector<px::BenchRow>{row};
  ASSERT_TRUE(j.is_array());
  EXPECT_EQ(j[0]["method"].get<std::string>(), "func");
  EXPECT_DOUBLE_EQ(j[0]["ratio_to_hh4"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(j[0]["min_ratio_to_hh4"].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(j[0]["ratio_to_sgbm"].get<double>(), 0.75);
  EXPECT_DOUBLE_EQ(j[0]["min_ratio_to_sgbm"].get<double>(), 0.5);
  EXPECT_EQ(j[0].size(), 9u);
}

}  // namespace
