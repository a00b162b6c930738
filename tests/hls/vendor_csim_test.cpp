// Exported projects built against the vendor's own C-simulation headers (Xilinx's Apache-2.0
// ap_int.h and hls_stream.h in shared/third_party/xilinx-hls-types, `make csim HLS_INCLUDE=DIR`;
// ap_axi_sdata.h, which that set lacks, from the project's compat/ behind it) give the same bits
// as against compat/, Parallax's stand-ins: a one-pass design, the two-pass design and a
// rectifying design, each built both ways with warnings in the project's code as errors. Both C
// simulations must report a bit-exact run, and their outputs must equal each other and the
// simulator's golden file; the reduced frame (`make csim-reduced`) against the vendor's headers too.
// The vendor-header run counts the kernels' accesses (csim_accesses.json, issue 41): every stage's
// counts fit its declared II, for the five designs of that issue (the seed, the seed on eight
// paths, frontier-census, the synthesised preset, MGM with subpixel codes and uniqueness) and
// the others. Skipped when the vendor headers are absent (a fresh machine has no shared/).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "export_util.hpp"

namespace {

namespace fs = std::filesystem;
using parallax::test::expect_accesses_fit;
using parallax::test::expect_storage_fits;
using parallax::test::export_design;
using parallax::test::fresh_dir;
using parallax::test::read_file;
using parallax::test::Shell;
using parallax::test::shell;

const char kBitExact[] = "bit-exact against the simulator's golden output";

struct Design {
  const char* id;
  const char* config;
  const char* sets;
  bool rectify;  // a small synthetic scene through distorting lenses, as HlsCsimRectify makes it
};

const Design kDesigns[] = {
    {"one_pass", "configs/ruf2018-census.yaml", "", false},
    {"two_pass", "configs/ruf2018-census.yaml", "--set paths=8", false},
    {"rectify", "configs/ruf2018-census.yaml", "--set paths=4", true},
    // The uniqueness register, a census variant and a minimum disparity, through the vendor's
    // ap_uint ports.
    {"knobs", "configs/ruf2018-census.yaml",
     "--set uniqueness_pct=10 --set census=sparse --set window=9x7 --set min_disparity=6 --set subpixel_bits=3", false},
    // MGM on eight paths in two passes (the second pass's datapaths on the reversed stream), with
    // subpixel codes and the uniqueness check.
    {"mgm_two_pass", "configs/ruf2018-census.yaml",
     "--set paths=8 --set aggregation=mgm --set subpixel_bits=4 --set uniqueness_pct=10", false},
    {"frontier", "configs/frontier-census.yaml", "", false},
    {"synthesised", "configs/ruf2018-synthesised.yaml", "", false},
    // The 180-degree path in one pass, with adaptive P2 (intensities through the row reversal).
    {"five_paths", "configs/ruf2018-census.yaml",
     "--set paths=5 --set disparities=32 --set parallel_units=8 --set p2_adaptive=40 --set p2=64", false},
};

// Exports d into dir / "hls" and returns that folder (empty on failure, with the reason in `why`).
fs::path export_project(const Design& d, const fs::path& dir, std::string& why) {
  const fs::path out = dir / "hls";
  if (!d.rectify) {
    const Shell ex = export_design(d.config, out, d.sets);
    if (ex.status != 0) why = ex.output;
    return ex.status == 0 ? out : fs::path();
  }
  const std::string cli = std::string("cd ") + PARALLAX_SOURCE_DIR + " && " + PARALLAX_CLI;
  const Shell scene = shell(cli +
                            " scene --scenario configs/scenarios/single-pole.yaml --frames 1 --size 160"
                            " --distortion-k1 -0.15 --out " +
                            (dir / "scene").string());
  if (scene.status != 0) {
    why = scene.output;
    return fs::path();
  }
  const std::string s = (dir / "scene").string();
  const Shell ex = shell(cli + " export-hls --config " + d.config + " " + d.sets +
                         " --set roi=full --set disparities=30 --set parallel_units=3 --set rectify=bilinear"
                         " --set rectify_rows=32 --set rectify_maps_left=" +
                         s +
                         "/maps_left.yml"
                         " --set rectify_maps_right=" +
                         s + "/maps_right.yml --left " + s + "/training/image_2/000000_10.png --right " + s +
                         "/training/image_3/000000_10.png --out " + out.string());
  if (ex.status != 0) why = ex.output;
  return ex.status == 0 ? out : fs::path();
}

class HlsVendorCsim : public ::testing::TestWithParam<Design> {};

TEST_P(HlsVendorCsim, MatchesTheCompatBuildAndTheGoldenBitForBit) {
  const fs::path vendor = PARALLAX_VENDOR_HLS_INCLUDE;
  if (!fs::exists(vendor / "ap_int.h") || !fs::exists(vendor / "hls_stream.h"))
    GTEST_SKIP() << "the vendor's HLS simulation headers are not at " << vendor
                 << " (shared/third_party/xilinx-hls-types, beside the project, is absent on this machine)";
  const Design& d = GetParam();
  const fs::path dir = fresh_dir(std::string("vendor_") + d.id);
  std::string why;
  const fs::path out = export_project(d, dir, why);
  ASSERT_FALSE(out.empty()) << why;
  const std::string make = "make -C " + out.string() + " csim WERROR=1";

  // The project's own stand-ins (without the access count, which the vendor-header run makes).
  const Shell compat = shell(make + " ACCESSES=0");
  ASSERT_EQ(compat.status, 0) << compat.output;
  EXPECT_NE(compat.output.find(kBitExact), std::string::npos) << compat.output;
  const std::string compat_pgm = read_file(out / "tb/csim_disparity.pgm");

  // The vendor's headers. -H lists every header the compiler opened: ap_int.h and hls_stream.h
  // must be the vendor's, ap_axi_sdata.h compat's.
  fs::remove(out / "tb/csim_disparity.pgm");
  const Shell vend = shell(make + " HLS_INCLUDE=" + vendor.string() + " CXXFLAGS='-O2 -H'");
  ASSERT_EQ(vend.status, 0) << vend.output;
  EXPECT_NE(vend.output.find(kBitExact), std::string::npos) << vend.output;
  EXPECT_NE(vend.output.find("-isystem " + vendor.string()), std::string::npos)
      << "rebuilt against the vendor's headers";
  for (const char* h : {"/ap_int.h", "/hls_stream.h", "/etc/ap_private.h"})
    EXPECT_NE(vend.output.find(vendor.string() + h), std::string::npos) << h << " is not the vendor's";
  EXPECT_NE(vend.output.find("compat/ap_axi_sdata.h"), std::string::npos);
  EXPECT_EQ(vend.output.find("compat/ap_int.h"), std::string::npos) << "compat's ap_int.h beside the vendor's";
  EXPECT_EQ(vend.output.find("compat/hls_stream.h"), std::string::npos) << "compat's hls_stream.h beside the vendor's";
  // The vendor's streams do not stop on a read while empty or tokens left over; they warn.
  EXPECT_EQ(vend.output.find("WARNING: Hls::stream"), std::string::npos) << vend.output;
  const std::string vendor_pgm = read_file(out / "tb/csim_disparity.pgm");
  EXPECT_NE(vend.output.find("every stage's accesses and recurrences fit its declared II"), std::string::npos)
      << vend.output;
  expect_accesses_fit(out);
  EXPECT_NE(vend.output.find("every memory stores the word the model prices"), std::string::npos) << vend.output;
  expect_storage_fits(out);
  // The reduced frame of C/RTL co-simulation, against the vendor's headers too.
  const Shell reduced = shell("make -C " + out.string() + " csim-reduced WERROR=1 HLS_INCLUDE=" + vendor.string());
  ASSERT_EQ(reduced.status, 0) << reduced.output;
  EXPECT_NE(reduced.output.find(kBitExact), std::string::npos) << reduced.output;
  EXPECT_EQ(reduced.output.find("WARNING: Hls::stream"), std::string::npos) << reduced.output;
  EXPECT_TRUE(read_file(out / "tb/csim_disparity_reduced.pgm") == read_file(out / "tb/golden_disparity_reduced.pgm"));

  const std::string golden = read_file(out / "tb/golden_disparity.pgm");
  ASSERT_FALSE(golden.empty());
  EXPECT_TRUE(compat_pgm == golden) << "compat/ output differs from the golden file";
  EXPECT_TRUE(vendor_pgm == golden) << "vendor-header output differs from the golden file";
  EXPECT_TRUE(vendor_pgm == compat_pgm) << "vendor-header and compat/ outputs differ";
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Designs, HlsVendorCsim, ::testing::ValuesIn(kDesigns),
                         [](const ::testing::TestParamInfo<Design>& i) { return std::string(i.param.id); });

}  // namespace
