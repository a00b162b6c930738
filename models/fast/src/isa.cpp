// The fast engine's hot loops (isa.hpp), written as plain loops over disparities that the
// compiler vectorises for the level this file is built for. Built three times with
// PARALLAX_FAST_ISA_NAME / PARALLAX_FAST_ISA_FN set (models/fast/CMakeLists.txt). No standard
// library: see isa.hpp. Every function computes docs/algorithm.md exactly; the equivalence tests
// compare it with the golden model at every level.
#include "isa.hpp"

// Intrinsics only where the compiler does not find the instruction itself (byte table lookups);
// their functions are always-inline and define no symbol (check_isa_object.sh).
#if defined(__AVX2__)
// GCC 12 warns inside its own AVX-512 headers (a vector left undefined on purpose, GCC bug
// 105593); the warning is about the header's code, not this file's.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>
#pragma GCC diagnostic pop
#else
#include <emmintrin.h>
#endif

namespace parallax::fast::detail {
namespace {

template <class T>
inline T tmin(T a, T b) {
  return b < a ? b : a;
}
template <class T>
inline T tmax(T a, T b) {
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

// ---- census -----------------------------------------------------------------------------

// Census codes as byte planes: the used taps of the window, in raster order, are bits of the
// code, tap u in plane u / 8 (codes[y][u / 8][x], planes = ceil(bits / 8)). The order of the bits
// is the engine's own (the cost reads only popcount(CL ^ CR), the same for any bit order shared
// by both images); byte planes let the cost count bits in 8-bit lanes.
void census_image(const uint8_t* img, int W, int H, int ww, int wh, int kind, int planes, uint8_t* codes) {
  const int rw = ww / 2, rh = wh / 2, taps = ww * wh, centre = taps / 2;
  // One row padded by rw replicated pixels each side, per window row.
  uint8_t pad[9][4096 + 16];
  for (int y = 0; y < H; ++y) {
    for (int j = 0; j < wh; ++j) {
      const uint8_t* src = img + static_cast<int64_t>(clampi(y + j - rh, 0, H - 1)) * W;
      uint8_t* dst = pad[j];
      for (int x = 0; x < rw; ++x) dst[x] = src[0];
      for (int x = 0; x < W; ++x) dst[rw + x] = src[x];
      for (int x = 0; x < rw; ++x) dst[rw + W + x] = src[W - 1];
    }
    uint8_t* out = codes + static_cast<int64_t>(y) * planes * W;
    for (int i = 0; i < planes * W; ++i) out[i] = 0;
    const uint8_t* c = pad[rh] + rw;
    int used_count = 0;
    for (int k = 0; k < taps; ++k) {
      const int j = k / ww, i = k % ww - rw;  // j: window row 0..wh-1
      const bool used = kind == 2 ? k < centre : (kind == 1 ? (k % 2 == 0 && k != centre) : k != centre);
      if (!used) continue;
      const uint8_t* __restrict a = pad[j] + rw + i;
      const uint8_t* __restrict b = kind == 2 ? pad[wh - 1 - j] + rw - i : c;  // mirror tap or the centre
      uint8_t* __restrict o = out + static_cast<int64_t>(used_count / 8) * W;
      ++used_count;
      for (int x = 0; x < W; ++x) o[x] = static_cast<uint8_t>((o[x] << 1) | (a[x] < b[x] ? 1 : 0));
    }
  }
}

// Bit counts summed over the planes, in byte lanes: sum_p popcount(l[p] ^ r[p][d0 + d]) for 32
// lanes d (and, with AVX-512, 64), widened to 16-bit lanes and stored to out[d0 + d]. l[p] holds
// the left code's byte p in every lane.
#if defined(__AVX2__)
using ByteVec32 = __m256i;
inline __m256i popcount_bytes(__m256i v) {
  const __m256i lut =
      _mm256_setr_epi8(0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4, 0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4);
  const __m256i low = _mm256_set1_epi8(0x0F);
  return _mm256_add_epi8(_mm256_shuffle_epi8(lut, _mm256_and_si256(v, low)),
                         _mm256_shuffle_epi8(lut, _mm256_and_si256(_mm256_srli_epi16(v, 4), low)));
}
template <int P>
inline void census_chunk32(const __m256i* l, const uint8_t* const* r, int d0, uint16_t* out) {
  __m256i acc = _mm256_setzero_si256();
  for (int p = 0; p < P; ++p)
    acc = _mm256_add_epi8(
        acc, popcount_bytes(_mm256_xor_si256(l[p], _mm256_loadu_si256(reinterpret_cast<const __m256i*>(r[p] + d0)))));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + d0), _mm256_cvtepu8_epi16(_mm256_castsi256_si128(acc)));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + d0 + 16),
                      _mm256_cvtepu8_epi16(_mm256_extracti128_si256(acc, 1)));
}
inline __m256i broadcast_byte32(uint8_t v) {
  return _mm256_set1_epi8(static_cast<char>(v));
}
#else
using ByteVec32 = __m128i;  // the byte in 16 lanes serves both halves of 32
inline __m128i popcount_bytes(__m128i v) {
  const __m128i m1 = _mm_set1_epi8(0x55), m2 = _mm_set1_epi8(0x33), m4 = _mm_set1_epi8(0x0F);
  v = _mm_sub_epi8(v, _mm_and_si128(_mm_srli_epi16(v, 1), m1));
  v = _mm_add_epi8(_mm_and_si128(v, m2), _mm_and_si128(_mm_srli_epi16(v, 2), m2));
  return _mm_and_si128(_mm_add_epi8(v, _mm_srli_epi16(v, 4)), m4);
}
template <int P>
inline void census_chunk32(const ByteVec32* l, const uint8_t* const* r, int d0, uint16_t* out) {
  __m128i acc0 = _mm_setzero_si128(), acc1 = _mm_setzero_si128();
  for (int p = 0; p < P; ++p) {
    const __m128i* rp = reinterpret_cast<const __m128i*>(r[p] + d0);
    acc0 = _mm_add_epi8(acc0, popcount_bytes(_mm_xor_si128(l[p], _mm_loadu_si128(rp))));
    acc1 = _mm_add_epi8(acc1, popcount_bytes(_mm_xor_si128(l[p], _mm_loadu_si128(rp + 1))));
  }
  const __m128i z = _mm_setzero_si128();
  __m128i* o = reinterpret_cast<__m128i*>(out + d0);
  _mm_storeu_si128(o, _mm_unpacklo_epi8(acc0, z));
  _mm_storeu_si128(o + 1, _mm_unpackhi_epi8(acc0, z));
  _mm_storeu_si128(o + 2, _mm_unpacklo_epi8(acc1, z));
  _mm_storeu_si128(o + 3, _mm_unpackhi_epi8(acc1, z));
}
inline __m128i broadcast_byte32(uint8_t v) {
  return _mm_set1_epi8(static_cast<char>(v));
}
#endif
#if defined(__AVX512BW__)
inline __m512i popcount_bytes(__m512i v) {
  const __m512i lut = _mm512_broadcast_i32x4(_mm_setr_epi8(0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4));
  const __m512i low = _mm512_set1_epi8(0x0F);
  return _mm512_add_epi8(_mm512_shuffle_epi8(lut, _mm512_and_si512(v, low)),
                         _mm512_shuffle_epi8(lut, _mm512_and_si512(_mm512_srli_epi16(v, 4), low)));
}
template <int P>
inline void census_chunk64(const __m512i* l, const uint8_t* const* r, int d0, uint16_t* out) {
  __m512i acc = _mm512_setzero_si512();
  for (int p = 0; p < P; ++p)
    acc = _mm512_add_epi8(acc, popcount_bytes(_mm512_xor_si512(l[p], _mm512_loadu_si512(r[p] + d0))));
  _mm512_storeu_si512(out + d0, _mm512_cvtepu8_epi16(_mm512_castsi512_si256(acc)));
  _mm512_storeu_si512(out + d0 + 32, _mm512_cvtepu8_epi16(_mm512_extracti64x4_epi64(acc, 1)));
}
#endif

