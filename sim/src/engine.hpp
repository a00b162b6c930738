// Internal: the pipeline assembly both runs share. Engine<Caps, Word, kTimed, kData> owns the
// kernels of kernels/ and wires them into the dataflow graph of one design (source -> cost ->
// aggregate -> WTA/LR -> median -> sink, or the two passes of the 8-path variant through the
// frame buffer of frame_buffer_stages.hpp), with the FIFOs and stages the pipeline table
// (kernels/pipeline.hpp) names, in its order; each stage's pump fires its kernel while the
// kernel's plan can be met. The run around it (options, report, input timing) is
// pipeline_run.hpp's, the scheduling scheduler.hpp's. kTimed = false is the func run (fire
// whenever the plan can be met); kTimed = true is the cycle model (fire at the earliest cycle
// the plan, II, token visibility and FIFO space allow). kData = false is the timing run: the
// disparity stages execute their control path only (plan() and step(), never the datapath) and
// the FIFOs carry tokens without payload; the front end (source, maps, rectification) still
// moves pixels. Plans depend on counters only, never on values, so the timing run's schedule
// equals the full run's (tested). Which Caps and Word run a design: design_dispatch.hpp.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "fast_forward.hpp"
#include "frame_buffer_stages.hpp"
#include "internal_error.hpp"
#include "parallax/kernels/census.hpp"
#include "parallax/kernels/frame_buffer.hpp"
#include "parallax/kernels/median.hpp"
#include "parallax/kernels/pipeline.hpp"
#include "parallax/kernels/rectify.hpp"
#include "parallax/kernels/row_reverse.hpp"
#include "parallax/kernels/sad.hpp"
#include "parallax/kernels/sgm.hpp"
#include "parallax/kernels/wta_lr.hpp"
#include "parallax/sim/cycle.hpp"
#include "parallax/sim/fifo.hpp"
#include "parallax/sim/func.hpp"
#include "pipeline_run.hpp"
#include "scheduler.hpp"

namespace parallax::sim::detail {

// One firing of a stage in a counting instantiation (kernels/access.hpp): the accesses of the
// kernel's arrays in between are that firing's. Nothing in the other instantiations.
template <bool kCount>
struct FiringScope {
  explicit FiringScope(const std::string&) {}
};
template <>
struct FiringScope<true> : kern::AccessFiring {
  explicit FiringScope(const std::string& stage) : kern::AccessFiring(stage.c_str()) {}
};

template <class Caps, class Word, bool kTimed, bool kData = true>
class Engine : private PipelineRun<kTimed> {
  using Run = PipelineRun<kTimed>;
  using Run::begin, Run::frame_pixels, Run::depth_of, Run::rectifying, Run::input_arrival, Run::ddr_rate,
      Run::ddr_latency_cycles, Run::schedule, Run::mark_done, Run::collect, Run::finish_report;
  using Run::p_, Run::setup_, Run::rep_, Run::timing_, Run::trace_, Run::graph_, Run::conditions_, Run::input_rate_;

 public:
  using CostTok = kern::CostLanes<Caps::lanes>;
  using SumTok = kern::Lanes<Word, Caps::lanes>;
  using NodeT = Node<kTimed>;

  void run(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p, const RunSetup& setup,
           DisparityCodes& out, CycleReport* rep) {
    begin(p, setup, rep);
    out.width_px = p.width_px;
    out.height_px = p.height_px;
    out.disparities = p.disparities;
    out.min_disparity = p.min_disparity;
    out.subpixel_bits = p.subpixel_bits;
    if (kData) out.code.assign(std::size_t(p.width_px) * p.height_px, 0);
    const bool two_pass = kern::two_pass_paths(p.path_mask);
    if (p.cost == kern::kCostCensus)
      two_pass ? run_two_pass(census_, left, right, out) : run_one_pass(census_, left, right, out);
    else
      two_pass ? run_two_pass(sad_, left, right, out) : run_one_pass(sad_, left, right, out);
    if (rep_) finish_report();
  }

  // Func run only (work sharing in sweeps): the matching-cost tokens of one frame, the cost
  // stage alone; and the rest of a one-pass pipeline fed with such tokens. Designs that share
  // cost, window and disparities (so the same lanes) share the tokens: a penalty sweep computes
  // them once per frame. run_from_costs gives the codes of run() (tested).
  void record_costs(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                    std::vector<CostTok>& tokens) {
    static_assert(!kTimed && kData, "cost recording belongs to the func run");
    begin(p, RunSetup{}, nullptr);
    tokens.clear();
    tokens.reserve(std::size_t(frame_pixels()) * std::size_t(p.disparities / p.parallel_units));
    if (p.cost == kern::kCostCensus)
      record_with(census_, left, right, tokens);
    else
      record_with(sad_, left, right, tokens);
  }
  // Func run only (the per-stage equality tests, issue 43): the sum tokens the WTA stage would
  // read for this frame, in the order the variant streams them (stage_setup("wta_lr").reverse:
  // each row reversed after row_reverse, the whole frame after the frame buffer; a pixel's tokens
  // always in ascending chunk order). The WTA, median and sink do not run.
  void record_sums(const GreyImage& left, const GreyImage& right, const kern::StereoParams& p,
                   std::vector<SumTok>& sums) {
    static_assert(!kTimed && kData, "sum recording belongs to the func run");
    sums.clear();
    sums.reserve(std::size_t(p.width_px) * std::size_t(p.height_px) * std::size_t(p.disparities / p.parallel_units));
    sum_tap_ = &sums;
    DisparityCodes unused;
    run(left, right, p, RunSetup{}, unused, nullptr);
    sum_tap_ = nullptr;
  }

