// The fast engine's hot loops, part 3 of 4 (isa.cpp): winner takes all, uniqueness, sub-pixel,
// left-right check and the median. Included once per level by isa.cpp (see isa_common.hpp).
#pragma once

#include "isa_common.hpp"

namespace parallax::fast::detail {
namespace {

// ---- winner takes all, uniqueness, sub-pixel, left-right check ----------------------------

template <class T>
inline T lane_min(const T* __restrict s, int n) {
  T v = type_max<T>();
  for (int d = 0; d < n; ++d) v = tmin<T>(v, s[d]);
  return v;
}
// Lanes [D, lanes) of every pixel's 16-bit sums set to 0xFFFF (what the WTA expects of the
// padding).
void pad_sums16(uint16_t* sum, int width_px, int disparities, int lanes) {
  const PadLanes16 pad(disparities, lanes, 0xFFFF);
  if (pad.count == 0) return;
  for (int x = 0; x < width_px; ++x) pad.apply(sum + static_cast<int64_t>(x) * lanes);
}

template <class T>
inline int first_lane_of(const T* __restrict s, int n, T value) {
  const uint16_t* __restrict lane = kLanes.v;
  uint16_t first = 0xFFFF;
  for (int d = 0; d < n; ++d) {
    const uint16_t hit = static_cast<uint16_t>(-static_cast<int>(s[d] == value));  // all ones when equal
    first = tmin<uint16_t>(first, static_cast<uint16_t>((lane[d] & hit) | static_cast<uint16_t>(~hit)));
  }
  return first;
}
// Candidates of one left pixel for the right disparities it may decide: rb[d] / rc[d] belong to
// the right pixel x - m - d. A padding lane (the type's maximum) is never better.
template <class T>
inline void right_update(const T* __restrict s, T* __restrict rb, uint16_t* __restrict rc, int n) {
  const uint16_t* __restrict lane = kLanes.v;
  for (int d = 0; d < n; ++d) {
    const uint16_t better = static_cast<uint16_t>(-static_cast<int>(s[d] < rb[d]));  // all ones when better
    rb[d] = tmin<T>(s[d], rb[d]);
    rc[d] = static_cast<uint16_t>((lane[d] & better) | (rc[d] & static_cast<uint16_t>(~better)));
  }
}

// The first lane of v[0..NV) equal to b (one exists: b is their minimum).
template <int NV>
inline int first_equal16(const U16V* v, U16V b) {
  for (int k = 0; k < NV - 1; ++k) {
#if defined(__AVX512BW__)
    const unsigned hit = _mm512_cmpeq_epi16_mask(as_int(v[k]), as_int(b));
    if (hit != 0) return k * kLanes16 + __builtin_ctz(hit);
#elif defined(__AVX2__)
    const unsigned hit = static_cast<unsigned>(_mm256_movemask_epi8(_mm256_cmpeq_epi16(as_int(v[k]), as_int(b))));
    if (hit != 0) return k * kLanes16 + __builtin_ctz(hit) / 2;
#else
    const unsigned hit = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi16(as_int(v[k]), as_int(b))));
    if (hit != 0) return k * kLanes16 + __builtin_ctz(hit) / 2;
#endif
  }
#if defined(__AVX512BW__)
  const unsigned hit = _mm512_cmpeq_epi16_mask(as_int(v[NV - 1]), as_int(b));
  return (NV - 1) * kLanes16 + __builtin_ctz(hit | 0x80000000u);
#elif defined(__AVX2__)
  const unsigned hit = static_cast<unsigned>(_mm256_movemask_epi8(_mm256_cmpeq_epi16(as_int(v[NV - 1]), as_int(b))));
  return (NV - 1) * kLanes16 + __builtin_ctz(hit | 0x80000000u) / 2;
#else
  const unsigned hit = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi16(as_int(v[NV - 1]), as_int(b))));
  return (NV - 1) * kLanes16 + __builtin_ctz(hit | 0x8000u) / 2;
#endif
}

