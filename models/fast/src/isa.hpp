// The fast engine's hot loops, compiled once per x86-64 level (isa.cpp is built three times:
// baseline x86-64, x86-64-v3 = AVX2, x86-64-v4 = AVX-512) and chosen at run time by the CPU's
// features (engine.cpp: pick_isa(), overridden by set_simd_level()). The tables hold plain functions over raw pointers:
// the per-level translation units include no standard-library header, so that no inline function compiled for one level
// can be picked by the linker for another (the one-definition-rule trap of per-file target flags).
//
// Layouts: images and codes row-major (y * W + x). Cost rows are [W][S] with the stride
// S = cost_stride(D) (D rounded up to 32) and the lanes d >= D set to kCostPad; path-cost and
// aggregate rows are [W][lanes], lanes either D or S. With lanes = S every loop runs whole
// vectors: a padding lane's path cost stays in [kCostPad, kCostPad + P2], above every real path
// cost (<= cost_max + P2) and high enough never to win as a neighbour (the 16-bit engine uses
// padding when cost_max + 2 P2 + P1 < kCostPad, engine.cpp). A path-cost row keeps two guard
// entries per pixel (lanes + 2 per pixel and recursion, lane d at d + 1; the recursions of a
// pass interleaved, Recursion below) so that the d - 1 and d + 1 neighbours need no test.
#pragma once

#include <stdint.h>