  void run_from_costs(const std::vector<CostTok>& tokens, const kern::StereoParams& p, DisparityCodes& out) {
    static_assert(!kTimed && kData, "cost replay belongs to the func run");
    begin(p, RunSetup{}, nullptr);
    out.width_px = p.width_px;
    out.height_px = p.height_px;
    out.disparities = p.disparities;
    out.min_disparity = p.min_disparity;
    out.subpixel_bits = p.subpixel_bits;
    out.code.assign(std::size_t(frame_pixels()), 0);
    if (kern::two_pass_paths(p.path_mask) ||
        tokens.size() != std::size_t(frame_pixels()) * std::size_t(p.disparities / p.parallel_units))
      internal_error("run_from_costs: a one-pass design and the tokens of its cost stage are needed");
    auto costs = make_graph_fifo<CostTok>("cost", kTokenDepth, "replay", "aggregate");
    NodeT& n_rep = node("replay");
    int64_t got = 0;
    const std::unique_ptr<BackEnd> be = one_pass_back_end(*costs, out, got);
    std::size_t next = 0;
    auto replay = [&]() -> bool {
      bool fired = false;
      while (next < tokens.size()) {
        if (!n_rep.attempt({}, {Port{costs.get(), true}}, [&] { costs->write(tokens[next]); })) break;
        ++next;
        fired = true;
      }
      return fired;
    };
    const int64_t total = frame_pixels();
    std::vector<std::function<bool()>> pumps = {replay};
    pumps.insert(pumps.end(), be->pumps.begin(), be->pumps.end());
    schedule(pumps, [&] { return got >= total; });
  }

 private:
  template <class CostStage>
  void record_with(CostStage& cost, const GreyImage& left, const GreyImage& right, std::vector<CostTok>& tokens) {
    cost.configure(p_);
    std::unique_ptr<FrontEnd> fe = front_end(left, right);
    auto costs = make_graph_fifo<CostTok>("cost", kTokenDepth, "cost", "recorder");
    NodeT& n_cost = node("cost");
    auto record = [&]() -> bool {
      bool fired = false;
      while (!costs->empty()) {
        tokens.push_back(costs->read());
        fired = true;
      }
      return fired;
    };
    std::vector<std::function<bool()>> pumps = fe->pumps;
    pumps.push_back(cost_pump(n_cost, cost, *fe->out_l, *fe->out_r, *costs));
    pumps.push_back(record);
    schedule(pumps, [&] { return cost.done() && costs->empty(); });
  }

  // A FIFO of the pipeline (kernels/pipeline.hpp): producer and consumer come from the table.
  template <class T>
  std::unique_ptr<Fifo<T>> make_fifo(const std::string& name, std::size_t func_depth) {
    const kern::PipelineFifo* d = kern::pipeline_fifo(name.c_str(), conditions_);
    if (!d) internal_error("FIFO '" + name + "' is not in this variant of the pipeline table (kernels/pipeline.hpp)");
    return make_graph_fifo<T>(name, func_depth, d->producer, d->consumer);
  }
  // A FIFO of the simulator's own cost recording and replay, which are not pipeline stages.
  template <class T>
  std::unique_ptr<Fifo<T>> make_graph_fifo(const std::string& name, std::size_t func_depth, const std::string& producer,
                                           const std::string& consumer) {
    auto f = std::make_unique<Fifo<T>>(name, depth_of(name, func_depth), kTimed);
    graph_->add_fifo(f.get(), producer, consumer);
    return f;
  }
  // A stage of the pipeline table (or the recording's own "replay" and "recorder").
  NodeT& node(const std::string& name) {
    bool known = name == "replay" || name == "recorder";
    for (const kern::PipelineStage& st : kern::kPipelineStages)
      known = known || (name == st.name && kern::pipeline_has(st.when, conditions_));
    if (!known)
      internal_error("stage '" + name + "' is not in this variant of the pipeline table (kernels/pipeline.hpp)");
    const auto it = timing_.find(name);
    return graph_->add_node(name, it != timing_.end() ? it->second : StageTiming{});
  }

  // --- pumps: fire a stage while it can ---------------------------------------------------

