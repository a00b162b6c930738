// Design-space sweeps (`parallax sweep`, `parallax pareto`): a base configuration, axes over any
// configuration field, a strategy that picks the designs, constraints and objectives; every
// design is evaluated for accuracy (func run on a dataset), timing (the cycle model's schedule,
// once per design: it does not depend on the images) and resources, and stored in SQLite so that
// a rerun skips finished work. docs/explorer.md.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "parallax/config/config.hpp"

namespace parallax::search {

struct Objective {
  std::string
      key;  // a metric key: correct_3px_pct, density_pct, bram18k, lut, latency_ms, fps, energy_mj_per_frame, ...
  bool maximise = true;
};

struct SweepSpec {
  std::string name = "sweep";
  std::string base;                                                    // configuration file the axes modify
  std::vector<std::pair<std::string, std::vector<std::string>>> axes;  // field -> values, in order
  std::string strategy = "grid";                                       // grid | random | lhs | nsga2 | list
  int samples = 20;                                                    // random / lhs: designs; nsga2: population size
  int generations = 10;                                                // nsga2: generations after the first population
  uint32_t seed = 1;
  // Constraints (a design that breaks one is stored, but never on the Pareto front).
  std::string device = "XCZU3EG";  // fits_device is evaluated against it
  bool require_fit = true;
  double min_fps = 0.0;
  double max_latency_ms = 0.0;  // 0: none
  bool one_pass = false;        // no second pass through a DDR frame buffer (metric passes = 1)
  std::vector<Objective> objectives = {{"correct_3px_pct", true}, {"density_pct", true}};
  // Evaluation.
  std::string frames;      // dataset frame filter ("" = all with ground truth)
  bool avoidance = false;  // also score the avoidance stage (obstacle_precision, ..., docs/avoidance.md)
  // Also fly each design through a scenario (docs/flight.md): flight_success_rate,
  // flight_collisions, flight_min_clearance_m, flight_time_to_goal_s. Empty: no flights.
  std::string flight_scenario;
  int flight_seeds = 3;
  double flight_speed_mps = 5.0;
  int flight_size_px = 0;  // the rig scaled to this width; 0: the design's own window (FlightParams::width_px)
  std::string gt = "noc";
  // Peers measured on the same frames and crops and stored beside the designs (status peer:
  // ResultStore::peers), with the base design itself as the seed: opencv-hh4, opencv-sgbm.
  std::vector<std::string> baselines;
  // Strategy list: the designs, each the fields it sets over the base (axes then hold the fields
  // and values they use, for checking and reports).
  std::vector<std::vector<std::pair<std::string, std::string>>> designs;
};

// Reads a sweep file (YAML, docs/explorer.md). Throws InputError naming the file and the field.
SweepSpec load_sweep(const std::string& path);
SweepSpec parse_sweep(const std::string& yaml_text, const std::string& source_name);
std::string sweep_to_yaml(const SweepSpec& s);
// "KEY=V1,V2,..." from --grid: replaces or appends the axis. InputError when malformed.
void add_axis(SweepSpec& s, const std::string& key_equals_values);

// The metric keys a design's row can carry (accuracy, timing, resources, and with the spec's
// avoidance or flight the keys those add): what objectives may name.
std::vector<std::string> metric_names(const SweepSpec& s);
// The designs the spec asks for before duplicates are removed: the grid's product, the samples
// of random / lhs, nsga2's population times its generations plus one.
double requested_designs(const SweepSpec& s);
constexpr double kLargeSweepDesigns = 10000;  // more needs SweepRunOptions::allow_large (--yes)
// Checks a spec against its base configuration before any design runs: every axis names a
// configuration field and each of its values is a valid value of that field on its own; every
// objective names a metric; no more than kLargeSweepDesigns designs unless allow_large. Throws
// InputError naming the axis, value or objective.
void check_sweep_spec(const SweepSpec& s, const config::PipelineConfig& base, bool allow_large);

// One point of the space: the field values that differ from the base.
struct DesignPoint {
  std::vector<std::pair<std::string, std::string>> fields;
};
// The designs the strategy picks, in a fixed order (grid: odometer order, last axis fastest;
// random / lhs: seeded, duplicates removed).
std::vector<DesignPoint> enumerate_designs(const SweepSpec& s);

// A design's configuration (base + fields), its validation errors, and its identity: a hash of
// the canonical YAML of the configuration.
struct MaterialisedDesign {
  config::PipelineConfig config;
  std::vector<std::string> errors;  // empty when valid
  std::string hash;                 // 16 hex digits
  std::string yaml;
};
MaterialisedDesign materialise(const config::PipelineConfig& base, const DesignPoint& d);

// What a result was measured on: the dataset (absolute path), the frames the filter selected,
// the ground-truth kind, everything else of the sweep that changes the metrics (device, avoidance,
// flight) and the results contract (kResultsContract and the models' version). Canonical JSON:
// equal text, equal measurement. Results are keyed by the design AND by this (result_key).
constexpr const char* kResultsContract = "parallax-results/2";
std::string measurement_of(const SweepSpec& s, const std::string& dataset_dir,
                           const std::vector<std::string>& frame_ids);
// "HASH@CONTEXT": the design hash, then a hash of the measurement.
std::string result_key(const std::string& design_hash, const std::string& measurement);

// Results store: SQLite (schema in docs/explorer.md, "The store"). One transaction per design: a
// killed process loses at most the designs it was evaluating, and never writes one twice.
// Results are keyed by design and measurement; each sweep name lists its own results (a table
// of sweep -> result keys); only successful evaluations (and invalid designs) are reused, a
// failed one is evaluated again by the next run. Concurrent sweeps on one store share work:
// a design is claimed (owner: host, pid, process start time) before it is evaluated, others
// wait for it, and the claim of a process that died is taken over. Lock waits are retried
// without limit and reported on stderr ("waiting for lock on FILE") once they last longer than
// lock_notice_ms (default 2000; environment PARALLAX_LOCK_NOTICE_MS).
class ResultStore {
 public:
  enum class Access {
    write,  // sweep, merge: create the store if the path is absent (or an empty file)
    read,   // pareto, report, export-hls: opened read-only, never created or altered
  };
  // InputError naming the file: not found (read), not an SQLite file, an SQLite file that is not
  // a Parallax store, a store of an older schema (refused: rerun into a new store), or one made by
  // a newer Parallax.
  explicit ResultStore(const std::string& path, Access access = Access::write);
  ~ResultStore();  // releases the claims this store still holds
  ResultStore(const ResultStore&) = delete;
  ResultStore& operator=(const ResultStore&) = delete;
  const std::string& path() const;

