// The fast engine's frame driver: cost rows, the raster passes, the WTA per row and the median,
// over the per-level hot loops of isa.cpp. See engine.hpp for the contract.
//
// Contract of this file (what the equivalence tests hold): for every design param_errors()
// accepts, run() returns the golden model's codes (ref::compute_disparity) bit for bit, at any
// SIMD level; record_costs() / record_aggregate() hold the golden cost and aggregate volumes in
// the padded layouts of isa.hpp (tests/models/fast/stage_test.cpp compares them stage by stage).
// Sums are 16-bit unless a path cost, a guard or a sum could exceed 65535 (needs_wide_sums), and
// then 32-bit; lanes are padded to whole vectors only where no real value can reach the padding.
// Memory: the Work rows below are reused between frames (an Engine is one thread's).
#include "parallax/fast/engine.hpp"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "isa.hpp"
#include "parallax/kernels/param_table.hpp"

namespace parallax::fast {
namespace {

using detail::AggregateRow;
using detail::IsaTable;

bool cpu_has_avx512() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
         __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx2") &&
         __builtin_cpu_supports("bmi2") && __builtin_cpu_supports("fma");
}
bool cpu_has_avx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2") &&
         __builtin_cpu_supports("fma") && __builtin_cpu_supports("popcnt") && __builtin_cpu_supports("sse4.2");
}

const IsaTable& pick_isa() {
  const char* forced = std::getenv("PARALLAX_SIMD");
  const std::string want = forced != nullptr ? forced : "";
  if (want.empty())
    return cpu_has_avx512() ? detail::isa_avx512() : cpu_has_avx2() ? detail::isa_avx2() : detail::isa_baseline();
  if (want == "baseline") return detail::isa_baseline();
  if (want == "avx2" && cpu_has_avx2()) return detail::isa_avx2();
  if (want == "avx512" && cpu_has_avx512()) return detail::isa_avx512();
  if (want == "avx2" || want == "avx512")
    throw std::invalid_argument("PARALLAX_SIMD=" + want + ": this CPU does not support it (use baseline, or unset it)");
  throw std::invalid_argument("PARALLAX_SIMD=" + want + ": unknown level (baseline, avx2 or avx512)");
}

std::atomic<const IsaTable*>& isa_slot() {
  static std::atomic<const IsaTable*> slot{nullptr};
  return slot;
}

const IsaTable& isa() {
  const IsaTable* t = isa_slot().load(std::memory_order_acquire);
  if (t == nullptr) {
    t = &pick_isa();
    isa_slot().store(t, std::memory_order_release);
  }
  return *t;
}

std::size_t sz(int64_t v) {
  return static_cast<std::size_t>(v);
}

// 16-bit sums when no path cost, guard or sum can exceed 16 bits (docs §3: L <= cost_max + P2).
bool needs_wide_sums(const kern::StereoParams& p) {
  const int64_t cmax = kern::cost_max(p), p2 = p.p2;
  return !(kern::path_count(p) * (cmax + p2) <= 65535 && cmax + 2 * p2 + p.p1 <= 65535);
}

// Whole-vector lanes (padding, isa.hpp) in the 16-bit engine when no real value can reach the
// padding's range.
int lanes_for(const kern::StereoParams& p) {
  const int64_t cmax = kern::cost_max(p);
  const bool pad = !needs_wide_sums(p) && cmax + 2 * int64_t(p.p2) + p.p1 < detail::kCostPad;
  return pad ? detail::cost_stride(p.disparities) : p.disparities;
}

// Cost rows on demand: row(y) is the [W][cost_stride(D)] row of y, valid until the next call.
struct CostRows {
  virtual ~CostRows() = default;
  virtual const uint16_t* row(int y) = 0;
};

struct StoredCosts final : CostRows {
  const CostVolume& v;
  explicit StoredCosts(const CostVolume& vol) : v(vol) {}
  const uint16_t* row(int y) override {
    return v.cost.data() + sz(int64_t(y) * v.width_px * detail::cost_stride(v.disparities));
  }
};

