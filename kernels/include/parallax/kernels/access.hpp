// Kernel arrays and their layout directives, written once for synthesis, software and the
// access-counting build (issue 41). C++14.
//
// A kernel declares each array that becomes memory or registers as Array<T, N...> (through its
// Caps, caps.hpp) and states its layout beside the other directives with the PX_PARTITION_* /
// PX_BIND_* macros below. One macro emits the HLS pragma (synthesis) and, in an instantiation
// whose Caps count accesses, tells the counted array the same layout, so the banks the count
// sees are the banks the pragma makes. Plain instantiations (software and synthesis) get the
// raw C array and the macros cost nothing.
//
// Counting (Caps::count_accesses, never synthesised): every element access is recorded with
// its access site, the place in the source (file and line, captured where the kernel indexes
// the array) times its unrolled copy (the k-th execution of that place within one firing of the
// stage), and the bank the layout puts the element in. A site that reaches more than one bank
// over a run is banked at run time: the scheduler cannot tell which bank it touches, so it counts
// on every bank it reached, on every firing it executes. Per firing the banks' reads and writes
// are summed over the sites that executed; the report (access_count.hpp) keeps the largest. The
// count is told nothing about what it should find: the kernel code indexes, the layout says
// where an index lands.
#pragma once

#include <stdint.h>

#include "parallax/kernels/common.hpp"

namespace parallax {
namespace kern {

// How a layout directive splits one dimension of an array (UG1399, ARRAY_PARTITION).
enum PartitionType : int { kPartitionNone = 0, kPartitionComplete = 1, kPartitionCyclic = 2, kPartitionBlock = 3 };

// What an array's banks are bound to (UG1399, BIND_STORAGE), and so their ports per bank:
// registers have as many as wanted; ram_1p one read-or-write port; ram_2p one read-or-write and
// one read; ram_s2p one read and one write; ram_t2p two read-or-write. kStorageDefault is an
// array without a binding, which Vitis implements as a RAM of one or two ports as the schedule
// needs (counted as ram_t2p).
enum StorageType : int {
  kStorageDefault = 0,
  kStorageRegisters = 1,
  kStorageRam1p = 2,
  kStorageRam2p = 3,
  kStorageRamS2p = 4,
  kStorageRamT2p = 5,
};

// The raw C array T[N0][N1]... of the plain instantiations.
template <class T, int... N>
struct RawArray;
template <class T>
struct RawArray<T> {
  typedef T type;
};
template <class T, int N0, int... N>
struct RawArray<T, N0, N...> {
  typedef typename RawArray<T, N...>::type type[N0];
};

// The type of a kernel's array member: raw, or counted in a counting instantiation (the
// specialisation for COUNT = true is in access_count.hpp).
template <bool COUNT, class T, int... N>
struct ArrayOf {
  typedef typename RawArray<T, N...>::type type;
};

// What a shift register (shift_reg.hpp) does with the index of an at() or set(): nothing but pass
// it on, except in a counting instantiation, where the index type captures the caller's site and
// the access is recorded on the entry's register (the specialisation in access_count.hpp).
template <bool COUNT, int N>
struct ShiftPorts {
  typedef int Index;
  int read(int k) const { return k; }
  int write(int k) const { return k; }
  void name(const char*) {}
};

// Layout statements on a raw array: nothing (the pragma is the statement).
template <class A>
inline void access_partition(A&, const char*, int, int, int) {}
template <class A>
inline void access_bind(A&, const char*, int) {}
template <class A>
inline void access_reshape(A&, const char*, int, int) {}
// The report's name of a counted array (one member of several objects: the object's name).
template <class A>
inline void access_name(A&, const char*) {}

}  // namespace kern
}  // namespace parallax

// clang-format off
#define PX_PRAGMA_TEXT_(...) PX_PRAGMA(#__VA_ARGS__)