// C(x, d) = popcount(CL(x) ^ CR(x - m - d)), cost_max where x - m - d < 0. The right planes are
// reversed into scratch (rev[p][t] = CR_p(W - 1 - t), zero for t >= W) so that the disparities
// read them forwards, 32 or 64 lanes at once (the stride is a multiple of 32); then the lanes
// d >= D are set to kCostPad and, near the left edge, the lanes without a right pixel to cost_max.
template <int P>
void cost_census_planes(const CostRow& r, const uint8_t* left, const uint8_t* right, uint8_t* scratch) {
  const int W = r.width_px, D = r.disparities, m = r.min_disparity, stride = cost_stride(D);
  const int rev_len = W + m + stride;
  const uint8_t* rev[P];
  for (int p = 0; p < P; ++p) {
    uint8_t* rp = scratch + static_cast<int64_t>(p) * rev_len;
    const uint8_t* src = right + static_cast<int64_t>(p) * W;
    for (int t = 0; t < W; ++t) rp[t] = src[W - 1 - t];
    for (int t = W; t < rev_len; ++t) rp[t] = 0;
    rev[p] = rp;
  }
  const int full_from = m + D - 1;  // x >= full_from: every d < D has a right pixel
  for (int x = 0; x < W; ++x) {
    uint16_t* __restrict out = r.out + static_cast<int64_t>(x) * stride;
    const uint8_t* rx[P];
    for (int p = 0; p < P; ++p) rx[p] = rev[p] + (W - 1 - x + m);
    int d0 = 0;
#if defined(__AVX512BW__)
    __m512i l64[P];
    for (int p = 0; p < P; ++p) l64[p] = _mm512_set1_epi8(static_cast<char>(left[static_cast<int64_t>(p) * W + x]));
    for (; d0 + 64 <= stride; d0 += 64) census_chunk64<P>(l64, rx, d0, out);
    if (d0 < stride) {
      __m256i l32[P];
      for (int p = 0; p < P; ++p) l32[p] = _mm512_castsi512_si256(l64[p]);
      census_chunk32<P>(l32, rx, d0, out);
    }
#else
    ByteVec32 l32[P];
    for (int p = 0; p < P; ++p) l32[p] = broadcast_byte32(left[static_cast<int64_t>(p) * W + x]);
    for (; d0 < stride; d0 += 32) census_chunk32<P>(l32, rx, d0, out);
#endif
    if (x < full_from)
      for (int d = clampi(x - m + 1, 0, D); d < D; ++d) out[d] = r.cost_max;
    for (int d = D; d < stride; ++d) out[d] = kCostPad;
  }
}