  // The source streams the left and right images in raster order, pixel i no earlier than it
  // arrives (input_arrival); a camera pixel that finds no room is an overrun (the first one is
  // reported). It stops after truncate_input_px pixels when that is set.
  std::function<bool()> source_pump(NodeT& n, const GreyImage& left, const GreyImage& right, Fifo<uint8_t>& l,
                                    Fifo<uint8_t>& r, int64_t& next) {
    int64_t total = int64_t(left.px.size());
    if (kTimed && setup_.opt && setup_.opt->truncate_input_px >= 0)
      total = std::min(total, setup_.opt->truncate_input_px);
    return [this, &n, &left, &right, &l, &r, &next, total] {
      bool fired = false;
      if (n.still_blocked()) return false;
      while (next < total) {
        const int64_t i = next;
        if (!n.attempt(
                {}, {Port{&l, true}, Port{&r, true}},
                [&] {
                  l.write(left.px[std::size_t(i)]);
                  r.write(right.px[std::size_t(i)]);
                },
                input_arrival(i)))
          break;
        if (kTimed && rep_ && setup_.opt->input == InputKind::camera && rep_->input_overrun.empty() &&
            n.report().last_fire_cycle > input_arrival(i))
          rep_->input_overrun = "camera overrun: pixel " + std::to_string(i) + " arrived at cycle " +
                                std::to_string(input_arrival(i)) + " but FIFO '" + l.name() +
                                "' had room only at cycle " + std::to_string(n.report().last_fire_cycle);
        ++next;
        fired = true;
      }
      if (next >= total) mark_done("source");
      return fired;
    };
  }

  template <class CostStage>
  std::function<bool()> cost_pump(NodeT& n, CostStage& cost, Fifo<uint8_t>& l, Fifo<uint8_t>& r, Fifo<CostTok>& out) {
    return [&n, &cost, &l, &r, &out] {
      bool fired = false;
      if (n.still_blocked()) return false;
      while (!cost.done()) {
        const kern::CostPlan pl = cost.plan();
        if (!pl.read && !pl.write && !pl.prime) break;
        if (!n.attempt({Port{&l, pl.read}, Port{&r, pl.read}}, {Port{&out, pl.write}}, [&] {
              if constexpr (kData) {
                const FiringScope<Caps::count_accesses> scope(n.name());
                cost.fire(pl, l, r, out);
              } else {
                cost.step(pl);
                if (pl.write) out.skip_write();
                if (pl.read) {
                  l.skip_read();
                  r.skip_read();
                }
              }
            }))
          break;
        fired = true;
      }
      return fired;
    };
  }

  template <class CostIn, class FwdIn, class SumOut, class TeeOut>
  std::function<bool()> agg_pump(NodeT& n, CostIn& c, FwdIn* f, SumOut& s, TeeOut* t) {
    return agg_pump_of(agg_, n, c, f, s, t);
  }
  // The same for any aggregation stage (its row memories take one read and one write per firing,
  // a word per chunk: no port conflict beyond the stage's II).
  template <class Agg, class CostIn, class FwdIn, class SumOut, class TeeOut>
  std::function<bool()> agg_pump_of(Agg& agg, NodeT& n, CostIn& c, FwdIn* f, SumOut& s, TeeOut* t) {
    return [&agg, &n, &c, f, &s, t]() mutable {
      bool fired = false;
      if (n.still_blocked()) return false;
      kern::NoStream<SumTok> no_sum;
      kern::NoStream<CostTok> no_cost;
      while (!agg.done()) {
        const kern::AggPlan pl = agg.plan();
        const bool ok =
            n.attempt({Port{&c, true}, Port{f, f != nullptr}}, {Port{&s, true}, Port{t, t != nullptr}}, [&] {
              const FiringScope<Caps::count_accesses> scope(n.name());
              if constexpr (!kData) {
                agg.step(pl);
                c.skip_read();
                if (f) f->skip_read();
                s.skip_write();
                if (t) t->skip_write();
              } else if (f && t)
                agg.fire(pl, c, *f, s, *t);
              else if (f)
                agg.fire(pl, c, *f, s, no_cost);
              else if (t)
                agg.fire(pl, c, no_sum, s, *t);
              else
                agg.fire(pl, c, no_sum, s, no_cost);
            });
        if (!ok) break;
        fired = true;
      }
      return fired;
    };
  }

