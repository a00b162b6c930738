// The fast engine's hot loops, part 2 of 4 (isa.cpp): the SGM and MGM recursions over one
// stream row. Included once per level by isa.cpp (see isa_common.hpp).
#pragma once

#include "isa_common.hpp"

namespace parallax::fast::detail {
namespace {

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
  const int W = r.width_px, N = NC > 0 ? NC : r.lanes, dir = r.dir, S = rc.stride, MS = rc.min_stride;
  const int cs = r.cost_stride;
  const T p1 = static_cast<T>(r.p1);
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
    T* out = cur + static_cast<int64_t>(x) * S;
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
        const T* lq = (up ? prev : cur) + static_cast<int64_t>(qx) * S;
        const T mq = (up ? prev_min : cur_min)[qx * MS];
        int p2 = r.p2;
        if (adapt) p2 = adaptive(r.p1, r.p2, r.p2_adaptive, r.intensity[x], (up ? r.prev_intensity : r.intensity)[qx]);
        mn = sgm_step<T, Acc, Twice, NC>(c, lq, mq, p1, static_cast<T>(p2), out, sum, N);
      }
    } else if (!qok) {  // MGM, the second predecessor alone
      const T* lq = prev + static_cast<int64_t>(q2x) * S;
      int p2 = r.p2;
      if (adapt) p2 = adaptive(r.p1, r.p2, r.p2_adaptive, r.intensity[x], r.prev_intensity[q2x]);
      mn = sgm_step<T, Acc, Twice, NC>(c, lq, prev_min[q2x * MS], p1, static_cast<T>(p2), out, sum, N);
    } else {
      const T* la = (up ? prev : cur) + static_cast<int64_t>(qx) * S;
      const T ma = (up ? prev_min : cur_min)[qx * MS];
      const T* lb = prev + static_cast<int64_t>(q2x) * S;
      int pa2 = r.p2, pb2 = r.p2;
      if (adapt) {
        pa2 = adaptive(r.p1, r.p2, r.p2_adaptive, r.intensity[x], (up ? r.prev_intensity : r.intensity)[qx]);
        pb2 = adaptive(r.p1, r.p2, r.p2_adaptive, r.intensity[x], r.prev_intensity[q2x]);
      }
      mn = mgm_step<T, Acc, Twice, NC>(c, la, ma, static_cast<T>(pa2), lb, prev_min[q2x * MS], static_cast<T>(pb2), p1,
                                       out, sum, N);
    }
    cur_min[x * MS] = mn;
  }
}

// Zeros for a missing predecessor (L = C + min(0, 0 + P1, 0 + P2) - 0 = C: a path start).
struct ZeroRow {
  uint16_t v[288] = {};
};
constexpr ZeroRow kZeroRow{};

// The 0-degree path of aggregate_sgm16 at one pixel: its previous pixel's costs l0 (and their
// minimum vm0, in every lane) live in registers, the d -+ 1 neighbours by lane shifts; l0 and vm0
// become this pixel's and l0 is added into s. Same arithmetic as sgm_step, lane for lane.
template <int NV>
inline void path0_step(const uint16_t* __restrict c, U16V* l0, U16V& vm0, U16V vp2, U16V vp1, U16V vguard, U16V* s) {
  const U16V vm = vm0, mp2 = vm0 + vp2;
  U16V mn = splat16(0xFFFF);
  U16V before = vguard;           // the previous register's old value (its last lane is d - 1 of lane 0)
  for (int v = 0; v < NV; ++v) {  // in place: l0[v] is replaced once its neighbours are read
    const U16V old = l0[v];
    const U16V lo = lanes_up(before, old);
    const U16V hi = lanes_down(old, v == NV - 1 ? vguard : l0[v + 1]);
    const U16V t = vmin16(vmin16(old, vmin16(lo, hi) + vp1), mp2);
    l0[v] = load16(c + v * kLanes16) + (t - vm);
    mn = vmin16(mn, l0[v]);
    s[v] += l0[v];
    before = old;
  }
  vm0 = hmin16_splat(mn);
}