void cost_census(const CostRow& r, const uint8_t* left, const uint8_t* right, int planes, uint8_t* scratch) {
  switch (planes) {
    case 1:
      cost_census_planes<1>(r, left, right, scratch);
      break;
    case 2:
      cost_census_planes<2>(r, left, right, scratch);
      break;
    case 3:
      cost_census_planes<3>(r, left, right, scratch);
      break;
    case 4:
      cost_census_planes<4>(r, left, right, scratch);
      break;
    case 5:
      cost_census_planes<5>(r, left, right, scratch);
      break;
    case 6:
      cost_census_planes<6>(r, left, right, scratch);
      break;
    case 7:
      cost_census_planes<7>(r, left, right, scratch);
      break;
    default:
      cost_census_planes<8>(r, left, right, scratch);
      break;
  }
}

// ---- SAD ----------------------------------------------------------------------------------

// Column sums col(u, d) = sum_j |L(clampx(u), yj) - R(clampx(u - m - d), yj)| for
// u in [-rw, W + rw), then the box over u. The right rows are read through a reversed, clamped
// copy g[t] = R(clampx(vmax - t)), vmax = W - 1 + rw, so that d reads forwards.
void cost_sad(const CostRow& r, const uint8_t* const* lrows, const uint8_t* const* rrows, int ww, int wh,
              uint16_t* col) {
  const int W = r.width_px, D = r.disparities, m = r.min_disparity, rw = ww / 2;
  const int vmax = W - 1 + rw, vmin = -rw - m - (D - 1), span = vmax - vmin + 1;
  const int cols = W + 2 * rw;
  for (int64_t i = 0; i < static_cast<int64_t>(cols) * D; ++i) col[i] = 0;
  uint8_t g[4096 + 2 * 9 + 2 * 256 + 16];
  for (int j = 0; j < wh; ++j) {
    for (int t = 0; t < span; ++t) g[t] = rrows[j][clampi(vmax - t, 0, W - 1)];
    for (int u = -rw; u < W + rw; ++u) {
      const int lv = lrows[j][clampi(u, 0, W - 1)];
      const uint8_t* gr = g + (vmax - u + m);
      uint16_t* c = col + static_cast<int64_t>(u + rw) * D;
      for (int d = 0; d < D; ++d) c[d] = static_cast<uint16_t>(c[d] + absi(lv - static_cast<int>(gr[d])));
    }
  }
  const int stride = cost_stride(D);
  uint16_t* out0 = r.out;
  for (int d = 0; d < D; ++d) out0[d] = 0;
  for (int i = 0; i < ww; ++i) {
    const uint16_t* c = col + static_cast<int64_t>(i) * D;
    for (int d = 0; d < D; ++d) out0[d] = static_cast<uint16_t>(out0[d] + c[d]);
  }
  for (int x = 1; x < W; ++x) {
    const uint16_t* prev = r.out + static_cast<int64_t>(x - 1) * stride;
    const uint16_t* add = col + static_cast<int64_t>(x - 1 + ww) * D;
    const uint16_t* sub = col + static_cast<int64_t>(x - 1) * D;
    uint16_t* out = r.out + static_cast<int64_t>(x) * stride;
    for (int d = 0; d < D; ++d) out[d] = static_cast<uint16_t>(prev[d] + add[d] - sub[d]);
  }
  for (int x = 0; x < W; ++x) {
    uint16_t* out = r.out + static_cast<int64_t>(x) * stride;
    for (int d = clampi(x - m + 1, 0, D); d < D; ++d) out[d] = r.cost_max;
    for (int d = D; d < stride; ++d) out[d] = kCostPad;
  }
}

