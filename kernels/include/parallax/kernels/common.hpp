// Shared building blocks of the kernels: lane tokens, loop-label support, small integer helpers.
// C++14 synthesisable subset: no heap, no exceptions, no virtual calls, no STL containers.
#pragma once

#include <stdint.h>

#include "parallax/kernels/params.hpp"

// Kernel loops carry labels (they name the loops in HLS reports and simulator statistics); a
// label that no goto uses is not a defect here.
#if defined(__GNUC__) && !defined(__SYNTHESIS__)
#pragma GCC diagnostic ignored "-Wunused-label"
#endif

#if defined(__SYNTHESIS__)
#define PX_PRAGMA(x) _Pragma(x)
#else
#define PX_PRAGMA(x)
#endif

// Storage directives sit with the declarations they describe: a kernel's member arrays get
// theirs in the class's constructor (the one scope that sees the members, as AMD's
// xf::cv::LineBuffer and Window do), which has no other code. Structural directives (complete
// partitioning of registers, lane banks of PU) are written there from the Caps constants; the
// mapping the resource model chooses for one design (BRAM or LUTRAM, packing, banks) comes from
// the HLS export's configuration header as PX_HLS_<MEMORY>_<WHAT> pragma strings, each use in an
// #ifdef (software builds leave them undefined). Exported tops keep their kernel objects local to
// a process call, so nothing needs dynamic initialisation.

// Inlining hint for small per-firing helpers (software builds; HLS inlines small functions itself).
#if defined(__GNUC__) && !defined(__SYNTHESIS__)
#define PX_INLINE inline __attribute__((always_inline))
#else
#define PX_INLINE inline
#endif

// Promise of non-overlapping pointers (lets software builds vectorise lane copies).
#if defined(__GNUC__) && !defined(__SYNTHESIS__)
#define PX_RESTRICT __restrict__
#else
#define PX_RESTRICT
#endif

namespace parallax {
namespace kern {

// One stream token of up to N disparity lanes. A firing of a disparity stage moves PU lanes;
// lanes [PU, N) are unused. In HLS the token becomes an ap_uint<PU * bits>.
template <class T, int N>
struct Lanes {
  T v[N];
};

// The cost stage's token: PU costs of one pixel and the pixel's left intensity, which the SGM
// aggregation's adaptive P2 reads (docs/algorithm.md §3). Every token of a pixel carries it; a
// design without adaptive P2 never reads it (the export's cost streams then drop it).
template <int N>
struct CostLanes : Lanes<uint16_t, N> {
  uint8_t px;
};

// The pixel-wise data between the WTA/LR stage, the median and the writer: a disparity code
// (code == D means invalid, docs/algorithm.md §5).
typedef uint16_t DispCode;

// A source position of the rectification map in fixed point (docs/algorithm.md §1).
struct MapEntry {
  int32_t x;
  int32_t y;
};

// A stream type that is never read or written: stands for an absent port.
template <class T>
struct NoStream {
  bool empty() const { return true; }
  bool full() const { return false; }
  T read() { return T(); }
  void write(const T&) {}
};

inline int clamp_int(int v, int lo, int hi) {
  return v < lo ? lo : (v > hi ? hi : v);
}
inline int min_int(int a, int b) {
  return a < b ? a : b;
}
inline int max_int(int a, int b) {
  return a > b ? a : b;
}

// Population count of the low BITS bits of v. Synthesis sees an explicit adder tree: level 1
// adds the bits in pairs (2-bit sums), level 2 adds pairs of those (4-bit sums), and so on,
// log2(64) = 6 levels of narrow adders on fixed wiring (no builtin, no multiplier). Software
// builds count with the CPU's instruction (vectorised over lanes where the CPU has one); the
// two forms are the same function (tests/kernels/common_test.cpp checks them against each other).
template <int BITS>
PX_INLINE int popcount_adder_tree(uint64_t v) {
  static_assert(BITS >= 1 && BITS <= 64, "popcount of 1 to 64 bits");
  if (BITS < 64) v &= (uint64_t(1) << (BITS < 64 ? BITS : 0)) - 1u;
  v = (v & 0x5555555555555555ull) + ((v >> 1) & 0x5555555555555555ull);
  v = (v & 0x3333333333333333ull) + ((v >> 2) & 0x3333333333333333ull);
  v = (v & 0x0F0F0F0F0F0F0F0Full) + ((v >> 4) & 0x0F0F0F0F0F0F0F0Full);
  v = (v & 0x00FF00FF00FF00FFull) + ((v >> 8) & 0x00FF00FF00FF00FFull);
  v = (v & 0x0000FFFF0000FFFFull) + ((v >> 16) & 0x0000FFFF0000FFFFull);
  v = (v & 0x00000000FFFFFFFFull) + (v >> 32);
  return int(v);
}

template <int BITS>
PX_INLINE int popcount_tree(uint64_t v) {
#if defined(__GNUC__) && !defined(__SYNTHESIS__)
  if (BITS < 64) v &= (uint64_t(1) << (BITS < 64 ? BITS : 0)) - 1u;
  return __builtin_popcountll(v);
#else
  return popcount_adder_tree<BITS>(v);
#endif
}

}  // namespace kern
}  // namespace parallax