// The sub-pixel offset of docs §5 from the neighbours' excess over the minimum,
// a = S(d - 1) - S(d) and b = S(d + 1) - S(d), in 1 / 2^f pixel.
inline int subpixel_offset(uint64_t a, uint64_t b, int f) {
  if (a + b == 0) return 0;
  const uint64_t diff = a > b ? a - b : b - a;
  const uint64_t t = (diff << f) / (a + b);
  const int mag = static_cast<int>((t + 1) >> 1);
  return a > b ? mag : -mag;
}

// The row's codes from left_code / offset and, with the LR check, the right image's winners
// right_code[W - 1 - xr].
inline void write_codes(const SelectRow& r) {
  const int W = r.width_px, m = r.min_disparity, f = r.subpixel_bits;
  const uint16_t invalid = static_cast<uint16_t>(r.disparities << f);
  for (int x = 0; x < W; ++x) {
    const int dl = r.left_code[x];
    bool valid = dl >= 0;
    if (valid && r.lr_check) {
      const int xr = x - m - dl;
      const int dr = r.right_code[W - 1 - xr];
      valid = absi(dl - dr) <= r.lr_tolerance;
    }
    r.out[x] = valid ? static_cast<uint16_t>((dl << f) + r.offset[x]) : invalid;
  }
}

// keep_or_take(nb, ob, code, lane): code where nb == ob (the old best stays), else lane.
inline U16V keep_or_take(U16V nb, U16V ob, U16V code, U16V lane) {
#if defined(__AVX512BW__)
  return as_u16(_mm512_mask_blend_epi16(_mm512_cmpeq_epi16_mask(as_int(nb), as_int(ob)), as_int(lane), as_int(code)));
#elif defined(__AVX2__)
  return as_u16(_mm256_blendv_epi8(as_int(lane), as_int(code), _mm256_cmpeq_epi16(as_int(nb), as_int(ob))));
#else
  const U16V keep = __builtin_bit_cast(U16V, nb == ob);
  return (code & keep) | (lane & ~keep);
#endif
}

// select_row for 16-bit sums over NC lanes, a whole number of registers. The right image's
// winners travel in registers: at pixel x lane d of the window belongs to the right pixel
// x - m - d (t = W - 1 - x + m + d); from x to x + 1 every entry moves up one lane, a fresh one
// (the type's maximum, code 0) enters lane 0 and lane NC - 1 leaves, final (no later left pixel
// reaches that right pixel), to right_code[t]; the window left after the row is stored whole.
// Same results as select_row: ties keep the smaller d in both images.
template <int NC>
void select_row16(const SelectRow& r) {
  constexpr int NV = NC / kLanes16;
  const int W = r.width_px, D = r.disparities, m = r.min_disparity, f = r.subpixel_bits;
  const uint16_t* S = static_cast<const uint16_t*>(r.sum);
  U16V best[NV], code[NV];
  const U16V fresh_best = splat16(0xFFFF), fresh_code = U16V{};
  for (int v = 0; v < NV; ++v) {
    best[v] = fresh_best;
    code[v] = fresh_code;
  }
  for (int x = 0; x < W; ++x) {
    const uint16_t* __restrict s = S + static_cast<int64_t>(x) * NC;
    U16V sv[NV];
    for (int v = 0; v < NV; ++v) sv[v] = load16(s + v * kLanes16);
    U16V mn = sv[0];
    for (int v = 1; v < NV; ++v) mn = vmin16(mn, sv[v]);
    const uint16_t sl = hmin16(mn);
    const int dl = first_equal16<NV>(sv, splat16(sl));
    if (r.lr_check) {
      for (int v = 0; v < NV; ++v) {
        const U16V nb = vmin16(sv[v], best[v]);
        code[v] = keep_or_take(nb, best[v], code[v], load16(kLanes.v + v * kLanes16));
        best[v] = nb;
      }
      r.right_code[W - 1 - x + m + NC - 1] = code[NV - 1][kLanes16 - 1];
      for (int v = NV - 1; v > 0; --v) {
        best[v] = lanes_up(best[v - 1], best[v]);
        code[v] = lanes_up(code[v - 1], code[v]);
      }
      best[0] = lanes_up(fresh_best, best[0]);
      code[0] = lanes_up(fresh_code, code[0]);
    }
    bool valid = m + dl <= x;
    if (valid && r.uniqueness_pct > 0) {
      // The minimum over the lanes d with |d - dl| > 1 (padding lanes hold the maximum).
      const I16V lo = I16V{} + static_cast<int16_t>(dl - 1), hi = I16V{} + static_cast<int16_t>(dl + 1);
      U16V second = splat16(0xFFFF);
      for (int v = 0; v < NV; ++v) {
        const I16V li = __builtin_bit_cast(I16V, load16(kLanes.v + v * kLanes16));
        const I16V out = (li < lo) | (li > hi);
        const U16V sel = __builtin_bit_cast(U16V, out);
        second = vmin16(second, (sv[v] & sel) | (fresh_best & ~sel));
      }
      if (dl - 1 > 0 || dl + 2 < D)
        valid = !(static_cast<uint64_t>(hmin16(second)) * 100u < static_cast<uint64_t>(100 + r.uniqueness_pct) * sl);
    }
    r.left_code[x] = valid ? dl : -1;
    r.offset[x] = valid && f > 0 && dl > 0 && dl < D - 1 ? subpixel_offset(s[dl - 1] - sl, s[dl + 1] - sl, f) : 0;
  }
  if (r.lr_check) {  // after x = W - 1 the shifted window's lane d holds t = m + d - 1; lane 0 is fresh
    uint16_t rest[NC];
    for (int v = 0; v < NV; ++v) store16(rest + v * kLanes16, code[v]);
    for (int d = 1; d < NC; ++d) r.right_code[m - 1 + d] = rest[d];
  }
  write_codes(r);
}

