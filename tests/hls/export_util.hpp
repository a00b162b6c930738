// Shared by the HLS export tests: fresh folders and exporting a design with the CLI.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

#include "../common/shell.hpp"

namespace parallax::test {

inline std::filesystem::path fresh_dir(const std::string& name) {
  const auto d =
      std::filesystem::temp_directory_path() / ("parallax_hls_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  return d;
}

// Exports with the CLI from the source tree (relative paths, so the generated text does not
// depend on where the tree lives). `extra`: more options (e.g. --set ...).
inline Shell export_design(const std::string& config, const std::filesystem::path& out, const std::string& extra = "") {
  return shell(std::string("cd ") + PARALLAX_SOURCE_DIR + " && " + PARALLAX_CLI + " export-hls --config " + config +
               " --left data/kitti2015-640x360/training/image_2/000001_10.png"
               " --right data/kitti2015-640x360/training/image_3/000001_10.png --out " +
               out.string() + " " + extra);
}

}  // namespace parallax::test