// The buffers of DirectCosts, kept by the engine from one frame to the next: every element is
// written before it is read (census planes, reversed rows, cost rows; the SAD column sums are
// cleared when a window is summed afresh), so a frame's buffers are only resized, never cleared,
// and a frame of the same size allocates nothing (fresh zeroed pages cost more than the census).
struct CostBuffers {
  std::vector<uint8_t> cl, cr, scratch;
  std::vector<uint16_t> out, sad_cols;
};

// Computes a cost row from the images: census codes of both images once (byte planes,
// isa.hpp), then per row.
struct DirectCosts final : CostRows {
  const kern::StereoParams& p;
  const uint8_t* left;
  const uint8_t* right;
  int planes = 0;
  std::vector<uint8_t>&cl, &cr, &scratch;
  std::vector<uint16_t>&out, &sad_cols;
  int sad_row = -1;  // the row whose window sad_cols holds (-1: none)
  detail::CostRow cr_args;

  DirectCosts(const kern::StereoParams& params, const uint8_t* l, const uint8_t* r, CostBuffers& b)
      : p(params), left(l), right(r), cl(b.cl), cr(b.cr), scratch(b.scratch), out(b.out), sad_cols(b.sad_cols) {
    const int W = p.width_px, H = p.height_px;
    out.resize(sz(int64_t(W) * detail::cost_stride(p.disparities)));
    cr_args.width_px = W;
    cr_args.disparities = p.disparities;
    cr_args.min_disparity = p.min_disparity;
    cr_args.cost_max = static_cast<uint16_t>(kern::cost_max(p));
    cr_args.out = out.data();
    if (p.cost == kern::kCostCensus) {
      planes = detail::census_planes(kern::census_bits(p.census, p.window_w, p.window_h));
      cl.resize(sz(int64_t(W) * H * planes));
      cr.resize(cl.size());
      isa().census(left, W, H, p.window_w, p.window_h, p.census, planes, cl.data());
      isa().census(right, W, H, p.window_w, p.window_h, p.census, planes, cr.data());
      scratch.resize(sz(int64_t(planes) * detail::census_scratch_len(W, p.min_disparity, p.disparities)));
    } else {
      sad_cols.resize(sz(int64_t(W + 2 * (p.window_w / 2)) * detail::cost_stride(p.disparities)));
      scratch.resize(sz(detail::sad_scratch_len(W, p.window_w, p.min_disparity, p.disparities)));
    }
  }
  // SAD: the column sums of row y's window. From the row before or after (the passes run the
  // rows in order), one image row leaves and one enters; else they are summed afresh. The sums
  // are exact integers (at most 255 * window_h), so the order of additions does not matter.
  void sad_window(int y) {
    const int W = p.width_px, H = p.height_px, rh = p.window_h / 2;
    auto add = [&](int yy, int sign) {
      const std::size_t o = sz(int64_t(std::clamp(yy, 0, H - 1)) * W);
      isa().sad_columns(cr_args, left + o, right + o, p.window_w, sign, sad_cols.data(), scratch.data());
    };
    if (sad_row >= 0 && (y == sad_row + 1 || y == sad_row - 1)) {
      const int leaving = y > sad_row ? sad_row - rh : sad_row + rh;
      const int entering = y > sad_row ? y + rh : y - rh;
      if (std::clamp(leaving, 0, H - 1) != std::clamp(entering, 0, H - 1)) {
        add(entering, 1);
        add(leaving, -1);
      }
    } else {
      std::fill(sad_cols.begin(), sad_cols.end(), uint16_t(0));
      for (int j = -rh; j <= rh; ++j) add(y + j, 1);
    }
    sad_row = y;
  }
  const uint16_t* row(int y) override { return row_into(y, out.data()); }
  // Row y's costs written straight into dst (W x cost_stride lanes, every one of them written).
  const uint16_t* row_into(int y, uint16_t* dst) {
    const int W = p.width_px;
    cr_args.out = dst;
    if (p.cost == kern::kCostCensus) {
      const std::size_t o = sz(int64_t(y) * W * planes);
      isa().cost_census(cr_args, cl.data() + o, cr.data() + o, planes, scratch.data());
    } else {
      sad_window(y);
      isa().sad_box(cr_args, p.window_w, sad_cols.data());
    }
    cr_args.out = out.data();
    return dst;
  }
};

