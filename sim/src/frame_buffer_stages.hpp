// Internal: the memory side of the two-pass (8-path) variant, its layout and loops those of
// kernels/frame_buffer.hpp as exported. The frame buffer stands for off-chip memory (words of
// 32-bit limbs); pass 1's forward aggregation leaves a pair of tokens per firing (PU costs and
// PU forward sums), packed into `beats` power-of-two words. ddr_write reverses the pixels on
// chip in segments (a ping-pong buffer) and writes each segment at ascending addresses, so that
// ddr_read reads words 0 .. N-1 in order and pass 2 sees the pixels in reverse order; the map
// writer reverses the codes the same way. configure() sizes the memories for one run; the pumps
// follow scheduler.hpp's contract. kData = false (the timing run) moves tokens without payload
// and allocates nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "parallax/kernels/common.hpp"
#include "parallax/kernels/frame_buffer.hpp"
#include "parallax/kernels/params.hpp"
#include "parallax/sim/cycle.hpp"
#include "parallax/sim/fifo.hpp"
#include "parallax/sim/func.hpp"
#include "pipeline_run.hpp"
#include "scheduler.hpp"

namespace parallax::sim::detail {

// The frame buffer's figures for one design, in the units the two passes count in.
struct FrameLayout {
  int64_t pixels, words, seg_pixels, seg_tokens, seg_words, segments;
  int chunks, beats, word_limbs, pair_limbs, cost_w, sum_w, word_bytes;
};
inline FrameLayout frame_layout(const kern::StereoParams& p) {
  FrameLayout f{};
  f.pixels = int64_t(p.width_px) * p.height_px;
  f.chunks = kern::frame_chunks(p);
  f.beats = kern::frame_beats(p);
  f.word_limbs = kern::frame_word_bits(p) / 32;
  f.pair_limbs = kern::frame_limbs_of(kern::frame_pair_bits(p));
  f.words = kern::frame_words(p);
  f.seg_pixels = kern::frame_segment_pixels(p);
  f.seg_tokens = f.seg_pixels * f.chunks;
  f.seg_words = f.seg_tokens * f.beats;
  f.segments = f.pixels / f.seg_pixels;
  f.cost_w = kern::cost_bits(p);
  f.sum_w = kern::aggregate_bits(p);
  f.word_bytes = kern::frame_word_bytes(p);
  return f;
}

template <class Caps, class Word, bool kTimed, bool kData>
class FrameBufferStages {
 public:
  using CostTok = kern::CostLanes<Caps::lanes>;
  using SumTok = kern::Lanes<Word, Caps::lanes>;
  using NodeT = Node<kTimed>;

  // Sets the layout for a design and clears the memories; the report (may be null) gets the
  // map writer's first and last pixel cycles.
  void configure(const kern::StereoParams& p, CycleReport* rep) {
    p_ = p;
    rep_ = rep;
    fl_ = frame_layout(p);
    if (kData) {
      frame_.assign(std::size_t(fl_.words) * std::size_t(fl_.word_limbs), 0u);
      segment_.assign(2 * std::size_t(fl_.seg_tokens) * std::size_t(fl_.pair_limbs), 0u);
      map_segment_.assign(2 * std::size_t(kern::map_segment_pixels(p)), 0);
    }
    for (uint32_t& limb : read_pair_) limb = 0;
  }
  const FrameLayout& layout() const { return fl_; }

  // ddr_write: seg_tokens firings that only fill the first segment, then one firing per word
  // written (word w no earlier than ddr.at(w)), which also takes in the next segment's tokens
  // (one pair per `beats` words) while there are any. step counts its firings, stored the words
  // written; word_done (if set) is called after each word written (the fast-forward's hook).
  std::function<bool()> write_pump(NodeT& n, Fifo<CostTok>& tee, Fifo<SumTok>& fwd, Rate ddr, int64_t& step,
                                   int64_t& stored, const std::function<void()>& word_done = {}) {
    return [this, &n, &tee, &fwd, ddr, &step, &stored, word_done] {
      const FrameLayout& fl = fl_;
      bool fired = false;
      if (n.still_blocked()) return false;
      const int64_t firings = fl.seg_tokens + fl.words;
      while (step < firings) {
        const int64_t t = step;
        const bool writes = t >= fl.seg_tokens;
        const int64_t w = t - fl.seg_tokens;  // the word written (writes)
        const bool reads = !writes || (w < fl.words - fl.seg_words && w % fl.beats == 0);
        if (!n.attempt(
                {Port{&tee, reads}, Port{&fwd, reads}}, {},
                [&] {
                  if constexpr (kData) {
                    if (writes) {  // before the fill: the two halves differ
                      const int64_t seg = w / fl.seg_words, k = w % fl.seg_words;
                      const int64_t slot =
                          (seg % 2) * fl.seg_tokens + kern::reversed_slot(k / fl.beats, fl.chunks, fl.seg_pixels);
                      uint32_t pair[kPairLimbs] = {};
                      const uint32_t* from = &segment_[std::size_t(slot) * std::size_t(fl.pair_limbs)];
                      for (int i = 0; i < fl.pair_limbs; ++i) pair[i] = from[i];
                      uint32_t word[kern::kFrameWordMaxBits / 32];
                      kern::frame_beat_of(pair, int(k % fl.beats), fl.word_limbs, word);
                      const int64_t address = kern::reversed_block_base(fl.segments, fl.seg_words, seg) + k;
                      for (int i = 0; i < fl.word_limbs; ++i)
                        frame_[std::size_t(address) * std::size_t(fl.word_limbs) + std::size_t(i)] = word[i];
                    }
                    if (reads) {
                      const int64_t token = writes ? fl.seg_tokens + w / fl.beats : t;
                      const int64_t slot = ((token / fl.seg_tokens) % 2) * fl.seg_tokens + token % fl.seg_tokens;
                      uint32_t pair[kPairLimbs];
                      kern::frame_pack(tee.read(), fwd.read(), p_.parallel_units, fl.cost_w, fl.sum_w, pair);
                      uint32_t* to = &segment_[std::size_t(slot) * std::size_t(fl.pair_limbs)];
                      for (int i = 0; i < fl.pair_limbs; ++i) to[i] = pair[i];
                    }
                  } else if (reads) {
                    tee.skip_read();
                    fwd.skip_read();
                  }
                },
                writes ? ddr.at(w) : 0))
          break;
        ++step;
        fired = true;
        if (writes) {
          ++stored;
          if (word_done) word_done();
        }
      }
      return fired;
    };
  }

