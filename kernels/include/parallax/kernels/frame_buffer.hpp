// The two-pass variant's frame buffer in DDR (issue 14, item 5), described once: the exported top
// (hls/templates/top_two_pass.cpp.in), the cycle model (sim/src/engine.hpp), the resource model
// and the export's m_axi pragmas all take the layout from here, and
// tests/kernels/frame_buffer_test.cpp checks it. C++14, no STL, no heap.
//
// Words. Each firing of pass 1's forward aggregation leaves a pair of tokens for pass 2: PU
// matching costs of cb = cost_bits bits and PU forward sums of ab = aggregate_bits bits. The pair
// travels as one DDR word of W bits, W the next power of two >= PU * (cb + ab), at least 32 (the
// narrowest AXI data bus Vitis makes) and at most 1024 (AXI4's widest):
//
//   bits [l * cb, (l + 1) * cb)                      cost lane l,        l = 0 .. PU-1
//   bits [PU * cb + l * ab, PU * cb + (l + 1) * ab)  forward sum lane l, l = 0 .. PU-1
//   bits [PU * (cb + ab), W)                         zero
//
// A pair wider than 1024 bits (e.g. PU = 64 with 13-bit SAD costs and 17-bit sums) cannot be one
// AXI beat: it takes beats = ceil(bits / 1024) consecutive 1024-bit words, bit b of the pair in
// word b / 1024 at bit b % 1024 (the same layout, cut into beats). In memory a word is a struct
// of 32-bit limbs, limb i = bits [32 i, 32 i + 32): Vitis aggregates it into one W-bit bus word,
// and the compat headers (ap_uint up to 64 bits) and the simulator need no wide integer type.
//
// Addresses. Pass 2 consumes the pixels in reverse raster order, each pixel's chunks ascending, so
// the buffer holds them in that order: pixel q (raster index, P pixels), chunk c, beat b at word
//
//   ((P - 1 - q) * chunks + c) * beats + b,
//
// and pass 2 reads words 0 .. N - 1 (N = P * chunks * beats) in one ascending stream. Pass 1
// produces raster order and reverses on chip, in segments of S pixels: S is the largest divisor
// of P whose words, S * chunks * beats, fit one AXI burst (256 beats and 4 KB). Segment j (pixels
// j S .. j S + S - 1) fills one half of a ping-pong buffer while segment j - 1 leaves the other
// half reversed (pixels descending, each pixel's words ascending) into its block of S * chunks *
// beats words, block nseg - 1 - j, at ascending addresses: one burst per segment. Whole rows
// would give no longer bursts (AXI caps a burst at 4 KB) at up to a row's worth of BRAM.
// The disparity map leaves pass 2 in reverse raster order too and is written the same way, in
// segments of codes (map_segment_pixels), so that the map lands in raster order.
#pragma once

#include <stdint.h>

#include "parallax/kernels/common.hpp"
#include "parallax/kernels/params.hpp"