// The recursions of one pass over stream paths (bits 0, 45, 90, 135 in stream terms): SGM runs
// one recursion per path; MGM one per pair (0/90 as the pixel kind, 45/135 as the row kind), its
// weight the number of the pair's paths in the design (each adds the pair's Lr once).
struct PassPlan {
  int n = 0;
  int kind[4] = {0, 0, 0, 0};
  int weight[4] = {1, 1, 1, 1};
};
PassPlan plan_pass(unsigned stream_mask, bool mgm) {
  PassPlan pl;
  if (!mgm) {
    for (int b = 0; b < 4; ++b)
      if ((stream_mask >> b) & 1u) pl.kind[pl.n++] = b;
    return pl;
  }
  const int pixel = int((stream_mask >> 0) & 1u) + int((stream_mask >> 2) & 1u);
  const int rowk = int((stream_mask >> 1) & 1u) + int((stream_mask >> 3) & 1u);
  if (pixel > 0) {
    pl.kind[pl.n] = detail::kMgmPixel;
    pl.weight[pl.n++] = pixel;
  }
  if (rowk > 0) {
    pl.kind[pl.n] = detail::kMgmRow;
    pl.weight[pl.n++] = rowk;
  }
  return pl;
}

// The median's network (detail::make_median_net) as the (i, j) pair list median_row takes.
std::vector<int16_t> median_network(int taps) {
  const detail::MedianNet net = detail::make_median_net(taps);
  std::vector<int16_t> pairs;
  for (int c = 0; c < net.n; ++c) {
    pairs.push_back(net.lo[c]);
    pairs.push_back(net.hi[c]);
  }
  return pairs;
}

// One engine's row buffers for one sum type: the previous and the current stream row of path
// costs of a pass's (up to) four recursions, interleaved per pixel ([W][4][lanes + 2], guards at
// both ends of each, isa.hpp Recursion), and their per-pixel minima ([W][4]); the same of the
// one-pass 180-degree path ([W][lanes + 2], [W]); the sums of
// a row (or, for two passes, of the whole frame, since pass 2 adds to pass 1's); the WTA's
// right-image candidates and codes.
template <class T>
struct Work {
  std::vector<T> rows[2], mins[2];  // by row parity
  std::vector<T> rows180[2], mins180[2];
  std::vector<T> sum_row, sum_frame, right_best;
  std::vector<uint16_t> right_code;
  std::vector<int32_t> left_code, offset;
};

}  // namespace

struct Engine::Impl {
  Work<uint16_t> w16;
  Work<uint32_t> w32;
  CostBuffers costs;
  std::vector<uint16_t> taps, median_out;
  std::vector<int16_t> network[8];  // by k

  template <class T>
  Work<T>& work();

  // Runs the passes over `src`, handing each finished aggregate row (y, S row) to sink.
  template <class T, class Sink>
  void aggregate(CostRows& src, const uint8_t* left, const kern::StereoParams& p, Sink&& sink);
  // One row's codes from its finished sums [W][lanes]: the WTA (ties to the smaller d), the
  // uniqueness margin, the sub-pixel fraction and the LR check against the row's right-image
  // winners, exactly as ref::select_disparity does for that row.
  template <class T>
  void select(const T* sum_row, const kern::StereoParams& p, uint16_t* out_row);
  template <class T>
  std::vector<uint16_t> run_rows(CostRows& src, const uint8_t* left, const kern::StereoParams& p);
  // The k x k median in place (k = p.median; 0 and 1 leave the codes), the clamp border, by the
  // pruned sorting network of detail::make_median_net(): ref::median_filter's codes.
  void median(std::vector<uint16_t>& codes, const kern::StereoParams& p);
};