  // A stage with one input and one output stream (WTA/LR, median): fires while its plan can be
  // met; the timing run executes the control path only.
  template <class Stage, class In, class Out>
  std::function<bool()> io_pump(NodeT& n, Stage& st, Fifo<In>& in, Fifo<Out>& out) {
    return [&n, &st, &in, &out] {
      bool fired = false;
      if (n.still_blocked()) return false;
      while (!st.done()) {
        const auto pl = st.plan();
        if (!pl.read && !pl.write && !pl.prime) break;
        if (!n.attempt({Port{&in, pl.read}}, {Port{&out, pl.write}}, [&] {
              if constexpr (kData) {
                const FiringScope<Caps::count_accesses> scope(n.name());
                st.fire(pl, in, out);
              } else {
                st.step(pl);
                if (pl.read) in.skip_read();
                if (pl.write) out.skip_write();
              }
            }))
          break;
        fired = true;
      }
      return fired;
    };
  }
  // The WTA stage, or with record_sums() the recorder in its place: it takes every sum token and
  // counts a pixel in `got` with the pixel's last token, so the run ends as the sink would end it.
  std::function<bool()> wta_pump(NodeT& n, Fifo<SumTok>& in, Fifo<kern::DispCode>& out, int64_t& got) {
    if (!sum_tap_) return io_pump(n, wta_, in, out);
    const std::size_t per_px = std::size_t(p_.disparities / p_.parallel_units);
    return [this, &in, &got, per_px] {
      bool fired = false;
      while (!in.empty()) {
        sum_tap_->push_back(in.read());
        if (sum_tap_->size() % per_px == 0) ++got;
        fired = true;
      }
      return fired;
    };
  }
  std::function<bool()> median_pump(NodeT& n, Fifo<kern::DispCode>& in, Fifo<kern::DispCode>& out) {
    return io_pump(n, median_, in, out);
  }
  std::function<bool()> unreverse_pump(NodeT& n, Fifo<kern::DispCode>& in, Fifo<kern::DispCode>& out) {
    return io_pump(n, code_rev_, in, out);
  }
  // The row reversal of costs and forward sums: both streams in, both out, one token of each.
  std::function<bool()> row_reverse_pump(NodeT& n, Fifo<CostTok>& ci, Fifo<SumTok>& si, Fifo<CostTok>& co,
                                         Fifo<SumTok>& so) {
    return [this, &n, &ci, &si, &co, &so] {
      bool fired = false;
      if (n.still_blocked()) return false;
      while (!row_rev_.done()) {
        const kern::RowReversePlan pl = row_rev_.plan();
        if (!pl.read && !pl.write) break;
        if (!n.attempt({Port{&ci, pl.read}, Port{&si, pl.read}}, {Port{&co, pl.write}, Port{&so, pl.write}}, [&] {
              if constexpr (kData) {
                const FiringScope<Caps::count_accesses> scope(n.name());
                row_rev_.fire(pl, ci, si, co, so);
              } else {
                row_rev_.step(pl);
                if (pl.read) {
                  ci.skip_read();
                  si.skip_read();
                }
                if (pl.write) {
                  co.skip_write();
                  so.skip_write();
                }
              }
            }))
          break;
        fired = true;
      }
      return fired;
    };
  }

  // The sink of a one-pass design takes the codes in raster order, one per firing; in the timing
  // run each completed row goes to the fast-forward.
  std::function<bool()> sink_pump(NodeT& n, Fifo<kern::DispCode>& in, DisparityCodes& out, int64_t& got) {
    const int64_t total = frame_pixels();
    return [this, &n, &in, &out, &got, total] {
      bool fired = false;
      if (n.still_blocked()) return false;
      while (got < total) {
        const int64_t i = got;
        if (!n.attempt({Port{&in, true}}, {}, [&] {
              if constexpr (kData)
                out.code[std::size_t(i)] = in.read();
              else
                in.skip_read();
            }))
          break;
        if (rep_) {
          if (i == 0) rep_->first_pixel_cycle = in.last_read_cycle();
          rep_->last_pixel_cycle = in.last_read_cycle();
        }
        ++got;
        fired = true;
        if constexpr (kTimed && !kData)
          if (ff_.enabled() && got % p_.width_px == 0) ff_.row_done(*this);
      }
      return fired;
    };
  }

  // A map source streams one camera's rectification map, entry i no earlier than maps.at(i).
  std::function<bool()> map_pump(NodeT& n, const std::vector<kern::MapEntry>& table, Fifo<kern::MapEntry>& out,
                                 int64_t& next, Rate maps) {
    return [&n, &table, &out, &next, maps] {
      bool fired = false;
      if (n.still_blocked()) return false;
      while (next < int64_t(table.size())) {
        const int64_t i = next;
        if (!n.attempt(
                {}, {Port{&out, true}}, [&] { out.write(table[std::size_t(i)]); }, maps.at(i)))
          break;
        ++next;
        fired = true;
      }
      return fired;
    };
  }

  static constexpr int kRectifyRows = 256;
  using RectifyStage = kern::Rectify<kern::kMaxWidthPx, kRectifyRows>;
  // A rectify stage (one camera): raw pixels and map entries in, rectified pixels out.
  std::function<bool()> rect_pump(NodeT& n, RectifyStage& st, Fifo<uint8_t>& raw, Fifo<kern::MapEntry>& map,
                                  Fifo<uint8_t>& out) {
    return [&n, &st, &raw, &map, &out] {
      bool fired = false;
      if (n.still_blocked()) return false;
      while (!st.done()) {
        const kern::RectifyPlan pl = st.plan();
        if (!pl.read_pixel && !pl.write) break;
        if (!n.attempt({Port{&raw, pl.read_pixel}, Port{&map, pl.write}}, {Port{&out, pl.write}},
                       [&] { st.fire(pl, raw, map, out); }))
          break;
        fired = true;
      }
      return fired;
    };
  }

  // --- graphs ------------------------------------------------------------------------------

  static constexpr std::size_t kPixelDepth = 2048;
  static constexpr std::size_t kTokenDepth = 128;

