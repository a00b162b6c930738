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

namespace parallax::explore {

struct Objective {
  std::string key;  // a metric key: correct_3px_pct, density_pct, bram18k, lut, latency_ms, fps, energy_mj_per_frame, ...
  bool maximise = true;
};

struct SweepSpec {
  std::string name = "sweep";
  std::string base;  // configuration file the axes modify
  std::vector<std::pair<std::string, std::vector<std::string>>> axes;  // field -> values, in order
  std::string strategy = "grid";  // grid | random | lhs | nsga2
  int samples = 20;               // random / lhs: designs; nsga2: population size
  int generations = 10;           // nsga2: generations after the first population
  uint32_t seed = 1;
  // Constraints (a design that breaks one is stored, but never on the Pareto front).
  std::string device = "XCZU3EG";  // fits_device is evaluated against it
  bool require_fit = true;
  double min_fps = 0.0;
  double max_latency_ms = 0.0;  // 0: none
  std::vector<Objective> objectives = {{"correct_3px_pct", true}, {"density_pct", true}};
  // Evaluation.
  std::string frames;  // dataset frame filter ("" = all with ground truth)
  bool avoidance = false;  // also score the avoidance stage (obstacle_precision, ..., docs/avoidance.md)
  // Also fly each design through a scenario (docs/flight.md): flight_success_rate,
  // flight_collisions, flight_min_clearance_m, flight_time_to_goal_s. Empty: no flights.
  std::string flight_scenario;
  int flight_seeds = 3;
  double flight_speed_mps = 5.0;
  int flight_size_px = 160;
  std::string gt = "noc";
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
  std::string hash;                  // 16 hex digits
  std::string yaml;
};
MaterialisedDesign materialise(const config::PipelineConfig& base, const DesignPoint& d);

// Results store: SQLite, one transaction per design (a killed process loses at most the design
// it was evaluating, and never writes one twice).
class ResultStore {
 public:
  explicit ResultStore(const std::string& path);  // creates the schema; InputError naming the file
  ~ResultStore();
  ResultStore(const ResultStore&) = delete;
  ResultStore& operator=(const ResultStore&) = delete;

  void put_sweep(const SweepSpec& s);
  bool has_design(const std::string& hash);
  struct Row {
    std::string hash, sweep, config_yaml, status, reason;  // status: ok | invalid | error
    std::map<std::string, double> metrics;                 // pooled accuracy, timing, resources
    std::vector<std::pair<std::string, std::map<std::string, double>>> frames;  // per-frame accuracy
    std::string model_version, started_at, finished_at;
  };
  void put_design(const Row& row);  // one transaction; a second put of a hash is ignored
  // The designs of one sweep ("" = all), in insertion order; with_frames = false leaves each
  // Row::frames empty and skips reading the per-frame table (pareto, NSGA-II, export).
  std::vector<Row> designs(const std::string& sweep = "", bool with_frames = true);
  std::vector<SweepSpec> sweeps();
  int64_t count_designs();
  // Copies every sweep, design and frame of another store that this one lacks (same hash: kept
  // as is). Returns the designs added.
  int64_t merge_from(const std::string& other_path);

 private:
  struct Impl;
  Impl* impl_;
};

// Runs a sweep into the store. jobs: designs evaluated in parallel (0: all cores). progress:
// called after each design with (done, total, skipped).
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
  std::function<void(int done, int total, int skipped)> progress;
};
struct SweepSummary {
  int total = 0, evaluated = 0, skipped = 0, invalid = 0, failed = 0;
  double seconds = 0.0;
  // The first reasons of invalid or failed designs ("design HASH: reason"), at most five.
  std::vector<std::string> first_problems;
};
SweepSummary run_sweep(const SweepSpec& spec, ResultStore& store, const SweepRunOptions& opt);

// The designs of a sweep that meet its constraints and are not dominated on its objectives.
std::vector<ResultStore::Row> pareto_front(const SweepSpec& spec, const std::vector<ResultStore::Row>& rows);
bool meets_constraints(const SweepSpec& spec, const ResultStore::Row& row);

}  // namespace parallax::explore