template <class T>
void select_row(const SelectRow& r) {
  if constexpr (sizeof(T) == 2) {
    switch (r.lanes) {
      case 32:
        select_row16<32>(r);
        return;
      case 64:
        select_row16<64>(r);
        return;
      case 96:
        select_row16<96>(r);
        return;
      case 128:
        select_row16<128>(r);
        return;
      default:
        break;
    }
  }
  const int W = r.width_px, D = r.disparities, N = r.lanes, m = r.min_disparity, f = r.subpixel_bits;
  const T* S = static_cast<const T*>(r.sum);
  T* rbest = static_cast<T*>(r.right_best);
  const int rlen = W + N + m + 1;
  if (r.lr_check) {
    for (int k = 0; k < rlen; ++k) {
      rbest[k] = type_max<T>();
      r.right_code[k] = 0;
    }
  }
  for (int x = 0; x < W; ++x) {
    const T* __restrict s = S + static_cast<int64_t>(x) * N;
    // The minimum, then the smallest d holding it (padding lanes hold the type's maximum and
    // come after every real lane, so they never decide either).
    const T sl = lane_min<T>(s, N);
    const int dl = first_lane_of<T>(s, N, sl);
    if (r.lr_check) {
      // dR(xr) over d with xr = x - m - d: right_best is indexed t = W - 1 - xr = W - 1 - x + m + d
      // (t >= W: xr < 0, never read). Strict < keeps the smallest d (x increases with d).
      right_update<T>(s, rbest + (W - 1 - x + m), r.right_code + (W - 1 - x + m), N);
    }
    bool valid = m + dl <= x;
    if (valid && r.uniqueness_pct > 0) {
      T second = type_max<T>();
      for (int d = 0; d < dl - 1; ++d) second = tmin<T>(second, s[d]);
      for (int d = dl + 2; d < D; ++d) second = tmin<T>(second, s[d]);
      if (dl - 1 > 0 || dl + 2 < D)
        valid = !(static_cast<uint64_t>(second) * 100u < static_cast<uint64_t>(100 + r.uniqueness_pct) * sl);
    }
    r.left_code[x] = valid ? dl : -1;
    r.offset[x] = valid && f > 0 && dl > 0 && dl < D - 1 ? subpixel_offset(s[dl - 1] - sl, s[dl + 1] - sl, f) : 0;
  }
  write_codes(r);
}