template <>
Work<uint16_t>& Engine::Impl::work<uint16_t>() {
  return w16;
}
template <>
Work<uint32_t>& Engine::Impl::work<uint32_t>() {
  return w32;
}

namespace {
// Points the hot loop's recursions at the row buffers: `parity` (y & 1) selects which of the two
// rows is this row's, the other holds the previous stream row.
template <class T>
void fill_recursions(AggregateRow& a, const PassPlan& pl, Work<T>& w, int parity) {
  const int P = a.lanes + 2;
  a.recursions = pl.n;
  for (int k = 0; k < pl.n; ++k) {
    a.rec[k].kind = pl.kind[k];
    a.rec[k].weight = pl.weight[k];
    a.rec[k].cur = w.rows[parity].data() + k * P;
    a.rec[k].prev = w.rows[1 - parity].data() + k * P;
    a.rec[k].stride = 4 * P;
    a.rec[k].cur_min = w.mins[parity].data() + k;
    a.rec[k].prev_min = w.mins[1 - parity].data() + k;
    a.rec[k].min_stride = 4;
  }
}
// Every path-cost slot's two guards (the type's maximum minus P1, isa.hpp): written once a frame,
// the recursions write only the lanes between them.
template <class T>
void write_guards(std::vector<T>& row, int lanes, int p1) {
  const T guard = static_cast<T>(static_cast<T>(~T(0)) - static_cast<T>(p1));
  const std::size_t P = sz(lanes + 2);
  for (std::size_t o = 0; o < row.size(); o += P) {
    row[o] = guard;
    row[o + P - 1] = guard;
  }
}
template <class T>
void call_aggregate(const AggregateRow& a);
template <>
void call_aggregate<uint16_t>(const AggregateRow& a) {
  isa().aggregate16(a);
}
template <>
void call_aggregate<uint32_t>(const AggregateRow& a) {
  isa().aggregate32(a);
}
}  // namespace

namespace {
// Padding lanes of finished sums at the type's maximum (what the WTA expects, isa.hpp).
template <class T>
void clear_padding(T* sum, int width_px, int disparities, int lanes) {
  if (lanes == disparities) return;
  if constexpr (sizeof(T) == 2) {
    isa().pad_sums16(sum, width_px, disparities, lanes);
    return;
  }
  for (int x = 0; x < width_px; ++x) {
    T* s = sum + sz(int64_t(x) * lanes);
    for (int d = disparities; d < lanes; ++d) s[d] = static_cast<T>(~T(0));
  }
}
}  // namespace

