// parallax config: validate a configuration and print it in canonical form with the derived bit
// widths.
#include <iostream>
#include <memory>

#include "commands.hpp"

namespace parallax::cli {

namespace {

struct ConfigCommandArgs {
  ConfigArgs config;
  bool fields = false;
};

int run_config(const ConfigCommandArgs& a, const Invocation&) {
  if (a.fields) {
    std::cout << config::field_documentation();
    return 0;
  }
  const config::PipelineConfig cfg = load_config_args(a.config);
  std::cout << config::to_yaml(cfg);
  const kern::StereoParams p = cfg.stereo_params(cfg.roi_width_px, cfg.roi_height_px);
  std::cout << "# derived: cost_bits " << kern::cost_bits(p) << ", penalty_bits " << kern::penalty_bits(p)
            << ", path_bits " << kern::path_bits(p) << ", aggregate_bits " << kern::aggregate_bits(p)
            << ", disparity_bits " << kern::disparity_bits(p) << " (invalid code " << kern::invalid_code(p)
            << "); disparities " << cfg.min_disparity << "-" << cfg.disparity_end_px() - 1 << " px\n";
  return 0;
}

}  // namespace

Command add_config(CLI::App& app) {
  auto o = std::make_shared<ConfigCommandArgs>();
  auto* show = app.add_subcommand("config",
                                  "Validate a configuration and print it in canonical form with derived bit widths, "
                                  "or list every field (--fields)");
  // Exactly one of --config and --fields.
  auto* what = show->add_option_group("what", "a design to check, or the list of fields");
  what->add_option("--config", o->config.path, "Design configuration (YAML), e.g. configs/ruf2018-census.yaml");
  what->add_flag("--fields", o->fields,
                 "List every field: its meaning, its values, which stage reads it (cost, aggregate, select, median, "
                 "or system) and whether it is a run-time register; then the rules between fields");
  what->require_option(1);
  show->add_option("--set", o->config.sets, "Override one field, KEY=VALUE (repeatable), e.g. --set p2=64");
  return bind_command(show, o, run_config);
}

}  // namespace parallax::cli