// Layout directives: ARRAY_PARTITION of dimension DIM (1-based; 0 = every dimension) and
// BIND_STORAGE, each the pragma and, in a counting instantiation, the same statement to the
// counted array (its name is the member's).
// The arguments are pragma text as well as C++: they cannot take the parentheses a C++-only
// macro would put around them.
// NOLINTBEGIN(bugprone-macro-parentheses)
#define PX_PARTITION_COMPLETE(VAR, DIM)                                    \
  PX_PRAGMA_TEXT_(HLS ARRAY_PARTITION variable=VAR type=complete dim=DIM) \
  ::parallax::kern::access_partition(VAR, #VAR, ::parallax::kern::kPartitionComplete, 0, DIM);
#define PX_PARTITION_CYCLIC(VAR, FACTOR, DIM)                                                \
  PX_PRAGMA_TEXT_(HLS ARRAY_PARTITION variable=VAR type=cyclic factor=FACTOR dim=DIM) \
  ::parallax::kern::access_partition(VAR, #VAR, ::parallax::kern::kPartitionCyclic, FACTOR, DIM);
#define PX_PARTITION_BLOCK(VAR, FACTOR, DIM)                                                \
  PX_PRAGMA_TEXT_(HLS ARRAY_PARTITION variable=VAR type=block factor=FACTOR dim=DIM) \
  ::parallax::kern::access_partition(VAR, #VAR, ::parallax::kern::kPartitionBlock, FACTOR, DIM);
// ARRAY_RESHAPE cyclic: FACTOR consecutive elements of dimension DIM in one word (element i in
// word i / FACTOR); a later partition of DIM splits the words.
#define PX_RESHAPE_CYCLIC(VAR, FACTOR, DIM)                                                \
  PX_PRAGMA_TEXT_(HLS ARRAY_RESHAPE variable=VAR type=cyclic factor=FACTOR dim=DIM) \
  ::parallax::kern::access_reshape(VAR, #VAR, FACTOR, DIM);
// ARRAY_RESHAPE complete: all of dimension DIM in one word (the PU lanes of a chunk).
#define PX_RESHAPE_COMPLETE(VAR, DIM)                                             \
  PX_PRAGMA_TEXT_(HLS ARRAY_RESHAPE variable=VAR type=complete dim=DIM) \
  ::parallax::kern::access_reshape(VAR, #VAR, 0, DIM);
#define PX_BIND_RAM_S2P(VAR, IMPL)                                          \
  PX_PRAGMA_TEXT_(HLS BIND_STORAGE variable=VAR type=ram_s2p impl=IMPL) \
  ::parallax::kern::access_bind(VAR, #VAR, ::parallax::kern::kStorageRamS2p);
#define PX_BIND_RAM_S2P_ANY(VAR)                                          \
  PX_PRAGMA_TEXT_(HLS BIND_STORAGE variable=VAR type=ram_s2p) \
  ::parallax::kern::access_bind(VAR, #VAR, ::parallax::kern::kStorageRamS2p);
#define PX_BIND_RAM_T2P(VAR, IMPL)                                          \
  PX_PRAGMA_TEXT_(HLS BIND_STORAGE variable=VAR type=ram_t2p impl=IMPL) \
  ::parallax::kern::access_bind(VAR, #VAR, ::parallax::kern::kStorageRamT2p);
// No read-after-write dependence between firings through the array VAR (DEPENDENCE inter RAW
// false): no firing reads an element that a recent firing wrote (the kernel states why, and how
// many firings apart the nearest such pair is). Only RAW: a write-after-read between consecutive
// firings, as the SGM rows have (firing t reads the word t + 1 overwrites), stays ordered.
// Stated in the per-firing member function that accesses VAR, not in a constructor: the stage
// functions inline their kernels' calls (INLINE recursive), so the pragma lands in the body of
// the stage's pipelined loop, the scope UG1399 gives DEPENDENCE (issue 41, reviews R3, S1, S2).
#define PX_NO_DEPENDENCE(VAR) \
  PX_PRAGMA_TEXT_(HLS DEPENDENCE variable=VAR type=inter direction=RAW dependent=false)
// A counted array that is a memory but whose binding comes from elsewhere (the export's
// configuration header): the counting statement alone.
#define PX_COUNT_BIND(VAR, STORAGE) ::parallax::kern::access_bind(VAR, #VAR, STORAGE);
// NOLINTEND(bugprone-macro-parentheses)

// One firing of the stage STAGE (a string literal, the simulator's stage name) in an exported
// top's pipelined loop: with PARALLAX_COUNT_ACCESSES (the project's `make csim`) the kernels'
// counted arrays attribute the accesses up to the end of the loop body to it; otherwise, and in
// synthesis, nothing.
#if defined(PARALLAX_COUNT_ACCESSES) && !defined(__SYNTHESIS__) && !defined(PARALLAX_HLS_SUBSET_CHECK)
#define PX_COUNT_FIRING(STAGE) const ::parallax::kern::AccessFiring px_access_firing_(STAGE);
// The stage's kernel KERNEL after configure(): its storage members' widths against its storage
// descriptor's (storage_widths.hpp; extra arguments go to KERNEL.storage()).
#define PX_COUNT_STORAGE(STAGE, ...) ::parallax::kern::record_storage_widths(STAGE, __VA_ARGS__);
#else
#define PX_COUNT_FIRING(STAGE)
#define PX_COUNT_STORAGE(STAGE, ...)
#endif
// clang-format on

#if !defined(__SYNTHESIS__) && !defined(PARALLAX_HLS_SUBSET_CHECK)
#include "parallax/kernels/access_count.hpp"
#include "parallax/kernels/storage_widths.hpp"
#endif