// ---- aggregation --------------------------------------------------------------------------

// The SGM step from a predecessor's padded path costs lq (lq[0] and lq[N + 1] are guards that
// never win): L(d) = C(d) + min(Lq(d), Lq(d -+ 1) + P1, Mq + P2) - Mq over N lanes. Writes
// out[1..N], adds weight * L into sum (Acc) or sets it, returns min_d L.
template <class T, bool Acc, bool Twice, int NC>
inline T sgm_step(const uint16_t* __restrict c, const T* __restrict lq, T mq, T p1, T p2, T* __restrict out,
                  T* __restrict sum, int n) {
  const int N = NC > 0 ? NC : n;
  const T mp2 = static_cast<T>(mq + p2);
  T mn = type_max<T>();
  for (int d = 0; d < N; ++d) {
    T v = tmin<T>(lq[d + 1], static_cast<T>(tmin<T>(lq[d], lq[d + 2]) + p1));
    v = tmin<T>(v, mp2);
    const T l = static_cast<T>(c[d] + static_cast<T>(v - mq));
    out[d + 1] = l;
    mn = tmin<T>(mn, l);
    const T w = Twice ? static_cast<T>(l + l) : l;
    sum[d] = Acc ? static_cast<T>(sum[d] + w) : w;
  }
  return mn;
}

// A path start: L = C.
template <class T, bool Acc, bool Twice, int NC>
inline T start_step(const uint16_t* __restrict c, T* __restrict out, T* __restrict sum, int n) {
  const int N = NC > 0 ? NC : n;
  T mn = type_max<T>();
  for (int d = 0; d < N; ++d) {
    const T l = static_cast<T>(c[d]);
    out[d + 1] = l;
    mn = tmin<T>(mn, l);
    const T w = Twice ? static_cast<T>(l + l) : l;
    sum[d] = Acc ? static_cast<T>(sum[d] + w) : w;
  }
  return mn;
}

// The MGM step from two predecessors (both inside): L = C + floor((u_q + u_q2) / 2).
template <class T, bool Acc, bool Twice, int NC>
inline T mgm_step(const uint16_t* __restrict c, const T* __restrict la, T ma, T pa2, const T* __restrict lb, T mb,
                  T pb2, T p1, T* __restrict out, T* __restrict sum, int n) {
  const int N = NC > 0 ? NC : n;
  const T ea = static_cast<T>(ma + pa2), eb = static_cast<T>(mb + pb2);
  T mn = type_max<T>();
  for (int d = 0; d < N; ++d) {
    T va = tmin<T>(la[d + 1], static_cast<T>(tmin<T>(la[d], la[d + 2]) + p1));
    va = tmin<T>(va, ea);
    T vb = tmin<T>(lb[d + 1], static_cast<T>(tmin<T>(lb[d], lb[d + 2]) + p1));
    vb = tmin<T>(vb, eb);
    const T u = static_cast<T>(static_cast<T>(static_cast<T>(va - ma) + static_cast<T>(vb - mb)) >> 1);
    const T l = static_cast<T>(c[d] + u);
    out[d + 1] = l;
    mn = tmin<T>(mn, l);
    const T w = Twice ? static_cast<T>(l + l) : l;
    sum[d] = Acc ? static_cast<T>(sum[d] + w) : w;
  }
  return mn;
}