template <class T, class Sink>
void Engine::Impl::aggregate(CostRows& src, const uint8_t* left, const kern::StereoParams& p, Sink&& sink) {
  const int W = p.width_px, H = p.height_px, N = lanes_for(p);
  const std::size_t row_len = sz(int64_t(W) * N);
  Work<T>& w = work<T>();
  for (int parity = 0; parity < 2; ++parity) {
    w.rows[parity].resize(sz(int64_t(W) * 4 * (N + 2)));
    w.rows180[parity].resize(sz(int64_t(W) * (N + 2)));
    w.mins[parity].resize(sz(int64_t(W) * 4));
    w.mins180[parity].resize(sz(W));
    write_guards(w.rows[parity], N, p.p1);
    write_guards(w.rows180[parity], N, p.p1);
  }
  const bool mgm = p.aggregation == kern::kAggregationMgm;
  const bool two_pass = kern::two_pass_paths(p.path_mask), reverse_row = kern::row_reverse_paths(p.path_mask);
  const PassPlan fwd = plan_pass(p.path_mask & kern::kForwardPaths, mgm);
  const PassPlan bwd = plan_pass((p.path_mask & kern::kBackwardPaths) >> 4, mgm);
  w.sum_row.resize(row_len);
  if (two_pass) w.sum_frame.resize(row_len * sz(H));
  AggregateRow a;
  a.width_px = W;
  a.disparities = p.disparities;
  a.lanes = N;
  a.cost_stride = detail::cost_stride(p.disparities);
  a.p1 = p.p1;
  a.p2 = p.p2;
  a.p2_adaptive = p.p2_adaptive;
  for (int y = 0; y < H; ++y) {
    T* sum = two_pass ? w.sum_frame.data() + row_len * sz(y) : w.sum_row.data();
    a.dir = 1;
    a.first_row = y == 0;
    a.cost = src.row(y);
    a.intensity = left + sz(int64_t(y) * W);
    a.prev_intensity = y > 0 ? left + sz(int64_t(y - 1) * W) : nullptr;
    a.accumulate = false;
    a.sum = sum;
    fill_recursions(a, fwd, w, y & 1);
    if (fwd.n > 0) call_aggregate<T>(a);
    if (reverse_row) {  // the 180-degree path along the finished row (docs §7)
      AggregateRow h = a;
      h.dir = -1;
      h.first_row = true;
      h.accumulate = fwd.n > 0;
      h.recursions = 1;
      h.rec[0].kind = detail::kSgm0;
      h.rec[0].weight = 1;
      h.rec[0].cur = w.rows180[0].data();
      h.rec[0].prev = w.rows180[1].data();
      h.rec[0].stride = N + 2;
      h.rec[0].cur_min = w.mins180[0].data();
      h.rec[0].prev_min = w.mins180[1].data();
      h.rec[0].min_stride = 1;
      call_aggregate<T>(h);
    }
    if (!two_pass) {
      clear_padding<T>(sum, W, p.disparities, N);
      sink(y, static_cast<const T*>(sum));
    }
  }
  if (!two_pass) return;
  for (int y = H - 1; y >= 0; --y) {
    T* sum = w.sum_frame.data() + row_len * sz(y);
    a.dir = -1;
    a.first_row = y == H - 1;
    a.cost = src.row(y);
    a.intensity = left + sz(int64_t(y) * W);
    a.prev_intensity = y < H - 1 ? left + sz(int64_t(y + 1) * W) : nullptr;
    a.accumulate = fwd.n > 0;
    a.sum = sum;
    fill_recursions(a, bwd, w, y & 1);
    call_aggregate<T>(a);
    clear_padding<T>(sum, W, p.disparities, N);
    sink(y, static_cast<const T*>(sum));
  }
}

template <class T>
void Engine::Impl::select(const T* sum_row, const kern::StereoParams& p, uint16_t* out_row) {
  const int W = p.width_px;
  Work<T>& w = work<T>();
  const int N = lanes_for(p);
  const std::size_t rlen = sz(int64_t(W) + N + p.min_disparity + 1);
  w.right_best.resize(rlen);
  w.right_code.resize(rlen);
  w.left_code.resize(sz(W));
  w.offset.resize(sz(W));
  detail::SelectRow s;
  s.width_px = W;
  s.disparities = p.disparities;
  s.lanes = N;
  s.min_disparity = p.min_disparity;
  s.subpixel_bits = p.subpixel_bits;
  s.lr_check = p.lr_check;
  s.lr_tolerance = p.lr_tolerance;
  s.uniqueness_pct = p.uniqueness_pct;
  s.sum = sum_row;
  s.right_best = w.right_best.data();
  s.right_code = w.right_code.data();
  s.left_code = w.left_code.data();
  s.offset = w.offset.data();
  s.out = out_row;
  if constexpr (sizeof(T) == 2)
    isa().select16(s);
  else
    isa().select32(s);
}

