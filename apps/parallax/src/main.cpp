// parallax: the command-line front end, a dispatcher. Each command lives in commands/ (its
// options, handler and printers); this file builds the app, registers the commands in the
// documented order, parses, runs the one selected, and maps every exception to an exit status
// (cli_common.hpp). Every command has --help; user errors (bad files, bad configurations) print
// one clear message naming the file or field and exit with status 2.
#include <CLI/CLI.hpp>
#include <malloc.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "commands/commands.hpp"

using namespace parallax::cli;

namespace {

constexpr long long kMaxImagePixels = 8192LL * 8192LL;  // 64 Mpx: KITTI is 0.5, Middlebury 2014 full size 6

// The exit statuses (cli_common.hpp), at the end of `parallax --help` (and in the README).
const char* const kExitStatusFooter =
    "Exit status:\n"
    "  0   success\n"
    "  1   out of memory\n"
    "  2   user error: a bad file, field, value or option (one \"parallax: error:\" line names it)\n"
    "  3   parallax sim: the cycle model found a deadlock (the message names the FIFO or stage)\n"
    "  70  internal error: a defect of Parallax (please report it)";

// Parses the command line and runs the selected command; returns the exit status. A command's
// exception propagates to the caller.
int run_cli(int argc, char** argv) {
  CLI::App app{"parallax: bit-accurate simulator and design-space explorer of an FPGA stereo (SGM) pipeline"};
  app.require_subcommand(1);
  // Command-line mistakes read like every other error: one "parallax: error:" line.
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return std::string("parallax: error: ") + e.what() + "\nRun `parallax COMMAND --help` for the options.\n";
  });
  app.set_version_flag("--version", "parallax 0.1.0");

  std::vector<Command> commands;
  for (const auto add : kCommands) commands.push_back(add(app));
  // After the commands: a subcommand copies its parent's footer when it is created, and theirs
  // stay as they were.
  app.footer(kExitStatusFooter);

  if (argc > 1 && argv[1][0] != '-' &&
      std::none_of(commands.begin(), commands.end(), [&](const Command& c) { return c.app->get_name() == argv[1]; })) {
    std::string names;
    for (const Command& c : commands) names += (names.empty() ? "" : ", ") + c.app->get_name();
    std::fprintf(stderr, "parallax: error: unknown command '%s' (commands: %s)\n", argv[1], names.c_str());
    return kExitUserError;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version print and succeed; a malformed command line is a user error (2), as
    // every other bad input is, not CLI11's own codes.
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitUserError;
  }
  const Invocation inv{argc, argv};
  for (const Command& c : commands)
    if (*c.app) return c.run(inv);
  return 0;
}

// Large blocks (kernel instances of the timing run and the resource model, cost volumes, maps)
// are allocated and freed design after design in a sweep. By default glibc maps each block
// above a moving threshold afresh and returns the heap's free top to the system, so every
// allocation's first touch faults its pages again (a one-thread neighbourhood sweep: 580,000
// page faults, 4 s of system time). Keeping freed memory in the process makes the next block
// reuse resident pages (90,000 faults, 0.7 s); the price is resident memory the heap keeps
// between blocks (that sweep's peak 344 -> 400 MiB on one thread, 477 -> 640 MiB on two). Left
// alone when the user tunes the allocator (GLIBC_TUNABLES, MALLOC_*_ variables).
void keep_freed_memory() {
  for (const char* v : {"GLIBC_TUNABLES", "MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_", "MALLOC_TOP_PAD_"})
    if (std::getenv(v) != nullptr) return;
  mallopt(M_MMAP_THRESHOLD, 256 << 20);  // blocks below 256 MiB from the heap, reused when freed
  mallopt(M_TRIM_THRESHOLD, 1 << 30);    // the heap's free top kept up to 1 GiB
}

}  // namespace

int main(int argc, char** argv) {
  // Images are bounded (a forged header must not allocate gigabytes): OpenCV refuses to decode
  // more pixels than this, and the readers name the file. A user's own setting wins.
  setenv("OPENCV_IO_MAX_IMAGE_PIXELS", std::to_string(kMaxImagePixels).c_str(), 0);
  keep_freed_memory();
  try {
    return run_cli(argc, argv);
  } catch (...) {
    return report_exception(std::current_exception());
  }
}
