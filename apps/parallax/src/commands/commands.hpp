// The `parallax` commands: one file each in this folder. A command's add_X registers its CLI11
// subcommand on `app` (options, help texts, defaults, validators) and returns it bound to its
// handler; main() registers them in kCommands' order, parses, and runs the one selected.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <memory>

#include "../cli_common.hpp"

namespace parallax::cli {

// A registered subcommand: the CLI11 App its options are parsed into, and its handler, which
// reads the parsed options and returns the exit status (it may throw; main maps the exception
// through report_exception).
struct Command {
  CLI::App* app = nullptr;
  std::function<int(const Invocation&)> run;
};

// Binds a command's handler to the options its subcommand `app` parses into (`options` lives as
// long as the returned Command).
template <class Options>
Command bind_command(CLI::App* app, std::shared_ptr<Options> options,
                     int (*handler)(const Options&, const Invocation&)) {
  return {app, [options, handler](const Invocation& inv) { return handler(*options, inv); }};
}

Command add_run(CLI::App& app);
Command add_eval(CLI::App& app);
Command add_score(CLI::App& app);
Command add_baseline(CLI::App& app);
Command add_config(CLI::App& app);
Command add_crop_dataset(CLI::App& app);
Command add_bench(CLI::App& app);
Command add_sim(CLI::App& app);
Command add_sweep(CLI::App& app);
Command add_merge(CLI::App& app);
Command add_pareto(CLI::App& app);
Command add_report(CLI::App& app);
Command add_avoid(CLI::App& app);
Command add_scene(CLI::App& app);
Command add_fly(CLI::App& app);
Command add_export_hls(CLI::App& app);
Command add_import_hls(CLI::App& app);
Command add_fit_resources(CLI::App& app);

// The commands in the order `parallax --help` lists them (and the unknown-command message).
inline constexpr Command (*kCommands[])(CLI::App&) = {
    add_run,   add_eval,  add_score, add_baseline,   add_config,     add_crop_dataset,
    add_bench, add_sim,   add_sweep, add_merge,      add_pareto,     add_report,
    add_avoid, add_scene, add_fly,   add_export_hls, add_import_hls, add_fit_resources,
};

}  // namespace parallax::cli