// One previous-row path of aggregate_sgm16 at one pixel: from the predecessor's padded costs lq
// (guards at lq[0] and lq[NV * kLanes16 + 1]) and their minimum mq, writes out[1..] and *out_min,
// adds into s. Same arithmetic as sgm_step.
template <int NV>
inline void row_path_step(const uint16_t* __restrict c, const uint16_t* __restrict lq, uint16_t mq, U16V vp2, U16V vp1,
                          uint16_t* __restrict out, uint16_t* __restrict out_min, U16V* s) {
  const U16V vm = splat16(mq), mp2 = vm + vp2;  // lane for lane the 16-bit sum mq + P2
  U16V mn = splat16(0xFFFF);
  for (int v = 0; v < NV; ++v) {
    const uint16_t* lv = lq + v * kLanes16;
    const U16V t = vmin16(vmin16(load16(lv + 1), vmin16(load16(lv), load16(lv + 2)) + vp1), mp2);
    const U16V l = load16(c + v * kLanes16) + (t - vm);
    store16(out + 1 + v * kLanes16, l);
    mn = vmin16(mn, l);
    s[v] += l;
  }
  *out_min = hmin16(mn);
}

// An int as a type (a generic lambda's compile-time parameter: the stream's direction, a
// recursion kind, a slot).
template <int D>
struct DirTag {
  static constexpr int value = D;
};

// The path sets aggregate_sgm16 unrolls (the pass plans of 2, 3 and 4 paths): layout 1 is
// {0, 90}, 2 is {0, 45, 90}, 3 is {0, 45, 90, 135} degrees; the kind of recursion k.
constexpr int layout_kind(int layout, int k) {
  return k == 0 ? kSgm0 : (layout == 1 ? kSgm90 : kSgm0 + k);
}