  // The input of the graph: the source, and with rectification a map source and a rectify stage
  // per camera. Returns the pumps; out_l / out_r feed the cost stage.
  struct FrontEnd {
    std::unique_ptr<Fifo<uint8_t>> raw_l, raw_r, out_l, out_r;
    std::unique_ptr<Fifo<kern::MapEntry>> map_l, map_r;
    int64_t next_src = 0, next_map_l = 0, next_map_r = 0;
    std::vector<std::function<bool()>> pumps;
  };

  std::unique_ptr<FrontEnd> front_end(const GreyImage& left, const GreyImage& right) {
    auto fe = std::make_unique<FrontEnd>();
    FrontEnd& f = *fe;
    NodeT& n_src = node("source");
    if (!rectifying()) {
      f.out_l = make_fifo<uint8_t>("left_px", kPixelDepth);
      f.out_r = make_fifo<uint8_t>("right_px", kPixelDepth);
      f.pumps.push_back(source_pump(n_src, left, right, *f.out_l, *f.out_r, f.next_src));
      return fe;
    }
    const kern::RectifyParams& rp = setup_.opt->rectify;
    f.raw_l = make_fifo<uint8_t>("raw_left_px", kPixelDepth);
    f.raw_r = make_fifo<uint8_t>("raw_right_px", kPixelDepth);
    f.map_l = make_fifo<kern::MapEntry>("map_left", kPixelDepth);
    f.map_r = make_fifo<kern::MapEntry>("map_right", kPixelDepth);
    f.out_l = make_fifo<uint8_t>("left_px", kPixelDepth);
    f.out_r = make_fifo<uint8_t>("right_px", kPixelDepth);
    f.pumps.push_back(source_pump(n_src, left, right, *f.raw_l, *f.raw_r, f.next_src));
    if (!rect_l_) rect_l_ = std::make_unique<RectifyStage>();
    if (!rect_r_) rect_r_ = std::make_unique<RectifyStage>();
    rect_l_->configure(rp);
    rect_r_->configure(rp);
    Rate maps;
    maps.cycles_per_token = 8.0 * setup_.opt->clock_hz / setup_.opt->input_bytes_per_s;
    NodeT& n_ml = node("map_left");
    NodeT& n_mr = node("map_right");
    NodeT& n_rl = node("rectify_left");
    NodeT& n_rr = node("rectify_right");
    f.pumps.push_back(map_pump(n_ml, *setup_.opt->rectify_map_left, *f.map_l, f.next_map_l, maps));
    f.pumps.push_back(map_pump(n_mr, *setup_.opt->rectify_map_right, *f.map_r, f.next_map_r, maps));
    f.pumps.push_back(rect_pump(n_rl, *rect_l_, *f.raw_l, *f.map_l, *f.out_l));
    f.pumps.push_back(rect_pump(n_rr, *rect_r_, *f.raw_r, *f.map_r, *f.out_r));
    return fe;
  }

  // The SGM and WTA stages as the pipeline description configures them (kern::stage_setup()),
  // recorded in the report.
  template <class Agg>
  void configure_sgm(Agg& agg, const char* stage) {
    agg.configure(p_, kern::stage_setup(stage, p_.path_mask));
    if (rep_) rep_->stage_setups.emplace_back(stage, agg.setup());
  }
  void configure_wta() {
    wta_.configure(p_, kern::stage_setup("wta_lr", p_.path_mask));
    if (rep_) rep_->stage_setups.emplace_back("wta_lr", wta_.setup());
  }

  void collect_front_end(FrontEnd& f) {
    if (f.raw_l) collect(std::move(f.raw_l), std::move(f.raw_r), std::move(f.map_l), std::move(f.map_r));
    if (rep_ && rectifying()) rep_->rectify_window_misses = rect_l_->window_misses() + rect_r_->window_misses();
  }