namespace parallax {
namespace kern {

constexpr int kFrameWordMinBits = 32;
constexpr int kFrameWordMaxBits = 1024;
constexpr int kAxiMaxBurstBeats = 256;   // AXI4 INCR bursts
constexpr int kAxiMaxBurstBytes = 4096;  // no burst crosses a 4 KB boundary
constexpr int kMapCodeBytes = 2;         // the map's elements in memory: DispCode

// --- widths ------------------------------------------------------------------------------------

constexpr int frame_pair_bits_of(int lanes, int cost_bits, int sum_bits) {
  return lanes * (cost_bits + sum_bits);
}
// The DDR word: the next power of two >= the pair, in [32, 1024].
constexpr int frame_word_bits_of(int pair_bits) {
  int w = kFrameWordMinBits;
  while (w < pair_bits && w < kFrameWordMaxBits) w *= 2;
  return w;
}
// Words per pair: 1 unless the pair exceeds 1024 bits.
constexpr int frame_beats_of(int pair_bits) {
  return (pair_bits + frame_word_bits_of(pair_bits) - 1) / frame_word_bits_of(pair_bits);
}
constexpr int frame_limbs_of(int bits) {
  return (bits + 31) / 32;
}
// The longest burst of elements of this size: 256 beats, 4 KB.
constexpr int burst_elements_of(int element_bytes) {
  return kAxiMaxBurstBytes / element_bytes < kAxiMaxBurstBeats ? kAxiMaxBurstBytes / element_bytes : kAxiMaxBurstBeats;
}
// The largest divisor S of `units` with S * unit_elements <= max_elements (at least 1).
constexpr int64_t segment_units_of(int64_t units, int64_t unit_elements, int64_t max_elements) {
  int64_t s = unit_elements > 0 ? max_elements / unit_elements : 1;
  if (s > units) s = units;
  while (s > 1 && units % s != 0) --s;
  return s < 1 ? 1 : s;
}

inline int frame_chunks(const StereoParams& p) {
  return p.disparities / p.parallel_units;
}
inline int frame_pair_bits(const StereoParams& p) {
  return frame_pair_bits_of(p.parallel_units, cost_bits(p), aggregate_bits(p));
}
inline int frame_word_bits(const StereoParams& p) {
  return frame_word_bits_of(frame_pair_bits(p));
}
inline int frame_word_bytes(const StereoParams& p) {
  return frame_word_bits(p) / 8;
}
inline int frame_beats(const StereoParams& p) {
  return frame_beats_of(frame_pair_bits(p));
}
inline int64_t frame_pixels(const StereoParams& p) {
  return int64_t(p.width_px) * p.height_px;
}
// Words of one pixel: its chunks' pairs, each `beats` words.
inline int frame_pixel_words(const StereoParams& p) {
  return frame_chunks(p) * frame_beats(p);
}
// Words of one frame buffer (each is written once by pass 1 and read once by pass 2).
inline int64_t frame_words(const StereoParams& p) {
  return frame_pixels(p) * frame_pixel_words(p);
}
inline int64_t frame_bytes(const StereoParams& p) {
  return frame_words(p) * frame_word_bytes(p);
}
// Pixels per reversal segment and the segment's words (one burst).
inline int64_t frame_segment_pixels(const StereoParams& p) {
  return segment_units_of(frame_pixels(p), frame_pixel_words(p), burst_elements_of(frame_word_bytes(p)));
}
inline int64_t frame_segment_words(const StereoParams& p) {
  return frame_segment_pixels(p) * frame_pixel_words(p);
}
// Codes per segment of the disparity map's reversal.
inline int64_t map_segment_pixels(const StereoParams& p) {
  return segment_units_of(frame_pixels(p), 1, burst_elements_of(kMapCodeBytes));
}

// --- addresses ---------------------------------------------------------------------------------

// Word of pixel q (raster index), chunk c, beat b: the pixels in reverse raster order.
inline int64_t frame_word_address(const StereoParams& p, int64_t pixel, int chunk, int beat) {
  return ((frame_pixels(p) - 1 - pixel) * frame_chunks(p) + chunk) * frame_beats(p) + beat;
}
// First element of the block that segment j (in the order pass 1 fills them) goes to.
constexpr int64_t reversed_block_base(int64_t segments, int64_t segment_elements, int64_t j) {
  return (segments - 1 - j) * segment_elements;
}
// The buffer slot that leaves at step k of a segment of `units` units of `group` slots each:
// units descending, each unit's slots ascending.
constexpr int64_t reversed_slot(int64_t k, int64_t group, int64_t units) {
  return (units - 1 - k / group) * group + k % group;
}

// reversed_slot as the hardware steps through it: counters, no division. After a segment's last
// slot it starts over with the next segment's first (the same slots: one segment's walk per half).
class ReverseWalk {
 public:
  void start(int units, int group) {
    units_ = units;
    group_ = group;
    unit_ = units - 1;
    slot_in_unit_ = 0;
  }
  int slot() const { return unit_ * group_ + slot_in_unit_; }
  void next() {
    if (++slot_in_unit_ == group_) {
      slot_in_unit_ = 0;
      unit_ = unit_ == 0 ? units_ - 1 : unit_ - 1;
    }
  }

