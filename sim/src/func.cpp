// The `func` run: a round-robin dataflow scheduler that fires each kernel while its plan can be
// met. No timing is modelled; FIFOs are small so that the working set stays in cache.
#include "parallax/sim/func.hpp"

#include <cstdio>
#include <cstdlib>
#include <memory>

#include "parallax/kernels/caps.hpp"
#include "parallax/kernels/census.hpp"
#include "parallax/kernels/median.hpp"
#include "parallax/kernels/rectify.hpp"
#include "parallax/kernels/sad.hpp"
#include "parallax/kernels/sgm.hpp"
#include "parallax/kernels/wta_lr.hpp"
#include "parallax/sim/fifo.hpp"

namespace parallax::sim {
namespace {

using kern::DispCode;

[[noreturn]] void internal_error(const char* what) {
  std::fprintf(stderr, "parallax: internal error: %s\n", what);
  std::abort();
}

// Fires a stage until its plan cannot be met; returns whether it fired at all.
template <class CanFire, class Fire>
bool pump(CanFire&& can_fire, Fire&& fire) {
  bool fired = false;
  while (can_fire()) {
    fire();
    fired = true;
  }
  return fired;
}

constexpr std::size_t kPixelFifoDepth = 2048;
constexpr std::size_t kTokenFifoDepth = 128;
constexpr int kMaxRectifyRows = 256;

template <class Caps, class Word>
class Engine {
 public:
  using CostTok = kern::Lanes<uint16_t, Caps::lanes>;
  using SumTok = kern::Lanes<Word, Caps::lanes>;

  DisparityCodes run(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p) {
    const bool two_pass = (p.path_mask & kern::kBackwardPaths) != 0;
    DisparityCodes out;
    out.width_px = p.width_px;
    out.height_px = p.height_px;
    out.disparities = p.disparities;
    out.code.resize(std::size_t(p.width_px) * p.height_px);
    if (p.cost == kern::kCostCensus)
      two_pass ? run_two_pass(census_, left, right, p, out) : run_one_pass(census_, left, right, p, out);
    else
      two_pass ? run_two_pass(sad_, left, right, p, out) : run_one_pass(sad_, left, right, p, out);
    return out;
  }

 private:
  // Source -> cost -> aggregate (forward kinds) -> WTA/LR -> median -> sink.
  template <class CostStage>
  void run_one_pass(CostStage& cost, const GreyImage& left, const GreyImage& right,
                    const kern::StereoParams& p, DisparityCodes& out) {
    cost.configure(p);
    agg_.configure(p, kern::stream_kinds(p.path_mask, false), false, false);
    wta_.configure(p, false);
    median_.configure(p);
    Fifo<uint8_t> in_l("left_px", kPixelFifoDepth), in_r("right_px", kPixelFifoDepth);
    Fifo<CostTok> costs("cost", kTokenFifoDepth);
    Fifo<SumTok> sums("sum", kTokenFifoDepth);
    Fifo<DispCode> disp("disp_lr", kPixelFifoDepth), filtered("disp_out", kPixelFifoDepth);
    kern::NoStream<SumTok> no_sum;
    kern::NoStream<CostTok> no_cost;
    const std::size_t total = out.code.size();
    std::size_t src = 0, dst = 0;
    while (dst < total) {
      bool progress = false;
      while (src < total && !in_l.full()) {
        in_l.write(left.px[src]);
        in_r.write(right.px[src]);
        ++src;
        progress = true;
      }
      progress |= pump_cost(cost, in_l, in_r, costs);
      progress |= pump([&] { return !agg_.done() && !costs.empty() && !sums.full(); },
                       [&] { agg_.fire(agg_.plan(), costs, no_sum, sums, no_cost); });
      progress |= pump_wta(sums, disp);
      progress |= pump_median(disp, filtered);
      while (!filtered.empty()) {
        out.code[dst++] = filtered.read();
        progress = true;
      }
      if (!progress) internal_error("func scheduler made no progress (single pass)");
    }
  }

