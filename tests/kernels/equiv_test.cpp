// equiv: the kernels, fired by the func scheduler with the design's PU, and the fast engine
// (models/fast) at every SIMD level this CPU runs are bit-identical to the independent golden
// model (models/reference) over a table of configurations, patterns and awkward sizes.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "equiv_util.hpp"
#include "parallax/fast/engine.hpp"
#include "parallax/reference/stereo.hpp"
#include "parallax/sim/func.hpp"

namespace parallax::test {
namespace {

using kern::StereoParams;

StereoParams base_params(int w, int h) {
  return test_params(w, h);
}

// The fast engine at every SIMD level against the golden codes r; the level is restored.
void expect_fast_equivalent(const StereoPair& sp, const StereoParams& p, const std::vector<uint16_t>& r,
                            const std::string& what) {
  const std::string before = fast::simd_level();
  for (const std::string& level : fast::supported_simd_levels()) {
    fast::set_simd_level(level);
    fast::Engine e;
    const std::vector<uint16_t> f = e.run(sp.left.px.data(), sp.right.px.data(), p);
    const Comparison c = compare_maps(f, r, p.width_px);
    EXPECT_TRUE(c.sizes_equal && c.mismatches == 0)
        << "fast engine (" << level << ") " << describe(p) << " " << what << ": " << c.mismatches
        << " mismatching pixels, first at " << c.first;
  }
  fast::set_simd_level(before);
}

void expect_equivalent(const StereoParams& p, Pattern pat, uint32_t seed) {
  const StereoPair sp = make_pair(pat, p.width_px, p.height_px, seed, 3 + int(seed % 9));
  sim::FuncOptions opt;
  opt.use_design_pu = true;
  const sim::DisparityCodes k = sim::run_func(sp.left, sp.right, p, opt);
  const std::vector<uint16_t> r = ref::compute_disparity(to_ref(sp.left), to_ref(sp.right), p);
  const Comparison c = compare_maps(k.code, r, p.width_px);
  EXPECT_TRUE(c.sizes_equal && c.mismatches == 0) << describe(p) << " pattern " << int(pat) << " seed " << seed << ": "
                                                  << c.mismatches << " mismatching pixels, first at " << c.first;
  expect_fast_equivalent(sp, p, r, "pattern " + std::to_string(int(pat)) + " seed " + std::to_string(seed));
}

// With 180 alone among the backward paths the design stays one pass (row_reverse.hpp).
const unsigned kPathSets[] = {kern::kPath0,
                              kern::kPath0 | kern::kPath90,
                              kern::kPath0 | kern::kPath45 | kern::kPath90,
                              kern::kForwardPaths,
                              kern::kForwardPaths | kern::kPath180,
                              kern::kPath0 | kern::kPath180,
                              kern::kPath180,
                              kern::kAllPaths};

// The table of the issue: D in {16, 60, 64, 128} with several PU, paths 1-4 and 8, both costs.
struct TableRow {
  int d;
  int pu;
};
const TableRow kTable[] = {{16, 1}, {16, 16}, {60, 6}, {60, 4}, {60, 60}, {64, 8}, {64, 32}, {128, 16}, {128, 64}};

TEST(Equiv, TableOfDisparitiesParallelUnitsPathsAndCosts) {
  uint32_t seed = 1000;
  for (const TableRow& row : kTable)
    for (unsigned paths : kPathSets)
      for (int cost : {int(kern::kCostCensus), int(kern::kCostSad)}) {
        StereoParams p = base_params(row.d < 100 ? 53 : 141, 17);
        p.disparities = row.d;
        p.parallel_units = row.pu;
        p.path_mask = paths;
        p.cost = cost;
        if (cost == kern::kCostSad) {
          p.p1 = 200;
          p.p2 = 800;
        }
        expect_equivalent(p, Pattern::kShiftedTexture, ++seed);
      }
}

TEST(Equiv, PenaltiesMedianAndLrCheckOnAndOff) {
  uint32_t seed = 2000;
  const int penalties[][2] = {{0, 1}, {8, 32}, {10, 120}, {200, 800}, {3, 4000}};
  for (const auto& pen : penalties)
    for (int median : {0, 3, 5, 7})
      for (bool lr : {false, true}) {
        StereoParams p = base_params(47, 21);
        p.p1 = pen[0];
        p.p2 = pen[1];
        p.median = median;
        p.lr_check = lr;
        p.lr_tolerance = int(seed % 3);
        p.disparities = 24;
        p.parallel_units = 6;
        expect_equivalent(p, Pattern::kShiftedTexture, ++seed);
        expect_equivalent(p, Pattern::kRandom, ++seed);
      }
}

// The uniqueness test's streaming minima against the golden model's scan over all disparities:
// chunks of one lane (the best moving every chunk), of two (a best on a chunk's last lane), half
// of D and all of D (one chunk); margins from none to 100 %; with and without the LR check; one
// and two passes.
TEST(Equiv, UniquenessAcrossChunkShapes) {
  uint32_t seed = 7000;
  for (int d : {4, 16, 24})
    for (int pu : {1, 2, d / 2, d})
      for (int u : {0, 1, 5, 15, 50, 100})
        for (unsigned paths : {kern::kForwardPaths, kern::kForwardPaths | kern::kPath180, kern::kAllPaths}) {
          StereoParams p = base_params(29, 11);
          p.disparities = d;
          p.parallel_units = pu;
          p.path_mask = paths;
          p.uniqueness_pct = u;
          p.lr_check = (seed % 2) == 0;
          const Pattern pattern = seed % 3 == 0 ? Pattern::kRandom : Pattern::kShiftedTexture;
          expect_equivalent(p, pattern, ++seed);
        }
}

// The census variants at every window shape the kernel dispatches (3x3, 5x5, 7x5, 9x7) and the
// generic form (9x9, 1x3, 7x1), against the golden codes.
TEST(Equiv, CensusVariantsAndWindows) {
  uint32_t seed = 8000;
  const int sides[][2] = {{3, 3}, {5, 5}, {7, 5}, {9, 7}, {9, 9}, {1, 3}, {7, 1}};
  for (int kind : {kern::kCensusFull, kern::kCensusSparse, kern::kCensusSymmetric})
    for (const auto& wh : sides) {
      if (kern::census_bits(kind, wh[0], wh[1]) > kern::kMaxCensusBits) continue;
      StereoParams p = base_params(23, 13);
      p.census = kind;
      p.window_w = wh[0];
      p.window_h = wh[1];
      const Pattern pattern = seed % 2 == 0 ? Pattern::kRandom : Pattern::kShiftedTexture;
      expect_equivalent(p, pattern, ++seed);
    }
}

TEST(Equiv, WindowsAndPatterns) {
  uint32_t seed = 3000;
  const int windows[][2] = {{1, 1}, {3, 3}, {5, 5}, {7, 5}, {9, 7}, {3, 9}};
  for (const auto& win : windows)
    for (int cost : {int(kern::kCostCensus), int(kern::kCostSad)})
      for (Pattern pat : {Pattern::kRandom, Pattern::kShiftedTexture, Pattern::kStripes, Pattern::kFlat}) {
        if (cost == kern::kCostCensus && win[0] * win[1] - 1 > 64) continue;
        StereoParams p = base_params(38, 19);
        p.window_w = win[0];
        p.window_h = win[1];
        p.cost = cost;
        p.disparities = 20;
        p.parallel_units = 5;
        p.path_mask = seed % 3 == 0   ? kern::kAllPaths
                      : seed % 3 == 1 ? kern::kForwardPaths
                                      : kern::kForwardPaths | kern::kPath180;
        expect_equivalent(p, pat, ++seed);
      }
}

// A minimum disparity m: costs against right column x - m - d, validity m + d <= x, the LR check's
// right pixel x - m - d. Offsets below, around and beyond the image width (every pixel invalid),
// one and many chunks, both costs, one pass, the row reversal and two passes, with the LR check
// and the uniqueness test on and off; scenes shifted by m plus a few pixels so that the matches
// fall inside [m, m + D).
TEST(Equiv, MinDisparityOffsets) {
  uint32_t seed = 9000;
  const int offsets[] = {1, 3, 8, 17, 40, 70};
  for (int m : offsets)
    for (const TableRow& row : {TableRow{16, 4}, TableRow{24, 24}, TableRow{60, 6}})
      for (unsigned paths : {unsigned(kern::kForwardPaths), unsigned(kern::kForwardPaths | kern::kPath180),
                             unsigned(kern::kAllPaths), unsigned(kern::kPath0)})
        for (int cost : {int(kern::kCostCensus), int(kern::kCostSad)}) {
          StereoParams p = base_params(m < 40 ? 61 : 97, 13);
          p.min_disparity = m;
          p.disparities = row.d;
          p.parallel_units = row.pu;
          p.path_mask = paths;
          p.cost = cost;
          if (cost == kern::kCostSad) {
            p.p1 = 200;
            p.p2 = 800;
          }
          p.lr_check = seed % 3 != 0;
          p.uniqueness_pct = seed % 4 == 0 ? 10 : 0;
          p.median = seed % 2 == 0 ? 5 : 0;
          ++seed;
          const StereoPair sp = make_pair(seed % 5 == 0 ? Pattern::kRandom : Pattern::kShiftedTexture, p.width_px,
                                          p.height_px, seed, m + 2 + int(seed % 7));
          sim::FuncOptions opt;
          opt.use_design_pu = true;
          const sim::DisparityCodes k = sim::run_func(sp.left, sp.right, p, opt);
          const std::vector<uint16_t> r = ref::compute_disparity(to_ref(sp.left), to_ref(sp.right), p);
          const Comparison c = compare_maps(k.code, r, p.width_px);
          EXPECT_TRUE(c.sizes_equal && c.mismatches == 0)
              << describe(p) << " seed " << seed << ": " << c.mismatches << " mismatching pixels, first at " << c.first;
          EXPECT_EQ(k.min_disparity, m);
          expect_fast_equivalent(sp, p, r, "seed " + std::to_string(seed));
        }
}

// Intensity-adaptive P2: every one-pass path set (each row kind's window of the previous row's
// intensities, the pixel kind's previous pixel, the 180-degree path on reversed rows with the
// intensities carried through the row reversal), both costs, gains from barely any to the floor
// everywhere, one and many chunks, and widths of 1, 2 and 3 (the window's row-start registers).
TEST(Equiv, AdaptiveP2AcrossPathSetsAndSizes) {
  uint32_t seed = 9500;
  const unsigned one_pass[] = {kern::kPath0,
                               kern::kPath45,
                               kern::kPath90,
                               kern::kPath135,
                               kern::kPath0 | kern::kPath90,
                               kern::kPath0 | kern::kPath45 | kern::kPath90,
                               kern::kForwardPaths,
                               kern::kForwardPaths | kern::kPath180,
                               kern::kPath0 | kern::kPath180,
                               kern::kPath180};
  const int sizes[][2] = {{1, 5}, {2, 4}, {3, 3}, {29, 11}, {53, 9}};
  for (unsigned paths : one_pass)
    for (int a : {1, 16, 255})
      for (const auto& sz : sizes) {
        StereoParams p = base_params(sz[0], sz[1]);
        p.path_mask = paths;
        p.p2_adaptive = a;
        p.cost = seed % 3 == 0 ? int(kern::kCostSad) : int(kern::kCostCensus);
        if (p.cost == kern::kCostSad) {
          p.p1 = 100;
          p.p2 = 2000;
        }
        p.disparities = seed % 2 ? 16 : 24;
        p.parallel_units = seed % 4 < 2 ? 4 : p.disparities;
        const Pattern pattern = seed % 5 == 0 ? Pattern::kRandom : Pattern::kShiftedTexture;
        expect_equivalent(p, pattern, ++seed);
      }
}

// MGM (two predecessors per path step): every path set it supports (each forward path alone,
// the pairs sharing a recursion, the four, eight in two passes), rows of 1 .. 53 pixels (1 and 2: a diagonal window's
// columns x - 1 and x + 1 meet the one being written), one and many chunks, both costs, with and without adaptive P2
// (one pass).
TEST(Equiv, MgmAcrossPathSetsAndSizes) {
  uint32_t seed = 9700;
  const unsigned path_sets[] = {kern::kPath0,
                                kern::kPath45,
                                kern::kPath90,
                                kern::kPath135,
                                kern::kPath0 | kern::kPath90,    // one datapath, added twice
                                kern::kPath45 | kern::kPath135,  // likewise
                                kern::kPath0 | kern::kPath45,
                                kern::kForwardPaths,
                                kern::kAllPaths};
  const int sizes[][2] = {{1, 5}, {2, 4}, {3, 3}, {4, 6}, {29, 11}, {53, 9}};
  for (unsigned paths : path_sets)
    for (int a : {0, 24})
      for (const auto& sz : sizes) {
        if (a > 0 && kern::two_pass_paths(paths)) continue;
        StereoParams p = base_params(sz[0], sz[1]);
        p.path_mask = paths;
        p.aggregation = kern::kAggregationMgm;
        p.p2_adaptive = a;
        p.cost = seed % 3 == 0 ? int(kern::kCostSad) : int(kern::kCostCensus);
        if (p.cost == kern::kCostSad) {
          p.p1 = 100;
          p.p2 = 2000;
        }
        p.disparities = seed % 2 ? 16 : 24;
        p.parallel_units = seed % 4 < 2 ? 4 : p.disparities;
        const Pattern pattern = seed % 5 == 0 ? Pattern::kRandom : Pattern::kShiftedTexture;
        expect_equivalent(p, pattern, ++seed);
      }
}

// Sub-pixel codes (f = 1 .. 4) through the LR check, uniqueness, the median, the row reversal and
// two passes: every path layout, one and many chunks (the best's neighbours across chunk edges),
// PU = 1, awkward sizes, a minimum disparity.
TEST(Equiv, SubpixelCodesThroughEveryStage) {
  uint32_t seed = 9900;
  const int sizes[][2] = {{1, 3}, {2, 2}, {5, 4}, {31, 9}, {47, 7}};
  for (unsigned paths : {unsigned(kern::kForwardPaths), unsigned(kern::kForwardPaths | kern::kPath180),
                         unsigned(kern::kAllPaths), unsigned(kern::kPath0)})
    for (int f = 1; f <= kern::kMaxSubpixelBits; ++f)
      for (const auto& sz : sizes) {
        StereoParams p = base_params(sz[0], sz[1]);
        p.path_mask = paths;
        p.subpixel_bits = f;
        p.cost = seed % 3 == 0 ? int(kern::kCostSad) : int(kern::kCostCensus);
        if (p.cost == kern::kCostSad) {
          p.p1 = 100;
          p.p2 = 2000;
        }
        p.disparities = seed % 2 ? 16 : 24;
        const int pus[] = {1, 4, p.disparities};
        p.parallel_units = pus[seed % 3];
        p.lr_check = seed % 4 != 0;
        p.uniqueness_pct = seed % 5 == 0 ? 10 : 0;
        p.median = seed % 3 == 1 ? 5 : 0;
        p.min_disparity = seed % 7 == 0 ? 3 : 0;
        const Pattern pattern = seed % 5 == 1 ? Pattern::kRandom : Pattern::kShiftedTexture;
        expect_equivalent(p, pattern, ++seed);
      }
}

// Odd widths, widths not a multiple of PU, images smaller than the window, single rows/columns.
TEST(Equiv, AwkwardSizes) {
  uint32_t seed = 4000;
  const int sizes[][2] = {{1, 1}, {2, 3}, {3, 2}, {4, 4}, {1, 9}, {9, 1}, {17, 5}, {31, 7}, {33, 3}, {65, 6}};
  for (const auto& sz : sizes)
    for (unsigned paths : {unsigned(kern::kForwardPaths), unsigned(kern::kAllPaths), unsigned(kern::kPath135),
                           unsigned(kern::kForwardPaths | kern::kPath180)})
      for (int median : {0, 7}) {
        StereoParams p = base_params(sz[0], sz[1]);
        p.disparities = 16;
        p.parallel_units = median == 0 ? 8 : 16;  // two chunks, and one (a row kind's next column may be its own)
        p.path_mask = paths;
        p.median = median;
        p.window_w = 7;
        p.window_h = 5;
        expect_equivalent(p, Pattern::kRandom, ++seed);
        expect_equivalent(p, Pattern::kShiftedTexture, ++seed);
      }
}

// Seeded random sample of the whole space, including wide aggregates (32-bit words) and PU > 64.
TEST(Equiv, SeededRandomConfigurations) {
  const uint32_t master_seed = 5000;
  std::mt19937 rng(master_seed);
  for (int i = 0; i < 40; ++i) {
    StereoParams p = base_params(int(8 + rng() % 70), int(3 + rng() % 20));
    const int ds[] = {8, 16, 30, 60, 64, 96, 128, 256};
    p.disparities = ds[rng() % 8];
    std::vector<int> divisors;
    for (int pu = 1; pu <= p.disparities; ++pu)
      if (p.disparities % pu == 0) divisors.push_back(pu);
    p.parallel_units = divisors[rng() % divisors.size()];
    p.path_mask = 1u + unsigned(rng() % 255u);
    p.cost = int(rng() % 2);
    const int sides[] = {1, 3, 5, 7, 9};
    p.window_w = sides[rng() % 5];
    p.window_h = sides[rng() % 4];
    p.p1 = int(rng() % 300);
    p.p2 = p.p1 + 1 + int(rng() % (rng() % 4 == 0 ? 60000 : 900));
    p.lr_check = rng() % 2;
    p.lr_tolerance = int(rng() % 3);
    const int medians[] = {0, 3, 5, 7};
    p.median = medians[rng() % 4];
    p.uniqueness_pct = rng() % 3 == 0 ? int(rng() % 101) : 0;
    p.census = int(rng() % 3);
    p.min_disparity = rng() % 4 == 0 ? int(rng() % 48) : 0;
    p.p2_adaptive = rng() % 3 == 0 && !kern::two_pass_paths(p.path_mask) ? int(rng() % 256) : 0;
    p.aggregation = rng() % 4 == 0 && kern::mgm_paths_supported(p.path_mask) ? int(kern::kAggregationMgm)
                                                                             : int(kern::kAggregationSgm);
    p.subpixel_bits = rng() % 3 == 0 ? int(rng() % 5) : 0;
    SCOPED_TRACE("master seed " + std::to_string(master_seed) + " draw " + std::to_string(i));
    expect_equivalent(p, i % 2 ? Pattern::kRandom : Pattern::kShiftedTexture, master_seed + uint32_t(i));
  }
}

// The func default (widest lanes) gives the same bits as the design's PU; the kernels engine
// is asked for by name, as the default func engine is the fast one.
TEST(Equiv, FuncLanesIndependentOfDesignPu) {
  StereoParams p = base_params(80, 24);
  p.disparities = 60;
  const StereoPair sp = make_pair(Pattern::kShiftedTexture, p.width_px, p.height_px, 77, 9);
  sim::FuncOptions design;
  design.use_design_pu = true;
  for (int pu : {1, 3, 6, 20, 60}) {
    p.parallel_units = pu;
    const auto a = sim::run_func(sp.left, sp.right, p, design);
    sim::FuncOptions widest;
    widest.engine = sim::FuncEngine::kernels;
    const auto b = sim::run_func(sp.left, sp.right, p, widest);
    const Comparison c = compare_maps(a.code, b.code, p.width_px);
    EXPECT_EQ(c.mismatches, 0) << "PU " << pu << ": first at " << c.first;
  }
}

TEST(Equiv, RectifyNearestAndBilinear) {
  uint32_t seed = 6000;
  for (int mode : {int(kern::kRectifyNearest), int(kern::kRectifyBilinear)})
    for (int rows : {1, 2, 5, 16})
      for (const auto& sz : std::vector<std::pair<int, int>>{{1, 1}, {7, 3}, {40, 25}}) {
        std::mt19937 rng(++seed);
        const int w = sz.first, h = sz.second;
        const int frac = mode == kern::kRectifyBilinear ? 5 : 0;
        sim::GreyImage img{w, h, std::vector<uint8_t>(std::size_t(w) * h)};
        for (auto& v : img.px) v = uint8_t(rng());
        ref::RemapTable map;
        map.width_px = w;
        map.height_px = h;
        map.frac_bits = frac;
        std::vector<kern::MapEntry> entries;
        // A smooth warp (rotation + barrel-like term) plus sub-pixel offsets, partly outside.
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            const double cx = x - w / 2.0, cy = y - h / 2.0;
            const double sx = x + 0.05 * cy + 0.002 * cx * cx + 0.3, sy = y - 0.04 * cx + 0.7;
            const int32_t mx = int32_t(std::lround(sx * (1 << frac))) + int32_t(rng() % 3) - 1;
            const int32_t my = int32_t(std::lround(sy * (1 << frac))) + int32_t(rng() % 3) - 1;
            map.map_x.push_back(mx);
            map.map_y.push_back(my);
            entries.push_back({mx, my});
          }
        kern::RectifyParams rp{w, h, mode, frac, rows};
        const sim::RectifyOutput k = sim::run_rectify_func(img, entries, rp);
        const ref::RectifyResult r = ref::rectify(to_ref(img), map, rp);
        const Comparison c = compare_maps(k.image.px, r.image.px, w);
        EXPECT_TRUE(c.sizes_equal && c.mismatches == 0)
            << "mode " << mode << " rows " << rows << " " << w << "x" << h << " seed " << seed << ": " << c.mismatches
            << " mismatches, first at " << c.first;
        EXPECT_EQ(k.window_misses, r.window_misses) << "mode " << mode << " rows " << rows << " seed " << seed;
      }
}

// The comparison itself must be able to fail: one flipped pixel is found, with its position.
TEST(Equiv, ComparisonDetectsASingleDifference) {
  std::vector<uint16_t> a(12, 3), b(12, 3);
  b[7] = 4;
  const Comparison c = compare_maps(a, b, 4);
  EXPECT_EQ(c.mismatches, 1);
  EXPECT_EQ(c.first, "(3, 1): kernel 3, reference 4");
  const Comparison s = compare_maps(a, std::vector<uint16_t>(11, 3), 4);
  EXPECT_FALSE(s.sizes_equal);
}

}  // namespace
}  // namespace parallax::test