  // The one-pass graph after the cost FIFO: aggregate -> sum -> wta_lr -> disp_lr -> median ->
  // disp_out -> sink; with the 180-degree path (row_reverse.hpp) aggregate -> cost_to_row /
  // fwd_to_row -> row_reverse -> cost_row / fwd_row -> aggregate_row -> sum -> wta_lr (reverse
  // mode) -> disp_lr -> median -> disp_out -> row_unreverse -> disp_row -> sink. Configures the
  // stages, makes the FIFOs and nodes (after the caller's, so stage and FIFO order are the
  // graph's) and returns their pumps; shared by the whole one-pass run and the replay of recorded
  // costs, so the two cannot drift apart.
  struct BackEnd {
    std::unique_ptr<Fifo<CostTok>> cost_to_row, cost_row;
    std::unique_ptr<Fifo<SumTok>> fwd_to_row, fwd_row, sums;
    std::unique_ptr<Fifo<kern::DispCode>> disp, filtered, disp_row;
    std::vector<std::function<bool()>> pumps;
  };
  std::unique_ptr<BackEnd> one_pass_back_end(Fifo<CostTok>& costs, DisparityCodes& out, int64_t& got) {
    const bool rr = kern::row_reverse_paths(p_.path_mask);
    configure_sgm(agg_, "aggregate");
    if constexpr (Caps::count_accesses) agg_.count_row_layout();
    configure_wta();
    median_.configure(p_);
    auto be = std::make_unique<BackEnd>();
    if (rr) {
      row_rev_.configure(p_);
      configure_sgm(agg_row_, "aggregate_row");
      code_rev_.configure(p_);
      be->cost_to_row = make_fifo<CostTok>("cost_to_row", kTokenDepth);
      be->fwd_to_row = make_fifo<SumTok>("fwd_to_row", kTokenDepth);
      be->cost_row = make_fifo<CostTok>("cost_row", kTokenDepth);
      be->fwd_row = make_fifo<SumTok>("fwd_row", kTokenDepth);
    }
    be->sums = make_fifo<SumTok>("sum", kTokenDepth);
    be->disp = make_fifo<kern::DispCode>("disp_lr", kPixelDepth);
    be->filtered = make_fifo<kern::DispCode>("disp_out", kPixelDepth);
    if (rr) be->disp_row = make_fifo<kern::DispCode>("disp_row", kPixelDepth);
    NodeT& n_agg = node("aggregate");
    if (rr) {
      NodeT& n_rev = node("row_reverse");
      NodeT& n_row = node("aggregate_row");
      be->pumps.push_back(agg_pump<Fifo<CostTok>, Fifo<SumTok>, Fifo<SumTok>, Fifo<CostTok>>(
          n_agg, costs, nullptr, *be->fwd_to_row, be->cost_to_row.get()));
      be->pumps.push_back(row_reverse_pump(n_rev, *be->cost_to_row, *be->fwd_to_row, *be->cost_row, *be->fwd_row));
      be->pumps.push_back(agg_pump_of<decltype(agg_row_), Fifo<CostTok>, Fifo<SumTok>, Fifo<SumTok>, Fifo<CostTok>>(
          agg_row_, n_row, *be->cost_row, be->fwd_row.get(), *be->sums, nullptr));
    } else {
      be->pumps.push_back(agg_pump<Fifo<CostTok>, Fifo<SumTok>, Fifo<SumTok>, Fifo<CostTok>>(n_agg, costs, nullptr,
                                                                                             *be->sums, nullptr));
    }
    NodeT& n_wta = node("wta_lr");
    NodeT& n_med = node("median");
    be->pumps.push_back(wta_pump(n_wta, *be->sums, *be->disp, got));
    be->pumps.push_back(median_pump(n_med, *be->disp, *be->filtered));
    if (rr) {
      NodeT& n_unrev = node("row_unreverse");
      be->pumps.push_back(unreverse_pump(n_unrev, *be->filtered, *be->disp_row));
    }
    NodeT& n_sink = node("sink");
    be->pumps.push_back(sink_pump(n_sink, rr ? *be->disp_row : *be->filtered, out, got));
    return be;
  }
  // Moves the back end's FIFO statistics into the report, in graph order.
  void collect_back_end(BackEnd& be) {
    if (be.cost_to_row)
      collect(std::move(be.cost_to_row), std::move(be.fwd_to_row), std::move(be.cost_row), std::move(be.fwd_row));
    collect(std::move(be.sums), std::move(be.disp), std::move(be.filtered));
    if (be.disp_row) collect(std::move(be.disp_row));
  }

  template <class CostStage>
  void run_one_pass(CostStage& cost, const GreyImage& left, const GreyImage& right, DisparityCodes& out) {
    cost.configure(p_);
    std::unique_ptr<FrontEnd> fe = front_end(left, right);
    Fifo<uint8_t>& in_l = *fe->out_l;
    Fifo<uint8_t>& in_r = *fe->out_r;
    auto costs = make_fifo<CostTok>("cost", kTokenDepth);
    NodeT& n_cost = node("cost");
    int64_t got = 0;
    const std::unique_ptr<BackEnd> be = one_pass_back_end(*costs, out, got);
    const int64_t total = frame_pixels();
    start_fast_forward(fe->next_src, got, int64_t(left.px.size()));
    std::vector<std::function<bool()>> pumps = fe->pumps;
    pumps.push_back(cost_pump(n_cost, cost, in_l, in_r, *costs));
    pumps.insert(pumps.end(), be->pumps.begin(), be->pumps.end());
    schedule(pumps, [&] { return got >= total; });
    collect_front_end(*fe);
    collect(std::move(fe->out_l), std::move(fe->out_r), std::move(costs));
    collect_back_end(*be);
  }