 private:
  int units_ = 1, group_ = 1, unit_ = 0, slot_in_unit_ = 0;
};

// --- packing -----------------------------------------------------------------------------------

// A DDR word (or a pair) as 32-bit limbs.
template <int kLimbs>
struct FrameWord {
  uint32_t limb[kLimbs];
};

// ORs the low `width` (<= 32) bits of v into bits [offset, offset + width) of the limbs.
template <int kLimbs>
PX_INLINE void frame_put_bits(uint32_t (&limbs)[kLimbs], int offset, int width, uint32_t v) {
  const uint32_t field = width >= 32 ? v : (v & ((uint32_t(1) << width) - 1u));
  const uint64_t shifted = uint64_t(field) << (offset & 31);
  const int i = offset >> 5;
  limbs[i] |= uint32_t(shifted);
  if ((offset & 31) + width > 32) limbs[i + 1] |= uint32_t(shifted >> 32);
}
template <int kLimbs>
PX_INLINE uint32_t frame_get_bits(const uint32_t (&limbs)[kLimbs], int offset, int width) {
  const int i = offset >> 5;
  uint64_t v = limbs[i] >> (offset & 31);
  if ((offset & 31) + width > 32) v |= uint64_t(limbs[i + 1]) << (32 - (offset & 31));
  return width >= 32 ? uint32_t(v) : uint32_t(v) & ((uint32_t(1) << width) - 1u);
}

// The pair of `lanes` costs and sums in the layout above (limbs past the pair are zero).
template <class C, class S, int N, int kLimbs>
void frame_pack(const Lanes<C, N>& cost, const Lanes<S, N>& sum, int lanes, int cost_bits, int sum_bits,
                uint32_t (&limbs)[kLimbs]) {
frame_pack_clear:
  for (int i = 0; i < kLimbs; ++i) {
    PX_PRAGMA("HLS UNROLL")
    limbs[i] = 0;
  }
frame_pack_lanes:
  for (int l = 0; l < N; ++l) {
    PX_PRAGMA("HLS UNROLL")
    if (l < lanes) {
      frame_put_bits(limbs, l * cost_bits, cost_bits, uint32_t(cost.v[l]));
      frame_put_bits(limbs, lanes * cost_bits + l * sum_bits, sum_bits, uint32_t(sum.v[l]));
    }
  }
}
template <class C, class S, int N, int kLimbs>
void frame_unpack(const uint32_t (&limbs)[kLimbs], int lanes, int cost_bits, int sum_bits, Lanes<C, N>& cost,
                  Lanes<S, N>& sum) {
frame_unpack_lanes:
  for (int l = 0; l < N; ++l) {
    PX_PRAGMA("HLS UNROLL")
    if (l < lanes) {
      cost.v[l] = C(frame_get_bits(limbs, l * cost_bits, cost_bits));
      sum.v[l] = S(frame_get_bits(limbs, lanes * cost_bits + l * sum_bits, sum_bits));
    } else {
      cost.v[l] = C(0);
      sum.v[l] = S(0);
    }
  }
}

// Beat b of a pair as a word of word_limbs (<= kWordLimbs) limbs, limbs past the pair zero; and
// back (the decoder collects a pair's beats before unpacking it).
template <int kPairLimbs, int kWordLimbs>
PX_INLINE void frame_beat_of(const uint32_t (&pair)[kPairLimbs], int beat, int word_limbs,
                             uint32_t (&word)[kWordLimbs]) {
frame_beat_limbs:
  for (int i = 0; i < kWordLimbs; ++i) {
    PX_PRAGMA("HLS UNROLL")
    const int at = beat * word_limbs + i;
    word[i] = i < word_limbs && at < kPairLimbs ? pair[at] : 0u;
  }
}
template <int kPairLimbs, int kWordLimbs>
PX_INLINE void frame_set_beat(uint32_t (&pair)[kPairLimbs], int beat, int word_limbs,
                              const uint32_t (&word)[kWordLimbs]) {
frame_set_beat_limbs:
  for (int i = 0; i < kWordLimbs; ++i) {
    PX_PRAGMA("HLS UNROLL")
    const int at = beat * word_limbs + i;
    if (i < word_limbs && at < kPairLimbs) pair[at] = word[i];
  }
}

// --- resources ---------------------------------------------------------------------------------

// The on-chip reversal buffers (declare() vocabulary of resources.hpp): ddr_write's ping-pong
// segment buffer of pairs (both halves in one simple dual-port memory: one write and one read per
// cycle), and the map writer's of codes.
template <class R>
void declare_frame_segment_buffer(R& r, const StereoParams& p) {
  r.memory("segment_buffer", 2 * frame_segment_pixels(p) * frame_chunks(p), frame_pair_bits(p), 1, false);
}
template <class R>
void declare_map_segment_buffer(R& r, const StereoParams& p) {
  r.memory("map_segment_buffer", 2 * map_segment_pixels(p), disparity_bits(p), 1, false);
}

}  // namespace kern
}  // namespace parallax