  // Pass 1: source -> cost -> aggregate (forward kinds, tee) -> frame buffer (C and F).
  // Pass 2: frame buffer in reverse -> aggregate (backward kinds, + F) -> WTA/LR (reverse)
  //         -> median -> sink, which restores raster order.
  template <class CostStage>
  void run_two_pass(CostStage& cost, const GreyImage& left, const GreyImage& right,
                    const kern::StereoParams& p, DisparityCodes& out) {
    const std::size_t pixels = out.code.size();
    const int chunks = p.disparities / p.parallel_units;
    const std::size_t tokens = pixels * std::size_t(chunks);
    frame_cost_.resize(tokens);
    frame_fwd_.resize(tokens);
    {
      cost.configure(p);
      agg_.configure(p, kern::stream_kinds(p.path_mask, false), false, true);
      Fifo<uint8_t> in_l("left_px", kPixelFifoDepth), in_r("right_px", kPixelFifoDepth);
      Fifo<CostTok> costs("cost", kTokenFifoDepth), tee("cost_to_ddr", kTokenFifoDepth);
      Fifo<SumTok> sums("fwd_to_ddr", kTokenFifoDepth);
      kern::NoStream<SumTok> no_sum;
      std::size_t src = 0, stored_c = 0, stored_f = 0;
      while (stored_f < tokens || stored_c < tokens) {
        bool progress = false;
        while (src < pixels && !in_l.full()) {
          in_l.write(left.px[src]);
          in_r.write(right.px[src]);
          ++src;
          progress = true;
        }
        progress |= pump_cost(cost, in_l, in_r, costs);
        progress |= pump([&] { return !agg_.done() && !costs.empty() && !sums.full() && !tee.full(); },
                         [&] { agg_.fire(agg_.plan(), costs, no_sum, sums, tee); });
        while (!sums.empty()) { frame_fwd_[stored_f++] = sums.read(); progress = true; }
        while (!tee.empty()) { frame_cost_[stored_c++] = tee.read(); progress = true; }
        if (!progress) internal_error("func scheduler made no progress (forward pass)");
      }
    }
    agg_.configure(p, kern::stream_kinds(p.path_mask, true), true, false);
    wta_.configure(p, true);
    median_.configure(p);
    Fifo<CostTok> costs("cost_from_ddr", kTokenFifoDepth);
    Fifo<SumTok> fwd("fwd_from_ddr", kTokenFifoDepth), sums("sum", kTokenFifoDepth);
    Fifo<DispCode> disp("disp_lr", kPixelFifoDepth), filtered("disp_out", kPixelFifoDepth);
    kern::NoStream<CostTok> no_cost;
    std::size_t read_tok = 0, dst = 0;
    while (dst < pixels) {
      bool progress = false;
      // Reverse pixel order, ascending chunk order inside a pixel.
      while (read_tok < tokens && !costs.full() && !fwd.full()) {
        const std::size_t pix = pixels - 1 - read_tok / std::size_t(chunks);
        const std::size_t idx = pix * std::size_t(chunks) + read_tok % std::size_t(chunks);
        costs.write(frame_cost_[idx]);
        fwd.write(frame_fwd_[idx]);
        ++read_tok;
        progress = true;
      }
      progress |= pump([&] { return !agg_.done() && !costs.empty() && !fwd.empty() && !sums.full(); },
                       [&] { agg_.fire(agg_.plan(), costs, fwd, sums, no_cost); });
      progress |= pump_wta(sums, disp);
      progress |= pump_median(disp, filtered);
      while (!filtered.empty()) {
        out.code[pixels - 1 - dst++] = filtered.read();
        progress = true;
      }
      if (!progress) internal_error("func scheduler made no progress (backward pass)");
    }
  }

