// Shared by the tests that drive the CLI or generated projects: run a shell command, capture its
// output (stdout and stderr) and exit status; read a whole file.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace parallax::test {

struct Shell {
  int status = -1;     // exit status; -1 when the command did not exit normally
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

}  // namespace parallax::test