// ---- median -------------------------------------------------------------------------------

// The median network (isa.hpp: make_median_net) as a constant per window, so that it runs on
// registers.
template <int K>
struct MedianNetOf {
  static constexpr MedianNet net = make_median_net(K * K);
};
inline U16V vmax16(U16V a, U16V b) {
#if defined(__AVX512BW__)
  return as_u16(_mm512_max_epu16(as_int(a), as_int(b)));
#elif defined(__AVX2__)
  return as_u16(_mm256_max_epu16(as_int(a), as_int(b)));
#else
  return b + as_u16(_mm_subs_epu16(as_int(a), as_int(b)));
#endif
}
template <int K, int C>
inline void median_comparators(U16V* t) {
  constexpr MedianNet net = MedianNetOf<K>::net;
  if constexpr (C < net.n) {
    const U16V a = t[net.lo[C]], b = t[net.hi[C]];
    t[net.lo[C]] = vmin16(a, b);
    t[net.hi[C]] = vmax16(a, b);
    median_comparators<K, C + 1>(t);
  }
}
// dst[x + r] = src[clamp(x, 0, W - 1)] for x in [-r, W + r): the row copied, its ends repeated
// (the median's clamp border). W >= 1.
inline void pad_clamped(uint16_t* __restrict dst, const uint16_t* __restrict src, int W, int r) {
  copy_u16(dst + r, src, W);
  for (int e = 0; e < r; ++e) {
    dst[e] = src[0];
    dst[W + r + e] = src[W - 1];
  }
}
// k x k median of one row with the network unrolled over whole registers of pixels (the last
// register overlaps the one before when W is not a multiple of it; W >= kLanes16).
template <int K>
void median_row_k(const uint16_t* const* rows, int W, uint16_t* out) {
  constexpr int rk = K / 2;
  uint16_t pad[K][4096 + 8];
  for (int j = 0; j < K; ++j) pad_clamped(pad[j], rows[j], W, rk);
  for (int x0 = 0; x0 < W; x0 += kLanes16) {
    const int x = x0 + kLanes16 <= W ? x0 : W - kLanes16;
    U16V t[K * K];
    for (int j = 0; j < K; ++j)
      for (int i = 0; i < K; ++i) t[j * K + i] = load16(pad[j] + x + i);
    median_comparators<K, 0>(t);
    store16(out + x, t[(K * K - 1) / 2]);
  }
}

void median_row(const uint16_t* const* rows, int W, int k, const int16_t* pairs, int pair_count, int rank,
                uint16_t* taps, uint16_t* out) {
  if (W >= kLanes16 && rank == (k * k - 1) / 2) {  // the same network, compiled in
    if (k == 3) {
      median_row_k<3>(rows, W, out);
      return;
    }
    if (k == 5) {
      median_row_k<5>(rows, W, out);
      return;
    }
  }
  const int rk = k / 2;
  uint16_t pad[4096 + 8];
  for (int j = 0; j < k; ++j) {
    pad_clamped(pad, rows[j], W, rk);
    for (int i = 0; i < k; ++i)  // pad[x + i] = code(clampx(x + i - rk))
      copy_u16(taps + static_cast<int64_t>(j * k + i) * W, pad + i, W);
  }
  for (int p = 0; p < pair_count; ++p) {
    uint16_t* a = taps + static_cast<int64_t>(pairs[2 * p]) * W;
    uint16_t* b = taps + static_cast<int64_t>(pairs[2 * p + 1]) * W;
    for (int x = 0; x < W; ++x) {
      const uint16_t lo = tmin<uint16_t>(a[x], b[x]), hi = tmax<uint16_t>(a[x], b[x]);
      a[x] = lo;
      b[x] = hi;
    }
  }
  const uint16_t* res = taps + static_cast<int64_t>(rank) * W;
  for (int x = 0; x < W; ++x) out[x] = res[x];
}

}  // namespace
}  // namespace parallax::fast::detail
