// parallax config: validate a configuration and print it in canonical form with the derived bit
// widths.
#include <iostream>
#include <memory>

#include "commands.hpp"

namespace parallax::cli {

namespace {

int run_config(const ConfigArgs& o, const Invocation&) {
  const config::PipelineConfig cfg = load_config_args(o);
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
  auto o = std::make_shared<ConfigArgs>();
  auto* show =
      app.add_subcommand("config", "Validate a configuration and print it in canonical form with derived bit widths");
  add_config_options(show, *o, true);
  return bind_command(show, o, run_config);
}

}  // namespace parallax::cli
