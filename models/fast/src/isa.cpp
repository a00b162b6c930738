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

inline U16V load16(const uint16_t* p) {
  return *reinterpret_cast<const U16VUnaligned*>(p);
}
inline void store16(uint16_t* p, U16V v) {
  *reinterpret_cast<U16VUnaligned*>(p) = v;
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
// Lane shifts across two registers: lanes_up(a, b)[i] = (a:b)[kLanes16 - 1 + i] (the d - 1
// neighbour of b's lanes, a's last lane first), lanes_down(a, b)[i] = (a:b)[i + 1] (the d + 1
// neighbour of a's lanes).
typedef int16_t I16V __attribute__((vector_size(kVecBytes)));
#if defined(__AVX512BW__)
constexpr I16V kShiftUp = {31, 32, 33, 34, 35, 36, 37, 38, 39, 40, 41, 42, 43, 44, 45, 46,
                           47, 48, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59, 60, 61, 62};
constexpr I16V kShiftDown = {1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 11, 12, 13, 14, 15, 16,
                             17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30, 31, 32};
#elif defined(__AVX2__)
constexpr I16V kShiftUp = {15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30};
constexpr I16V kShiftDown = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
#else
constexpr I16V kShiftUp = {7, 8, 9, 10, 11, 12, 13, 14};
constexpr I16V kShiftDown = {1, 2, 3, 4, 5, 6, 7, 8};
#endif
inline U16V lanes_up(U16V a, U16V b) {
  return __builtin_shuffle(a, b, kShiftUp);
}
inline U16V lanes_down(U16V a, U16V b) {
  return __builtin_shuffle(a, b, kShiftDown);
}

// Zeros for a missing predecessor (L = C + min(0, 0 + P1, 0 + P2) - 0 = C: a path start).
struct ZeroRow {
  uint16_t v[288] = {};
};
constexpr ZeroRow kZeroRow{};

// A row of SGM recursions (each of weight 1) in 16 bits over NC lanes, a whole number of
// registers: one sweep over the pixels for all recursions, each pixel's costs loaded once and its
// sum kept in registers until stored once. The 0-degree path lives in registers from one pixel to
// the next (its d -+ 1 neighbours by lane shifts; its row buffer is not written, nothing reads it:
// only the next pixel of the same row uses it). The other paths read the previous stream row; a
// missing predecessor reads kZeroRow with Mq = 0. Same arithmetic as sgm_step, lane for lane.
template <int NC, bool Acc>
void aggregate_sgm16(const AggregateRow& r) {
  constexpr int NV = NC / kLanes16;
  const int W = r.width_px, dir = r.dir, P = NC + 2, cs = r.cost_stride;
  const uint16_t guard = static_cast<uint16_t>(0xFFFF - r.p1);
  const U16V vp1 = splat16(r.p1), vguard = splat16(guard);
  const bool adapt = r.p2_adaptive > 0, has_up = !r.first_row;
  // The recursions on the previous stream row, resolved once per row: predecessor column
  // x + qoff, present for the stream positions i in [ilo, ihi] (none on the first row).
  struct RowRec {
    const uint16_t* prev;
    const uint16_t* prev_min;
    uint16_t* cur;
    uint16_t* cur_min;
    int qoff, ilo, ihi;
  };
  bool has0 = false;
  RowRec mem[4];
  int nmem = 0;
  for (int k = 0; k < r.recursions; ++k) {
    const Recursion& rc = r.rec[k];
    if (rc.kind == kSgm0) {
      has0 = true;
      continue;
    }
    RowRec& q = mem[nmem++];
    q.prev = static_cast<const uint16_t*>(rc.prev);
    q.prev_min = static_cast<const uint16_t*>(rc.prev_min);
    q.cur = static_cast<uint16_t*>(rc.cur);
    q.cur_min = static_cast<uint16_t*>(rc.cur_min);
    q.qoff = rc.kind == kSgm45 ? -dir : (rc.kind == kSgm90 ? 0 : dir);
    q.ilo = rc.kind == kSgm45 ? 1 : 0;
    q.ihi = rc.kind == kSgm135 ? W - 2 : W - 1;
    if (!has_up) q.ilo = W;
  }
  uint16_t* const sum_base = static_cast<uint16_t*>(r.sum);
  U16V l0[NV];
  for (int v = 0; v < NV; ++v) l0[v] = U16V{};
  uint16_t m0 = 0;
  for (int i = 0; i < W; ++i) {
    const int x = dir > 0 ? i : W - 1 - i;
    const uint16_t* __restrict c = r.cost + static_cast<int64_t>(x) * cs;
    uint16_t* __restrict sum = sum_base + static_cast<int64_t>(x) * NC;
    U16V s[NV];
    for (int v = 0; v < NV; ++v) s[v] = Acc ? load16(sum + v * kLanes16) : U16V{};
    if (has0) {
      int p2 = r.p2;
      if (adapt && i > 0) p2 = adaptive(r.p1, r.p2, r.p2_adaptive, r.intensity[x], r.intensity[x - dir]);
      const U16V vm = splat16(m0), mp2 = splat16(static_cast<uint16_t>(m0 + p2));
      U16V nl[NV];
      U16V mn = splat16(0xFFFF);
      for (int v = 0; v < NV; ++v) {
        const U16V lo = lanes_up(v == 0 ? vguard : l0[v - 1], l0[v]);
        const U16V hi = lanes_down(l0[v], v == NV - 1 ? vguard : l0[v + 1]);
        const U16V t = vmin16(vmin16(l0[v], vmin16(lo, hi) + vp1), mp2);
        nl[v] = load16(c + v * kLanes16) + (t - vm);
        mn = vmin16(mn, nl[v]);
        s[v] += nl[v];
      }
      for (int v = 0; v < NV; ++v) l0[v] = nl[v];
      m0 = hmin16(mn);
    }
    for (int j = 0; j < nmem; ++j) {
      const RowRec& q = mem[j];
      const bool ok = i >= q.ilo && i <= q.ihi;
      const int qx = x + q.qoff;
      const uint16_t* __restrict lq = ok ? q.prev + static_cast<int64_t>(qx) * P : kZeroRow.v;
      const uint16_t mq = ok ? q.prev_min[qx] : 0;
      int p2 = r.p2;
      if (adapt && ok) p2 = adaptive(r.p1, r.p2, r.p2_adaptive, r.intensity[x], r.prev_intensity[qx]);
      const U16V vm = splat16(mq), mp2 = splat16(static_cast<uint16_t>(mq + p2));
      uint16_t* __restrict out = q.cur + static_cast<int64_t>(x) * P;
      U16V mn = splat16(0xFFFF);
      for (int v = 0; v < NV; ++v) {
        const uint16_t* lv = lq + v * kLanes16;
        const U16V t = vmin16(vmin16(load16(lv + 1), vmin16(load16(lv), load16(lv + 2)) + vp1), mp2);
        const U16V l = load16(c + v * kLanes16) + (t - vm);
        store16(out + 1 + v * kLanes16, l);
        mn = vmin16(mn, l);
        s[v] += l;
      }
      q.cur_min[x] = hmin16(mn);
      out[0] = guard;
      out[NC + 1] = guard;
    }
    for (int v = 0; v < NV; ++v) store16(sum + v * kLanes16, s[v]);
  }
}

template <class T, int NC>
void aggregate_row_n(const AggregateRow& r) {
  if constexpr (sizeof(T) == 2 && NC > 0 && NC <= 128 && NC % kLanes16 == 0) {
    bool sgm = r.recursions > 0;
    for (int k = 0; k < r.recursions; ++k) sgm = sgm && r.rec[k].kind < kMgmPixel && r.rec[k].weight == 1;
    if (sgm) {
      if (r.accumulate)
        aggregate_sgm16<NC, true>(r);
      else
        aggregate_sgm16<NC, false>(r);
      return;
    }
  }
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
  U16V lane[NV], best[NV], code[NV];
  const U16V fresh_best = splat16(0xFFFF), fresh_code = U16V{};
  for (int v = 0; v < NV; ++v) {
    lane[v] = load16(kLanes.v + v * kLanes16);
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
        const U16V keep = __builtin_bit_cast(U16V, nb == best[v]);
        code[v] = (code[v] & keep) | (lane[v] & ~keep);
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
        const I16V li = __builtin_bit_cast(I16V, lane[v]);
        const I16V out = (li < lo) | (li > hi);
        const U16V sel = __builtin_bit_cast(U16V, out);
        second = vmin16(second, (sv[v] & sel) | (fresh_best & ~sel));
      }
      if (dl - 1 > 0 || dl + 2 < D)
        valid = !(static_cast<uint64_t>(hmin16(second)) * 100u < static_cast<uint64_t>(100 + r.uniqueness_pct) * sl);
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
  if (r.lr_check) {  // after x = W - 1 the shifted window's lane d holds t = m + d - 1; lane 0 is fresh
    uint16_t rest[NC];
    for (int v = 0; v < NV; ++v) store16(rest + v * kLanes16, code[v]);
    for (int d = 1; d < NC; ++d) r.right_code[m - 1 + d] = rest[d];
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
