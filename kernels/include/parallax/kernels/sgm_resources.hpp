// The resources and schedule an SGM aggregation stage declares (resources.hpp), from what the
// stage's configuration instantiates (sgm.hpp: SgmAggregate::declare and ::schedule call these
// with the stage). C++14; never synthesised.
#pragma once

#include "parallax/kernels/params.hpp"
#include "parallax/kernels/resources.hpp"
#include "parallax/kernels/sgm_kinds.hpp"

namespace parallax {
namespace kern {

// Resources of this configuration (resources.hpp). Row paths keep the previous row's Lr in
// memories, a word of PU lanes per chunk, and the previous row's minimum per column; the pixel
// path keeps the previous pixel's Lr and minimum in registers; the row-left path delays the previous row's column by
// one pixel in registers. Every path holds the predecessor's lanes of the next chunk and lane lo - 1. Per lane and
// path: two +P1 adds, the min of four, + C - M, and the running minimum; per lane the sum over paths. Schedule of one
// firing (resources.hpp). Each row memory sees one read (the next chunk's word) and one write (this chunk's); each
// row-minimum memory one read (chunk 0) and one write (the last chunk). The pixel path's minimum M is written by a
// pixel's last firing and used by the next firing; the lanes' minimum is taken off that path (see aggregate_kind), so
// the chain from M to M is the subtraction, the min with C + P2, the running minimum and its register. The running
// minimum itself recurs every firing.
template <class A, class S>
void sgm_schedule(const A& a, S& s) {
  const StereoParams& p = a.params();
  const int lanes = a.lanes();
  const int pb = path_bits(p);
  const unsigned dk = a.datapaths();
  // The memories' accesses are counted, not declared (accesses.hpp, issue 41).
  if (a.mgm()) {
    // The previous pixel's minimum M recurs into the next pixel's (the pixel datapath): no
    // lane-minimum identity here, so the chain runs through the lanes: the step's P2 clamp
    // and subtraction, the average, + C, the min tree over the PU lanes, the running minimum
    // and its register.
    if ((dk & (1u << kKindPixel)) != 0) {
      s.recurrence("mgm_previous_pixel_minimum", 1);
      s.chain(kOpCompare, pb + 1, 1);  // min with M + P2
      s.chain(kOpMux, pb + 1, 1);
      s.chain(kOpAdd, pb + 1, 1);  // - M
      s.chain(kOpAdd, pb + 1, 1);  // u_a + u_b
      s.chain(kOpAdd, pb, 1);      // + C
      int levels = 0;              // of the min tree over the lanes
      while ((1 << levels) < lanes) ++levels;
      if (levels > 0) {
        s.chain(kOpCompare, pb, levels);
        s.chain(kOpMux, pb, levels);
      }
      s.chain(kOpCompare, pb, 1);  // running minimum over the chunks
      s.chain(kOpMux, pb, 1);
      s.chain(kOpRegister, pb, 1);
    }
    // The previous pixel's Lr in the register files pix_ (and the window win_): read C - 1
    // firings after its write; through a run-time-indexed register file the scheduler takes
    // distance 1 (the derivation's via). The chain of one firing: the read (the via adds its
    // mux), Lr(q, d +- 1) + P1, two compare-selects, the P2 clamp, - M, the average, + C, the
    // path-start select, the write (the via adds its decoder).
    if ((dk & (1u << kKindPixel)) != 0) {
      s.recurrence("mgm_previous_pixel_registers", max_int(1, a.disparity_count() / lanes - 1));
      s.via("pixel_path_previous");
      s.via("mgm_window");
      s.chain(kOpAdd, pb, 1);
      s.chain(kOpCompare, pb, 3);
      s.chain(kOpMux, pb, 3);
      s.chain(kOpAdd, pb + 1, 3);
      s.chain(kOpMux, pb, 1);
      s.chain(kOpRegister, pb, 1);
    }
  } else if ((dk & (1u << kKindPixel)) != 0) {
    // The previous pixel's Lr in the register file pix_, read C - 1 firings after its write;
    // through a run-time-indexed register file the scheduler takes distance 1 (the derivation's
    // via). The chain of one firing: the read (the via adds its mux), Lr(q, d +- 1) + P1, two
    // compare-selects (with the other candidates, then with M + P2), - M, + C, the path-start
    // select, the write (the via adds its decoder).
    s.recurrence("pixel_path_registers", max_int(1, a.disparity_count() / lanes - 1));
    s.via("pixel_path_previous");
    s.chain(kOpAdd, pb, 1);
    s.chain(kOpCompare, pb, 2);
    s.chain(kOpMux, pb, 2);
    s.chain(kOpAdd, pb + 1, 2);
    s.chain(kOpMux, pb, 1);
    s.chain(kOpRegister, pb, 1);
    s.recurrence("pixel_path_minimum", 1);
    s.chain(kOpAdd, pb + 1, 1);      // min_d (C_d + t_d) - M
    s.chain(kOpCompare, pb + 1, 1);  // min with min_d C_d + P2
    s.chain(kOpMux, pb + 1, 1);
    s.chain(kOpCompare, pb, 1);  // running minimum over the chunks
    s.chain(kOpMux, pb, 1);
    s.chain(kOpRegister, pb, 1);
  }
  s.recurrence("running_minimum", 1);
  s.chain(kOpCompare, pb, 1);
  s.chain(kOpMux, pb, 1);
  s.chain(kOpRegister, pb, 1);
}

template <class A, class R>
void sgm_declare(const A& a, R& r) {
  const StereoParams& p = a.params();
  const int pb = path_bits(p);
  const int ab = aggregate_bits(p);
  const int d = a.disparity_count();
  const int pu = a.lanes();
  declare_raster_control(r, p.width_px, p.height_px, d / pu);
  DeclareStorage<R> st(r);
  a.storage(st);
  const unsigned dk = a.datapaths();
agg_declare_paths:
  for (int k = 0; k < kKindCount; ++k) {
    if (((dk >> k) & 1u) == 0) continue;
    if (d > pu) r.mux("path_predecessor_select", pb, d / pu, pu);
    if (k == kKindRowLeft && d > pu) {
      // lag_ (the previous row's Lr of column x - 1) is indexed by the chunk: per lane a read
      // select of D/PU entries, per register its two write sources, one enable per chunk
      // (review S4, docs/hls-review.md).
      r.mux("row_left_delay_read", pb, d / pu, pu);
      r.op("row_left_delay_write_select", kOpMux, pb, d);
      r.op("row_left_delay_write_enable", kOpCompare, bits_for(uint64_t(d / pu)), d / pu);
    }
    r.op("path_p1_adds", kOpAdd, pb + 1, 2 * pu);
    r.op("path_p2_add", kOpAdd, pb + 1, 1);
    r.op("path_min_of_four", kOpCompare, pb + 1, 3 * pu);
    r.op("path_min_select", kOpMux, pb + 1, 3 * pu);
    r.op("path_cost_minus_min", kOpAdd, pb + 1, 2 * pu);
    r.op("path_running_min", kOpCompare, pb, pu);
    r.op("path_running_min_select", kOpMux, pb, pu);
  }
  if (a.mgm()) {
    // Per datapath, the second predecessor's step beside the first's (the SGM ops above): its
    // chunk select, the +P1 adds, min of four, - M; then the average of the two steps, the
    // selects of the sides inside the image, and the lanes' min tree (no identity with MGM).
  agg_declare_mgm:
    for (int k = 0; k < kKindCount; ++k) {
      if (((dk >> k) & 1u) == 0) continue;
      if (d > pu) r.mux("mgm_second_select", pb, d / pu, pu);
      r.op("mgm_second_p1_adds", kOpAdd, pb + 1, 2 * pu);
      r.op("mgm_second_p2_add", kOpAdd, pb + 1, 1);
      r.op("mgm_second_min_of_four", kOpCompare, pb + 1, 3 * pu);
      r.op("mgm_second_min_select", kOpMux, pb + 1, 3 * pu);
      r.op("mgm_second_minus_min", kOpAdd, pb + 1, pu);
      r.op("mgm_average", kOpAdd, pb + 1, pu);
      r.op("mgm_side_select", kOpMux, pb + 1, 2 * pu);
      if (pu > 1) {
        r.op("mgm_lane_min_tree", kOpCompare, pb, pu - 1);
        r.op("mgm_lane_min_select", kOpMux, pb, pu - 1);
      }
    }
  }
  if (p.p2_adaptive > 0) {
    // Per active kind: |I(p) - I(q)| (a subtraction and a negation's select), the product by
    // the design constant a (kP2Adaptive in the export: shift-and-add, review S9), P2 minus it
    // with the floor P1 + 1 (a subtraction, a compare and a select), and the selects of the
    // window's shift.
    const int pen = penalty_bits(p);
    r.op("p2_adaptive_step", kOpAdd, 9, 2 * a.steps());
    r.op("p2_adaptive_abs", kOpMux, 8, a.steps());
    const uint64_t factor = uint64_t(p.p2_adaptive);
    if ((factor & (factor - 1)) != 0)  // a power of two is a shift: wiring
      r.mul_const("p2_adaptive_product", 8, bits_for(factor), a.steps());
    r.op("p2_adaptive_lower", kOpAdd, pen + 1, a.steps());
    r.op("p2_adaptive_floor", kOpCompare, pen + 1, a.steps());
    r.op("p2_adaptive_floor_select", kOpMux, pen, a.steps());
  }
  r.op("sum_over_paths", kOpAdd, ab, pu * a.slots());
  r.registers("cost_in", pu * cost_bits(p), 1);
  r.registers("sum_token", pu * ab, 1);
}

// SgmAggregate::storage (declared in sgm.hpp with its contract).
template <class Caps, class Word>
template <class V>
void SgmAggregate<Caps, Word>::storage(V& v) const {
  const int pb = path_bits(p_);
  const int64_t words = int64_t(p_.width_px) * chunks_;
  v.unused("software_lane_pad", pad_);  // read only where !Caps::fixed
  const unsigned dk = datapaths();
agg_storage_kinds:
  for (int k = 0; k < kKindCount; ++k) {
    if (((dk >> k) & 1u) == 0) {  // an inactive kind's state is never written: no hardware
      if (k == kKindPixel) {
        v.unused("pixel_path_previous", pix_);
        pix_q_.storage(v, "pixel_path_previous_chunks", 0, pb);
      }
      if (k == kKindRowLeft) v.unused("row_left_delay", lag_);
      if (k != kKindPixel) v.unused("row_path", row_[k - 1]);
      if (k != kKindPixel) v.unused("row_min", row_min_[k - 1]);
      v.unused("path_predecessor_lanes", ahead_[k]);
      continue;
    }
    if (k == kKindPixel) {
      // The same D registers, as a plain register file or (exported and counting instantiations)
      // the shift register of the chunks written (pix_read).
      if (kRotatingPix) {
        v.unused("pixel_path_previous_flat", pix_);
        pix_q_.storage(v, "pixel_path_previous", d_, pb);
      } else {
        v.registers("pixel_path_previous", pix_, d_, pb);
        pix_q_.storage(v, "pixel_path_previous_chunks", 0, pb);
      }
      v.registers("pixel_path_min", pix_min_, 1, pb);
    } else {
      const int m = k - 1;
      v.memory(k == kKindRowLeft ? "row_path_left"
               : k == kKindRowUp ? "row_path_up"
                                 : "row_path_right",
               row_[m], words, lanes_ * pb, 1, false, lanes_);
      v.memory(k == kKindRowLeft ? "row_min_left"
               : k == kKindRowUp ? "row_min_up"
                                 : "row_min_right",
               row_min_[m], p_.width_px, pb, 1, false, 1);
      if (k == kKindRowLeft && !mgm()) {  // MGM's row-left reads x - 1 from its window instead
        v.registers("row_left_delay", lag_, d_, pb);
        v.registers("row_left_delay_min", mlag_, 1, pb);
      } else if (k == kKindRowLeft) {
        v.unused("row_left_delay", lag_);
        v.unused("row_left_delay_min", mlag_);
      }
    }
    v.registers_part("path_predecessor_lanes", ahead_[k], lanes_ + 1, pb);
    v.registers("path_min_previous", mq_[k], 1, pb);
    v.registers("path_min_running", run_min_[k], 1, pb);
  }
  mgm_storage(v, words);
  intensity_storage(v);
}

// The p2_adaptive intensities' storage (SgmAggregate::storage): the current and previous pixels'
// intensities and the per-kind P2, and with row kinds a row of intensities and its window.
template <class Caps, class Word>
template <class V>
void SgmAggregate<Caps, Word>::intensity_storage(V& v) const {
  const bool on = p_.p2_adaptive > 0;
  const bool rows = on && row_intensities();
  if (on) {
    v.registers("intensity_current", cur_px_, 1, 8);
    v.registers("intensity_previous_pixel", prev_px_, 1, 8);
    v.registers_part("p2_adaptive_per_kind", p2k_, steps(), penalty_bits(p_));
  } else {
    v.unused("intensity_current", cur_px_);
    v.unused("intensity_previous_pixel", prev_px_);
    v.unused("p2_adaptive_per_kind", p2k_);
  }
  if (rows) {
    v.memory("row_intensity", row_px_, p_.width_px, 8, 1, false, 1);
    v.registers("intensity_row_window", up_px_, 3, 8);
    v.registers("intensity_row_head", head_px_, 2, 8);
    v.registers("intensity_row_fetched", fetched_px_, 1, 8);
  } else {
    v.unused("row_intensity", row_px_);
    v.unused("intensity_row_window", up_px_);
    v.unused("intensity_row_head", head_px_);
    v.unused("intensity_row_fetched", fetched_px_);
  }
}

}  // namespace kern
}  // namespace parallax
