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

// Storage directives of one exported design: the HLS export's configuration header defines
// PX_HLS_<MEMORY>_<WHAT> as pragma strings (ARRAY_PARTITION, BIND_STORAGE) for the kernels'
// member arrays, which the kernels place in configure(), where the arrays are in scope. Software
// builds leave them undefined, and each use sits in an #ifdef.

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

// Copies n lanes between two distinct memories.
template <class T>
inline void copy_lanes(T* PX_RESTRICT dst, const T* PX_RESTRICT src, int n) {
copy_lanes_loop:
  for (int i = 0; i < n; ++i) dst[i] = src[i];
}

// One stream token of up to N disparity lanes. A firing of a disparity stage moves PU lanes;
// lanes [PU, N) are unused. In HLS the token becomes an ap_uint<PU * bits>.
template <class T, int N>
struct Lanes {
  T v[N];
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

inline int clamp_int(int v, int lo, int hi) { return v < lo ? lo : (v > hi ? hi : v); }
inline int min_int(int a, int b) { return a < b ? a : b; }
inline int max_int(int a, int b) { return a > b ? a : b; }

inline int popcount64(uint64_t v) {
#if defined(__GNUC__)
  return __builtin_popcountll(v);
#else
  int n = 0;
  for (int i = 0; i < 64; ++i) n += int((v >> i) & 1u);
  return n;
#endif
}

}  // namespace kern
}  // namespace parallax