  // Records the sweep (its spec, the dataset folder and the measurement). Returns true when the
  // sweep existed with another measurement: its name now lists only the new measurement's
  // results (the earlier results stay in the store, reusable by a sweep measured like them).
  bool put_sweep(const SweepSpec& s, const std::string& dataset_dir = "", const std::string& measurement = "");
  // The dataset folder the sweep was last run on ("" when unknown).
  std::string sweep_dataset(const std::string& sweep);
  // A reusable result: status ok or invalid (a failed evaluation is not reused).
  bool has_result(const std::string& key);
  struct Row {
    std::string hash, sweep, config_yaml, status, reason;  // status: ok | invalid | error
    std::map<std::string, double> metrics;                 // pooled accuracy, timing, resources; finite only
    std::vector<std::pair<std::string, std::map<std::string, double>>> frames;  // per-frame accuracy
    std::string model_version, started_at, finished_at;
    std::string measurement;  // measurement_of(...) ("" = unknown)
    std::string key;          // result_key(hash, measurement); put_design fills it when empty
  };
  // One transaction: the row, its frames, its sweep's membership, and the end of its claim. A
  // reusable row of the same key is kept (the put only adds the membership; returns false); a
  // failed one is replaced. Non-finite metrics are stored as absent.
  bool put_design(const Row& row);
  void add_member(const std::string& sweep, const std::string& key);
  // Claims before evaluating, one transaction for the batch: mine (evaluate it), reusable (a
  // result exists), or busy (a live process claimed it; wait, then ask again).
  enum class Claim { mine, reusable, busy };
  std::vector<Claim> claim(const std::vector<std::string>& keys);
  void release(const std::string& key);
  // The results of one sweep ("" = every result), in insertion order; with_frames = false leaves
  // each Row::frames empty and skips reading the per-frame table (pareto, NSGA-II, export). A row
  // whose stored metrics cannot be read (not JSON, not numbers) is returned as status error with
  // the reason, and a warning naming the store and the row goes to stderr.
  std::vector<Row> designs(const std::string& sweep = "", bool with_frames = true);
  // The peers stored beside a sweep's designs (SweepSpec::baselines): rows of status peer whose
  // config_yaml names the method and its parameters, measured as the sweep was last run.
  std::vector<Row> peers(const std::string& sweep);
  std::vector<SweepSpec> sweeps();
  int64_t count_designs();
  // Copies every sweep, result, membership and frame of another store that this one lacks (same
  // key: kept as is, a failed result replaced by a reusable one). Returns the results added.
  int64_t merge_from(const std::string& other_path);

