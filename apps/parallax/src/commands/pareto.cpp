// parallax pareto: the non-dominated designs of a sweep that meet its constraints.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "parallax/search/json.hpp"
#include "parallax/search/sweep.hpp"

namespace parallax::cli {

namespace {

using nlohmann::json;
using namespace parallax::eval;
using namespace parallax::search;

struct ParetoOptions {
  std::string db, sweep;
  bool json = false;
};

// The front as text on stdout: how many designs are stored, meet the constraints and are on the
// front, then one row per front design with its objectives, fps and BRAM ("-" where missing).
void print_front_text(const SweepSpec& spec, const std::vector<ResultStore::Row>& rows,
                      const std::vector<ResultStore::Row>& front) {
  int meets = 0;
  for (const auto& r : rows) meets += meets_constraints(spec, r) ? 1 : 0;
  std::printf("sweep '%s': %zu designs stored, %d meet the constraints, %zu on the front\n", spec.name.c_str(),
              rows.size(), meets, front.size());
  std::printf("objectives:");
  for (const auto& o : spec.objectives) std::printf(" %s %s", o.maximise ? "max" : "min", o.key.c_str());
  std::printf("\n\n%-18s %-40s", "hash", "design");
  for (const auto& o : spec.objectives) std::printf(" %16s", o.key.c_str());
  std::printf(" %8s %8s\n", "fps", "bram18k");
  for (const auto& r : front) {
    std::string name;
    const auto pos = r.config_yaml.find("name: ");
    if (pos != std::string::npos) name = r.config_yaml.substr(pos + 6, r.config_yaml.find('\n', pos) - pos - 6);
    std::printf("%-18s %-40s", r.hash.c_str(), name.substr(0, 40).c_str());
    auto cell = [&](const std::string& k, int width, int decimals) {  // a missing metric: "-"
      if (r.metrics.count(k))
        std::printf(" %*.*f", width, decimals, r.metrics.at(k));
      else
        std::printf(" %*s", width, "-");
    };
    for (const auto& o : spec.objectives) cell(o.key, 16, 3);
    cell("fps", 8, 1);
    cell("bram18k", 8, 0);
    std::printf("\n");
  }
}

// The seed and the peers stored beside the sweep (SweepSpec::baselines), with the front designs
// that beat each on both accuracy figures.
void print_references(const SweepSpec& spec, const std::vector<ResultStore::Row>& rows,
                      const std::vector<ResultStore::Row>& front, const std::vector<ResultStore::Row>& peers) {
  if (peers.empty()) return;
  auto line = [&](const std::string& what, const ResultStore::Row& r) {
    const auto c = r.metrics.find("correct_3px_pct"), d = r.metrics.find("density_pct");
    std::printf("%-30s correct %6.2f %%  density %6.2f %%  beaten on both by %d front design(s)\n", what.c_str(),
                c == r.metrics.end() ? std::nan("") : c->second, d == r.metrics.end() ? std::nan("") : d->second,
                beaten_on_accuracy_by(r, front));
  };
  std::printf("\nreferences on the same frames:\n");
  const std::string seed = seed_hash(spec);
  for (const auto& r : rows)
    if (!seed.empty() && r.hash == seed) line("seed (" + spec.base + ")", r);
  for (const auto& p : peers) line(peer_name(p), p);
}

int run_pareto(const ParetoOptions& o, const Invocation&) {
  ResultStore store(o.db, ResultStore::Access::read);
  const SweepSpec spec = choose_sweep(store, o.db, o.sweep);
  const auto rows = store.designs(spec.name, false);
  const auto front = pareto_front(spec, rows);
  if (o.json)
    std::cout << json(front).dump(2) << "\n";  // hash, configuration, metrics (parallax/search/json.hpp)
  else {
    print_front_text(spec, rows, front);
    print_references(spec, rows, front, store.peers(spec.name));
  }
  return 0;
}

}  // namespace

Command add_pareto(CLI::App& app) {
  auto o = std::make_shared<ParetoOptions>();
  auto* paretoc = app.add_subcommand("pareto", "The non-dominated designs of a sweep that meet its constraints");
  paretoc->add_option("--db", o->db, "Results store")->required();
  paretoc->add_option("--sweep", o->sweep, "Sweep name (default: the only one in the store)");
  paretoc->add_flag("--json", o->json, "Print JSON: a list of designs with configuration and metrics");
  return bind_command(paretoc, o, run_pareto);
}

}  // namespace parallax::cli
