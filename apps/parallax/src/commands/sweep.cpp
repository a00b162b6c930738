// parallax sweep: evaluate many designs (accuracy, timing, resources) into a SQLite store; reruns
// skip finished designs. Shards (--shard K/N) and, under mpirun, ranks (--mpi) split the designs.
// Exits 2 when no design could be evaluated.
#include <sys/resource.h>
#include <unistd.h>

#ifdef PARALLAX_HAVE_MPI
#include <mpi.h>
#endif

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/search/sweep.hpp"
#include "parallax/uav/scene.hpp"

namespace parallax::cli {

namespace {

// This process's peak resident memory so far (Linux reports ru_maxrss in KiB).
double peak_rss_mib() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return double(ru.ru_maxrss) / 1024.0;
}

using namespace parallax::eval;
using namespace parallax::uav;
using namespace parallax::search;

struct SweepOptions {
  std::string spec, base, dataset, frames, gt, db, strategy, name, flight, shard;
  std::vector<std::string> grid;
  int jobs = 0, samples = 0, generations = 0;
  int flight_seeds = 0, flight_size_px = -1;  // 0 / -1: the file's, else the defaults
  double flight_speed_mps = 0;
  uint32_t seed = 0;
  bool avoidance = false, yes = false, mpi = false, no_sharing = false;
};

// The sweep file (or an empty spec) with the command line's overrides. Throws InputError on a bad
// --gt or --strategy.
SweepSpec sweep_spec(const SweepOptions& o) {
  SweepSpec spec = o.spec.empty() ? SweepSpec{} : load_sweep(o.spec);
  if (!o.base.empty()) spec.base = o.base;
  for (const auto& g : o.grid) add_axis(spec, g);
  if (!o.frames.empty()) spec.frames = o.frames;
  if (!o.gt.empty()) {
    if (o.gt != "noc" && o.gt != "occ") throw InputError("--gt '" + o.gt + "': expected noc or occ");
    spec.gt = o.gt;
  }
  if (!o.strategy.empty()) {
    if (o.strategy != "grid" && o.strategy != "random" && o.strategy != "lhs" && o.strategy != "nsga2")
      throw InputError("--strategy '" + o.strategy + "': expected grid, random, lhs or nsga2");
    spec.strategy = o.strategy;
  }
  if (o.samples > 0) spec.samples = o.samples;
  if (o.generations > 0) spec.generations = o.generations;
  if (o.seed > 0) spec.seed = o.seed;
  if (!o.name.empty()) spec.name = o.name;
  if (o.avoidance) spec.avoidance = true;
  if (!o.flight.empty()) spec.flight_scenario = o.flight;
  if (o.flight_seeds > 0) spec.flight_seeds = o.flight_seeds;
  if (o.flight_speed_mps > 0) spec.flight_speed_mps = o.flight_speed_mps;
  if (o.flight_size_px >= 0) spec.flight_size_px = o.flight_size_px;
  return spec;
}

// --shard K/N into the run options. Throws InputError unless 1 <= K <= N.
void parse_shard(const std::string& shard, SweepRunOptions& ro) {
  const auto slash = shard.find('/');
  try {
    if (slash == std::string::npos) throw std::invalid_argument("no slash");
    ro.shard_index = std::stoi(shard.substr(0, slash));
    ro.shard_count = std::stoi(shard.substr(slash + 1));
  } catch (const std::exception&) {
    throw InputError("--shard '" + shard + "': expected K/N, e.g. 2/8");
  }
  if (ro.shard_count < 1 || ro.shard_index < 1 || ro.shard_index > ro.shard_count)
    throw InputError("--shard '" + shard + "': expected 1 <= K <= N");
}

// The sweep's progress on stderr with an ETA from the designs evaluated so far: a bar rewritten in
// place on a terminal, one line per design otherwise.
std::function<void(int, int, int)> sweep_progress() {
  const bool tty = isatty(fileno(stderr)) != 0;
  const auto t0 = std::chrono::steady_clock::now();
  return [tty, t0](int done, int total, int settled) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const int worked = done - settled;
    // Before the first design is evaluated (invalid and stored ones settle at once) there is no
    // rate to extrapolate from.
    char eta[48];
    if (worked > 0)
      std::snprintf(eta, sizeof eta, "ETA %.0f s", s / worked * double(total - done));
    else
      std::snprintf(eta, sizeof eta, "ETA unknown");
    if (tty) {
      const int width = 30, filled = total > 0 ? done * width / total : width;
      std::fprintf(stderr, "\r[%s%s] %d/%d designs (%d stored or invalid), %s   ",
                   std::string(std::size_t(filled), '#').c_str(), std::string(std::size_t(width - filled), '.').c_str(),
                   done, total, settled, eta);
      if (done == total) std::fprintf(stderr, "\n");
    } else {
      std::fprintf(stderr, "parallax: sweep %d/%d designs (%d stored or invalid), %s\n", done, total, settled, eta);
    }
  };
}