// A row of SGM recursions (each of weight 1) in 16 bits over NC lanes, a whole number of
// registers: one sweep over the pixels for all recursions, each pixel's costs loaded once and its
// sum kept in registers until stored once. The 0-degree path lives in registers from one pixel to
// the next (path0_step; its row buffer is not written, nothing reads it: only the next pixel of
// the same row uses it). The other paths read the previous stream row; a missing predecessor
// reads kZeroRow with Mq = 0. Layout (layout_kind): the pass's path set when it is one of the
// 2-, 3- or 4-path sets, else 0. Such a pass in the engine's interleaved row buffers (isa.hpp,
// Recursion) runs its inner pixels (all predecessors present) unrolled from one pointer per
// buffer, the direction and every offset constants; the first row, the two end pixels of every
// row and every other pass take the general form.
template <int NC, bool Acc, int Layout>
void aggregate_sgm16(const AggregateRow& r) {
  constexpr int NV = NC / kLanes16;
  constexpr int P = NC + 2;
  const int W = r.width_px, dir = r.dir, cs = r.cost_stride;
  const U16V vp1 = splat16(r.p1), vguard = splat16(static_cast<uint16_t>(0xFFFF - r.p1));
  const bool adapt = r.p2_adaptive > 0, has_up = !r.first_row;
  // The recursions on the previous stream row, resolved once per row: predecessor column
  // x + qoff, present for the stream positions i in [ilo, ihi] (none on the first row).
  struct RowRec {
    const uint16_t* prev;
    const uint16_t* prev_min;
    uint16_t* cur;
    uint16_t* cur_min;
    int kind, qoff, ilo, ihi, stride, min_stride;
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
    q.kind = rc.kind;
    q.qoff = rc.kind == kSgm45 ? -dir : (rc.kind == kSgm90 ? 0 : dir);
    q.ilo = rc.kind == kSgm45 ? 1 : 0;
    q.ihi = rc.kind == kSgm135 ? W - 2 : W - 1;
    q.stride = rc.stride;
    q.min_stride = rc.min_stride;
    if (!has_up) q.ilo = W;
  }
  uint16_t* const sum_base = static_cast<uint16_t*>(r.sum);
  U16V l0[NV];
  for (int v = 0; v < NV; ++v) l0[v] = U16V{};
  U16V vm0 = U16V{};  // the 0-degree path's previous minimum in every lane
  const U16V vp2 = splat16(r.p2);
  const int count = Layout > 0 ? Layout : nmem;

  // Any pixel, any recursions.
  auto general = [&](int i) {
    const int x = dir > 0 ? i : W - 1 - i;
    const uint16_t* __restrict c = r.cost + static_cast<int64_t>(x) * cs;
    uint16_t* __restrict sum = sum_base + static_cast<int64_t>(x) * NC;
    U16V s[NV];
    for (int v = 0; v < NV; ++v) s[v] = Acc ? load16(sum + v * kLanes16) : U16V{};
    if (has0) {
      const U16V p2 =
          adapt && i > 0 ? splat16(adaptive(r.p1, r.p2, r.p2_adaptive, r.intensity[x], r.intensity[x - dir])) : vp2;
      path0_step<NV>(c, l0, vm0, p2, vp1, vguard, s);
    }
    for (int j = 0; j < count; ++j) {
      const RowRec& q = mem[j];
      const bool ok = i >= q.ilo && i <= q.ihi;
      const int qx = x + q.qoff;
      const uint16_t* lq = ok ? q.prev + static_cast<int64_t>(qx) * q.stride : kZeroRow.v;
      const uint16_t mq = ok ? q.prev_min[qx * q.min_stride] : 0;
      const U16V p2 =
          adapt && ok ? splat16(adaptive(r.p1, r.p2, r.p2_adaptive, r.intensity[x], r.prev_intensity[qx])) : vp2;
      row_path_step<NV>(c, lq, mq, p2, vp1, q.cur + static_cast<int64_t>(x) * q.stride,
                        q.cur_min + static_cast<int64_t>(x) * q.min_stride, s);
    }
    for (int v = 0; v < NV; ++v) store16(sum + v * kLanes16, s[v]);
  };

  // The interleaved fast form: recursion k of the pass in slot k of every pixel's block of four
  // (slot 0 the 0-degree path's, unused: it is in registers).
  bool interleaved = Layout > 0 && has_up && W >= 3 && r.recursions == Layout + 1 && r.rec[0].kind == kSgm0;
  for (int k = 0; interleaved && k < r.recursions; ++k) {
    const Recursion& rc = r.rec[k];
    interleaved = rc.kind == layout_kind(Layout, k) && rc.stride == 4 * P && rc.min_stride == 4 &&
                  rc.prev == static_cast<const uint16_t*>(r.rec[0].prev) + k * P &&
                  rc.cur == static_cast<uint16_t*>(r.rec[0].cur) + k * P &&
                  rc.prev_min == static_cast<const uint16_t*>(r.rec[0].prev_min) + k &&
                  rc.cur_min == static_cast<uint16_t*>(r.rec[0].cur_min) + k;
  }
  if (!interleaved) {
    for (int i = 0; i < W; ++i) general(i);
    return;
  }
  // Pixel x's block starts at base + x * 4P in both rows, its minima at base_min + 4x.
  const uint16_t* const prev4 = static_cast<const uint16_t*>(r.rec[0].prev);
  uint16_t* const cur4 = static_cast<uint16_t*>(r.rec[0].cur);
  const uint16_t* const prev_min4 = static_cast<const uint16_t*>(r.rec[0].prev_min);
  uint16_t* const cur_min4 = static_cast<uint16_t*>(r.rec[0].cur_min);
  auto inner = [&](auto tag) {
    constexpr int D = decltype(tag)::value;
    for (int i = 1; i < W - 1; ++i) {
      const int x = D > 0 ? i : W - 1 - i;
      const uint16_t* __restrict c = r.cost + static_cast<int64_t>(x) * cs;
      uint16_t* __restrict sum = sum_base + static_cast<int64_t>(x) * NC;
      const uint16_t* pv = prev4 + static_cast<int64_t>(x) * (4 * P);
      uint16_t* cv = cur4 + static_cast<int64_t>(x) * (4 * P);
      const uint16_t* pm = prev_min4 + static_cast<int64_t>(x) * 4;
      uint16_t* cm = cur_min4 + static_cast<int64_t>(x) * 4;
      const int ix = adapt ? r.intensity[x] : 0;
      U16V s[NV];
      for (int v = 0; v < NV; ++v) s[v] = Acc ? load16(sum + v * kLanes16) : U16V{};
      path0_step<NV>(c, l0, vm0, adapt ? splat16(adaptive(r.p1, r.p2, r.p2_adaptive, ix, r.intensity[x - D])) : vp2,
                     vp1, vguard, s);
      auto slot = [&](auto kind_tag, auto slot_tag) {
        constexpr int kKind = decltype(kind_tag)::value, kSlot = decltype(slot_tag)::value;
        constexpr int q = kKind == kSgm45 ? -D : (kKind == kSgm90 ? 0 : D);  // predecessor column x + q
        const U16V p2 = adapt ? splat16(adaptive(r.p1, r.p2, r.p2_adaptive, ix, r.prev_intensity[x + q])) : vp2;
        row_path_step<NV>(c, pv + q * 4 * P + kSlot * P, pm[q * 4 + kSlot], p2, vp1, cv + kSlot * P, cm + kSlot, s);
      };
      if constexpr (Layout == 1) {
        slot(DirTag<kSgm90>{}, DirTag<1>{});
      } else {
        slot(DirTag<kSgm45>{}, DirTag<1>{});
        slot(DirTag<kSgm90>{}, DirTag<2>{});
        if constexpr (Layout == 3) slot(DirTag<kSgm135>{}, DirTag<3>{});
      }
      for (int v = 0; v < NV; ++v) store16(sum + v * kLanes16, s[v]);
    }
  };
  general(0);
  if (dir > 0)
    inner(DirTag<1>{});
  else
    inner(DirTag<-1>{});
  general(W - 1);
}

