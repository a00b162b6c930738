// The fast engine's hot loops, part 1 of 4 (isa.cpp): scalar helpers and one register of 16-bit
// lanes of the level being built. Included only by the isa*.cpp/hpp files of one translation unit
// per level (models/fast/CMakeLists.txt); everything sits in an unnamed namespace, so that no
// inline function of one level can be picked by the linker for another. No standard library (isa.hpp).
#pragma once

#include "isa.hpp"

// Intrinsics only where the compiler does not find the instruction itself (byte table lookups);
// their functions are always-inline and define no symbol (check_isa_object.sh).
#if defined(__AVX2__)
// GCC 12 warns inside its own AVX-512 headers (a vector left undefined on purpose, GCC bug
// 105593; -Wuninitialized or its maybe- form, by how the extract got inlined); the warning is
// about the header's code, not this file's.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>
#pragma GCC diagnostic pop
#else
#include <immintrin.h>
#endif
#else
#include <emmintrin.h>
#endif

namespace parallax::fast::detail {
namespace {

template <class T>
constexpr T tmin(T a, T b) {
  return b < a ? b : a;
}
template <class T>
constexpr T tmax(T a, T b) {
  return a < b ? b : a;
}
inline int clampi(int v, int lo, int hi) {
  return v < lo ? lo : (v > hi ? hi : v);
}
inline int absi(int v) {
  return v < 0 ? -v : v;
}
template <class T>
inline T type_max() {
  return static_cast<T>(~T(0));
}

// ---- 16-bit vectors (GCC vector extensions, one register of the level) ---------------------

#if defined(__AVX512BW__)
constexpr int kVecBytes = 64;
#elif defined(__AVX2__)
constexpr int kVecBytes = 32;
#else
constexpr int kVecBytes = 16;
#endif
constexpr int kLanes16 = kVecBytes / 2;
typedef uint16_t U16V __attribute__((vector_size(kVecBytes)));
typedef uint16_t U16VUnaligned __attribute__((vector_size(kVecBytes), aligned(2), may_alias));
typedef int16_t I16V __attribute__((vector_size(kVecBytes)));

inline U16V load16(const uint16_t* p) {
  return *reinterpret_cast<const U16VUnaligned*>(p);
}
inline void store16(uint16_t* p, U16V v) {
  *reinterpret_cast<U16VUnaligned*>(p) = v;
}
// dst[0, n) = src[0, n) (no overlap), whole registers then the rest.
inline void copy_u16(uint16_t* __restrict dst, const uint16_t* __restrict src, int n) {
  int i = 0;
  for (; i + kLanes16 <= n; i += kLanes16) store16(dst + i, load16(src + i));
  for (; i < n; ++i) dst[i] = src[i];
}
inline U16V splat16(int v) {
  return U16V{} + static_cast<uint16_t>(v);
}
#if defined(__AVX512BW__)
typedef __m512i IntV;
#elif defined(__AVX2__)
typedef __m256i IntV;
#else
typedef __m128i IntV;
#endif
inline IntV as_int(U16V v) {
  return __builtin_bit_cast(IntV, v);
}
inline U16V as_u16(IntV v) {
  return __builtin_bit_cast(U16V, v);
}
inline U16V vmin16(U16V a, U16V b) {
#if defined(__AVX512BW__)
  return as_u16(_mm512_min_epu16(as_int(a), as_int(b)));
#elif defined(__AVX2__)
  return as_u16(_mm256_min_epu16(as_int(a), as_int(b)));
#else
  return a - as_u16(_mm_subs_epu16(as_int(a), as_int(b)));  // SSE2 has no unsigned 16-bit min
#endif
}
inline uint16_t hmin16(U16V v) {
  const IntV z = as_int(v);
#if defined(__AVX512BW__)
  const __m256i h = _mm256_min_epu16(_mm512_castsi512_si256(z), _mm512_extracti64x4_epi64(z, 1));
  const __m128i q = _mm_min_epu16(_mm256_castsi256_si128(h), _mm256_extracti128_si256(h, 1));
  return static_cast<uint16_t>(_mm_cvtsi128_si32(_mm_minpos_epu16(q)));
#elif defined(__AVX2__)
  const __m128i q = _mm_min_epu16(_mm256_castsi256_si128(z), _mm256_extracti128_si256(z, 1));
  return static_cast<uint16_t>(_mm_cvtsi128_si32(_mm_minpos_epu16(q)));
#else
  __m128i q = z;
  q = _mm_sub_epi16(q, _mm_subs_epu16(q, _mm_srli_si128(q, 8)));
  q = _mm_sub_epi16(q, _mm_subs_epu16(q, _mm_srli_si128(q, 4)));
  q = _mm_sub_epi16(q, _mm_subs_epu16(q, _mm_srli_si128(q, 2)));
  return static_cast<uint16_t>(_mm_cvtsi128_si32(q));
#endif
}
// hmin16(v) in every lane, without a trip through a general register where the level has a
// word broadcast from a vector.
inline U16V hmin16_splat(U16V v) {
#if defined(__AVX512BW__)
  const IntV z = as_int(v);
  const __m256i h = _mm256_min_epu16(_mm512_castsi512_si256(z), _mm512_extracti64x4_epi64(z, 1));
  const __m128i q = _mm_min_epu16(_mm256_castsi256_si128(h), _mm256_extracti128_si256(h, 1));
  return as_u16(_mm512_broadcastw_epi16(_mm_minpos_epu16(q)));
#elif defined(__AVX2__)
  const IntV z = as_int(v);
  const __m128i q = _mm_min_epu16(_mm256_castsi256_si128(z), _mm256_extracti128_si256(z, 1));
  return as_u16(_mm256_broadcastw_epi16(_mm_minpos_epu16(q)));
#else
  return splat16(hmin16(v));
#endif
}
// 0, 1, 2, ...: the lane numbers as data, so that lane tests and searches are vector compares.
// Constant initialised (constexpr): a dynamic initialiser here would run this file's
// instructions at program start, on every CPU.
struct LaneNumbers {
  uint16_t v[288] = {};
  constexpr LaneNumbers() {
    for (int i = 0; i < 288; ++i) v[i] = static_cast<uint16_t>(i);
  }
};
constexpr LaneNumbers kLanes{};

// Lanes [D, lanes) of a pixel's row of 16-bit lanes set to one value, the lanes below kept: the
// masks are built once per row of pixels and applied per pixel as a load, and/or and a store
// over the registers that hold padding. lanes is cost_stride(D) (a multiple of 32, less than
// D + 32) or D itself (no padding), so those are the last one or two registers (32 / kLanes16
// at most; a larger count, a caller's error, is cut there rather than overrun the masks).
struct PadLanes16 {
  int first = 0, count = 0;  // the first register holding padding (lane index), and how many
  U16V keep[32 / kLanes16] = {}, fill[32 / kLanes16] = {};
  PadLanes16(int disparities, int lanes, uint16_t value) {
    if (lanes <= disparities) return;
    first = disparities / kLanes16 * kLanes16;
    count = (lanes - first) / kLanes16;
    if (count > 32 / kLanes16) count = 32 / kLanes16;
    for (int j = 0; j < count; ++j) {
      const I16V li = __builtin_bit_cast(I16V, load16(kLanes.v + first + j * kLanes16));
      keep[j] = __builtin_bit_cast(U16V, li < static_cast<int16_t>(disparities));
      fill[j] = splat16(value) & ~keep[j];
    }
  }
  void apply(uint16_t* row) const {
    for (int j = 0; j < count; ++j) {
      uint16_t* p = row + first + j * kLanes16;
      store16(p, (load16(p) & keep[j]) | fill[j]);
    }
  }
};

// Lane shifts across two registers: lanes_up(a, b)[i] = (a:b)[kLanes16 - 1 + i] (the d - 1
// neighbour of b's lanes, a's last lane first), lanes_down(a, b)[i] = (a:b)[i + 1] (the d + 1
// neighbour of a's lanes).
#if defined(__AVX512BW__)
struct ShiftIndex {
  int16_t up[32] = {}, down[32] = {};
  constexpr ShiftIndex() {
    for (int i = 0; i < 32; ++i) {
      up[i] = static_cast<int16_t>(31 + i);
      down[i] = static_cast<int16_t>(1 + i);
    }
  }
};
constexpr ShiftIndex kShift{};
inline U16V lanes_up(U16V a, U16V b) {
  return as_u16(_mm512_permutex2var_epi16(as_int(a), _mm512_loadu_si512(kShift.up), as_int(b)));
}
inline U16V lanes_down(U16V a, U16V b) {
  return as_u16(_mm512_permutex2var_epi16(as_int(a), _mm512_loadu_si512(kShift.down), as_int(b)));
}
#elif defined(__AVX2__)
inline U16V lanes_up(U16V a, U16V b) {  // (a.high:b.low) then byte-align per 128-bit half
  return as_u16(_mm256_alignr_epi8(as_int(b), _mm256_permute2x128_si256(as_int(a), as_int(b), 0x21), 14));
}
inline U16V lanes_down(U16V a, U16V b) {
  return as_u16(_mm256_alignr_epi8(_mm256_permute2x128_si256(as_int(a), as_int(b), 0x21), as_int(a), 2));
}
#else
inline U16V lanes_up(U16V a, U16V b) {
  return as_u16(_mm_or_si128(_mm_slli_si128(as_int(b), 2), _mm_srli_si128(as_int(a), 14)));
}
inline U16V lanes_down(U16V a, U16V b) {
  return as_u16(_mm_or_si128(_mm_srli_si128(as_int(a), 2), _mm_slli_si128(as_int(b), 14)));
}
#endif

}  // namespace
}  // namespace parallax::fast::detail