  // Pass 1 writes C and F to the frame buffer through `ddr_write`; pass 2 starts when the last
  // word is written and reads them back in reverse pixel order through `ddr_read`; the map writer
  // (the sink) restores raster order (frame_buffer_stages.hpp).
  template <class CostStage>
  void run_two_pass(CostStage& cost, const GreyImage& left, const GreyImage& right, DisparityCodes& out) {
    fb_.configure(p_, rep_);
    const FrameLayout& fl = fb_.layout();
    if (rep_) {
      rep_->ddr_word_bits = kern::frame_word_bits(p_);
      rep_->ddr_bytes_written = rep_->ddr_bytes_read = rep_->map_bytes_written = 0;
    }
    const Rate ddr = ddr_rate();
    cost.configure(p_);
    configure_sgm(agg_, "aggregate");
    if constexpr (Caps::count_accesses) agg_.count_row_layout();
    std::unique_ptr<FrontEnd> fe = front_end(left, right);
    Fifo<uint8_t>& in_l = *fe->out_l;
    Fifo<uint8_t>& in_r = *fe->out_r;
    auto costs = make_fifo<CostTok>("cost", kTokenDepth);
    auto tee = make_fifo<CostTok>("cost_to_ddr", kTokenDepth);
    auto fwd = make_fifo<SumTok>("fwd_to_ddr", kTokenDepth);
    NodeT& n_cost = node("cost");
    NodeT& n_agg = node("aggregate");
    NodeT& n_wr = node("ddr_write");
    const int64_t write_firings = fl.seg_tokens + fl.words;
    int64_t wr_step = 0, stored = 0, wr_last = 0;
    start_fast_forward_pass1(fe->next_src, int64_t(left.px.size()), wr_step, stored, wr_last, ddr);
    const int64_t words_per_row = frame_words_per_row();
    std::function<void()> wr_row_done;
    if (ff_.enabled())
      wr_row_done = [this, &n_wr, &stored, &wr_last, words_per_row] {
        if (stored % words_per_row != 0) return;
        wr_last = n_wr.report().last_fire_cycle;
        ff_.row_done(*this);
      };
    std::vector<std::function<bool()>> pass1 = fe->pumps;
    pass1.push_back(cost_pump(n_cost, cost, in_l, in_r, *costs));
    pass1.push_back(
        agg_pump<Fifo<CostTok>, Fifo<SumTok>, Fifo<SumTok>, Fifo<CostTok>>(n_agg, *costs, nullptr, *fwd, tee.get()));
    pass1.push_back(fb_.write_pump(n_wr, *tee, *fwd, ddr, wr_step, stored, wr_row_done));
    if (!schedule(pass1, [&] { return wr_step >= write_firings; })) {
      collect_front_end(*fe);
      collect(std::move(fe->out_l), std::move(fe->out_r), std::move(costs), std::move(tee), std::move(fwd));
      return;
    }
    if (rep_) rep_->ddr_bytes_written = stored * fl.word_bytes;
    const int64_t pass2_start = n_wr.t_next() + ddr_latency_cycles();
    configure_sgm(agg_, "aggregate_back");
    if constexpr (Caps::count_accesses) agg_.count_row_layout();
    configure_wta();
    median_.configure(p_);
    const std::size_t pass2_fifos = graph_->fifo_list().size();
    auto back_c = make_fifo<CostTok>("cost_from_ddr", kTokenDepth);
    auto back_f = make_fifo<SumTok>("fwd_from_ddr", kTokenDepth);
    auto sums = make_fifo<SumTok>("sum", kTokenDepth);
    auto disp = make_fifo<kern::DispCode>("disp_lr", kPixelDepth);
    auto filtered = make_fifo<kern::DispCode>("disp_out", kPixelDepth);
    NodeT& n_rd = node("ddr_read");
    NodeT& n_back = node("aggregate_back");
    NodeT& n_wta = node("wta_lr");
    NodeT& n_med = node("median");
    NodeT& n_sink = node("sink");
    Rate rd = ddr;
    rd.start = pass2_start;
    int64_t read_word = 0, got = 0, map_step = 0;
    const int64_t total = fl.pixels;
    start_fast_forward_pass2(read_word, rd, got, map_step, pass2_fifos);
    std::function<void()> map_row_done;
    if (ff_.enabled())
      map_row_done = [this, &got] {
        if (got % p_.width_px == 0) ff_.row_done(*this);
      };
    schedule({fb_.read_pump(n_rd, *back_c, *back_f, rd, read_word),
              agg_pump<Fifo<CostTok>, Fifo<SumTok>, Fifo<SumTok>, Fifo<CostTok>>(n_back, *back_c, back_f.get(), *sums,
                                                                                 nullptr),
              wta_pump(n_wta, *sums, *disp, got), median_pump(n_med, *disp, *filtered),
              fb_.map_writer_pump(n_sink, *filtered, out, got, map_step, map_row_done)},
             [&] { return got >= total; });
    if (rep_) {
      rep_->ddr_bytes_read = read_word * fl.word_bytes;
      rep_->map_bytes_written = got * kern::kMapCodeBytes;
    }
    collect_front_end(*fe);
    collect(std::move(fe->out_l), std::move(fe->out_r), std::move(costs), std::move(tee), std::move(fwd),
            std::move(back_c), std::move(back_f), std::move(sums), std::move(disp), std::move(filtered));
  }

  // --- periodic fast-forward hooks (fast_forward.hpp) ------------------------------------------

