// The `func` run: a round-robin dataflow scheduler that fires each kernel while its plan can be
// met. No timing is modelled; FIFOs are small so that the working set stays in cache.
#include "parallax/sim/func.hpp"

#include <cstdio>
#include <atomic>
#include <cstdlib>
#include <memory>
#include <tuple>
#include <type_traits>

#include "design_dispatch.hpp"
#include "engine.hpp"
#include "parallax/fast/engine.hpp"
#include "parallax/kernels/rectify.hpp"
#include "parallax/sim/fifo.hpp"

namespace parallax::sim {
namespace {

using detail::internal_error;

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
constexpr int kMaxRectifyRows = 256;

template <class Caps, class Word>
using Engine = detail::Engine<Caps, Word, false>;
using Narrow = detail::NarrowCaps;
using Wide = detail::WideCaps;

int largest_divisor_at_most(int d, int cap) {
  for (int pu = cap < d ? cap : d; pu > 1; --pu)
    if (d % pu == 0) return pu;
  return 1;
}

std::atomic<FuncEngine>& default_engine_slot() {
  static std::atomic<FuncEngine> slot{FuncEngine::fast};
  return slot;
}

}  // namespace

void set_default_func_engine(FuncEngine e) {
  default_engine_slot().store(e == FuncEngine::automatic ? FuncEngine::fast : e);
}
FuncEngine default_func_engine() {
  return default_engine_slot().load();
}
const char* to_string(FuncEngine e) {
  return e == FuncEngine::kernels ? "kernels" : "fast";
}
bool parse_func_engine(const std::string& name, FuncEngine& out) {
  if (name == "fast")
    out = FuncEngine::fast;
  else if (name == "kernels")
    out = FuncEngine::kernels;
  else
    return false;
  return true;
}
FuncEngine resolve_engine(const FuncOptions& opt) {
  if (opt.use_design_pu) return FuncEngine::kernels;
  return opt.engine == FuncEngine::automatic ? default_func_engine() : opt.engine;
}

// One check for every engine: kern::for_each_param_violation (kernels/param_table.hpp), which
// holds the kernels' own rules too (PU divides D; adaptive P2 in one pass).
std::vector<std::string> func_param_errors(const kern::StereoParams& p) {
  return fast::param_errors(p);
}

struct CostRecording::Impl {
  std::string key;
  FuncEngine engine = FuncEngine::kernels;
  std::vector<kern::CostLanes<Narrow::lanes>> tokens;  // kernels
  fast::CostVolume costs;                              // fast
  fast::AggregateVolume aggregate;                     // fast, kept for the next design
};
CostRecording::CostRecording() : impl(std::make_unique<Impl>()) {}
CostRecording::~CostRecording() = default;
CostRecording::CostRecording(CostRecording&&) noexcept = default;
CostRecording& CostRecording::operator=(CostRecording&&) noexcept = default;

std::string aggregate_sharing_key(const kern::StereoParams& p, FuncEngine engine) {
  FuncOptions o;
  o.engine = engine;
  return resolve_engine(o) == FuncEngine::fast ? fast::aggregate_key(p) : std::string();
}

std::string cost_sharing_key(const kern::StereoParams& p, FuncEngine engine) {
  FuncOptions o;
  o.engine = engine;
  if (resolve_engine(o) == FuncEngine::fast) return fast::cost_key(p);
  // The kernels engine records the first pass's cost tokens: a two-pass design has none to share.
  return kern::two_pass_paths(p.path_mask) ? std::string() : fast::cost_key(p);
}

std::string selection_sharing_key(const kern::StereoParams& p, FuncEngine engine) {
  FuncOptions o;
  o.engine = engine;
  return resolve_engine(o) == FuncEngine::fast ? fast::selection_key(p) : std::string();
}

// One engine per instantiation the func run uses, made on first use and kept (its stages are
// large).
struct FuncPipeline::Impl {
  std::tuple<std::unique_ptr<Engine<Narrow, uint16_t>>, std::unique_ptr<Engine<Narrow, uint32_t>>,
             std::unique_ptr<Engine<Wide, uint16_t>>, std::unique_ptr<Engine<Wide, uint32_t>>>
      engines;
  std::unique_ptr<fast::Engine> fast_engine;
  fast::Engine& fast() {
    if (!fast_engine) fast_engine = std::make_unique<fast::Engine>();
    return *fast_engine;
  }
  template <class Design>
  Engine<typename Design::Caps, typename Design::Word>& engine(Design) {
    using E = Engine<typename Design::Caps, typename Design::Word>;
    std::unique_ptr<E>& e = std::get<std::unique_ptr<E>>(engines);
    if (!e) e = std::make_unique<E>();
    return *e;
  }
};

namespace {
DisparityCodes codes_of(const kern::StereoParams& p, std::vector<uint16_t>&& code) {
  DisparityCodes out;
  out.width_px = p.width_px;
  out.height_px = p.height_px;
  out.disparities = p.disparities;
  out.min_disparity = p.min_disparity;
  out.subpixel_bits = p.subpixel_bits;
  out.code = std::move(code);
  return out;
}
}  // namespace

FuncPipeline::FuncPipeline() : impl_(std::make_unique<Impl>()) {}
FuncPipeline::~FuncPipeline() = default;

DisparityCodes FuncPipeline::run(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p_in,
                                 const FuncOptions& opt) {
  const auto errors = func_param_errors(p_in);
  if (!errors.empty()) internal_error(("invalid parameters reached the func run: " + errors.front()).c_str());
  if (left.width_px != p_in.width_px || left.height_px != p_in.height_px || right.width_px != p_in.width_px ||
      right.height_px != p_in.height_px)
    internal_error("image size differs from the parameters");
  if (resolve_engine(opt) == FuncEngine::fast)
    return codes_of(p_in, impl_->fast().run(left.px.data(), right.px.data(), p_in));
  kern::StereoParams p = p_in;
  if (!opt.use_design_pu) p.parallel_units = largest_divisor_at_most(p.disparities, 64);
  DisparityCodes out;
  detail::dispatch_design<Narrow, Wide>(p.parallel_units, kern::aggregate_bits(p), [&](auto design) {
    impl_->engine(design).run(left, right, p, detail::RunSetup{}, out, nullptr);
  });
  return out;
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
    while (src < in.px.size() && !pix.full()) {
      pix.write(in.px[src++]);
      progress = true;
    }
    while (map_src < map.size() && !maps.full()) {
      maps.write(map[map_src++]);
      progress = true;
    }
    progress |= pump(
        [&] {
          if (stage->done()) return false;
          const kern::RectifyPlan pl = stage->plan();
          return !((pl.read_pixel && pix.empty()) || (pl.write && (maps.empty() || out.full())) ||
                   (!pl.read_pixel && !pl.write));
        },
        [&] { stage->fire(stage->plan(), pix, maps, out); });
    while (!out.empty()) {
      r.image.px[dst++] = out.read();
      progress = true;
    }
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

void FuncPipeline::record_costs(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p_in,
                                CostRecording& rec, const FuncOptions& opt) {
  const auto errors = func_param_errors(p_in);
  if (!errors.empty()) internal_error(("invalid parameters reached record_costs: " + errors.front()).c_str());
  rec.impl->engine = resolve_engine(opt);
  rec.impl->aggregate.key.clear();
  if (rec.impl->engine == FuncEngine::fast) {
    rec.impl->key = fast::cost_key(p_in);
    impl_->fast().record_costs(left.px.data(), right.px.data(), p_in, rec.impl->costs);
    return;
  }
  kern::StereoParams p = p_in;
  p.parallel_units = largest_divisor_at_most(p.disparities, 64);
  rec.impl->key = cost_sharing_key(p_in, FuncEngine::kernels);
  if (rec.impl->key.empty()) internal_error("record_costs: the 8-path variant cannot replay costs");
  impl_->engine(detail::Design<Narrow, uint16_t>{}).record_costs(left, right, p, rec.impl->tokens);
}

std::vector<uint32_t> recorded_cost_volume(const CostRecording& rec, const kern::StereoParams& p) {
  const std::size_t pixels = std::size_t(p.width_px) * std::size_t(p.height_px);
  const std::size_t d_count = std::size_t(p.disparities);
  std::vector<uint32_t> out(pixels * d_count);
  if (rec.impl->engine == FuncEngine::fast) {
    const fast::CostVolume& cv = rec.impl->costs;
    const std::size_t lanes = pixels > 0 ? cv.cost.size() / pixels : 0;
    for (std::size_t i = 0; i < pixels; ++i)
      for (std::size_t d = 0; d < d_count; ++d) out[i * d_count + d] = cv.cost[i * lanes + d];
    return out;
  }
  // The kernels' tokens: per pixel in raster order, D/PU tokens of PU lanes (d = token * PU + lane).
  const std::size_t pu = std::size_t(largest_divisor_at_most(p.disparities, 64));
  const std::size_t per_px = d_count / pu;
  if (rec.impl->tokens.size() != pixels * per_px) internal_error("recorded_cost_volume: the recording is not of p");
  for (std::size_t i = 0; i < pixels; ++i)
    for (std::size_t t = 0; t < per_px; ++t)
      for (std::size_t l = 0; l < pu; ++l) out[i * d_count + t * pu + l] = rec.impl->tokens[i * per_px + t].v[l];
  return out;
}

DisparityCodes FuncPipeline::run_from_costs(CostRecording& rec, const kern::StereoParams& p_in, bool keep_aggregate) {
  const auto errors = func_param_errors(p_in);
  if (!errors.empty()) internal_error(("invalid parameters reached run_from_costs: " + errors.front()).c_str());
  if (rec.impl->engine == FuncEngine::fast) {
    if (rec.impl->key != fast::cost_key(p_in))
      internal_error("run_from_costs: the recording belongs to another cost stage");
    fast::Engine& e = impl_->fast();
    fast::AggregateVolume& agg = rec.impl->aggregate;
    if (agg.key == fast::aggregate_key(p_in)) return codes_of(p_in, e.run_from_aggregate(agg, p_in));
    agg.key.clear();
    if (!keep_aggregate) return codes_of(p_in, e.run_from_costs(rec.impl->costs, p_in));
    e.record_aggregate(rec.impl->costs, p_in, agg);
    return codes_of(p_in, e.run_from_aggregate(agg, p_in));
  }
  if (rec.impl->key.empty() || rec.impl->key != cost_sharing_key(p_in, FuncEngine::kernels))
    internal_error("run_from_costs: the recording belongs to another cost stage");
  kern::StereoParams p = p_in;
  p.parallel_units = largest_divisor_at_most(p.disparities, 64);
  DisparityCodes out;
  detail::dispatch_design<Narrow>(p.parallel_units, kern::aggregate_bits(p),
                                  [&](auto design) { impl_->engine(design).run_from_costs(rec.impl->tokens, p, out); });
  return out;
}

std::vector<uint32_t> FuncPipeline::kernels_aggregate_volume(const GreyImage& left, const GreyImage& right,
                                                             const kern::StereoParams& p_in) {
  const auto errors = func_param_errors(p_in);
  if (!errors.empty())
    internal_error(("invalid parameters reached kernels_aggregate_volume: " + errors.front()).c_str());
  kern::StereoParams p = p_in;
  p.parallel_units = largest_divisor_at_most(p.disparities, 64);
  const std::size_t w = std::size_t(p.width_px), pixels = w * std::size_t(p.height_px);
  const std::size_t pu = std::size_t(p.parallel_units), per_px = std::size_t(p.disparities) / pu;
  // Where the WTA's input runs right to left (kernels/pipeline.hpp): per row after the row
  // reversal, over the whole frame after the frame buffer's reversed read.
  const bool reversed = kern::stage_setup("wta_lr", p.path_mask).reverse;
  const bool whole_frame = kern::two_pass_paths(p.path_mask);
  std::vector<uint32_t> out(pixels * std::size_t(p.disparities));
  detail::dispatch_design<Narrow, Wide>(p.parallel_units, kern::aggregate_bits(p), [&](auto design) {
    auto& e = impl_->engine(design);
    std::vector<typename std::decay_t<decltype(e)>::SumTok> sums;
    e.record_sums(left, right, p, sums);
    if (sums.size() != pixels * per_px) internal_error("kernels_aggregate_volume: the WTA did not get a whole frame");
    for (std::size_t i = 0; i < pixels; ++i) {
      std::size_t px = i;
      if (reversed) px = whole_frame ? pixels - 1 - i : (i / w) * w + (w - 1 - i % w);
      for (std::size_t t = 0; t < per_px; ++t)
        for (std::size_t l = 0; l < pu; ++l)
          out[px * std::size_t(p.disparities) + t * pu + l] = uint32_t(sums[i * per_px + t].v[l]);
    }
  });
  return out;
}

}  // namespace parallax::sim