  struct Impl;  // store.cpp

 private:
  std::vector<Row> rows_of(const std::string& sweep, bool with_frames, bool peers);
  Impl* impl_;
};

// Runs a sweep into the store. jobs: designs evaluated in parallel (0: all cores). progress:
// called after each design with (done, total, settled).
struct SweepRunOptions {
  std::string dataset;
  int jobs = 0;
  // Shard K of N (1 <= K <= N): only the designs whose index in the strategy's order is
  // K - 1 modulo N. Shards of one sweep are disjoint and together the whole sweep.
  int shard_index = 1, shard_count = 1;
  // Designs that share the cost stage (sim::cost_sharing_key) are evaluated together: each frame
  // is decoded once and its matching costs computed once for all of them. Same results.
  bool share_costs = true;
  // More than kLargeSweepDesigns designs are run only when this is set (the CLI's --yes).
  bool allow_large = false;
  // settled: the designs among `done` that needed no evaluation (already stored, duplicates,
  // invalid), so that a rate or ETA counts the evaluated ones alone.
  std::function<void(int done, int total, int settled)> progress;
};
struct SweepSummary {
  std::vector<std::string> notes;  // for the user (e.g. the sweep's measurement changed), also on stderr
  int total = 0, evaluated = 0, skipped = 0, invalid = 0, failed = 0;
  int threads = 0;            // the threads the designs were evaluated on
  int64_t design_frames = 0;  // frames scored over the designs this run evaluated (one design x one frame each)
  double seconds = 0.0;
  // The first reasons of invalid or failed designs ("design HASH: reason"), at most five.
  std::vector<std::string> first_problems;
};
SweepSummary run_sweep(const SweepSpec& spec, ResultStore& store, const SweepRunOptions& opt);

// A peer's method from its stored description ("baseline: NAME"; its hash when there is none).
std::string peer_name(const ResultStore::Row& peer);
// How many of `designs` beat `reference` on both accuracy figures: at least as good on correct
// pixels and density, better on one (a missing figure beats nothing and is beaten by nothing).
int beaten_on_accuracy_by(const ResultStore::Row& reference, const std::vector<ResultStore::Row>& designs);

// The hash of the sweep's base design as a sweep stores it (the seed its peers stand beside); ""
// when the base configuration cannot be read any more.
std::string seed_hash(const SweepSpec& spec);

// The designs of a sweep that meet its constraints and are not dominated on its objectives. A
// design without a metric (absent or not finite) ranks last on it: it fails a constraint on it,
// and its objective value is -infinity (objective_value; larger is better).
std::vector<ResultStore::Row> pareto_front(const SweepSpec& spec, const std::vector<ResultStore::Row>& rows);
bool meets_constraints(const SweepSpec& spec, const ResultStore::Row& row);
double objective_value(const ResultStore::Row& row, const Objective& objective);

}  // namespace parallax::search