template <int NC, bool Acc>
void aggregate_sgm16_layout(const AggregateRow& r, int layout) {
  switch (layout) {
    case 1:
      aggregate_sgm16<NC, Acc, 1>(r);
      break;
    case 2:
      aggregate_sgm16<NC, Acc, 2>(r);
      break;
    case 3:
      aggregate_sgm16<NC, Acc, 3>(r);
      break;
    default:
      aggregate_sgm16<NC, Acc, 0>(r);
      break;
  }
}

template <class T, int NC>
void aggregate_row_n(const AggregateRow& r) {
  if constexpr (sizeof(T) == 2 && NC > 0 && NC <= 128 && NC % kLanes16 == 0) {
    bool sgm = r.recursions > 0;
    for (int k = 0; k < r.recursions; ++k) sgm = sgm && r.rec[k].kind < kMgmPixel && r.rec[k].weight == 1;
    if (sgm) {
      int layout = 0;  // the path sets of 2, 3 and 4 paths (kinds in plan order, 0 degrees first)
      for (int l = 1; l <= 3 && layout == 0; ++l) {
        bool match = r.recursions == l + 1;
        for (int k = 0; match && k < r.recursions; ++k) match = r.rec[k].kind == layout_kind(l, k);
        if (match) layout = l;
      }
      if (r.accumulate)
        aggregate_sgm16_layout<NC, true>(r, layout);
      else
        aggregate_sgm16_layout<NC, false>(r, layout);
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

}  // namespace
}  // namespace parallax::fast::detail