void Engine::Impl::median(std::vector<uint16_t>& codes, const kern::StereoParams& p) {
  const int k = p.median;
  if (k <= 1) return;
  const int W = p.width_px, H = p.height_px, rk = k / 2, rank = (k * k - 1) / 2;
  std::vector<int16_t>& net = network[k];
  if (net.empty()) net = median_network(k * k);
  taps.resize(sz(int64_t(k) * k * W));
  std::vector<uint16_t>& out = median_out;  // every element written below
  out.resize(codes.size());
  const uint16_t* rows[7];
  for (int y = 0; y < H; ++y) {
    for (int j = 0; j < k; ++j) rows[j] = codes.data() + sz(int64_t(std::clamp(y + j - rk, 0, H - 1)) * W);
    isa().median_row(rows, W, k, net.data(), static_cast<int>(net.size() / 2), rank, taps.data(),
                     out.data() + sz(int64_t(y) * W));
  }
  codes.swap(out);
}

template <class T>
std::vector<uint16_t> Engine::Impl::run_rows(CostRows& src, const uint8_t* left, const kern::StereoParams& p) {
  std::vector<uint16_t> codes(sz(int64_t(p.width_px) * p.height_px));
  aggregate<T>(src, left, p,
               [&](int y, const T* sum) { select<T>(sum, p, codes.data() + sz(int64_t(y) * p.width_px)); });
  median(codes, p);
  return codes;
}

std::vector<std::string> param_errors(const kern::StereoParams& p) {
  std::vector<std::string> e;
  kern::for_each_param_violation(p, [&](const kern::ParamViolation& v) {
    if (v.rule < 0)
      e.push_back(std::string(v.field.name) + " out of [" + std::to_string(v.field.lo) + ", " +
                  std::to_string(v.field.hi) + "] (got " + std::to_string(v.field.value) + ")");
    else
      e.emplace_back(v.requires_text);
  });
  return e;
}

namespace {
void check(const kern::StereoParams& p) {
  const auto e = param_errors(p);
  if (!e.empty()) throw std::invalid_argument("fast engine: " + e.front());
}
}  // namespace

const char* simd_level() {
  return isa().name;
}

std::vector<std::string> supported_simd_levels() {
  std::vector<std::string> v{"baseline"};
  if (cpu_has_avx2()) v.emplace_back("avx2");
  if (cpu_has_avx512()) v.emplace_back("avx512");
  return v;
}

void set_simd_level(const std::string& name) {
  if (name == "baseline")
    isa_slot().store(&detail::isa_baseline());
  else if (name == "avx2" && cpu_has_avx2())
    isa_slot().store(&detail::isa_avx2());
  else if (name == "avx512" && cpu_has_avx512())
    isa_slot().store(&detail::isa_avx512());
  else
    throw std::invalid_argument("SIMD level '" + name + "' is unknown or not supported by this CPU");
}

std::string stage_key(const kern::StereoParams& p, unsigned stage) {
  const unsigned upstream = kern::readers_up_to(stage);
  std::string key;
  kern::for_each_param(p, [&](const kern::ParamField& f) {
    if ((f.readers & upstream) != 0)
      key += std::string(key.empty() ? "" : " ") + f.name + "=" + std::to_string(f.value);
  });
  return key;
}

std::string cost_key(const kern::StereoParams& p) {
  return stage_key(p, kern::kReadByCost);
}

std::string aggregate_key(const kern::StereoParams& p) {
  return stage_key(p, kern::kReadByAggregate);
}

std::string selection_key(const kern::StereoParams& p) {
  return stage_key(p, kern::kReadBySelect);
}

Engine::Engine() : impl_(std::make_unique<Impl>()) {}
Engine::~Engine() = default;

std::vector<uint16_t> Engine::run(const uint8_t* left, const uint8_t* right, const kern::StereoParams& p) {
  check(p);
  DirectCosts src(p, left, right, impl_->costs);
  return needs_wide_sums(p) ? impl_->run_rows<uint32_t>(src, left, p) : impl_->run_rows<uint16_t>(src, left, p);
}

