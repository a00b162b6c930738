// The fast engine's hot loops (isa.hpp), part 4 of 4: census, the costs and the table; the
// helpers and vector types are in isa_common.hpp, the recursions in isa_aggregate.hpp, the
// selection and median in isa_select.hpp, all in this one translation unit. Plain loops the
// compiler vectorises, and intrinsics or GCC vector types where it would not. Built three times with
// PARALLAX_FAST_ISA_NAME / PARALLAX_FAST_ISA_FN set (models/fast/CMakeLists.txt). No standard
// library: see isa.hpp. Every function computes docs/algorithm.md exactly; the equivalence tests
// compare it with the golden model at every level.
#include "isa.hpp"

#include "isa_common.hpp"

namespace parallax::fast::detail {
namespace {

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
#if !defined(__AVX512BW__)  // AVX-512 broadcasts 64 lanes and narrows them (cost_census_planes)
inline __m256i broadcast_byte32(uint8_t v) {
  return _mm256_set1_epi8(static_cast<char>(v));
}
#endif
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
  const PadLanes16 pad(D, stride, kCostPad);
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
    pad.apply(out);
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

// Column sums over the window's rows, kept by the caller from row to row: one image row pair
// added (Sign +1) or taken off (Sign -1), col[u + rw][d] += Sign * |L(clampx(u)) - R(clampx(u - m - d))|
// for u in [-rw, W + rw) and every lane d < stride (lanes d >= D are never read). The right row
// is read through a reversed, clamped copy g[t] = R(clampx(vmax - t)), vmax = W - 1 + rw, so that
// d reads forwards; the absolute differences are taken in bytes and widened to 16-bit lanes.
typedef uint8_t U8Half __attribute__((vector_size(kLanes16)));
typedef uint8_t U8HalfUnaligned __attribute__((vector_size(kLanes16), aligned(1), may_alias));
template <int Sign>
void sad_rows(const CostRow& r, const uint8_t* lrow, const uint8_t* rrow, int ww, uint16_t* col, uint8_t* g) {
  const int W = r.width_px, m = r.min_disparity, rw = ww / 2, S = cost_stride(r.disparities);
  const int vmax = W - 1 + rw, span = sad_scratch_len(W, ww, m, r.disparities);
  for (int t = 0; t < span; ++t) g[t] = rrow[clampi(vmax - t, 0, W - 1)];
  for (int u = -rw; u < W + rw; ++u) {
    const U8Half lv = U8Half{} + lrow[clampi(u, 0, W - 1)];
    const uint8_t* gr = g + (vmax - u + m);
    uint16_t* __restrict c = col + static_cast<int64_t>(u + rw) * S;
    for (int d0 = 0; d0 < S; d0 += kLanes16) {
      const U8Half a = *reinterpret_cast<const U8HalfUnaligned*>(gr + d0);
      const U8Half diff = (a > lv ? a : lv) - (a > lv ? lv : a);
      const U16V w = __builtin_convertvector(diff, U16V);
      store16(c + d0, Sign > 0 ? load16(c + d0) + w : load16(c + d0) - w);
    }
  }
}
void sad_columns(const CostRow& r, const uint8_t* left_row, const uint8_t* right_row, int ww, int sign, uint16_t* col,
                 uint8_t* scratch) {
  if (sign > 0)
    sad_rows<1>(r, left_row, right_row, ww, col, scratch);
  else
    sad_rows<-1>(r, left_row, right_row, ww, col, scratch);
}

// One SAD cost row from the column sums: the box over ww columns, then cost_max where
// x - m - d < 0 and kCostPad in the lanes d >= D.
void sad_box(const CostRow& r, int ww, const uint16_t* col) {
  const int W = r.width_px, D = r.disparities, m = r.min_disparity, S = cost_stride(D);
  for (int d0 = 0; d0 < S; d0 += kLanes16) {
    U16V v = U16V{};
    for (int i = 0; i < ww; ++i) v += load16(col + static_cast<int64_t>(i) * S + d0);
    store16(r.out + d0, v);
  }
  for (int x = 1; x < W; ++x) {
    const uint16_t* prev = r.out + static_cast<int64_t>(x - 1) * S;
    const uint16_t* add = col + static_cast<int64_t>(x - 1 + ww) * S;
    const uint16_t* sub = col + static_cast<int64_t>(x - 1) * S;
    uint16_t* out = r.out + static_cast<int64_t>(x) * S;
    for (int d0 = 0; d0 < S; d0 += kLanes16) store16(out + d0, load16(prev + d0) + load16(add + d0) - load16(sub + d0));
  }
  const PadLanes16 pad(D, S, kCostPad);
  for (int x = 0; x < W; ++x) {
    uint16_t* out = r.out + static_cast<int64_t>(x) * S;
    for (int d = clampi(x - m + 1, 0, D); d < D; ++d) out[d] = r.cost_max;
    pad.apply(out);
  }
}

}  // namespace
}  // namespace parallax::fast::detail

#include "isa_aggregate.hpp"
#include "isa_select.hpp"

namespace parallax::fast::detail {
namespace {

const IsaTable kTable = {PARALLAX_FAST_ISA_NAME,
                         census_image,
                         cost_census,
                         sad_columns,
                         sad_box,
                         aggregate_row<uint16_t>,
                         aggregate_row<uint32_t>,
                         pad_sums16,
                         select_row<uint16_t>,
                         select_row<uint32_t>,
                         median_row};

}  // namespace

const IsaTable& PARALLAX_FAST_ISA_FN() {
  return kTable;
}

}  // namespace parallax::fast::detail
