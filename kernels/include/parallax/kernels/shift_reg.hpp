// The kernels' shift registers (ShiftReg): the last D columns a stage looks back over. C++14,
// synthesisable.
#pragma once

#include <stdint.h>

#include "parallax/kernels/access.hpp"
#include "parallax/kernels/common.hpp"

namespace parallax {
namespace kern {

// A shift register of N entries, entry 0 the newest: what the stages that look back over the
// last D columns keep (the Census right codes, the WTA/LR candidates and delayed results).
// LITERAL (the exported, FIXED instantiations): every entry is a register (complete
// partitioning) and a shift moves each along its fixed wire. Software instantiations keep the
// same sequence as a window sliding over a longer array (one copy, entries 0 .. N-1 contiguous
// from the base): a shift moves the base, and only when the base reaches an end of the array
// are the N entries copied back to the other end, so a shift costs O(1) amortised instead of N
// moves and a loop over consecutive entries is a loop over consecutive addresses (vectorised).
// The entries read and written are the same (the equivalence tests run the window, the
// exported C simulation runs the registers, both against one golden model).
// COUNT (a counting instantiation, access.hpp): at() and set() record a read or a write of entry
// k at the caller's site (its file and line, through ShiftPorts' index type), whichever form
// stores the entries: an index that reaches several entries over a run is a run-time mux (read)
// or demux (write) across the registers. Shifts are not recorded: each entry reads its fixed
// neighbour, a wire, never a mux.
template <class T, int N, bool LITERAL, bool COUNT = false>
class ShiftReg;

// The ports are a base (empty outside counting: no storage of their own).
template <class T, int N, bool COUNT>
class ShiftReg<T, N, true, COUNT> : private ShiftPorts<COUNT, N> {
  typedef ShiftPorts<COUNT, N> Ports;
  typedef typename Ports::Index Index;

 public:
  typedef T element_type;  // store.hpp: StoredBits
  ShiftReg() { PX_PRAGMA("HLS ARRAY_PARTITION variable=v_ type=complete dim=1") }
  // The report's name of the registers (counting instantiations).
  void name(const char* n) { Ports::name(n); }
  // Every entry 0 (not counted: initialisation, outside the pipelined loop).
  void clear() {
  shift_reg_clear:
    for (int k = 0; k < N; ++k) v_[k] = T(0);
  }
  // Entries 0 .. n-1 move `by` places towards 0, the first `by` wrapping to the end: entry k
  // takes entry (k + by) mod n (0 < by < n). Wires, like a shift: not counted.
  void rotate(int by, int n) {
    T old[N];
    PX_PRAGMA("HLS ARRAY_PARTITION variable=old type=complete dim=1")
  shift_reg_rotate_copy:
    for (int k = 0; k < N; ++k) {
      PX_PRAGMA("HLS UNROLL")
      old[k] = v_[k];
    }
  shift_reg_rotate:
    for (int k = 0; k < N; ++k) {
      PX_PRAGMA("HLS UNROLL")
      if (k < n) v_[k] = old[k + by < n ? k + by : k + by - n];
    }
  }
  // Entries 1 .. n-1 take their predecessor's value, entry 0 takes x.
  void shift_in(const T& x, int n) {
  shift_reg_in:
    for (int k = N - 1; k > 0; --k) {
      PX_PRAGMA("HLS UNROLL")
      if (k < n) v_[k] = v_[k - 1];
    }
    v_[0] = x;
  }
  // Entries 0 .. n-2 take their successor's value, entry n-1 takes x.
  void shift_back(const T& x, int n) {
  shift_reg_back:
    for (int k = 0; k + 1 < N; ++k) {
      PX_PRAGMA("HLS UNROLL")
      if (k + 1 < n) v_[k] = v_[k + 1];
    }
    v_[n - 1] = x;
  }
  const T& at(Index k) const { return v_[Ports::read(k)]; }
  void set(Index k, const T& x) { v_[Ports::write(k)] = x; }
  // Storage descriptor (resources.hpp): entries 0 .. used-1 are registers of width_bits; used is
  // N (the whole register) or less when the last entries are never shifted into (n < N).
  template <class V>
  void storage(V& v, const char* name, int used, int width_bits) const {
    if (used == N)
      v.registers(name, v_, used, width_bits);
    else if (used > 0)
      v.registers_part(name, v_, used, width_bits);
    else
      v.unused(name, v_);
  }

 private:
  T v_[N];
};

template <class T, int N, bool COUNT>
class ShiftReg<T, N, false, COUNT> : private ShiftPorts<COUNT, N> {
  typedef ShiftPorts<COUNT, N> Ports;
  typedef typename Ports::Index Index;

 public:
  typedef T element_type;  // store.hpp: StoredBits
  void name(const char* n) { Ports::name(n); }
  void clear() {
    for (long k = 0; k < kSpan; ++k) v_[k] = T(0);
    base_ = (kSpan - N) / 2;
  }
  void rotate(int by, int n) {
    T old[N];
    for (int k = 0; k < n; ++k) old[k] = v_[base_ + k];
    for (int k = 0; k < n; ++k) v_[base_ + k] = old[k + by < n ? k + by : k + by - n];
  }
  void shift_in(const T& x, int) {
    if (base_ == 0) relocate(kSpan - N);
    --base_;
    v_[base_] = x;
  }
  void shift_back(const T& x, int n) {
    if (base_ == kSpan - N) relocate(0);
    ++base_;
    v_[base_ + n - 1] = x;
  }
  const T& at(Index k) const { return v_[base_ + Ports::read(k)]; }
  void set(Index k, const T& x) { v_[base_ + Ports::write(k)] = x; }
  // Storage descriptor (resources.hpp): the hardware is the literal form's used registers.
  template <class V>
  void storage(V& v, const char* name, int used, int width_bits) const {
    if (used > 0)
      v.registers_part(name, v_, used, width_bits);
    else
      v.unused(name, v_);
  }

 private:
  // The window's N entries move to start at `to`, the other end of the array (the two ranges
  // never overlap: the array is 8 windows long).
  void relocate(long to) {
    for (int k = 0; k < N; ++k) v_[to + k] = v_[base_ + k];
    base_ = to;
  }
  static constexpr long kSpan = 8L * N;
  T v_[kSpan] = {};
  // long, not int: a store to an entry (of any 32-bit or narrower T) cannot alias the base, so
  // loops over at()/set() keep it in a register.
  long base_ = (kSpan - N) / 2;
};

}  // namespace kern
}  // namespace parallax