void Engine::record_costs(const uint8_t* left, const uint8_t* right, const kern::StereoParams& p, CostVolume& out) {
  check(p);
  DirectCosts src(p, left, right, impl_->costs);
  const std::size_t row_len = sz(int64_t(p.width_px) * detail::cost_stride(p.disparities));
  out.key = cost_key(p);
  out.width_px = p.width_px;
  out.height_px = p.height_px;
  out.disparities = p.disparities;
  out.cost.resize(row_len * sz(p.height_px));
  for (int y = 0; y < p.height_px; ++y) (void)src.row_into(y, out.cost.data() + row_len * sz(y));
  out.left.assign(left, left + sz(int64_t(p.width_px) * p.height_px));
}

std::vector<uint16_t> Engine::run_from_costs(const CostVolume& costs, const kern::StereoParams& p) {
  check(p);
  if (costs.key != cost_key(p))
    throw std::invalid_argument("run_from_costs: the costs are of '" + costs.key + "', the design needs '" +
                                cost_key(p) + "'");
  StoredCosts src(costs);
  return needs_wide_sums(p) ? impl_->run_rows<uint32_t>(src, costs.left.data(), p)
                            : impl_->run_rows<uint16_t>(src, costs.left.data(), p);
}

void Engine::record_aggregate(const CostVolume& costs, const kern::StereoParams& p, AggregateVolume& out) {
  check(p);
  if (costs.key != cost_key(p))
    throw std::invalid_argument("record_aggregate: the costs are of '" + costs.key + "', the design needs '" +
                                cost_key(p) + "'");
  StoredCosts src(costs);
  const std::size_t row_len = sz(int64_t(p.width_px) * lanes_for(p));
  out.key = aggregate_key(p);
  out.selected_key.clear();
  out.width_px = p.width_px;
  out.height_px = p.height_px;
  out.disparities = p.disparities;
  out.wide = needs_wide_sums(p);
  if (out.wide) {
    out.sum16.clear();
    out.sum32.resize(row_len * sz(p.height_px));
    impl_->aggregate<uint32_t>(src, costs.left.data(), p, [&](int y, const uint32_t* s) {
      std::memcpy(out.sum32.data() + row_len * sz(y), s, row_len * 4);
    });
  } else {
    out.sum32.clear();
    out.sum16.resize(row_len * sz(p.height_px));
    impl_->aggregate<uint16_t>(src, costs.left.data(), p, [&](int y, const uint16_t* s) {
      std::memcpy(out.sum16.data() + row_len * sz(y), s, row_len * 2);
    });
  }
}

std::vector<uint16_t> Engine::run_from_aggregate(AggregateVolume& agg, const kern::StereoParams& p) {
  check(p);
  if (agg.key != aggregate_key(p))
    throw std::invalid_argument("run_from_aggregate: the sums are of '" + agg.key + "', the design needs '" +
                                aggregate_key(p) + "'");
  const int W = p.width_px;
  const std::string sel = selection_key(p);
  if (agg.selected_key != sel) {
    const std::size_t row_len = sz(int64_t(W) * lanes_for(p));
    agg.selected.resize(sz(int64_t(W) * p.height_px));
    for (int y = 0; y < p.height_px; ++y) {
      if (agg.wide)
        impl_->select<uint32_t>(agg.sum32.data() + row_len * sz(y), p, agg.selected.data() + sz(int64_t(y) * W));
      else
        impl_->select<uint16_t>(agg.sum16.data() + row_len * sz(y), p, agg.selected.data() + sz(int64_t(y) * W));
    }
    agg.selected_key = sel;
  }
  std::vector<uint16_t> codes = agg.selected;
  impl_->median(codes, p);
  return codes;
}

}  // namespace parallax::fast