  template <class CostStage>
  bool pump_cost(CostStage& cost, Fifo<uint8_t>& in_l, Fifo<uint8_t>& in_r, Fifo<CostTok>& out) {
    bool fired = false;
    while (!cost.done()) {
      const kern::CostPlan pl = cost.plan();
      if ((pl.read && (in_l.empty() || in_r.empty())) || (pl.write && out.full())) break;
      if (!pl.read && !pl.write) break;
      cost.fire(pl, in_l, in_r, out);
      fired = true;
    }
    return fired;
  }
  bool pump_wta(Fifo<SumTok>& in, Fifo<DispCode>& out) {
    bool fired = false;
    while (!wta_.done()) {
      const kern::WtaPlan pl = wta_.plan();
      if ((pl.read && in.empty()) || (pl.write && out.full())) break;
      wta_.fire(pl, in, out);
      fired = true;
    }
    return fired;
  }
  bool pump_median(Fifo<DispCode>& in, Fifo<DispCode>& out) {
    bool fired = false;
    while (!median_.done()) {
      const kern::MedianPlan pl = median_.plan();
      if ((pl.read && in.empty()) || (pl.write && out.full())) break;
      if (!pl.read && !pl.write) break;
      median_.fire(pl, in, out);
      fired = true;
    }
    return fired;
  }

