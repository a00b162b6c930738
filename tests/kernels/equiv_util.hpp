// Helpers of the equivalence tests: seeded images, and a two-sided comparison of two disparity
// maps that reports the count of differing pixels and the first one in raster order.
#pragma once

#include <cstdint>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "parallax/kernels/params.hpp"
#include "parallax/reference/stereo.hpp"
#include "parallax/sim/func.hpp"

namespace parallax::test {

enum class Pattern { kRandom, kShiftedTexture, kStripes, kFlat };

struct StereoPair {
  sim::GreyImage left, right;
};

// Seeded: the same (pattern, size, seed) always gives the same pair.
inline StereoPair make_pair(Pattern pat, int w, int h, uint32_t seed, int shift_px = 5) {
  std::mt19937 rng(seed);
  StereoPair sp;
  sp.left = {w, h, std::vector<uint8_t>(std::size_t(w) * h)};
  sp.right = {w, h, std::vector<uint8_t>(std::size_t(w) * h)};
  auto at = [w](int x, int y) { return std::size_t(y) * w + x; };
  switch (pat) {
    case Pattern::kRandom:
      for (auto& v : sp.left.px) v = uint8_t(rng());
      for (auto& v : sp.right.px) v = uint8_t(rng());
      break;
    case Pattern::kShiftedTexture: {
      // Right view of a textured plane at disparity shift_px, with noise and an occluding box.
      std::vector<uint8_t> tex(std::size_t(w + shift_px + 8) * h);
      for (auto& v : tex) v = uint8_t(rng() % 200 + 20);
      const int tw = w + shift_px + 8;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          sp.left.px[at(x, y)] = tex[std::size_t(y) * tw + x + shift_px];
          sp.right.px[at(x, y)] = uint8_t(tex[std::size_t(y) * tw + x] + rng() % 5);
        }
      for (int y = h / 3; y < h / 2; ++y)
        for (int x = w / 3; x < w / 2; ++x) sp.left.px[at(x, y)] = uint8_t(240 - (x % 7) * 9);
      break;
    }
    case Pattern::kStripes:
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          sp.left.px[at(x, y)] = uint8_t(((x + 3) / 4 + y / 5) % 2 ? 200 : 40);
          sp.right.px[at(x, y)] = uint8_t(((x + shift_px + 3) / 4 + y / 5) % 2 ? 200 : 40);
        }
      break;
    case Pattern::kFlat:
      for (auto& v : sp.left.px) v = 128;
      for (auto& v : sp.right.px) v = 128;
      break;
  }
  return sp;
}

// The Census design the tests start from (5x5, P1/P2 8/32, 4 paths, LR check, 5x5 median).
inline kern::StereoParams test_params(int w, int h, int d = 16, int pu = 4, unsigned paths = kern::kForwardPaths) {
  kern::StereoParams p{};
  p.width_px = w;
  p.height_px = h;
  p.cost = kern::kCostCensus;
  p.window_w = 5;
  p.window_h = 5;
  p.disparities = d;
  p.parallel_units = pu;
  p.path_mask = paths;
  p.p1 = 8;
  p.p2 = 32;
  p.lr_check = true;
  p.lr_tolerance = 1;
  p.median = 5;
  return p;
}

inline ref::Image8 to_ref(const sim::GreyImage& g) {
  ref::Image8 r;
  r.width_px = g.width_px;
  r.height_px = g.height_px;
  r.px = g.px;
  return r;
}

struct Comparison {
  bool sizes_equal = true;
  int64_t mismatches = 0;
  std::string first;  // "(x, y): kernel K, reference R"
};

// Two-sided: sizes must agree, and every pixel of each map is checked against the other.
template <class A, class B>
Comparison compare_maps(const std::vector<A>& kernel, const std::vector<B>& reference, int width_px) {
  Comparison c;
  if (kernel.size() != reference.size()) {
    c.sizes_equal = false;
    std::ostringstream o;
    o << "sizes differ: kernel " << kernel.size() << ", reference " << reference.size();
    c.first = o.str();
    return c;
  }
  for (std::size_t i = 0; i < kernel.size(); ++i) {
    if (uint64_t(kernel[i]) == uint64_t(reference[i])) continue;
    if (c.mismatches++ == 0) {
      std::ostringstream o;
      o << "(" << i % std::size_t(width_px) << ", " << i / std::size_t(width_px) << "): kernel " << uint64_t(kernel[i])
        << ", reference " << uint64_t(reference[i]);
      c.first = o.str();
    }
  }
  return c;
}

inline std::string describe(const kern::StereoParams& p) {
  std::ostringstream o;
  o << p.width_px << "x" << p.height_px << " " << (p.cost == kern::kCostCensus ? "census" : "sad") << " " << p.window_w
    << "x" << p.window_h << " D=" << p.disparities << " PU=" << p.parallel_units << " paths=0x" << std::hex
    << p.path_mask << std::dec << " P1/P2=" << p.p1 << "/" << p.p2 << " lr=" << p.lr_check << "/" << p.lr_tolerance
    << " median=" << p.median << " uniqueness=" << p.uniqueness_pct << " census=" << p.census
    << " min_disparity=" << p.min_disparity << " p2_adaptive=" << p.p2_adaptive
    << (p.aggregation == kern::kAggregationMgm ? " mgm" : " sgm") << " subpixel_bits=" << p.subpixel_bits;
  return o.str();
}

}  // namespace parallax::test
