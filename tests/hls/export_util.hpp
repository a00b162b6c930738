// Shared by the HLS export tests: running shell commands, exporting a design with the CLI, and
// reading files.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace parallax::test {

struct Shell {
  int status = -1;
  std::string output;  // stdout and stderr
};

inline Shell shell(const std::string& cmd) {
  Shell r;
  FILE* p = popen(("(" + cmd + ") 2>&1").c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), int(buf.size()), p)) r.output += buf.data();
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline std::filesystem::path fresh_dir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / ("parallax_hls_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  return d;
}

// Exports with the CLI from the source tree (relative paths, so the generated text does not
// depend on where the tree lives). `extra`: more options (e.g. --set ...).
inline Shell export_design(const std::string& config, const std::filesystem::path& out, const std::string& extra = "") {
  return shell(std::string("cd ") + PARALLAX_SOURCE_DIR + " && " + PARALLAX_CLI + " export-hls --config " + config +
               " --left data/kitti2015-640x360/training/image_2/000001_10.png"
               " --right data/kitti2015-640x360/training/image_3/000001_10.png --out " + out.string() + " " + extra);
}

}  // namespace parallax::test
