// docs/algorithm.md §3: path costs by hand, path symmetries, the aggregate, the bit widths.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

#include "test_util.hpp"

namespace parallax::ref {
namespace {

using test::at;
using test::make_params;
using test::volume_from;

constexpr unsigned kAllPathBits[8] = {kern::kPath0,   kern::kPath45,  kern::kPath90,  kern::kPath135,
                                      kern::kPath180, kern::kPath225, kern::kPath270, kern::kPath315};

// One row, W = 3, D = 4, P1 = 1, P2 = 3. SAD 1x1 so that cost_max = 255 allows these costs.
const std::vector<std::vector<uint32_t>> kRowCosts = {{9, 0, 9, 9}, {1, 8, 8, 2}, {0, 6, 6, 6}};

kern::StereoParams row_params(unsigned mask) {
  return make_params(3, 1, kern::kCostSad, 1, 4, mask, 1, 3);
}

void expect_pixel(const std::vector<uint32_t>& v, int x, int y, const kern::StereoParams& p,
                  const std::vector<uint32_t>& expected) {
  for (int d = 0; d < p.disparities; ++d)
    EXPECT_EQ(at(v, x, y, d, p), expected[static_cast<std::size_t>(d)]) << "pixel (" << x << ", " << y << ") d=" << d;
}

TEST(PathCosts, LeftToRightByHand) {
  const kern::StereoParams p = row_params(kern::kPath0);
  const std::vector<uint32_t> c = volume_from({kRowCosts});
  const std::vector<uint32_t> l = path_costs(c, p, kern::kPath0);
  // x=0: path start, L = C.
  expect_pixel(l, 0, 0, p, {9, 0, 9, 9});
  // x=1: q = [9 0 9 9], M = 0, M + P2 = 3.
  //   d0: min(9, 0+1, 3) = 1 -> 1+1 = 2;  d1: min(0, 10, 10, 3) = 0 -> 8
  //   d2: min(9, 0+1, 10, 3) = 1 -> 9;    d3: min(9, 9+1, 3) = 3 (P2) -> 2+3 = 5
  expect_pixel(l, 1, 0, p, {2, 8, 9, 5});
  // x=2: q = [2 8 9 5], M = 2, M + P2 = 5.
  //   d0: min(2, 9, 5) = 2 -> 0+2-2 = 0;  d1: min(8, 3, 10, 5) = 3 -> 6+3-2 = 7
  //   d2: min(9, 9, 6, 5) = 5 (P2) -> 9;  d3: min(5, 10, 5) = 5 -> 9
  expect_pixel(l, 2, 0, p, {0, 7, 9, 9});
}

// Adaptive P2 with a = 16: P2' = max(P1 + 1, P2 - |dI|) = max(2, 3 - |dI|) on the left row
// [10 11 13]: 2 at x = 1 (step 1) and at x = 2 (step 2, the floor).
TEST(PathCosts, AdaptiveP2ByHand) {
  kern::StereoParams p = row_params(kern::kPath0);
  p.p2_adaptive = 16;
  const Image8 left = test::image_from_rows({{10, 11, 13}});
  const std::vector<uint32_t> c = volume_from({kRowCosts});
  const std::vector<uint32_t> l = path_costs(c, p, kern::kPath0, &left);
  expect_pixel(l, 0, 0, p, {9, 0, 9, 9});
  // x=1: q = [9 0 9 9], M = 0, M + P2' = 2: d3 takes the P2 term, 2 + 2 = 4 (5 with P2 3).
  expect_pixel(l, 1, 0, p, {2, 8, 9, 4});
  // x=2: q = [2 8 9 4], M = 2, M + P2' = 4: d2 min(9, 9, 5, 4) = 4 -> 8; d3 min(4, 10, 4) -> 8.
  expect_pixel(l, 2, 0, p, {0, 7, 8, 8});
  EXPECT_EQ(kern::adaptive_p2(1, 3, 16, 11, 10), 2);
  EXPECT_EQ(kern::adaptive_p2(1, 3, 16, 10, 13), 2);  // the floor P1 + 1
  EXPECT_EQ(kern::adaptive_p2(8, 64, 40, 0, 6), 64 - (40 * 6 >> 4));
  EXPECT_EQ(kern::adaptive_p2(8, 64, 0, 0, 255), 64);                   // a = 0: P2
  EXPECT_THROW(path_costs(c, p, kern::kPath0), std::invalid_argument);  // the image is required
  p.p2_adaptive = 256;
  EXPECT_THROW(path_costs(c, p, kern::kPath0, &left), std::invalid_argument);
}

// MGM, 2 x 2 pixels, D = 2, P1 = 1, P2 = 3; path 0 steps from (x-1, y) and (x, y-1).
TEST(PathCosts, MgmByHand) {
  kern::StereoParams p = make_params(2, 2, kern::kCostSad, 1, 2, kern::kPath0, 1, 3);
  p.aggregation = kern::kAggregationMgm;
  const std::vector<uint32_t> c = volume_from({{{4, 0}, {6, 0}}, {{0, 6}, {2, 2}}});
  const std::vector<uint32_t> l = path_costs(c, p, kern::kPath0);
  expect_pixel(l, 0, 0, p, {4, 0});  // neither predecessor: L = C
  // (1, 0): only q = (0, 0) = [4 0], M = 0: d0 min(4, 1, 3) = 1 -> 7; d1 min(0, 5, 3) = 0 -> 0.
  expect_pixel(l, 1, 0, p, {7, 0});
  // (0, 1): only q2 = (0, 0), the same step: [0 + 1, 6 + 0].
  expect_pixel(l, 0, 1, p, {1, 6});
  // (1, 1): q = (0, 1) = [1 6], M 1: u = [min(1, 7, 4) - 1, min(6, 2, 4) - 1] = [0 1];
  //         q2 = (1, 0) = [7 0], M 0: u = [min(7, 1, 3), min(0, 8, 3)] = [1 0];
  //         L = C + floor((u + u2) / 2) = [2 + 0, 2 + 0] (SGM from q alone: [2 3]).
  expect_pixel(l, 1, 1, p, {2, 2});
  // Path 90 steps from the same two neighbours: the same recursion (docs §3).
  EXPECT_EQ(path_costs(c, p, kern::kPath90), l);
  p.aggregation = 2;
  EXPECT_THROW(path_costs(c, p, kern::kPath0), std::invalid_argument);
}

TEST(PathCosts, RightToLeftByHand) {
  const kern::StereoParams p = row_params(kern::kPath180);
  const std::vector<uint32_t> c = volume_from({kRowCosts});
  const std::vector<uint32_t> l = path_costs(c, p, kern::kPath180);
  expect_pixel(l, 2, 0, p, {0, 6, 6, 6});
  // x=1: q = [0 6 6 6], M = 0, M + P2 = 3.
  //   d0: min(0, 7, 3) = 0 -> 1;  d1: min(6, 1, 7, 3) = 1 -> 9
  //   d2: min(6, 7, 7, 3) = 3 -> 11;  d3: min(6, 7, 3) = 3 -> 5
  expect_pixel(l, 1, 0, p, {1, 9, 11, 5});
  // x=0: q = [1 9 11 5], M = 1, M + P2 = 4.
  //   d0: min(1, 10, 4) = 1 -> 9;  d1: min(9, 2, 12, 4) = 2 -> 0+2-1 = 1
  //   d2: min(11, 10, 6, 4) = 4 -> 9+4-1 = 12;  d3: min(5, 12, 4) = 4 -> 12
  expect_pixel(l, 0, 0, p, {9, 1, 12, 12});
}

TEST(PathCosts, OneRowNonHorizontalPathsAreTheCost) {
  const std::vector<uint32_t> c = volume_from({kRowCosts});
  for (const unsigned bit :
       {kern::kPath45, kern::kPath90, kern::kPath135, kern::kPath225, kern::kPath270, kern::kPath315}) {
    EXPECT_EQ(path_costs(c, row_params(bit), bit), c) << "path bit " << bit;
  }
}

TEST(PathCosts, TopToBottomOnOneColumnByHand) {
  // The same numbers as LeftToRightByHand, transposed into a column.
  const kern::StereoParams p = make_params(1, 3, kern::kCostSad, 1, 4, kern::kPath90, 1, 3);
  const std::vector<uint32_t> c = volume_from({{kRowCosts[0]}, {kRowCosts[1]}, {kRowCosts[2]}});
  const std::vector<uint32_t> l = path_costs(c, p, kern::kPath90);
  expect_pixel(l, 0, 0, p, {9, 0, 9, 9});
  expect_pixel(l, 0, 1, p, {2, 8, 9, 5});
  expect_pixel(l, 0, 2, p, {0, 7, 9, 9});
  // Bottom to top: the reverse walk, as RightToLeftByHand.
  const std::vector<uint32_t> u = path_costs(c, p, kern::kPath270);
  expect_pixel(u, 0, 2, p, {0, 6, 6, 6});
  expect_pixel(u, 0, 1, p, {1, 9, 11, 5});
  expect_pixel(u, 0, 0, p, {9, 1, 12, 12});
}

TEST(PathCosts, DiagonalPredecessorsOnTwoByTwo) {
  // For each diagonal path exactly one pixel of a 2x2 frame has its predecessor inside:
  // give the predecessor A = [9 0 9 9] and the successor B = [1 8 8 2]: the successor's Lr is
  // then [2 8 9 5] (see LeftToRightByHand), every other pixel keeps its cost.
  const std::vector<uint32_t> a = {9, 0, 9, 9};
  const std::vector<uint32_t> b = {1, 8, 8, 2};
  const std::vector<uint32_t> z = {4, 4, 4, 4};
  struct Case {
    unsigned bit;
    int qx, qy, px, py;
  };
  const Case cases[] = {{kern::kPath45, 0, 0, 1, 1},
                        {kern::kPath135, 1, 0, 0, 1},
                        {kern::kPath225, 1, 1, 0, 0},
                        {kern::kPath315, 0, 1, 1, 0}};
  for (const Case& k : cases) {
    const kern::StereoParams p = make_params(2, 2, kern::kCostSad, 1, 4, k.bit, 1, 3);
    std::vector<std::vector<std::vector<uint32_t>>> grid(2, std::vector<std::vector<uint32_t>>(2, z));
    grid[static_cast<std::size_t>(k.qy)][static_cast<std::size_t>(k.qx)] = a;
    grid[static_cast<std::size_t>(k.py)][static_cast<std::size_t>(k.px)] = b;
    const std::vector<uint32_t> c = volume_from(grid);
    const std::vector<uint32_t> l = path_costs(c, p, k.bit);
    SCOPED_TRACE(testing::Message() << "path bit " << k.bit);
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x)
        if (x == k.px && y == k.py)
          expect_pixel(l, x, y, p, {2, 8, 9, 5});
        else
          expect_pixel(l, x, y, p, grid[static_cast<std::size_t>(y)][static_cast<std::size_t>(x)]);
  }
}

// Flips a volume: mirror_x maps x -> W-1-x, mirror_y maps y -> H-1-y.
std::vector<uint32_t> flip(const std::vector<uint32_t>& v, const kern::StereoParams& p, bool mirror_x, bool mirror_y) {
  std::vector<uint32_t> out(v.size());
  for (int y = 0; y < p.height_px; ++y)
    for (int x = 0; x < p.width_px; ++x)
      for (int d = 0; d < p.disparities; ++d) {
        const int sx = mirror_x ? p.width_px - 1 - x : x;
        const int sy = mirror_y ? p.height_px - 1 - y : y;
        out[volume_index(x, y, d, p.width_px, p.disparities)] = at(v, sx, sy, d, p);
      }
  return out;
}

std::vector<uint32_t> transpose(const std::vector<uint32_t>& v, const kern::StereoParams& p) {
  std::vector<uint32_t> out(v.size());
  for (int y = 0; y < p.height_px; ++y)
    for (int x = 0; x < p.width_px; ++x)
      for (int d = 0; d < p.disparities; ++d)
        out[volume_index(y, x, d, p.height_px, p.disparities)] = at(v, x, y, d, p);
  return out;
}

TEST(PathCosts, DirectionsAreMirrorImagesOfEachOther) {
  const unsigned seed = 12345u;
  SCOPED_TRACE(testing::Message() << "seed " << seed);
  std::mt19937 rng(seed);
  kern::StereoParams p = make_params(7, 5, kern::kCostCensus, 5, 6, kern::kAllPaths, 2, 7);
  std::uniform_int_distribution<uint32_t> dist(0, kern::cost_max(p));
  std::vector<uint32_t> c(static_cast<std::size_t>(7 * 5 * 6));
  for (uint32_t& v : c) v = dist(rng);

  auto path = [&](const std::vector<uint32_t>& cost, unsigned bit) { return path_costs(cost, p, bit); };
  // Mirroring x turns 0 <-> 180, 45 <-> 135, 225 <-> 315; mirroring y turns 90 <-> 270,
  // 45 <-> 315, 135 <-> 225; both turn 45 <-> 225, 135 <-> 315.
  const auto cx = flip(c, p, true, false);
  const auto cy = flip(c, p, false, true);
  const auto cxy = flip(c, p, true, true);
  EXPECT_EQ(path(c, kern::kPath180), flip(path(cx, kern::kPath0), p, true, false));
  EXPECT_EQ(path(c, kern::kPath135), flip(path(cx, kern::kPath45), p, true, false));
  EXPECT_EQ(path(c, kern::kPath315), flip(path(cx, kern::kPath225), p, true, false));
  EXPECT_EQ(path(c, kern::kPath270), flip(path(cy, kern::kPath90), p, false, true));
  EXPECT_EQ(path(c, kern::kPath315), flip(path(cy, kern::kPath45), p, false, true));
  EXPECT_EQ(path(c, kern::kPath225), flip(path(cy, kern::kPath135), p, false, true));
  EXPECT_EQ(path(c, kern::kPath225), flip(path(cxy, kern::kPath45), p, true, true));
  EXPECT_EQ(path(c, kern::kPath315), flip(path(cxy, kern::kPath135), p, true, true));

  // Transposing swaps x and y: top-to-bottom is left-to-right of the transposed volume.
  kern::StereoParams pt = p;
  pt.width_px = p.height_px;
  pt.height_px = p.width_px;
  EXPECT_EQ(transpose(path(c, kern::kPath90), p), path_costs(transpose(c, p), pt, kern::kPath0));
}

TEST(Aggregate, IsTheSumOfTheActivePaths) {
  const unsigned seed = 777u;
  SCOPED_TRACE(testing::Message() << "seed " << seed);
  std::mt19937 rng(seed);
  kern::StereoParams p = make_params(6, 4, kern::kCostCensus, 3, 5, 0, 1, 5);
  std::uniform_int_distribution<uint32_t> dist(0, kern::cost_max(p));
  std::vector<uint32_t> c(static_cast<std::size_t>(6 * 4 * 5));
  for (uint32_t& v : c) v = dist(rng);

  const unsigned masks[] = {kern::kPath0, kern::kPath0 | kern::kPath90, kern::kForwardPaths, kern::kAllPaths,
                            kern::kPath45 | kern::kPath270};
  for (const unsigned mask : masks) {
    p.path_mask = mask;
    std::vector<uint32_t> expected(c.size(), 0);
    for (const unsigned bit : kAllPathBits) {
      if ((mask & bit) == 0) continue;
      const std::vector<uint32_t> l = path_costs(c, p, bit);
      for (std::size_t i = 0; i < c.size(); ++i) expected[i] += l[i];
    }
    EXPECT_EQ(aggregate(c, p), expected) << "mask " << mask;
  }
}

TEST(Aggregate, HandExampleTwoPaths) {
  // Paths 0 and 180 on the hand row: S = L0 + L180.
  const kern::StereoParams p = row_params(kern::kPath0 | kern::kPath180);
  const std::vector<uint32_t> s = aggregate(volume_from({kRowCosts}), p);
  expect_pixel(s, 0, 0, p, {18, 1, 21, 21});
  expect_pixel(s, 1, 0, p, {3, 17, 20, 10});
  expect_pixel(s, 2, 0, p, {0, 13, 15, 15});
}

TEST(BitWidths, PathCostReachesItsBoundExactly) {
  // One row, D = 3: C(0) = [0 max max], C(1) = [max max max] with P2 <= cost_max:
  // L(1, 2) = max + min(max, max + P1, 0 + P2) - 0 = max + P2, the bound of docs §3.
  kern::StereoParams p = make_params(2, 1, kern::kCostCensus, 3, 3, kern::kPath0, 6, 7);
  const uint32_t m = kern::cost_max(p);  // 8
  const std::vector<uint32_t> c = volume_from({{{0, m, m}, {m, m, m}}});
  const std::vector<uint32_t> l = path_costs(c, p, kern::kPath0);
  EXPECT_EQ(at(l, 1, 0, 2, p), m + 7u);
  EXPECT_LT(uint64_t(m + 7u), uint64_t(1) << kern::path_bits(p));
}

TEST(BitWidths, HoldForMaxCostImagesAndLargeP2) {
  const unsigned seed = 4242u;
  SCOPED_TRACE(testing::Message() << "seed " << seed);
  std::mt19937 rng(seed);
  const int w = 16, h = 9;
  std::vector<std::pair<Image8, Image8>> pairs;
  pairs.emplace_back(make_image(w, h, 255), make_image(w, h, 0));
  pairs.emplace_back(test::random_image(w, h, rng), test::random_image(w, h, rng));
  Image8 stripes = make_image(w, h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; x += 2) stripes.px[static_cast<std::size_t>(y * w + x)] = 255;
  Image8 inverse = stripes;
  for (uint8_t& v : inverse.px) v = static_cast<uint8_t>(255 - v);
  pairs.emplace_back(stripes, inverse);

  for (const int cost : {int(kern::kCostCensus), int(kern::kCostSad)}) {
    for (const int p2 : {50, 4095, 100000}) {
      kern::StereoParams p = make_params(w, h, cost, 5, 12, kern::kAllPaths, p2 - 1, p2);
      p.window_h = 3;
      for (const auto& lr : pairs) {
        const std::vector<uint32_t> c = cost_volume(lr.first, lr.second, p);
        const uint64_t path_limit = (uint64_t(1) << kern::path_bits(p)) - 1;
        for (const unsigned bit : kAllPathBits) {
          const std::vector<uint32_t> l = path_costs(c, p, bit);
          const uint32_t biggest = *std::max_element(l.begin(), l.end());
          EXPECT_LE(uint64_t(biggest), uint64_t(kern::cost_max(p)) + uint64_t(p2));
          EXPECT_LE(uint64_t(biggest), path_limit);
        }
        const std::vector<uint32_t> s = aggregate(c, p);
        EXPECT_LE(uint64_t(*std::max_element(s.begin(), s.end())), (uint64_t(1) << kern::aggregate_bits(p)) - 1);
      }
    }
  }
}

TEST(PathCosts, RejectsBadInputs) {
  const kern::StereoParams p = row_params(kern::kPath0);
  const std::vector<uint32_t> c = volume_from({kRowCosts});
  EXPECT_THROW(path_costs(c, p, kern::kPath0 | kern::kPath90), std::invalid_argument);
  EXPECT_THROW(path_costs(c, p, 1u << 9), std::invalid_argument);
  EXPECT_THROW(path_costs(std::vector<uint32_t>(5, 0), p, kern::kPath0), std::invalid_argument);
  std::vector<uint32_t> too_big = c;
  too_big[3] = 256;  // cost_max = 255 for SAD 1x1
  EXPECT_THROW(path_costs(too_big, p, kern::kPath0), std::invalid_argument);
}

}  // namespace
}  // namespace parallax::ref
