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
//   r.mul(name, a_bits, b_bits, count)     multipliers (their operand widths decide DSP binding).
//
// A stage's schedule(S& s) declares what limits the initiation interval of its pipelined loop
// (issue 14; sim/ derives II = max(1, ResMII, RecMII) from it, docs/hls.md):
//   s.memory(name, reads, writes, ports)   one physical memory after partitioning and its
//       accesses in the busiest firing (every branch of the loop body counts: synthesis schedules
//       the loop for all of them); ports: 2 for a dual-port RAM, 1 for a single-port one;
//   s.recurrence(name, distance)           a value one firing produces and the firing `distance`
//       later uses (a loop-carried dependence), followed by
//   s.chain(kind, width_bits, count)        the operators on the path from that use to the value's
//       next definition, in order (count of them in series); kOpMemRead for a memory read.
#pragma once

#include "parallax/kernels/params.hpp"

namespace parallax {
namespace kern {

enum OpKind {
  kOpAdd = 0,    // adder / subtractor / incrementer (a carry chain)
  kOpCompare,    // magnitude or equality comparator
  kOpMux,        // 2:1 multiplexer per bit (select of a min, a clamp)
  kOpPopcount,   // population count of width_bits inputs
  kOpXor,        // bitwise XOR
  kOpMul,        // multiplier; width_bits = the wider operand, see the name's suffix for both
  kOpKindCount,
  kOpMemRead = kOpKindCount,  // a memory read (schedule chains only)
  kOpRegister                 // a register write (schedule chains only)
};

inline const char* op_kind_name(OpKind k) {
  return k == kOpAdd ? "add"
         : k == kOpCompare ? "compare"
         : k == kOpMux ? "mux"
         : k == kOpPopcount ? "popcount"
         : k == kOpXor ? "xor"
                      : "mul";
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
