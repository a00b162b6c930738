// What a stage instantiates in hardware for one configuration, declared by the stage itself from
// the constants it runs with (models/resources turns the declarations into BRAM_18K, LUT, FF and
// DSP). C++14 synthesisable subset; the declare() methods are never synthesised.
//
// A stage's declare(R& r) calls, per hardware instance (after unrolling over lanes and paths):
//   r.memory(name, depth_words, width_bits, copies, true_dual_port)
//       an array of `copies` identical memories (one per partition); true_dual_port when one
//       memory needs two ports that both write or three accesses per cycle;
//   r.registers(name, width_bits, count)   state and pipeline registers;
//   r.op(name, kind, width_bits, count)    operators of the datapath and the control counters;
//   r.mul(name, a_bits, b_bits, count)     multipliers (their operand widths decide DSP binding);
//   r.mul_const(name, a_bits, const_bits, count)   multipliers by a design constant of the export
//       (shift-and-add unless the binding rule puts them on a slice);
//   r.mux(name, width_bits, fan_in, count)  count fan_in:1 multiplexers of width_bits (a register
//       file or partitioned array read at a run-time index: one mux per read port).
//
// A stage's schedule(S& s) declares what limits the initiation interval of its pipelined loop
// (issue 14; sim/ derives II = max(1, ResMII, RecMII) from it, docs/hls.md):
//   s.memory(name, reads, writes, ports)   a memory the counting run does not see (the rectify
//       stages' line buffer): its accesses in the busiest firing over its ports. Every other
//       memory's accesses are counted in C simulation (access.hpp, sim/accesses.hpp), not declared;
//   s.recurrence(name, distance)           a value one firing produces and the firing `distance`
//       later uses (a loop-carried dependence), followed by
//   s.chain(kind, width_bits, count)        the operators on the path from that use to the value's
//       next definition, in order (count of them in series); kOpMemRead for a memory read.
#pragma once

#include "parallax/kernels/params.hpp"

namespace parallax {
namespace kern {

enum OpKind {
  kOpAdd = 0,   // adder / subtractor / incrementer (a carry chain)
  kOpCompare,   // magnitude or equality comparator
  kOpMux,       // 2:1 multiplexer per bit (select of a min, a clamp)
  kOpPopcount,  // population count of width_bits inputs
  kOpXor,       // bitwise XOR
  kOpMul,       // multiplier; width_bits = the wider operand, see the name's suffix for both
  kOpKindCount,
  kOpMemRead = kOpKindCount,  // a memory read (schedule chains only)
  kOpRegister                 // a register write (schedule chains only)
};

inline const char* op_kind_name(OpKind k) {
  return k == kOpAdd        ? "add"
         : k == kOpCompare  ? "compare"
         : k == kOpMux      ? "mux"
         : k == kOpPopcount ? "popcount"
         : k == kOpXor      ? "xor"
                            : "mul";
}

// Storage descriptors (issue 14, item 4). Every member array that becomes hardware is described
// once, beside its declaration, by the kernel's storage(V& v) method (and ShiftReg, WindowRegs
// and LineBuffer describe their own arrays), which hands the visitor the member itself, the
// elements this configuration uses and the bits the design needs per element:
//   v.registers(name, member, count, width_bits)        complete partitioning, one register per
//       element; in an exported (FIXED) instantiation count is the member's whole extent;
//   v.registers_part(name, member, count, width_bits)   the first count elements of a member
//       sized for a larger case (the rest are never written there; synthesis drops them);
//   v.window(name, member, cols, rows, width_bits)      window registers member[rows][>= cols];
//   v.memory(name, member, depth, width_bits, copies, true_dual_port, per_word)  a memory of
//       `copies` partitions of depth words, each word per_word elements of the member.
//   v.unused(name, member)   a member this configuration never writes (no hardware: synthesis
//       removes it), e.g. the LR registers without the check, a path kind's state when inactive.
// declare() turns the description into r.registers / r.memory through DeclareStorage, so the
// model's registers and memories are computed from the same expressions that size and partition
// the members; tests/models/resources/storage_test.cpp checks the description against the members'
// extents (sizeof) in FIXED instantiations.
template <class R>
class DeclareStorage {
 public:
  explicit DeclareStorage(R& r) : r_(r) {}
  template <class M>
  void registers(const char* name, const M&, int count, int width_bits) {
    r_.registers(name, width_bits, count);
  }
  template <class M>
  void registers_part(const char* name, const M&, int count, int width_bits) {
    r_.registers(name, width_bits, count);
  }
  template <class M>
  void window(const char* name, const M&, int cols, int rows, int width_bits) {
    r_.registers(name, width_bits, cols * rows);
  }
  template <class M>
  void unused(const char*, const M&) {}
  template <class M>
  void memory(const char* name, const M&, int64_t depth, int width_bits, int copies, bool true_dual_port, int) {
    r_.memory(name, depth, width_bits, copies, true_dual_port);
  }

 private:
  R& r_;
};

// Declares what a kernel's storage() describes.
template <class R, class K, class... A>
void declare_storage(R& r, const K& kernel, const A&... a) {
  DeclareStorage<R> s(r);
  kernel.storage(s, a...);
}

// Control of a raster stage: column, row and chunk counters with their end compares.
template <class R>
void declare_raster_control(R& r, int width_px, int height_px, int chunks) {
  r.op("column_counter", kOpAdd, bits_for(uint64_t(width_px)), 1);
  r.op("row_counter", kOpAdd, bits_for(uint64_t(height_px)), 1);
  r.op("counter_ends", kOpCompare, bits_for(uint64_t(width_px)), 2);
  if (chunks > 1) {
    r.op("chunk_counter", kOpAdd, bits_for(uint64_t(chunks)), 1);
    r.op("chunk_end", kOpCompare, bits_for(uint64_t(chunks)), 1);
  }
  r.registers("counters", bits_for(uint64_t(width_px)) + bits_for(uint64_t(height_px)) + bits_for(uint64_t(chunks)), 1);
}

}  // namespace kern
}  // namespace parallax