  // Whether the fast-forward may run: the timing run without rectification or VCD trace.
  bool fast_forward_allowed() const {
    return kTimed && !kData && rep_ && setup_.opt && setup_.opt->fast_forward && !rectifying() &&
           !(trace_ && trace_->active());
  }
  // The input as a rate the source waits for, in pixels (one pass, pass 1).
  RateBound input_bound(int64_t& next_src, int64_t source_pixels) const {
    const CycleOptions& o = *setup_.opt;
    const int64_t total = o.truncate_input_px >= 0 ? std::min(source_pixels, o.truncate_input_px) : source_pixels;
    const double stride = double(p_.width_px) + (o.input == InputKind::camera ? double(o.camera_h_blank_px) : 0.0);
    return RateBound{"source", &next_src, p_.width_px, total, stride * input_rate_.cycles_per_token, [this](int64_t i) {
                       return input_arrival(i);
                     }};
  }
  // The frame buffer's words of one row, and the memory's rate as a RateBound of a node counting
  // words in `next`.
  int64_t frame_words_per_row() const { return int64_t(p_.width_px) * fb_.layout().chunks * fb_.layout().beats; }
  RateBound memory_bound(const char* node, int64_t& next, const Rate& r) const {
    const int64_t per_row = frame_words_per_row();
    return RateBound{node,
                     &next,
                     per_row,
                     fb_.layout().words,
                     double(per_row) * r.cycles_per_token,
                     [r](int64_t i) { return r.at(i); }};
  }
  // Arms the fast-forward for a one-pass design where it is allowed.
  void start_fast_forward(int64_t& next_src, int64_t& got, int64_t source_pixels) {
    const bool enabled = fast_forward_allowed();
    FastForwardRun run;
    if (enabled) {
      run.got = &got;
      run.sink_per_row = p_.width_px;
      run.last_cycle = &rep_->last_pixel_cycle;
      run.rows_fast_forwarded = &rep_->rows_fast_forwarded;
      run.settle_rows = p_.window_h / 2 + p_.median / 2 + 2 + (kern::row_reverse_paths(p_.path_mask) ? 2 : 0);
      run.source = input_bound(next_src, source_pixels);
    }
    ff_.start(enabled, *graph_, run);
  }
  // Pass 1 of the two-pass design: from the input to the frame-buffer writer, whose rows are
  // words (stored, a row's words per row) and which waits for the memory's write rate.
  void start_fast_forward_pass1(int64_t& next_src, int64_t source_pixels, int64_t& wr_step, int64_t& stored,
                                int64_t& wr_last, const Rate& ddr) {
    const bool enabled = fast_forward_allowed();
    FastForwardRun run;
    if (enabled) {
      run.got = &stored;
      run.sink_per_row = frame_words_per_row();
      run.last_cycle = &wr_last;
      run.rows_fast_forwarded = &rep_->first_pass_rows_fast_forwarded;
      run.counters = {&wr_step};
      run.settle_rows = p_.window_h / 2 + 3;
      run.source = input_bound(next_src, source_pixels);
      run.sink_rate = memory_bound("ddr_write", stored, ddr);
    }
    ff_.start(enabled, *graph_, run);
  }
  // Pass 2: from the frame-buffer reader (rows of words, read at the memory's rate) to the map
  // writer (rows of codes); the FIFOs from first_fifo on are the pass's.
  void start_fast_forward_pass2(int64_t& read_word, const Rate& rd, int64_t& got, int64_t& map_step,
                                std::size_t first_fifo) {
    const bool enabled = fast_forward_allowed();
    FastForwardRun run;
    if (enabled) {
      run.got = &got;
      run.sink_per_row = p_.width_px;
      run.last_cycle = &rep_->last_pixel_cycle;
      run.rows_fast_forwarded = &rep_->rows_fast_forwarded;
      run.counters = {&map_step};
      run.settle_rows = p_.median / 2 + 3;
      run.first_fifo = first_fifo;
      run.source = memory_bound("ddr_read", read_word, rd);
    }
    ff_.start(enabled, *graph_, run);
  }
  template <class IO>
  void visit_kernels(IO& io) {
    if (p_.cost == kern::kCostCensus)
      census_.visit(io);
    else
      sad_.visit(io);
    agg_.visit(io);
    row_rev_.visit(io);
    agg_row_.visit(io);
    wta_.visit(io);
    median_.visit(io);
    code_rev_.visit(io);
  }
  void resync_kernels() {
    census_.resync();
    sad_.resync();
    agg_.resync();
    row_rev_.resync();
    agg_row_.resync();
    wta_.resync();
    median_.resync();
    code_rev_.resync();
  }
  friend class FastForward<kTimed>;

  FastForward<kTimed> ff_;
  kern::CensusCostStage<Caps> census_;
  kern::SadCostStage<Caps> sad_;
  kern::SgmAggregate<Caps, Word> agg_;
  kern::RowReverse<Caps, Word> row_rev_;
  kern::SgmAggregate<kern::PixelPathCaps<Caps>, Word> agg_row_;
  kern::WtaLr<Caps, Word> wta_;
  kern::Median<Caps> median_;
  kern::RowReverseCodes<Caps> code_rev_;
  std::unique_ptr<RectifyStage> rect_l_, rect_r_;
  std::vector<SumTok>* sum_tap_ = nullptr;  // record_sums(): the WTA's input goes here instead
  FrameBufferStages<Caps, Word, kTimed, kData> fb_;
};

}  // namespace parallax::sim::detail