inline int adaptive(int p1, int p2, int a, int ip, int iq) {
  const int lowered = p2 - ((a * absi(ip - iq)) >> 4);
  return lowered > p1 + 1 ? lowered : p1 + 1;
}

// One recursion over one stream row.
template <class T, bool Acc, bool Twice, int NC>
void aggregate_recursion(const AggregateRow& r, const Recursion& rc) {
  const int W = r.width_px, N = NC > 0 ? NC : r.lanes, dir = r.dir, P = N + 2, cs = r.cost_stride;
  const T p1 = static_cast<T>(r.p1), guard = static_cast<T>(type_max<T>() - r.p1);
  const bool adapt = r.p2_adaptive > 0;
  T* sum_base = static_cast<T*>(r.sum);
  T* cur = static_cast<T*>(rc.cur);
  const T* prev = static_cast<const T*>(rc.prev);
  T* cur_min = static_cast<T*>(rc.cur_min);
  const T* prev_min = static_cast<const T*>(rc.prev_min);
  const bool has_up = !r.first_row;
  for (int i = 0; i < W; ++i) {
    const int x = dir > 0 ? i : W - 1 - i;
    const uint16_t* c = r.cost + static_cast<int64_t>(x) * cs;
    T* out = cur + static_cast<int64_t>(x) * P;
    T* sum = sum_base + static_cast<int64_t>(x) * N;
    // Predecessors in stream terms: x - dir comes before x in the stream, x + dir after it.
    const bool has_before = i > 0, has_after = i < W - 1;
    int qx = -1;  // column of the (first) predecessor
    bool up = false;
    int q2x = -1;  // MGM: second predecessor's column, always on the previous row
    bool q2ok = false, qok = false;
    switch (rc.kind) {
      case kSgm0:
        qok = has_before;
        qx = x - dir;
        break;
      case kSgm45:
        qok = has_before && has_up;
        qx = x - dir;
        up = true;
        break;
      case kSgm90:
        qok = has_up;
        qx = x;
        up = true;
        break;
      case kSgm135:
        qok = has_after && has_up;
        qx = x + dir;
        up = true;
        break;
      case kMgmPixel:
        qok = has_before;
        qx = x - dir;
        q2ok = has_up;
        q2x = x;
        break;
      default:
        qok = has_before && has_up;
        qx = x - dir;
        up = true;
        q2ok = has_after && has_up;
        q2x = x + dir;
        break;
    }
    T mn;
    if (rc.kind < kMgmPixel || !q2ok) {
      if (!qok) {
        mn = start_step<T, Acc, Twice, NC>(c, out, sum, N);
      } else {
        const T* lq = (up ? prev : cur) + static_cast<int64_t>(qx) * P;
        const T mq = (up ? prev_min : cur_min)[qx];
        int p2 = r.p2;
        if (adapt) p2 = adaptive(r.p1, r.p2, r.p2_adaptive, r.intensity[x], (up ? r.prev_intensity : r.intensity)[qx]);
        mn = sgm_step<T, Acc, Twice, NC>(c, lq, mq, p1, static_cast<T>(p2), out, sum, N);
      }
    } else if (!qok) {  // MGM, the second predecessor alone
      const T* lq = prev + static_cast<int64_t>(q2x) * P;
      int p2 = r.p2;
      if (adapt) p2 = adaptive(r.p1, r.p2, r.p2_adaptive, r.intensity[x], r.prev_intensity[q2x]);
      mn = sgm_step<T, Acc, Twice, NC>(c, lq, prev_min[q2x], p1, static_cast<T>(p2), out, sum, N);
    } else {
      const T* la = (up ? prev : cur) + static_cast<int64_t>(qx) * P;
      const T ma = (up ? prev_min : cur_min)[qx];
      const T* lb = prev + static_cast<int64_t>(q2x) * P;
      int pa2 = r.p2, pb2 = r.p2;
      if (adapt) {
        pa2 = adaptive(r.p1, r.p2, r.p2_adaptive, r.intensity[x], (up ? r.prev_intensity : r.intensity)[qx]);
        pb2 = adaptive(r.p1, r.p2, r.p2_adaptive, r.intensity[x], r.prev_intensity[q2x]);
      }
      mn = mgm_step<T, Acc, Twice, NC>(c, la, ma, static_cast<T>(pa2), lb, prev_min[q2x], static_cast<T>(pb2), p1, out,
                                       sum, N);
    }
    cur_min[x] = mn;
    out[0] = guard;
    out[N + 1] = guard;
  }
}