  // ddr_read: one firing per word at ascending addresses (word i no earlier than rd.at(i)); the
  // last beat of a pair sends its two tokens. read_word counts the words read.
  std::function<bool()> read_pump(NodeT& n, Fifo<CostTok>& c_out, Fifo<SumTok>& f_out, Rate rd, int64_t& read_word) {
    return [this, &n, &c_out, &f_out, rd, &read_word] {
      const FrameLayout& fl = fl_;
      bool fired = false;
      if (n.still_blocked()) return false;
      while (read_word < fl.words) {
        const int64_t i = read_word;  // ascending addresses
        const bool last_beat = i % fl.beats == fl.beats - 1;
        if (!n.attempt(
                {}, {Port{&c_out, last_beat}, Port{&f_out, last_beat}},
                [&] {
                  if constexpr (kData) {
                    uint32_t word[kern::kFrameWordMaxBits / 32];
                    for (int k = 0; k < fl.word_limbs; ++k)
                      word[k] = frame_[std::size_t(i) * std::size_t(fl.word_limbs) + std::size_t(k)];
                    kern::frame_set_beat(read_pair_, int(i % fl.beats), fl.word_limbs, word);
                    if (last_beat) {
                      CostTok c;
                      SumTok f;
                      kern::frame_unpack(read_pair_, p_.parallel_units, fl.cost_w, fl.sum_w, c, f);
                      c_out.write(c);
                      f_out.write(f);
                    }
                  } else if (last_beat) {
                    c_out.skip_write();
                    f_out.skip_write();
                  }
                },
                rd.at(i)))
          break;
        ++read_word;
        fired = true;
      }
      return fired;
    };
  }

  // The map writer (the sink of pass 2): the codes arrive in reverse raster order; the writer
  // buffers segments of them (ping-pong) and writes each segment reversed at ascending
  // addresses, so that the map lands in raster order. Its loop: seg firings that only fill the
  // first segment, then one firing per code written, which also takes in the next code while
  // there are any. A code leaves when it is written to memory; got counts them, step the
  // firings; code_done (if set) is called after each code written (the fast-forward's hook).
  std::function<bool()> map_writer_pump(NodeT& n, Fifo<kern::DispCode>& in, DisparityCodes& out, int64_t& got,
                                        int64_t& step, const std::function<void()>& code_done = {}) {
    const int64_t total = fl_.pixels;
    const int64_t seg = kern::map_segment_pixels(p_);
    return [this, &n, &in, &out, &got, total, seg, &step, code_done] {
      bool fired = false;
      if (n.still_blocked()) return false;
      while (step < seg + total) {
        const int64_t t = step;
        const bool writes = t >= seg;
        const int64_t w = t - seg;
        const bool reads = !writes || w < total - seg;
        if (!n.attempt({Port{&in, reads}}, {}, [&] {
              if constexpr (kData) {
                if (writes) {
                  const int64_t s = w / seg, k = w % seg;
                  out.code[std::size_t(kern::reversed_block_base(total / seg, seg, s) + k)] =
                      map_segment_[std::size_t((s % 2) * seg + kern::reversed_slot(k, 1, seg))];
                }
                if (reads) {
                  const int64_t code = writes ? seg + w : t;
                  map_segment_[std::size_t(((code / seg) % 2) * seg + code % seg)] = in.read();
                }
              } else if (reads) {
                in.skip_read();
              }
            }))
          break;
        ++step;
        fired = true;
        if (!writes) continue;
        if (rep_) {
          if (w == 0) rep_->first_pixel_cycle = n.report().last_fire_cycle;
          rep_->last_pixel_cycle = n.report().last_fire_cycle;
        }
        ++got;
        if (code_done) code_done();
      }
      return fired;
    };
  }

 private:
  // kPairLimbs holds the widest pair of tokens these lanes carry.
  static constexpr int kPairLimbs = kern::frame_limbs_of(Caps::lanes * (16 + 32));
  kern::StereoParams p_{};
  CycleReport* rep_ = nullptr;
  FrameLayout fl_{};
  // The frame buffer, and the on-chip reversal buffers of ddr_write (pairs) and of the map
  // writer (codes).
  std::vector<uint32_t> frame_, segment_;
  std::vector<kern::DispCode> map_segment_;
  uint32_t read_pair_[kPairLimbs] = {};  // the pair ddr_read is collecting from its beats
};

}  // namespace parallax::sim::detail
