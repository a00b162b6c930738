// unit: the two-pass frame buffer's layout (kernels/frame_buffer.hpp), which the exported top, the
// cycle model and the resource model share. Words are the pair's next power of two in [32, 1024]
// (several 1024-bit beats above that); packing puts each lane at its documented bit range and
// round-trips; the on-chip reversal writes every word once, each segment as one ascending burst,
// at the address pass 2 reads it from (pixels in reverse raster order, chunks ascending), and pass
// 2 reads 0 .. N-1; the map writer's reversal lands the codes in raster order.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "parallax/kernels/frame_buffer.hpp"

namespace parallax::kern {
namespace {

bool power_of_two(int v) {
  return v > 0 && (v & (v - 1)) == 0;
}

TEST(FrameBufferWords, NextPowerOfTwoBetween32And1024) {
  for (int bits = 1; bits <= 5000; ++bits) {
    const int w = frame_word_bits_of(bits), beats = frame_beats_of(bits);
    ASSERT_TRUE(power_of_two(w)) << bits;
    ASSERT_GE(w, 32) << bits;
    ASSERT_LE(w, 1024) << bits;
    ASSERT_GE(w * beats, bits) << bits;
    if (bits <= 1024) {
      ASSERT_EQ(beats, 1) << bits;
      ASSERT_TRUE(w == 32 || w / 2 < bits) << bits << ": " << w << " is not the next power of two";
    } else {
      ASSERT_EQ(w, 1024) << bits;
      ASSERT_EQ(beats, (bits + 1023) / 1024) << bits;
    }
  }
  EXPECT_EQ(frame_word_bits_of(90), 128);  // the seed's 8-path variant: 6 x (5 + 10) bits
  EXPECT_EQ(frame_word_bits_of(20), 32);
  EXPECT_EQ(frame_word_bits_of(1024), 1024);
  EXPECT_EQ(frame_beats_of(1025), 2);
}

TEST(FrameBufferWords, TheSeedVariantsPairIn128Bits) {
  StereoParams p{640, 360, kCostCensus, 5, 5, 60, 6, kAllPaths, 10, 120, true, 1, 5, 0, 0};
  EXPECT_EQ(cost_bits(p), 5);
  EXPECT_EQ(frame_pair_bits(p), 6 * (cost_bits(p) + aggregate_bits(p)));
  EXPECT_EQ(frame_word_bits(p), 128);
  EXPECT_EQ(frame_word_bytes(p), 16);
  EXPECT_EQ(frame_beats(p), 1);
  EXPECT_EQ(frame_words(p), 640LL * 360 * 10);
  EXPECT_EQ(frame_bytes(p), 640LL * 360 * 10 * 16);
  EXPECT_EQ(frame_segment_pixels(p), 25);  // 250 words of 16 bytes: one burst <= 256 beats, 4 KB
  EXPECT_EQ(map_segment_pixels(p), 256);
}

// The documented bit ranges, checked bit by bit against a plain bit vector.
template <int N, int kLimbs>
void expect_layout(int lanes, int cb, int ab, std::mt19937& rng) {
  Lanes<uint16_t, N> cost{}, cost_back{};
  Lanes<uint32_t, N> sum{}, sum_back{};
  for (int l = 0; l < N; ++l) {
    cost.v[l] = l < lanes ? uint16_t(rng() & ((1u << cb) - 1u)) : uint16_t(0xFFFF);  // unused lanes must not leak
    sum.v[l] = l < lanes ? uint32_t(rng()) & (ab >= 32 ? ~0u : (1u << ab) - 1u) : ~0u;
  }
  uint32_t limbs[kLimbs];
  frame_pack(cost, sum, lanes, cb, ab, limbs);
  std::vector<int> bit(static_cast<std::size_t>(kLimbs) * 32, 0);
  for (int l = 0; l < lanes; ++l) {
    for (int b = 0; b < cb; ++b) bit[std::size_t(l * cb + b)] = (cost.v[l] >> b) & 1;
    for (int b = 0; b < ab; ++b) bit[std::size_t(lanes * cb + l * ab + b)] = (sum.v[l] >> b) & 1;
  }
  for (int i = 0; i < kLimbs * 32; ++i)
    ASSERT_EQ(int((limbs[i / 32] >> (i % 32)) & 1u), bit[std::size_t(i)])
        << "bit " << i << ", lanes " << lanes << ", cost " << cb << ", sum " << ab;
  // Cut into beats of the DDR word and put together again, then unpacked: the same lanes.
  const int pair_bits = frame_pair_bits_of(lanes, cb, ab);
  const int word_limbs = frame_word_bits_of(pair_bits) / 32, beats = frame_beats_of(pair_bits);
  uint32_t again[kLimbs] = {};
  for (int b = 0; b < beats; ++b) {
    uint32_t word[32];
    frame_beat_of(limbs, b, word_limbs, word);
    for (int i = 0; i < word_limbs; ++i) {
      const int at = b * word_limbs + i;
      ASSERT_EQ(word[i], at < kLimbs ? limbs[at] : 0u) << "beat " << b << " limb " << i;
    }
    frame_set_beat(again, b, word_limbs, word);
  }
  for (int i = 0; i < kLimbs; ++i) ASSERT_EQ(again[i], limbs[i]);
  frame_unpack(again, lanes, cb, ab, cost_back, sum_back);
  for (int l = 0; l < lanes; ++l) {
    ASSERT_EQ(cost_back.v[l], cost.v[l]) << l;
    ASSERT_EQ(sum_back.v[l], sum.v[l]) << l;
  }
}

TEST(FrameBufferPacking, LanesAtTheirBitRangesAndRoundTrip) {
  std::mt19937 rng(514);
  for (int rep = 0; rep < 20; ++rep) {
    expect_layout<6, 4>(6, 5, 10, rng);      // the seed: 90 bits, one 128-bit word
    expect_layout<1, 2>(1, 16, 31, rng);     // widest lanes
    expect_layout<8, 12>(3, 7, 13, rng);     // fields straddling limbs
    expect_layout<64, 96>(64, 13, 16, rng);  // 1856 bits: two 1024-bit beats
    expect_layout<64, 96>(60, 16, 31, rng);  // 2820 bits: three beats
  }
}

// Pass 1 in the order the exported ddr_write runs (and the cycle model counts): the first
// segment's pairs in, then per step one word out (ReverseWalk over the other half) and, every
// `beats` words, one pair in; the last segment out. Every word lands once, at the address
// frame_word_address gives its pixel, chunk and beat; each segment's words leave at ascending,
// contiguous addresses; and pass 2, reading 0 .. N-1, meets the pixels in reverse raster order.
void expect_reversal(const StereoParams& p) {
  const int64_t pixels = frame_pixels(p), words = frame_words(p);
  const int chunks = frame_chunks(p), beats = frame_beats(p);
  const int64_t seg = frame_segment_pixels(p), seg_tokens = seg * chunks, seg_words = frame_segment_words(p);
  ASSERT_EQ(pixels % seg, 0);
  ASSERT_LE(seg_words, burst_elements_of(frame_word_bytes(p)));
  for (int64_t s = seg + 1; s <= pixels; ++s)  // the largest such divisor
    if (pixels % s == 0) {
      ASSERT_GT(s * chunks * beats, burst_elements_of(frame_word_bytes(p))) << s;
    }
  const int64_t segments = pixels / seg;
  struct Pair {
    int64_t pixel;
    int chunk;
  };
  std::vector<Pair> half[2] = {std::vector<Pair>(std::size_t(seg_tokens)), std::vector<Pair>(std::size_t(seg_tokens))};
  std::vector<int64_t> written(std::size_t(words), -1);  // address -> the token's word (pixel, chunk, beat) code
  int64_t next_token = 0;
  auto take = [&](std::vector<Pair>& h, int64_t slot) {
    h[std::size_t(slot)] = {next_token / chunks, int(next_token % chunks)};
    ++next_token;
  };
  for (int64_t t = 0; t < seg_tokens; ++t) take(half[0], t);
  ReverseWalk walk;
  walk.start(int(seg), chunks);
  int beat = 0;
  int64_t in = 0, last_address = -1;
  auto emit = [&](int64_t j, int64_t k, const std::vector<Pair>& h) {
    const int64_t address = reversed_block_base(segments, seg_words, j) + k;
    ASSERT_EQ(walk.slot(), reversed_slot(k / beats, chunks, seg));
    const Pair& pr = h[std::size_t(walk.slot())];
    ASSERT_EQ(address, frame_word_address(p, pr.pixel, pr.chunk, beat)) << "segment " << j << " step " << k;
    if (k > 0) {
      ASSERT_EQ(address, last_address + 1) << "segment " << j << ": not one ascending burst";
    }
    ASSERT_EQ(written[std::size_t(address)], -1) << "address " << address << " written twice";
    written[std::size_t(address)] = (pr.pixel * chunks + pr.chunk) * beats + beat;
    last_address = address;
    if (++beat == beats) {
      beat = 0;
      walk.next();
    }
  };
  for (int64_t j = 1; j < segments; ++j)
    for (int64_t k = 0; k < seg_words; ++k) {
      emit(j - 1, k, half[(j - 1) % 2]);
      if (k % beats == 0) {
        take(half[j % 2], in);
        in = in + 1 == seg_tokens ? 0 : in + 1;
      }
    }
  for (int64_t k = 0; k < seg_words; ++k) emit(segments - 1, k, half[(segments - 1) % 2]);
  ASSERT_EQ(next_token, pixels * chunks);
  // Pass 2 reads 0 .. N-1: pixels descending from the last, each pixel's chunks and beats ascending.
  for (int64_t a = 0; a < words; ++a) {
    const int64_t q = pixels - 1 - a / (int64_t(chunks) * beats), in_pixel = a % (int64_t(chunks) * beats);
    ASSERT_EQ(written[std::size_t(a)], q * chunks * beats + in_pixel) << "address " << a;
  }
}

TEST(FrameBufferAddresses, SegmentReversalWritesWhatPassTwoReadsInOrder) {
  //                       W   H  cost         win   D   PU  paths
  expect_reversal(
      StereoParams{640, 16, kCostCensus, 5, 5, 60, 6, kAllPaths, 10, 120, true, 1, 5, 0, 0});          // reduced seed
  expect_reversal(StereoParams{37, 9, kCostCensus, 5, 5, 32, 8, kAllPaths, 8, 32, true, 1, 3, 0, 0});  // odd sizes
  expect_reversal(
      StereoParams{13, 7, kCostSad, 5, 5, 64, 64, kAllPaths, 8, 32, true, 1, 0, 0, 0});  // 2 beats, 91 pixels
  expect_reversal(
      StereoParams{11, 1, kCostCensus, 3, 3, 16, 16, kAllPaths, 8, 32, false, 1, 0, 0, 0});  // 11 pixels: S = 11
  expect_reversal(StereoParams{1, 1, kCostCensus, 3, 3, 4, 1, kAllPaths, 8, 32, false, 1, 0, 0, 0});  // one pixel
  expect_reversal(
      StereoParams{7, 3, kCostCensus, 3, 3, 256, 1, kAllPaths, 8, 32, false, 1, 0, 0, 0});  // 256 chunks: S = 1
}

TEST(FrameBufferAddresses, ReverseWalkCountsWhatReversedSlotComputesAndWraps) {
  for (int units : {1, 2, 25, 7})
    for (int group : {1, 3, 10}) {
      ReverseWalk w;
      w.start(units, group);
      for (int64_t k = 0; k < 3LL * units * group; ++k) {  // three segments: it starts over
        ASSERT_EQ(w.slot(), reversed_slot(k % (int64_t(units) * group), group, units))
            << units << "x" << group << " " << k;
        w.next();
      }
    }
  EXPECT_EQ(reversed_slot(0, 10, 25), 240);  // the last pixel's first chunk leaves first
  EXPECT_EQ(reversed_slot(9, 10, 25), 249);
  EXPECT_EQ(reversed_slot(10, 10, 25), 230);
  EXPECT_EQ(reversed_block_base(4, 250, 0), 750);  // the first segment filled goes last
  EXPECT_EQ(reversed_block_base(4, 250, 3), 0);
}

// The map writer: codes arrive in reverse raster order, segments leave reversed at ascending
// addresses, and the map is in raster order.
TEST(FrameBufferAddresses, MapSegmentsLandTheCodesInRasterOrder) {
  for (int w : {640, 13, 1})
    for (int h : {360, 16, 7, 1}) {
      StereoParams p{w, h, kCostCensus, 5, 5, 60, 6, kAllPaths, 10, 120, true, 1, 5, 0, 0};
      const int64_t pixels = frame_pixels(p), seg = map_segment_pixels(p);
      ASSERT_EQ(pixels % seg, 0);
      ASSERT_LE(seg, burst_elements_of(kMapCodeBytes));
      const int64_t segments = pixels / seg;
      std::vector<int64_t> map(std::size_t(pixels), -1);
      for (int64_t j = 0; j < segments; ++j) {
        ReverseWalk walk;
        walk.start(int(seg), 1);
        for (int64_t k = 0; k < seg; ++k) {
          const int64_t code = j * seg + walk.slot();  // the code-th code from pass 2: pixel P-1-code
          map[std::size_t(reversed_block_base(segments, seg, j) + k)] = pixels - 1 - code;
          walk.next();
        }
      }
      for (int64_t a = 0; a < pixels; ++a) ASSERT_EQ(map[std::size_t(a)], a) << w << "x" << h;
    }
}

// The reversal buffers as the resource model counts them.
struct Memories {
  struct M {
    const char* name;
    int64_t depth;
    int width_bits;
    int copies;
  };
  std::vector<M> list;
  void memory(const char* name, int64_t depth, int width_bits, int copies, bool) {
    list.push_back({name, depth, width_bits, copies});
  }
};

TEST(FrameBufferResources, BothHalvesOfTheSegmentBuffersInOneMemory) {
  StereoParams p{640, 360, kCostCensus, 5, 5, 60, 6, kAllPaths, 10, 120, true, 1, 5, 0, 0};
  Memories m;
  declare_frame_segment_buffer(m, p);
  declare_map_segment_buffer(m, p);
  ASSERT_EQ(m.list.size(), 2u);
  EXPECT_EQ(m.list[0].depth, 2 * 25 * 10);
  EXPECT_EQ(m.list[0].width_bits, frame_pair_bits(p));
  EXPECT_EQ(m.list[1].depth, 2 * 256);
  EXPECT_EQ(m.list[1].width_bits, disparity_bits(p));
}

}  // namespace
}  // namespace parallax::kern