  kern::CensusCostStage<Caps> census_;
  kern::SadCostStage<Caps> sad_;
  kern::SgmAggregate<Caps, Word> agg_;
  kern::WtaLr<Caps, Word> wta_;
  kern::Median<Caps> median_;
  std::vector<CostTok> frame_cost_;  // the frame buffer standing for off-chip memory
  std::vector<SumTok> frame_fwd_;
};

using Narrow = kern::Caps<kern::kMaxWidthPx, kern::kMaxDisparities, 64>;
using Wide = kern::Caps<kern::kMaxWidthPx, kern::kMaxDisparities, 256>;

int largest_divisor_at_most(int d, int cap) {
  for (int pu = cap < d ? cap : d; pu > 1; --pu)
    if (d % pu == 0) return pu;
  return 1;
}

}  // namespace

std::vector<std::string> func_param_errors(const kern::StereoParams& p) {
  std::vector<std::string> e;
  auto need = [&](bool ok, const char* msg) {
    if (!ok) e.emplace_back(msg);
  };
  need(p.width_px >= 1 && p.width_px <= kern::kMaxWidthPx, "width_px out of [1, 4096]");
  need(p.height_px >= 1 && p.height_px <= kern::kMaxHeightPx, "height_px out of [1, 4096]");
  need(p.disparities >= 1 && p.disparities <= kern::kMaxDisparities, "disparities out of [1, 256]");
  need(p.parallel_units >= 1 && p.disparities % (p.parallel_units > 0 ? p.parallel_units : 1) == 0,
       "parallel_units must divide disparities");
  need(p.window_w % 2 == 1 && p.window_h % 2 == 1 && p.window_w <= kern::kMaxWindow &&
           p.window_h <= kern::kMaxWindow,
       "window sides must be odd and at most 9");
  need(p.cost != kern::kCostCensus || p.window_w * p.window_h - 1 <= kern::kMaxCensusBits,
       "census window needs w*h-1 <= 64");
  need(p.cost == kern::kCostCensus || p.cost == kern::kCostSad, "unknown cost");
  need(p.path_mask != 0 && (p.path_mask & ~kern::kAllPaths) == 0, "path set empty or unknown");
  need(p.p1 >= 0 && p.p1 < p.p2, "need 0 <= p1 < p2");
  need(p.median == 0 || p.median == 1 || p.median == 3 || p.median == 5 || p.median == 7,
       "median must be 0, 3, 5 or 7");
  need(p.lr_tolerance >= 0, "lr_tolerance must be >= 0");
  need(kern::aggregate_bits(p) <= 31, "aggregate wider than 31 bits");
  return e;
}

struct FuncPipeline::Impl {
  std::unique_ptr<Engine<Narrow, uint16_t>> n16;
  std::unique_ptr<Engine<Narrow, uint32_t>> n32;
  std::unique_ptr<Engine<Wide, uint16_t>> w16;
  std::unique_ptr<Engine<Wide, uint32_t>> w32;
};

FuncPipeline::FuncPipeline() : impl_(std::make_unique<Impl>()) {}
FuncPipeline::~FuncPipeline() = default;

DisparityCodes FuncPipeline::run(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p_in,
                                 const FuncOptions& opt) {
  const auto errors = func_param_errors(p_in);
  if (!errors.empty()) internal_error(("invalid parameters reached the func run: " + errors.front()).c_str());
  if (left.width_px != p_in.width_px || left.height_px != p_in.height_px || right.width_px != p_in.width_px ||
      right.height_px != p_in.height_px)
    internal_error("image size differs from the parameters");
  kern::StereoParams p = p_in;
  if (!opt.use_design_pu) p.parallel_units = largest_divisor_at_most(p.disparities, 64);
  const bool wide = p.parallel_units > 64;
  const bool word32 = kern::aggregate_bits(p) > 16;
  auto& i = *impl_;
  if (!wide && !word32) {
    if (!i.n16) i.n16 = std::make_unique<Engine<Narrow, uint16_t>>();
    return i.n16->run(left, right, p);
  }
  if (!wide) {
    if (!i.n32) i.n32 = std::make_unique<Engine<Narrow, uint32_t>>();
    return i.n32->run(left, right, p);
  }
  if (!word32) {
    if (!i.w16) i.w16 = std::make_unique<Engine<Wide, uint16_t>>();
    return i.w16->run(left, right, p);
  }
  if (!i.w32) i.w32 = std::make_unique<Engine<Wide, uint32_t>>();
  return i.w32->run(left, right, p);
}

RectifyOutput run_rectify_func(const GreyImage& in, const std::vector<kern::MapEntry>& map,
                               const kern::RectifyParams& p) {
  if (in.width_px != p.width_px || in.height_px != p.height_px ||
      map.size() != std::size_t(p.width_px) * std::size_t(p.height_px))
    internal_error("rectify: image or map size differs from the parameters");
  if (p.buffer_rows < 1 || p.buffer_rows > kMaxRectifyRows || p.width_px > kern::kMaxWidthPx)
    internal_error("rectify: buffer_rows or width outside the build's capacity");
  using Stage = kern::Rectify<kern::kMaxWidthPx, kMaxRectifyRows>;
  auto stage = std::make_unique<Stage>();
  stage->configure(p);
  Fifo<uint8_t> pix("raw_px", kPixelFifoDepth), out("rect_px", kPixelFifoDepth);
  Fifo<kern::MapEntry> maps("map", kPixelFifoDepth);
  RectifyOutput r;
  r.image.width_px = p.width_px;
  r.image.height_px = p.height_px;
  r.image.px.resize(map.size());
  std::size_t src = 0, map_src = 0, dst = 0;
  while (dst < map.size()) {
    bool progress = false;
    while (src < in.px.size() && !pix.full()) { pix.write(in.px[src++]); progress = true; }
    while (map_src < map.size() && !maps.full()) { maps.write(map[map_src++]); progress = true; }
    progress |= pump(
        [&] {
          if (stage->done()) return false;
          const kern::RectifyPlan pl = stage->plan();
          return !((pl.read_pixel && pix.empty()) || (pl.write && (maps.empty() || out.full())) ||
                   (!pl.read_pixel && !pl.write));
        },
        [&] { stage->fire(stage->plan(), pix, maps, out); });
    while (!out.empty()) { r.image.px[dst++] = out.read(); progress = true; }
    if (!progress) internal_error("func scheduler made no progress (rectify)");
  }
  r.window_misses = stage->window_misses();
  return r;
}

DisparityCodes run_func(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                        const FuncOptions& opt) {
  FuncPipeline pipe;
  return pipe.run(left, right, p, opt);
}

}  // namespace parallax::sim
