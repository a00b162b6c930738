// unit: the function-description format (models/data/functions) and the published-row CSV
// reader: expressions, item kinds, storage mapping, unstated variables, errors naming the place.
#include <gtest/gtest.h>

#include <string>

#include "parallax/config/config.hpp"
#include "parallax/resources/functions.hpp"
#include "parallax/resources/points_csv.hpp"

namespace parallax::test {
namespace {

res::RowVariables row(double width, double k, double npc = 1) {
  res::RowVariables r;
  r.values = {{"width", width}, {"height", 1080}, {"k", k}, {"npc", npc}, {"channels", 1}, {"uram", 0}};
  r.text = "filter 3ch | design | notes";
  return r;
}

const char* kFilter = R"yaml(
function: toyFilter
group: filter
matches: "^toy"
source: "a test"
flags: {three: "3ch"}
let: {lanes: "npc * (three ? 3 : 1)"}
stages:
  - stage: filter
    items:
      - {kind: line_buffer, name: rows, rows: "k", depth: "width / npc", width_bits: "8 * lanes"}
      - {kind: window, name: win, rows: "k", cols: "k", width_bits: 8}
      - {kind: adder_tree, name: sum, inputs: "k * k", width_bits: 8}
      - {kind: mul_const, name: scale, a_bits: 16, b_bits: "bits(k * k * 255) - 5"}
      - {kind: compare, name: never, width_bits: 8, when: "k > 100"}
      - {kind: fmul, name: gain, count: 2}
      - {kind: axis, name: in, width_bits: "8 * lanes"}
)yaml";

TEST(Functions, InstantiatesItemsFromExpressions) {
  const res::FunctionDescription fn = res::parse_function(kFilter, "toy.yaml");
  const res::Inventory inv = res::instantiate(fn, row(1920, 5));
  ASSERT_EQ(inv.stages, std::vector<std::string>{"filter"});
  ASSERT_EQ(inv.memories.size(), 1u);
  EXPECT_EQ(inv.memories[0].copies, 5);
  EXPECT_EQ(inv.memories[0].depth, 1920);
  EXPECT_EQ(inv.memories[0].width_bits, 24);       // the flag matched "3ch" in the row's text
  EXPECT_EQ(inv.memories[0].per_copy.bram18k, 3);  // 1920 x 24: three 2K x 9
  ASSERT_EQ(inv.registers.size(), 1u);
  EXPECT_EQ(inv.registers[0].count, 25);
  // An adder tree of 25 inputs: 24 adders, 12 + 6 + 3 + 1 + 1 + 1 by level, one bit wider each.
  int64_t adders = 0;
  for (const auto& o : inv.ops)
    if (o.name == "sum") adders += o.count;
  EXPECT_EQ(adders, 24);
  bool scale = false, never = false, gain = false;
  for (const auto& o : inv.ops) {
    if (o.name == "scale") scale = o.constant_operand && o.b_bits == 13 - 5 && o.width_bits == 16;
    if (o.name == "never") never = true;
    if (o.name == "gain") gain = o.float_kind == res::kFloatMul && o.count == 2;
  }
  EXPECT_TRUE(scale) << "bits(25 * 255) = 13";
  EXPECT_FALSE(never) << "an item whose when is 0 is left out";
  EXPECT_TRUE(gain);
  ASSERT_EQ(inv.interfaces.size(), 1u);
  EXPECT_EQ(inv.interfaces[0].width_bits, 24);
}

TEST(Functions, UnstatedVariableMakesTheRowNotDescribable) {
  const res::FunctionDescription fn = res::parse_function(kFilter, "toy.yaml");
  res::RowVariables r = row(1920, 3);
  r.values.erase("width");
  r.unstated.insert("width");
  try {
    (void)res::instantiate(fn, r);
    FAIL() << "expected NotDescribable";
  } catch (const res::NotDescribable& e) {
    EXPECT_NE(std::string(e.what()).find("width not stated"), std::string::npos) << e.what();
  }
}

TEST(Functions, DefectsNameTheFileTheItemAndTheField) {
  const std::string bad_kind = std::string(kFilter) + "      - {kind: teleporter, name: beam}\n";
  try {
    (void)res::instantiate(res::parse_function(bad_kind, "toy.yaml"), row(1920, 3));
    FAIL();
  } catch (const config::ConfigError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("toy.yaml"), std::string::npos) << m;
    EXPECT_NE(m.find("'beam'"), std::string::npos) << m;
    EXPECT_NE(m.find("teleporter"), std::string::npos) << m;
  }
  const std::string fraction = std::string(kFilter) + "      - {kind: registers, name: half, width_bits: \"k / 2\"}\n";
  try {
    (void)res::instantiate(res::parse_function(fraction, "toy.yaml"), row(1920, 3));
    FAIL();
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("'half'.width_bits"), std::string::npos) << e.what();
  }
  EXPECT_THROW(res::parse_function("function: x\ngroup: g\nmatches: \"(\"\nsource: s\nstages: []\n", "bad.yaml"),
               config::ConfigError);
}

