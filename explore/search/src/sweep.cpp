// Running a sweep (sweep.hpp): designs claimed in the store, evaluated (those sharing their
// matching costs together) through evaluate_point, stored; NSGA-II's generations. The spec is read
// in spec.cpp, designs picked in strategies.cpp, fronts found in pareto.cpp, results kept in store.cpp.
#include "parallax/search/sweep.hpp"

#include "frame_cache.hpp"
#include "internal.hpp"
#include "parallax/eval/text_util.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <map>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <mutex>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "parallax/uav/avoid.hpp"
#include "parallax/design/result.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/evaluate.hpp"
#include "parallax/uav/scene.hpp"
#include "parallax/resources/devices.hpp"

namespace parallax::search {

// The names this file takes from the other rooms (one namespace per room).
using design::AccuracyFigures;
using design::AvoidanceFigures;
using design::complete_point;
using design::DesignResult;
using design::frame_columns;
using design::PointRequest;
using eval::Baseline;
using eval::BaselineParams;
using eval::count_frame;
using eval::Dataset;
using eval::DisparityMap;
using eval::EvalOptions;
using eval::EvalResult;
using eval::evaluate;
using eval::FrameRef;
using eval::GtKind;
using eval::InputError;
using eval::list_frames;
using eval::make_frame_row;
using eval::Matcher;
using eval::named_metrics;
using eval::open_dataset;
using eval::parse_baseline;
using eval::pool_rows;
using eval::Roi;
using eval::roi_for;
using eval::RoiSize;
using eval::run_baseline;
using eval::to_disparity_map;
using eval::to_grey_image;
using eval::detail::utc_now;
using uav::AvoidAccumulator;
using uav::kitti_default_rig;
using uav::load_scenario;
using uav::scenario_reference;

using json = nlohmann::json;
using nsga2::Genome;
using nsga2::objective_vector;
using nsga2::point_of;
using nsga2::rank_and_crowd;

// --- running ----------------------------------------------------------------------------------

namespace {

// Changes when a model's results change: 2026-12-01, census variants no longer share the full
// census's costs in a sweep (sim::cost_sharing_key), and the 180-degree path in one pass.
constexpr const char* kModelVersion = "parallax-models/2026-12-01 (kernels, cycle schedule, resources)";

std::string absolute_path(const std::string& p) {
  std::error_code ec;
  const std::filesystem::path a = std::filesystem::weakly_canonical(std::filesystem::absolute(p, ec), ec);
  return ec ? p : a.lexically_normal().string();
}

}  // namespace

std::string measurement_of(const SweepSpec& s, const std::string& dataset_dir,
                           const std::vector<std::string>& frame_ids) {
  json j;  // keys sorted: one text per measurement
  j["contract"] = kResultsContract;
  j["models"] = kModelVersion;
  j["dataset"] = absolute_path(dataset_dir);
  j["gt"] = s.gt;
  j["frames"] = frame_ids;
  j["device"] = s.device;
  j["avoidance"] = s.avoidance;
  if (!s.flight_scenario.empty())
    j["flight"] = {{"scenario", scenario_reference(s.flight_scenario)},
                   {"seeds", s.flight_seeds},
                   {"speed_mps", s.flight_speed_mps},
                   {"size_px", s.flight_size_px}};
  return j.dump();
}

std::string result_key(const std::string& design_hash, const std::string& measurement) {
  return design_hash + "@" + detail::fnv1a_hex(measurement);
}

namespace {

// What the sweep asks of every design (docs/explorer.md): its dataset's frames, avoidance,
// flights and device.
PointRequest point_request(const SweepSpec& spec, const Dataset* dataset) {
  PointRequest req;
  req.dataset = dataset;
  req.gt_kind = spec.gt == "occ" ? GtKind::occ : GtKind::noc;
  req.frames = spec.frames;
  req.avoidance = spec.avoidance;
  req.device = spec.device;
  req.flight_scenario = spec.flight_scenario;
  req.flight_seeds = spec.flight_seeds;
  req.flight_speed_mps = spec.flight_speed_mps;
  req.flight_size_px = spec.flight_size_px;
  return req;
}

// Completes a design's result (what the sweep's shared evaluation has not measured) and writes
// it into its row.
void finish_row(const SweepSpec& spec, DesignResult& result, const Dataset* dataset, ResultStore::Row& row) {
  complete_point(result, point_request(spec, dataset));
  row.metrics = metric_columns(result);
  row.frames = frame_columns(result);
  row.status = result.status;
  row.reason = result.reason;
  row.finished_at = utc_now();
}

ResultStore::Row new_row(const SweepSpec& spec, const MaterialisedDesign& m) {
  ResultStore::Row row;
  row.hash = m.hash;
  row.sweep = spec.name;
  row.config_yaml = m.yaml;
  row.model_version = kModelVersion;
  row.started_at = utc_now();
  return row;
}

ResultStore::Row evaluate_one(const SweepSpec& spec, const MaterialisedDesign& m, const Dataset& dataset) {
  ResultStore::Row row = new_row(spec, m);
  DesignResult result;
  result.config = m.config;
  finish_row(spec, result, &dataset, row);
  return row;
}

// The decoded, cropped frames a sweep keeps for its cost groups (frame_cache.hpp): 200 KITTI
// frames at 640x360 take 320 MiB; beyond the budget frames are decoded per group as before.
constexpr std::size_t kFrameCacheBytes = std::size_t(512) << 20;

// Designs sharing the cost stage, evaluated together: each frame's costs recorded once and
// replayed into every design; the frames come from the sweep's cache (decoded and cropped once
// for every group, frame_cache.hpp). The frames may be split into chunks that threads evaluate
// side by side (GroupJob): each frame's figures land at the frame's index, so the pooled figures
// are those of one thread, in frame order.
struct GroupFrames {
  std::vector<const MaterialisedDesign*> designs;
  std::vector<FrameRef> refs;
  RoiSize roi;
  // The evaluation order: designs of one aggregate (they differ only after the aggregation) next
  // to each other, so that each aggregate is computed once per frame and replayed into the rest
  // (fast engine); within an aggregate, designs with the same WTA knobs next to each other (a
  // median-only difference then reruns the median alone).
  std::vector<std::size_t> order;
  std::vector<std::string> agg_key;
  std::vector<std::vector<eval::FrameRow>> rows;  // [design][frame]
  std::vector<AvoidAccumulator> avoidance;        // only with one chunk (its sums run in frame order)
  std::string started_at;
};

// The group's evaluation order and storage, over the sweep's frames (refs, at least one).
void prepare_group(const SweepSpec& spec, const std::vector<const MaterialisedDesign*>& group,
                   std::vector<FrameRef> refs, GroupFrames& g) {
  g.designs = group;
  g.refs = std::move(refs);
  g.started_at = utc_now();
  g.roi = roi_for(group.front()->config);
  g.order.resize(group.size());
  g.agg_key.assign(group.size(), "");
  std::vector<std::string> wta_key(group.size());
  for (std::size_t k = 0; k < group.size(); ++k) {
    g.order[k] = k;
    const kern::StereoParams p = group[k]->config.stereo_params(g.roi.width_px, g.roi.height_px);
    g.agg_key[k] = sim::aggregate_sharing_key(p);
    wta_key[k] = sim::selection_sharing_key(p);
  }
  std::stable_sort(g.order.begin(), g.order.end(), [&](std::size_t a, std::size_t b) {
    return g.agg_key[a] != g.agg_key[b] ? g.agg_key[a] < g.agg_key[b] : wta_key[a] < wta_key[b];
  });
  g.rows.assign(group.size(), std::vector<eval::FrameRow>(g.refs.size()));
  g.avoidance.assign(spec.avoidance ? group.size() : 0, AvoidAccumulator{});
}

// Frames [lo, hi) of every design of the group.
void evaluate_group_frames(const SweepSpec& spec, GroupFrames& g, std::size_t lo, std::size_t hi,
                           detail::FrameCache& frames) {
  // One pipeline and one recording per thread, kept from group to group: their buffers (the cost
  // volume, the kept aggregate, a two-pass frame's sums, up to about 60 MiB each at D = 128) are
  // then allocated and zeroed once per thread instead of once per group. record_costs resets the
  // recording (its kept aggregate too) for every frame.
  thread_local sim::FuncPipeline pipe;
  thread_local sim::CostRecording rec;
  const auto& group = g.designs;
  for (std::size_t fi = lo; fi < hi; ++fi) {
    const std::shared_ptr<const detail::CroppedFrame> f = frames.get(g.refs[fi], g.roi);
    const Roi& r = f->roi;
    const cv::Mat &l = f->left, &rr = f->right, &gtd = f->gt_disparity_px, &gtm = f->gt_mask;
    pipe.record_costs(to_grey_image(l), to_grey_image(rr), group.front()->config.stereo_params(l.cols, l.rows), rec);
    for (std::size_t i = 0; i < group.size(); ++i) {
      const std::size_t k = g.order[i];
      const kern::StereoParams p = group[k]->config.stereo_params(l.cols, l.rows);
      const bool next_shares =
          i + 1 < group.size() && !g.agg_key[k].empty() && g.agg_key[g.order[i + 1]] == g.agg_key[k];
      const DisparityMap d = to_disparity_map(pipe.run_from_costs(rec, p, next_shares));
      g.rows[k][fi] = make_frame_row(f->id, count_frame(d.disparity_px, d.valid_mask, gtd, gtm));
      if (spec.avoidance)
        g.avoidance[k].add(d.disparity_px, d.valid_mask, gtd, gtm, p.min_disparity + p.disparities,
                           kitti_default_rig(r.x0, r.y0));
    }
  }
}

// The group's rows once every frame is in: pooled figures, then what the shared evaluation has
// not measured (the design's schedule, resources, flights).
std::vector<ResultStore::Row> finish_group(const SweepSpec& spec, GroupFrames& g, const Dataset& dataset) {
  std::vector<ResultStore::Row> rows;
  for (std::size_t k = 0; k < g.designs.size(); ++k) {
    rows.push_back(new_row(spec, *g.designs[k]));
    rows.back().started_at = g.started_at;
    DesignResult result;
    result.config = g.designs[k]->config;
    AccuracyFigures accuracy;
    accuracy.frames = std::move(g.rows[k]);
    accuracy.pooled = pool_rows(accuracy.frames);
    result.accuracy = std::move(accuracy);
    if (spec.avoidance) result.avoidance = AvoidanceFigures{g.avoidance[k].metrics()};
    finish_row(spec, result, &dataset, rows.back());
  }
  return rows;
}

}  // namespace

namespace {

// Designs evaluated together: those sharing the cost stage (sim::cost_sharing_key) when
// share_costs, else one each. Threads share a unit's work by its frames (frame_chunks).
using Unit = std::vector<const MaterialisedDesign*>;
std::vector<Unit> cost_sharing_units(const std::vector<const MaterialisedDesign*>& designs, bool share_costs) {
  std::vector<Unit> units;
  std::map<std::string, std::size_t> unit_of_key;
  for (const auto* m : designs) {
    const RoiSize roi = roi_for(m->config);
    const std::string key = share_costs && m->config.rectify == "none" && !roi.full
                                ? sim::cost_sharing_key(m->config.stereo_params(roi.width_px, roi.height_px))
                                : "";
    const auto it = key.empty() ? unit_of_key.end() : unit_of_key.find(key);
    if (it != unit_of_key.end()) {
      units[it->second].push_back(m);
      continue;
    }
    if (!key.empty()) unit_of_key[key] = units.size();
    units.push_back({m});
  }
  return units;
}

// How many chunks of frames a unit's work is cut into: on one thread (or for one design, or with
// avoidance, whose sums run in frame order) one; else about 8 pieces of work per thread over the
// whole batch, in proportion to the unit's designs, so that the threads finish close together
// (a chunk costs its frames' cost recording, which the unit's designs share; nothing is
// computed twice).
int frame_chunks(std::size_t unit_designs, std::size_t batch_designs, std::size_t frames, int jobs, bool avoidance) {
  if (jobs <= 1 || unit_designs < 2 || avoidance || frames < 2) return 1;
  const std::size_t want = (8 * std::size_t(jobs) * unit_designs + batch_designs - 1) / batch_designs;
  return int(std::clamp<std::size_t>(want, 1, frames));
}

// Calls work(0 .. count-1) on up to `jobs` threads. The first exception stops every thread (no
// new index is started) and is rethrown here.
void for_each_on_threads(std::size_t count, int jobs, const std::function<void(std::size_t)>& work) {
  std::atomic<std::size_t> next{0};
  std::atomic<bool> stop{false};
  std::mutex mu;
  std::exception_ptr failure;
  auto worker = [&] {
    try {
      while (!stop) {
        const std::size_t i = next.fetch_add(1);
        if (i >= count) return;
        work(i);
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(mu);
      if (!failure) failure = std::current_exception();
      stop = true;
    }
  };
  std::vector<std::thread> pool;
  for (int j = 0; j < std::min<int>(jobs, int(count)); ++j) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

// One unit's work in `chunks` pieces (frame ranges) that any thread takes: the first piece to
// start claims the designs, the last to end pools, finishes and stores them. A failure in any
// piece makes every design of the unit an error row carrying the first message.
struct UnitJob {
  Unit unit;
  int chunks = 1;
  std::once_flag claimed;
  Unit mine;
  GroupFrames g;
  std::atomic<int> left{0};
  std::mutex mu;
  std::string error;  // the first failure
  void fail(const std::string& what) {
    const std::lock_guard<std::mutex> lock(mu);
    if (error.empty()) error = what.empty() ? "evaluation failed" : what;
  }
  bool failed() {
    const std::lock_guard<std::mutex> lock(mu);
    return !error.empty();
  }
};

// What a piece needs of its batch: the claim of a unit's designs in the store (those this
// process evaluates), storing a finished row, and the error row of a design.
struct BatchHooks {
  std::function<Unit(const Unit&)> claim;
  std::function<void(ResultStore::Row&)> store;
  std::function<ResultStore::Row(const MaterialisedDesign&, const std::string&)> error_row;
};

void run_unit_chunk(UnitJob& job, int c, const SweepSpec& spec, const Dataset& dataset, detail::FrameCache& frames,
                    const BatchHooks& hooks) {
  std::call_once(job.claimed, [&] {
    job.mine = hooks.claim(job.unit);
    if (job.mine.size() < 2) return;
    try {
      std::vector<FrameRef> refs = list_frames(dataset, spec.gt == "occ" ? GtKind::occ : GtKind::noc, spec.frames);
      if (refs.empty())
        throw InputError(dataset.root.string() + ": no frame with ground truth matches '" + spec.frames + "'");
      prepare_group(spec, job.mine, std::move(refs), job.g);
    } catch (const std::exception& e) {
      job.fail(e.what());
    }
  });
  if (!job.failed() && job.mine.size() >= 2) {
    const std::size_t n = job.g.refs.size(), chunks = std::size_t(job.chunks);
    try {
      evaluate_group_frames(spec, job.g, n * std::size_t(c) / chunks, n * std::size_t(c + 1) / chunks, frames);
    } catch (const std::exception& e) {
      job.fail(e.what());
    }
  }
  if (job.left.fetch_sub(1) != 1 || job.mine.empty()) return;  // not the unit's last piece, or none of it here
  std::vector<ResultStore::Row> rows;
  try {
    if (job.failed()) throw std::runtime_error(job.error);
    if (job.mine.size() == 1)
      rows.push_back(evaluate_one(spec, *job.mine.front(), dataset));
    else
      rows = finish_group(spec, job.g, dataset);
  } catch (const std::exception& e) {
    rows.clear();
    for (const auto* m : job.mine) rows.push_back(hooks.error_row(*m, e.what()));
  }
  for (auto& r : rows) hooks.store(r);
}

// The units on `jobs` threads, each cut into frame chunks (frame_chunks), every unit's chunks in
// order in one queue.
void run_units_in_chunks(const std::vector<Unit>& units, int jobs, const SweepSpec& spec, const Dataset& dataset,
                         detail::FrameCache& frames, const BatchHooks& hooks) {
  const std::size_t frame_count =
      list_frames(dataset, spec.gt == "occ" ? GtKind::occ : GtKind::noc, spec.frames).size();
  std::size_t designs_in_batch = 0;
  for (const Unit& u : units) designs_in_batch += u.size();
  std::vector<std::unique_ptr<UnitJob>> unit_jobs;
  std::vector<std::pair<std::size_t, int>> pieces;  // (unit, chunk)
  for (const Unit& u : units) {
    auto job = std::make_unique<UnitJob>();
    job->unit = u;
    job->chunks = frame_chunks(u.size(), designs_in_batch, frame_count, jobs, spec.avoidance);
    job->left = job->chunks;
    for (int c = 0; c < job->chunks; ++c) pieces.emplace_back(unit_jobs.size(), c);
    unit_jobs.push_back(std::move(job));
  }
  for_each_on_threads(pieces.size(), jobs, [&](std::size_t i) {
    run_unit_chunk(*unit_jobs[pieces[i].first], pieces[i].second, spec, dataset, frames, hooks);
  });
}

// Evaluates the designs (skipping stored ones) with `jobs` threads; counts into `sum`. Designs
// sharing the cost stage form groups (opt.share_costs) that a thread evaluates together. Each
// group claims its designs in the store first: designs another live process claimed are left to
// it and waited for at the end (and evaluated here if it dies or fails them).
void evaluate_batch(const SweepSpec& spec, const std::vector<MaterialisedDesign>& designs, ResultStore& store,
                    const Dataset& dataset, const SweepRunOptions& opt, SweepSummary& sum, int total_for_progress,
                    int done_before, const std::string& measurement, detail::FrameCache& frames) {
  std::atomic<int> done{0}, skipped{0}, evaluated{0}, invalid{0}, failed{0};
  std::atomic<int64_t> design_frames{0};
  std::mutex mu;  // progress, the waiting list, the first failure
  const int settled_before = sum.skipped + sum.invalid;
  auto report = [&] {  // settled: done without an evaluation (stored, duplicate or invalid)
    if (!opt.progress) return;
    std::lock_guard<std::mutex> lock(mu);
    opt.progress(done_before + done.load(), total_for_progress, settled_before + skipped.load() + invalid.load());
  };
  std::mutex problems_mu;
  auto note_problem = [&](const ResultStore::Row& r) {  // the first reasons, for the summary
    std::lock_guard<std::mutex> lock(problems_mu);
    if (sum.first_problems.size() < 5)
      sum.first_problems.push_back("design " + r.hash + " (" + r.status + "): " + r.reason);
  };
  auto key_of = [&](const MaterialisedDesign& m) { return result_key(m.hash, measurement); };
  auto reused = [&](const MaterialisedDesign& m) {
    store.add_member(spec.name, key_of(m));
    ++skipped;
    ++done;
    report();
  };
  // Stored, duplicate and invalid designs are settled now; the rest is evaluated.
  std::vector<const MaterialisedDesign*> todo;
  std::set<std::string> seen;
  for (const auto& m : designs) {
    if (!seen.insert(m.hash).second) {
      ++skipped;
      ++done;
      report();
      continue;
    }
    if (store.has_result(key_of(m))) {
      reused(m);
      continue;
    }
    if (!m.errors.empty()) {
      ResultStore::Row r = new_row(spec, m);
      r.status = "invalid";
      for (const auto& e : m.errors) r.reason += (r.reason.empty() ? "" : "; ") + e;
      r.finished_at = r.started_at;
      r.measurement = measurement;
      r.key = key_of(m);
      if (store.put_design(r)) {
        note_problem(r);
        ++invalid;
      } else {
        ++skipped;
      }
      ++done;
      report();
      continue;
    }
    todo.push_back(&m);
  }
  const int jobs = opt.jobs > 0 ? opt.jobs : std::max(1, int(std::thread::hardware_concurrency()));
  auto store_row = [&](ResultStore::Row& r) {
    r.measurement = measurement;
    r.key = result_key(r.hash, measurement);
    if (store.put_design(r)) {
      if (r.status == "error") {
        ++failed;
        note_problem(r);
      }
      const auto scored = r.metrics.find("frames");
      if (scored != r.metrics.end()) design_frames += int64_t(scored->second);
      ++evaluated;
    } else {
      ++skipped;  // another process stored it meanwhile (it took over a claim it thought stale)
    }
    ++done;
    report();
  };
  auto error_row = [&](const MaterialisedDesign& m, const std::string& what) {
    ResultStore::Row r = new_row(spec, m);
    r.status = "error";
    r.reason = what;
    r.finished_at = utc_now();
    return r;
  };
  std::vector<const MaterialisedDesign*> waiting;  // claimed by another live process
  // Claims the unit's designs in the store: the reusable are settled, those another live process
  // holds wait, the rest are this process's.
  auto claim_unit = [&](const Unit& unit) {
    std::vector<std::string> keys;
    for (const auto* m : unit) keys.push_back(key_of(*m));
    const std::vector<ResultStore::Claim> claims = store.claim(keys);
    Unit mine;
    for (std::size_t k = 0; k < unit.size(); ++k) {
      if (claims[k] == ResultStore::Claim::reusable) {
        reused(*unit[k]);
      } else if (claims[k] == ResultStore::Claim::busy) {
        std::lock_guard<std::mutex> lock(mu);
        waiting.push_back(unit[k]);
      } else {
        mine.push_back(unit[k]);
      }
    }
    return mine;
  };
  const BatchHooks hooks{claim_unit, store_row, error_row};
  auto run_units = [&](const std::vector<Unit>& units) {
    run_units_in_chunks(units, jobs, spec, dataset, frames, hooks);
  };
  run_units(cost_sharing_units(todo, opt.share_costs));
  // Designs other processes are evaluating: wait for their results; take over a design whose
  // process died or failed it.
  auto last_note = std::chrono::steady_clock::now() - std::chrono::hours(1);
  while (!waiting.empty()) {
    std::vector<const MaterialisedDesign*> again;
    again.swap(waiting);
    run_units(cost_sharing_units(again, opt.share_costs));
    if (waiting.empty()) break;
    if (std::chrono::steady_clock::now() - last_note > std::chrono::seconds(60)) {
      std::fprintf(stderr, "parallax: note: waiting for %zu designs that another sweep on %s is evaluating\n",
                   waiting.size(), store.path().c_str());
      last_note = std::chrono::steady_clock::now();
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  sum.evaluated += evaluated;
  sum.design_frames += design_frames;
  sum.threads = jobs;
  sum.skipped += skipped;
  sum.invalid += invalid;
  sum.failed += failed;
}

// The seed (the base design) and the peers of SweepSpec::baselines, measured on the sweep's frames
// and crops (the base design's ROI) and stored beside its designs, once per measurement; the
// peers with `parallax baseline`'s defaults (BaselineParams), as status peer.
void evaluate_peers(const SweepSpec& spec, const config::PipelineConfig& base, const Dataset& dataset,
                    const std::string& measurement, ResultStore& store, const SweepRunOptions& opt, SweepSummary& sum,
                    detail::FrameCache& frames) {
  if (spec.baselines.empty()) return;
  const std::vector<MaterialisedDesign> seed = {materialise(base, DesignPoint{})};
  evaluate_batch(spec, seed, store, dataset, opt, sum, sum.total + 1, sum.total, measurement, frames);
  const BaselineParams bp;
  for (const std::string& name : spec.baselines) {
    ResultStore::Row row;
    row.hash = "peer-" + name;
    row.sweep = spec.name;
    row.config_yaml = "baseline: " + name + "\ndisparities: " + std::to_string(bp.disparities) +
                      "\nblock_size: " + std::to_string(bp.block_size) + "\np1: " + std::to_string(bp.p1) +
                      "\np2: " + std::to_string(bp.p2) + "\ndisp12_max_diff: " + std::to_string(bp.disp12_max_diff) +
                      "\n";
    row.measurement = measurement;
    row.key = result_key(row.hash, measurement);
    if (store.has_result(row.key)) {
      store.add_member(spec.name, row.key);
      continue;
    }
    row.model_version = kModelVersion;
    row.started_at = utc_now();
    EvalOptions eo;
    eo.gt_kind = spec.gt == "occ" ? GtKind::occ : GtKind::noc;
    eo.frames = spec.frames;
    eo.roi_from_config = false;
    eo.roi = roi_for(base);
    eo.threads = opt.jobs > 0 ? opt.jobs : int(std::max(1u, std::thread::hardware_concurrency()));
    const Baseline b = parse_baseline(name);
    const EvalResult r = evaluate(
        dataset, eo.roi,
        [&]() -> Matcher { return [&](const cv::Mat& l, const cv::Mat& rr) { return run_baseline(b, bp, l, rr); }; },
        eo);
    for (const auto& kv : named_metrics(r.pooled.metrics)) row.metrics[kv.first] = kv.second;
    row.metrics["frames"] = double(r.frames.size());
    for (const auto& f : r.frames) {
      std::map<std::string, double> fm;
      for (const auto& kv : named_metrics(f.metrics)) fm[kv.first] = kv.second;
      row.frames.emplace_back(f.frame_id, std::move(fm));
    }
    row.status = "peer";
    row.finished_at = utc_now();
    store.put_design(row);
    std::fprintf(stderr, "parallax: peer %s: correct %.2f %%, density %.2f %% (%zu frames)\n", name.c_str(),
                 row.metrics["correct_3px_pct"], row.metrics["density_pct"], r.frames.size());
  }
}

}  // namespace

SweepSummary run_sweep(const SweepSpec& spec, ResultStore& store, const SweepRunOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  if (spec.base.empty()) throw InputError("sweep '" + spec.name + "': no base configuration (field 'base' or --base)");
  const config::PipelineConfig base = config::load_config(spec.base);
  check_sweep_spec(spec, base, opt.allow_large);
  const Dataset dataset = open_dataset(opt.dataset);
  if (!res::find_device(spec.device)) throw InputError("sweep: unknown device '" + spec.device + "'");
  if (opt.shard_count < 1 || opt.shard_index < 1 || opt.shard_index > opt.shard_count)
    throw InputError("shard " + std::to_string(opt.shard_index) + "/" + std::to_string(opt.shard_count) +
                     ": expected K/N with 1 <= K <= N");
  if (spec.strategy == "nsga2" && opt.shard_count > 1)
    throw InputError("nsga2 cannot be sharded: each generation depends on the last");
  if (spec.strategy == "nsga2" && spec.axes.empty()) throw InputError("nsga2 needs at least one axis");
  // What the results are measured on; inputs that would fail every design fail the sweep now,
  // before anything is stored.
  const GtKind gt = spec.gt == "occ" ? GtKind::occ : GtKind::noc;
  std::vector<std::string> frame_ids;
  for (const auto& ref : list_frames(dataset, gt, spec.frames)) frame_ids.push_back(ref.id);
  if (frame_ids.empty())
    throw InputError(opt.dataset + ": no frame with " + spec.gt + " ground truth matches '" + spec.frames + "'");
  if (!spec.flight_scenario.empty()) (void)load_scenario(spec.flight_scenario);
  const std::string dataset_dir = absolute_path(dataset.root.string());
  const std::string measurement = measurement_of(spec, dataset_dir, frame_ids);
  SweepSummary sum;
  detail::FrameCache frames(kFrameCacheBytes);
  if (store.put_sweep(spec, dataset_dir, measurement)) {
    sum.notes.push_back("sweep '" + spec.name + "' in " + store.path() +
                        " was measured on other data (dataset, frames, ground truth or models) before: it now lists "
                        "only the designs measured on " +
                        dataset_dir + " frames '" + spec.frames + "' (" + spec.gt +
                        "); the earlier results stay in the store");
    std::fprintf(stderr, "parallax: note: %s\n", sum.notes.back().c_str());
  }
  if (spec.strategy == "nsga2") {
    std::mt19937 rng(spec.seed);
    const int pop_n = std::max(4, spec.samples);
    auto random_genome = [&] {
      Genome g;
      for (const auto& a : spec.axes)
        g.push_back(std::uniform_int_distribution<std::size_t>(0, a.second.size() - 1)(rng));
      return g;
    };
    std::map<Genome, std::string> hash_of;  // genome -> design hash
    std::set<std::string> visited;
    auto evaluate = [&](const std::vector<Genome>& genomes, int generation) {
      std::vector<MaterialisedDesign> batch;
      for (const auto& g : genomes) {
        batch.push_back(materialise(base, point_of(spec, g)));
        hash_of[g] = batch.back().hash;
        visited.insert(batch.back().hash);
      }
      const int total = pop_n * (spec.generations + 1);
      evaluate_batch(spec, batch, store, dataset, opt, sum, total, generation * pop_n, measurement, frames);
    };
    auto rows_by_hash = [&] {
      std::map<std::string, ResultStore::Row> m;
      for (auto& r : store.designs(spec.name, false)) m[r.hash] = std::move(r);  // this sweep's, as measured now
      return m;
    };
    std::vector<Genome> pop;
    for (int i = 0; i < pop_n; ++i) pop.push_back(random_genome());
    evaluate(pop, 0);
    for (int gen = 1; gen <= spec.generations; ++gen) {
      const auto rows = rows_by_hash();
      auto fitness = [&](const std::vector<Genome>& gs) {
        std::vector<std::vector<double>> f;
        for (const auto& g : gs) {
          const auto it = rows.find(hash_of[g]);
          f.push_back(objective_vector(spec, it == rows.end() ? nullptr : &it->second));
        }
        return f;
      };
      std::vector<int> rank;
      std::vector<double> crowd;
      rank_and_crowd(fitness(pop), rank, crowd);
      auto tournament = [&]() -> const Genome& {
        const std::size_t a = std::uniform_int_distribution<std::size_t>(0, pop.size() - 1)(rng);
        const std::size_t b = std::uniform_int_distribution<std::size_t>(0, pop.size() - 1)(rng);
        if (rank[a] != rank[b]) return rank[a] < rank[b] ? pop[a] : pop[b];
        return crowd[a] >= crowd[b] ? pop[a] : pop[b];
      };
      std::vector<Genome> children;
      const double p_mut = 1.0 / double(spec.axes.size());
      for (int tries = 0; int(children.size()) < pop_n && tries < pop_n * 50; ++tries) {
        const Genome& x = tournament();
        const Genome& y = tournament();
        Genome c(x.size());
        for (std::size_t k = 0; k < c.size(); ++k) {
          c[k] = std::uniform_int_distribution<int>(0, 1)(rng) ? x[k] : y[k];  // uniform crossover
          if (std::uniform_real_distribution<double>(0.0, 1.0)(rng) < p_mut)
            c[k] = std::uniform_int_distribution<std::size_t>(0, spec.axes[k].second.size() - 1)(rng);
        }
        const std::string h = materialise(base, point_of(spec, c)).hash;
        if (visited.count(h)) continue;  // only new designs cost an evaluation
        children.push_back(c);
        visited.insert(h);
      }
      if (children.empty()) break;  // the space is exhausted
      evaluate(children, gen);
      // Environmental selection: the best pop_n of parents + children by rank, then crowding.
      std::vector<Genome> merged = pop;
      merged.insert(merged.end(), children.begin(), children.end());
      const auto rows2 = rows_by_hash();
      std::vector<std::vector<double>> f;
      for (const auto& g : merged) {
        const auto it = rows2.find(hash_of[g]);
        f.push_back(objective_vector(spec, it == rows2.end() ? nullptr : &it->second));
      }
      rank_and_crowd(f, rank, crowd);
      std::vector<std::size_t> idx(merged.size());
      for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
      std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) {
        return rank[a] != rank[b] ? rank[a] < rank[b] : crowd[a] > crowd[b];
      });
      pop.clear();
      for (std::size_t i = 0; i < idx.size() && int(pop.size()) < pop_n; ++i) pop.push_back(merged[idx[i]]);
    }
    sum.total = int(visited.size());
  } else {
    std::vector<DesignPoint> points;
    const std::vector<DesignPoint> all = enumerate_designs(spec);
    for (std::size_t i = 0; i < all.size(); ++i)
      if (int(i % std::size_t(opt.shard_count)) == opt.shard_index - 1) points.push_back(all[i]);
    sum.total = int(points.size());
    std::vector<MaterialisedDesign> designs;
    for (const auto& p : points) designs.push_back(materialise(base, p));
    evaluate_batch(spec, designs, store, dataset, opt, sum, sum.total, 0, measurement, frames);
  }
  if (opt.shard_index == 1) evaluate_peers(spec, base, dataset, measurement, store, opt, sum, frames);
  sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return sum;
}
}  // namespace parallax::search