template <class T, int NC>
void aggregate_row_n(const AggregateRow& r) {
  for (int k = 0; k < r.recursions; ++k) {
    const bool acc = r.accumulate || k > 0, twice = r.rec[k].weight == 2;
    if (acc && twice)
      aggregate_recursion<T, true, true, NC>(r, r.rec[k]);
    else if (acc)
      aggregate_recursion<T, true, false, NC>(r, r.rec[k]);
    else if (twice)
      aggregate_recursion<T, false, true, NC>(r, r.rec[k]);
    else
      aggregate_recursion<T, false, false, NC>(r, r.rec[k]);
  }
}

// Common lane counts as constants (whole vectors, no loop remainders), any other at run time.
template <class T>
void aggregate_row(const AggregateRow& r) {
  switch (r.lanes) {
    case 32:
      aggregate_row_n<T, 32>(r);
      break;
    case 64:
      aggregate_row_n<T, 64>(r);
      break;
    case 96:
      aggregate_row_n<T, 96>(r);
      break;
    case 128:
      aggregate_row_n<T, 128>(r);
      break;
    case 256:
      aggregate_row_n<T, 256>(r);
      break;
    default:
      aggregate_row_n<T, 0>(r);
      break;
  }
}

// ---- winner takes all, uniqueness, sub-pixel, left-right check ----------------------------

template <class T>
inline T lane_min(const T* __restrict s, int n) {
  T v = type_max<T>();
  for (int d = 0; d < n; ++d) v = tmin<T>(v, s[d]);
  return v;
}
// 0, 1, 2, ...: the lane numbers as data, so that the search below is a vector min. Constant
// initialised (constexpr): a dynamic initialiser here would run this file's instructions at
// program start, on every CPU.
struct LaneNumbers {
  uint16_t v[288] = {};
  constexpr LaneNumbers() {
    for (int i = 0; i < 288; ++i) v[i] = static_cast<uint16_t>(i);
  }
};
constexpr LaneNumbers kLanes{};

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

template <class T>
void select_row(const SelectRow& r) {
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
    int off = 0;
    if (valid && f > 0 && dl > 0 && dl < D - 1) {
      const uint64_t a = s[dl - 1] - sl, b = s[dl + 1] - sl;
      if (a + b > 0) {
        const uint64_t diff = a > b ? a - b : b - a;
        const uint64_t t = (diff << f) / (a + b);
        const int mag = static_cast<int>((t + 1) >> 1);
        off = a > b ? mag : -mag;
      }
    }
    r.left_code[x] = valid ? dl : -1;
    r.offset[x] = off;
  }
  const uint16_t invalid = static_cast<uint16_t>(D << f);
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

// ---- median -------------------------------------------------------------------------------

void median_row(const uint16_t* const* rows, int W, int k, const int16_t* pairs, int pair_count, int rank,
                uint16_t* taps, uint16_t* out) {
  const int rk = k / 2;
  uint16_t pad[4096 + 8];
  for (int j = 0; j < k; ++j) {
    for (int x = -rk; x < W + rk; ++x) pad[x + rk] = rows[j][clampi(x, 0, W - 1)];
    for (int i = 0; i < k; ++i) {
      uint16_t* t = taps + static_cast<int64_t>(j * k + i) * W;
      const uint16_t* src = pad + i;  // pad[x + i] = code(clampx(x + i - rk))
      for (int x = 0; x < W; ++x) t[x] = src[x];
    }
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

const IsaTable kTable = {
    PARALLAX_FAST_ISA_NAME,  census_image,         cost_census,          cost_sad,  aggregate_row<uint16_t>,
    aggregate_row<uint32_t>, select_row<uint16_t>, select_row<uint32_t>, median_row};

}  // namespace

const IsaTable& PARALLAX_FAST_ISA_FN() {
  return kTable;
}

}  // namespace parallax::fast::detail