TEST(Functions, CompiledLibraryCoversTheRequiredFamilies) {
  const auto& fns = res::default_functions();
  for (const char* kernel :
       {"StereoBM", "SemiGlobalBM", "medianBlur 3x3", "boxFilter 3x3", "GaussianBlur 5x5", "Sobel 3x3", "Scharr 3x3",
        "filter2D 3x3", "dilate 3x3 (rect)", "erode 3x3 (rect)", "remap XF_INTERPOLATION_BILINEAR",
        "warpTransform Affine Bilinear", "resize Downscale Bilinear"})
    EXPECT_NE(res::find_function(fns, kernel), nullptr) << kernel;
  EXPECT_EQ(res::find_function(fns, "no such kernel"), nullptr);
}

TEST(PointsCsv, ReadsQuotedFieldsWindowsAndUnstatedValues) {
  const std::string csv =
      "kernel,design,width,height,npc,window,notes,bram18k,dsp,ff,lut,device\n"
      "medianBlur 3x3,\"gray, \"\"8UC1\"\"\",1920,1080,8 Pixel (as printed),3x3,\"two\nlines\",6,0,1595,6559,xczu9eg\n"
      "resize,r,3840,2160,1,3840X2160 TO 1920X1080,UltraRAM enabled,12,,10,20,xcvc1902\n"
      "remap,m,not stated,not stated,1,WIN_ROWS=64,,64,17,1738,1593,\n";
  const auto pts = res::parse_points_csv(csv, "t.csv");
  ASSERT_EQ(pts.size(), 3u);
  EXPECT_EQ(pts[0].design, "gray, \"8UC1\"");
  EXPECT_EQ(pts[0].vars.values.at("npc"), 8);
  EXPECT_EQ(pts[0].vars.values.at("k"), 3);
  EXPECT_EQ(pts[0].published.lut, 6559);
  EXPECT_EQ(pts[1].line, 4);  // the quoted newline counts
  EXPECT_EQ(pts[1].vars.values.at("out_width"), 1920);
  EXPECT_EQ(pts[1].vars.values.at("uram"), 1);
  EXPECT_EQ(pts[1].vars.values.at("versal"), 1);
  EXPECT_EQ(pts[1].published.dsp, -1);  // empty: not published
  EXPECT_TRUE(pts[2].vars.unstated.count("width"));
  EXPECT_EQ(pts[2].vars.values.at("win_rows"), 64);
  EXPECT_THROW(res::parse_points_csv("design,lut\nx,1\n", "t.csv"), config::ConfigError);  // no kernel column
  try {
    (void)res::parse_points_csv("kernel,design,lut\nk,d,many\n", "t.csv");
    FAIL();
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("t.csv:2: lut"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace parallax::test