int run_sweep_command(const SweepOptions& o, const Invocation& inv) {
  const SweepSpec spec = sweep_spec(o);
  SweepRunOptions ro;
  ro.allow_large = o.yes;
  // The spec is checked before the store is opened: a bad axis, value or objective touches no file.
  if (spec.base.empty()) throw InputError("sweep '" + spec.name + "': no base configuration (field 'base' or --base)");
  check_sweep_spec(spec, config::load_config(spec.base), ro.allow_large);
  // A missing or unknown dataset folder, and a frame filter that selects nothing, too.
  (void)list_frames(open_dataset(o.dataset), parse_gt_kind(spec.gt), spec.frames);
  ro.dataset = o.dataset;
  ro.jobs = o.jobs;
  ro.share_costs = !o.no_sharing;
  if (!o.shard.empty()) parse_shard(o.shard, ro);
  std::string db_path = o.db;
  int mpi_rank = 0, mpi_size = 1;
#ifdef PARALLAX_HAVE_MPI
  int argc = inv.argc;
  char** argv = inv.argv;
  if (o.mpi) {
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &mpi_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &mpi_size);
    ro.shard_index = mpi_rank + 1;
    ro.shard_count = mpi_size;
    db_path = o.db + ".rank" + std::to_string(mpi_rank);
  }
#endif
  (void)inv;
  ResultStore store(db_path);
  ro.progress = sweep_progress();
  const SweepSummary sum = run_sweep(spec, store, ro);
  std::printf(
      "sweep '%s'%s: %d designs: %d evaluated (%d invalid, %d failed), %d already in %s; %.1f s\n", spec.name.c_str(),
      ro.shard_count > 1 ? (" shard " + std::to_string(ro.shard_index) + "/" + std::to_string(ro.shard_count)).c_str()
                         : "",
      sum.total, sum.evaluated + sum.invalid, sum.invalid, sum.failed, sum.skipped, db_path.c_str(), sum.seconds);
  // The throughput figure (docs/benchmarks.md): design-frames scored per hour of this run.
  if (sum.design_frames > 0 && sum.seconds > 0)
    std::printf("%lld design-frames in %.1f s: %.0f design-frames per hour on %d thread%s; peak memory %.0f MiB\n",
                static_cast<long long>(sum.design_frames), sum.seconds,
                double(sum.design_frames) * 3600.0 / sum.seconds, sum.threads, sum.threads == 1 ? "" : "s",
                peak_rss_mib());
  for (const auto& p : sum.first_problems) std::fprintf(stderr, "parallax: %s\n", p.c_str());
  const bool all_failed = sum.total > 0 && sum.skipped == 0 && sum.invalid + sum.failed >= sum.evaluated + sum.invalid;
#ifdef PARALLAX_HAVE_MPI
  if (o.mpi) {
    MPI_Barrier(MPI_COMM_WORLD);
    if (mpi_rank == 0) {
      ResultStore merged(o.db);
      int64_t added = 0;
      for (int r = 0; r < mpi_size; ++r) added += merged.merge_from(o.db + ".rank" + std::to_string(r));
      std::printf("merged %d ranks into %s: %lld designs added\n", mpi_size, o.db.c_str(), (long long)added);
    }
    MPI_Finalize();
  }