namespace parallax::fast::detail {

constexpr uint16_t kCostPad = 0x8000;
constexpr int cost_stride(int disparities) {
  return (disparities + 31) / 32 * 32;
}

// The reversed right row sad_columns reads: u - m - d over u in [-rw, W + rw), d < cost_stride(D).
constexpr int sad_scratch_len(int width_px, int window_w, int min_disparity, int disparities) {
  return width_px + 2 * (window_w / 2) + min_disparity + cost_stride(disparities);
}

// Byte planes of a census code of `bits` bits (bits <= 64; a 1x1 window's empty code takes one
// plane of zeros), and the length per plane of the reversed right row that cost_census reads.
constexpr int census_planes(int bits) {
  return bits <= 8 ? 1 : (bits + 7) / 8;
}
constexpr int census_scratch_len(int width_px, int min_disparity, int disparities) {
  return width_px + min_disparity + cost_stride(disparities);
}

// The recursions one raster pass can hold (docs/algorithm.md §3, in stream coordinates: the
// backward pass runs the same kinds with the directions mirrored). SGM: one per path; MGM: the
// 0/90 and 45/135 pairs are one recursion each.
enum RecursionKind : int { kSgm0 = 0, kSgm45 = 1, kSgm90 = 2, kSgm135 = 3, kMgmPixel = 4, kMgmRow = 5 };

// Row buffers: pixel x's path costs start at prev + x * stride (lanes + 2 of them: a guard, the
// lanes, a guard; the guards hold the type's maximum minus P1 for the whole frame, written by the
// engine, never by the recursions), its minimum at prev_min[x * min_stride]. The engine keeps the
// four recursions of a pass interleaved per pixel (recursion k at offset k * (lanes + 2), stride
// 4 * (lanes + 2), minima at k with min_stride 4), which lets the 2-, 3- and 4-path loops address
// all of them from one pointer per row.
struct Recursion {
  int kind = 0;              // RecursionKind
  int weight = 1;            // paths that add this recursion (MGM pairs: 1 or 2)
  void* prev = nullptr;      // previous stream row's path costs, [W] x stride of the pass's type
  void* cur = nullptr;       // this row's
  void* prev_min = nullptr;  // per pixel minimum over d of prev, [W] x min_stride
  void* cur_min = nullptr;
  int stride = 0;  // elements from one pixel's path costs to the next's (>= lanes + 2)
  int min_stride = 1;
};

// One stream row of one pass. Pixels are addressed by their image column x; the stream runs
// x = 0..W-1 (dir +1) or W-1..0 (dir -1), and "the previous pixel" is x - dir.
struct AggregateRow {
  int width_px = 0;
  int disparities = 0;
  int lanes = 0;        // D or cost_stride(D)
  int cost_stride = 0;  // of cost rows
  int dir = 1;
  bool first_row = true;               // no previous stream row (its predecessors are outside the image)
  const uint16_t* cost = nullptr;      // [W][cost_stride]
  const uint8_t* intensity = nullptr;  // this row's left intensities (adaptive P2), or null
  const uint8_t* prev_intensity = nullptr;
  int p1 = 0, p2 = 0, p2_adaptive = 0;
  int recursions = 0;
  Recursion rec[4];
  bool accumulate = false;  // S += (else S =)
  void* sum = nullptr;      // [W][lanes] of the pass's type
};

struct SelectRow {
  int width_px = 0, disparities = 0, lanes = 0, min_disparity = 0, subpixel_bits = 0;
  bool lr_check = false;
  int lr_tolerance = 0, uniqueness_pct = 0;
  const void* sum = nullptr;       // [W][lanes]
  void* right_best = nullptr;      // scratch [W + lanes + m + 1] of the type
  uint16_t* right_code = nullptr;  // scratch, same length
  int32_t* left_code = nullptr;    // scratch [W]: dL, or -1 when invalid before the LR check
  int32_t* offset = nullptr;       // scratch [W]: sub-pixel offsets
  uint16_t* out = nullptr;         // [W] codes (docs §5)
};

struct CostRow {
  int width_px = 0, disparities = 0, min_disparity = 0;
  uint16_t cost_max = 0;
  uint16_t* out = nullptr;  // [W][cost_stride(D)], padding lanes kCostPad
};

// The median's comparator network: Batcher's odd-even merge sort over n = 2^k >= taps inputs,
// pruned to the comparators (lo[c], hi[c]) (min to lo) that decide the output of rank
// (taps - 1) / 2; comparators touching the padding (inputs >= taps, +inf) are left out. taps <=
// 64 (windows up to 7 x 7, 319 comparators). constexpr and without the standard library: the
// engine builds its run-time list from it and isa.cpp compiles it in for the common windows, so
// both run the same network.
struct MedianNet {
  int16_t lo[512] = {}, hi[512] = {};
  int n = 0;
};
constexpr MedianNet make_median_net(int taps) {
  const int rank = (taps - 1) / 2;
  int n = 1;
  while (n < taps) n *= 2;
  int16_t all_lo[1024] = {}, all_hi[1024] = {};
  int count = 0;
  for (int p = 1; p < n; p *= 2)
    for (int k = p; k >= 1; k /= 2)
      for (int j = k % p; j <= n - 1 - k; j += 2 * k)
        for (int i = 0; i <= (k - 1 < n - j - k - 1 ? k - 1 : n - j - k - 1); ++i)
          if ((i + j) / (2 * p) == (i + j + k) / (2 * p)) {
            all_lo[count] = static_cast<int16_t>(i + j);
            all_hi[count] = static_cast<int16_t>(i + j + k);
            ++count;
          }
  bool needed[64] = {};
  needed[rank] = true;
  MedianNet net;
  for (int c = count - 1; c >= 0; --c) {  // backwards from the output, kept in reverse order
    if (all_hi[c] >= taps) continue;
    if (needed[all_lo[c]] || needed[all_hi[c]]) {
      net.lo[net.n] = all_lo[c];
      net.hi[net.n] = all_hi[c];
      ++net.n;
      needed[all_lo[c]] = needed[all_hi[c]] = true;
    }
  }
  for (int c = 0; c < net.n / 2; ++c) {  // into network order
    const int16_t l = net.lo[c], h = net.hi[c];
    net.lo[c] = net.lo[net.n - 1 - c];
    net.hi[c] = net.hi[net.n - 1 - c];
    net.lo[net.n - 1 - c] = l;
    net.hi[net.n - 1 - c] = h;
  }
  return net;
}

struct IsaTable {
  const char* name;
  // Census codes of a whole image (docs §2), kind = kern::CensusKind, as byte planes:
  // codes[y][plane][x], planes = census_planes(bits); the engine's own bit order (isa.cpp).
  void (*census)(const uint8_t* img, int width_px, int height_px, int window_w, int window_h, int kind, int planes,
                 uint8_t* codes);
  // One cost row from the census planes of that row ([planes][W]) of the left and of the right
  // image. scratch: planes * census_scratch_len(W, m, D) bytes.
  void (*cost_census)(const CostRow& r, const uint8_t* left, const uint8_t* right, int planes, uint8_t* scratch);
  // SAD in two steps. Column sums [W + 2 rw][cost_stride(D)] of the rows in the window, kept
  // from row to row by the caller: sad_columns adds (sign +1) or takes off (sign -1) one image
  // row pair's |L(clampx(u)) - R(clampx(u - m - d))|; scratch: sad_scratch_len bytes. sad_box
  // makes one cost row from them (the box over window_w columns).
  void (*sad_columns)(const CostRow& r, const uint8_t* left_row, const uint8_t* right_row, int window_w, int sign,
                      uint16_t* col, uint8_t* scratch);
  void (*sad_box)(const CostRow& r, int window_w, const uint16_t* col);
  void (*aggregate16)(const AggregateRow& r);
  void (*aggregate32)(const AggregateRow& r);
  // A row of finished 16-bit sums [W][lanes]: the padding lanes d >= D set to 0xFFFF.
  void (*pad_sums16)(uint16_t* sum, int width_px, int disparities, int lanes);
  void (*select16)(const SelectRow& r);
  void (*select32)(const SelectRow& r);
  // k x k median of one output row by a comparator network over the window (a list of
  // (i, j) tap pairs, min to i): taps = scratch [k * k][W]; rows[j] = code rows clampy(y + j - k/2).
  void (*median_row)(const uint16_t* const* rows, int width_px, int k, const int16_t* pairs, int pair_count, int rank,
                     uint16_t* taps, uint16_t* out);
};

const IsaTable& isa_baseline();
const IsaTable& isa_avx2();
const IsaTable& isa_avx512();

}  // namespace parallax::fast::detail
