// Helpers shared by the reference model's tests.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "parallax/kernels/params.hpp"
#include "parallax/reference/stereo.hpp"

namespace parallax::ref::test {

// Parameters with every field set: no LR check, no median, PU 1.
inline kern::StereoParams make_params(int width_px, int height_px, int cost, int window, int disparities,
                                      unsigned path_mask, int p1, int p2) {
  kern::StereoParams p{};
  p.width_px = width_px;
  p.height_px = height_px;
  p.cost = cost;
  p.window_w = window;
  p.window_h = window;
  p.disparities = disparities;
  p.parallel_units = 1;
  p.path_mask = path_mask;
  p.p1 = p1;
  p.p2 = p2;
  p.lr_check = false;
  p.lr_tolerance = 1;
  p.median = 0;
  return p;
}

// An image from explicit rows (all rows the same length).
inline Image8 image_from_rows(const std::vector<std::vector<int>>& rows) {
  Image8 img = make_image(static_cast<int>(rows.front().size()), static_cast<int>(rows.size()));
  for (int y = 0; y < img.height_px; ++y)
    for (int x = 0; x < img.width_px; ++x)
      img.px[static_cast<std::size_t>(y * img.width_px + x)] =
          static_cast<uint8_t>(rows[static_cast<std::size_t>(y)][static_cast<std::size_t>(x)]);
  return img;
}

inline Image8 random_image(int width_px, int height_px, std::mt19937& rng) {
  std::uniform_int_distribution<int> dist(0, 255);
  Image8 img = make_image(width_px, height_px);
  for (uint8_t& v : img.px) v = static_cast<uint8_t>(dist(rng));
  return img;
}

// A cost volume from per-pixel rows of costs: costs[y][x][d].
inline std::vector<uint32_t> volume_from(const std::vector<std::vector<std::vector<uint32_t>>>& c) {
  std::vector<uint32_t> v;
  for (const auto& row : c)
    for (const auto& px : row) v.insert(v.end(), px.begin(), px.end());
  return v;
}

inline uint32_t at(const std::vector<uint32_t>& v, int x, int y, int d, const kern::StereoParams& p) {
  return v[volume_index(x, y, d, p.width_px, p.disparities)];
}

}  // namespace parallax::ref::test