#endif
  (void)mpi_size;
  if (all_failed) {
    std::fprintf(stderr, "parallax: error: sweep '%s': no design could be evaluated (the first reasons are above)\n",
                 spec.name.c_str());
    return kExitUserError;
  }
  return 0;
}

}  // namespace

Command add_sweep(CLI::App& app) {
  auto o = std::make_shared<SweepOptions>();
  auto* sweepc = app.add_subcommand(
      "sweep", "Evaluate many designs (accuracy, timing, resources) into a SQLite store; reruns skip finished designs");
  sweepc->add_option("spec", o->spec,
                     "Sweep file (YAML, docs/explorer.md); optional when --base and --grid say it all");
  sweepc->add_option("--base", o->base, "Base configuration the axes modify (overrides the file's)");
  sweepc->add_option("--grid", o->grid, "Axis KEY=V1,V2,... over any configuration field (repeatable)");
  add_engine_option(sweepc);
  sweepc->add_option("--dataset", o->dataset, "Dataset folder (KITTI 2015/2012, Middlebury)")->required();
  sweepc->add_option("--frames", o->frames, "Frame filter, e.g. 0-9,15, or @FILE (default: the file's, else all)")
      ->transform(FrameList());
  sweepc->add_option("--gt", o->gt, "Ground truth: noc or occ (default: the file's, else noc)");
  sweepc->add_option("--db", o->db, "Results store (SQLite); created if absent")->required();
  sweepc->add_option("--threads,--jobs", o->jobs, "Designs in parallel (default: all cores; --jobs: the same)")
      ->check(InRange(0, 256));
  sweepc->add_option("--strategy", o->strategy, "grid, random, lhs or nsga2 (default: the file's, else grid)");
  sweepc->add_option("--samples", o->samples, "Designs drawn by random / lhs; population of nsga2")
      ->check(InRange(1, 1000000));
  sweepc->add_option("--generations", o->generations, "Generations of nsga2 after the first population")
      ->check(InRange(1, 10000));
  sweepc->add_option("--seed", o->seed, "Seed of random / lhs");
  sweepc->add_option("--name", o->name, "Sweep name in the store (default: the file's, else 'sweep')");
  sweepc->add_option("--flight", o->flight,
                     "Also fly every design through this scenario (3 seeds at 5 m/s at the design's own size unless "
                     "told); " +
                         scenario_option_help());
  sweepc->add_option("--flight-seeds", o->flight_seeds, "Flights per design (seeds 1..N; default: the file's, else 3)")
      ->check(InRange(1, 10000));
  sweepc->add_option("--flight-speed-mps", o->flight_speed_mps, "Flight cruise speed (default: the file's, else 5)")
      ->check(InRange(0.1, 50.0));
  sweepc
      ->add_option("--flight-size", o->flight_size_px,
                   "Fly with the rig scaled to this image width (0: the design's own region of interest, the "
                   "default; e.g. 160 for a quick look, with the design's timing and range at that size)")
      ->check(CLI::Range(0, 0) | InRange(64, 4096));
  sweepc->add_flag("--avoidance", o->avoidance,
                   "Also score the avoidance stage on every design (obstacle_precision, ...)");
  sweepc->add_flag("--yes", o->yes,
                   "Run a sweep of more than 10,000 designs (otherwise refused: sample with lhs or nsga2)");
  sweepc->add_flag(
      "--no-sharing", o->no_sharing,
      "Evaluate every design on its own (by default designs sharing the cost stage share each frame's costs)");
  sweepc->add_option("--shard", o->shard, "K/N: evaluate only shard K of N (merge the stores with `parallax merge`)");
#ifdef PARALLAX_HAVE_MPI
  sweepc->add_flag("--mpi", o->mpi,
                   "Under mpirun: rank r evaluates shard r+1 of the ranks into DB.rank<r>; rank 0 merges them into DB");
#endif
  return bind_command(sweepc, o, run_sweep_command);
}

}  // namespace parallax::cli
