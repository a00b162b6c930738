// What the `parallax` commands share: exit codes, option validators, the configuration options,
// progress and note printing, image loading, the printers of an evaluation result, and the one
// handler of every exception that reaches the top. Each helper exists here once; a helper that
// only one command uses lives in that command's file (commands/).
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include <exception>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "parallax/config/config.hpp"
#include "parallax/eval/evaluate.hpp"
#include "parallax/eval/metrics.hpp"
#include "parallax/search/sweep.hpp"

namespace parallax::cli {

// Exit statuses: 0 success; 2 a user error (bad file, field, value or option); 3 `sim` found a
// deadlock in the cycle model; 70 (EX_SOFTWARE) an internal error, a defect of Parallax. These four
// are listed in `parallax --help`; out of memory exits 1.
constexpr int kExitUserError = 2;
constexpr int kExitDeadlock = 3;
constexpr int kExitInternalError = 70;

// The command line as main() received it: for "reproduce with" lines and for MPI_Init.
struct Invocation {
  int argc = 0;
  char** argv = nullptr;
};

// --- option validators (checked when the command line is parsed, before any work) -------------

// An inclusive range check that NaN cannot pass (CLI::Range tests `v < min || v > max`, which NaN
// passes): the value must parse and lie in [min, max].
template <class T>
CLI::Validator InRange(T min_value, T max_value);

// Where an output file goes. The path must not be a folder, its folder must exist and be
// writable, and an existing file must be writable; "udp:..." (a network destination) passes.
// `extension` (e.g. ".png"), when not empty, is the only one accepted.
CLI::Validator OutputFile(const std::string& extension = "");

// Where an output folder goes: an existing writable folder, or a new one whose nearest existing
// ancestor is a writable folder (never a file).
CLI::Validator OutputFolder();

// --frames: a list of ids and ranges as typed ("1-5,7,000046", "teddy"), or @FILE with one id or
// range per line (blank lines and # comments skipped), turned into the same comma list.
CLI::Validator FrameList();

// --- the design configuration options ----------------------------------------------------------

// --config FILE and the --set KEY=VALUE overrides, as typed.
struct ConfigArgs {
  std::string path;
  std::vector<std::string> sets;
};

// Adds --config (required when `required`) and --set to `cmd`, filling `a`.
void add_config_options(CLI::App* cmd, ConfigArgs& a, bool required);

// --engine fast|kernels: what computes the designs' disparities (sim::FuncEngine; both give the
// same bits). Sets the process default when given; fast otherwise.
void add_engine_option(CLI::App* cmd);

// The configuration with every override applied and validated. Throws ConfigError naming the file
// and every problem (bad override, invalid field) at once.
config::PipelineConfig load_config_args(const ConfigArgs& a);

// --- printing ----------------------------------------------------------------------------------

// Each note on stderr as "parallax: note: NOTE".
void print_notes(const std::vector<std::string>& notes);

// A progress line on stderr: rewritten in place on a terminal, one line per step otherwise;
// empty (no progress) when `quiet`.
std::function<void(int, int, const std::string&)> progress_printer(bool quiet);

// The command as typed, for "reproduce with": "parallax" and the arguments, those with a space or
// a quote in single quotes.
std::string command_line(const Invocation& inv);

// Writes `text` to `path` and says so on stderr ("parallax: wrote PATH"). Throws InputError when
// the file cannot be written.
void write_text_file(const std::string& path, const std::string& text);

// --- evaluation (eval, score, baseline) --------------------------------------------------------

// All hardware threads, at least 1: the default of --threads.
int default_threads();

// The EvalOptions that eval and baseline share. Throws InputError on a bad `gt` kind.
eval::EvalOptions eval_options(const std::string& gt, const std::string& frames, int threads, const std::string& save,
                               double colour_max_px, bool quiet);

// An evaluation on stdout. As JSON (`as_json`): its own form (parallax/eval/json.hpp: pooled
// metrics, frame count, pooled counts, per-frame rows and seconds) with the fields of `extra`
// added. As text: a table under `title`, one row per frame, then the pooled row and the time.
void print_evaluation(const eval::EvalResult& r, bool as_json, const nlohmann::json& extra, const std::string& title);

// --- inputs ------------------------------------------------------------------------------------

// An 8-bit image as grey (colour converted, with a note in `notes`). Throws InputError naming the
// file when it is missing, undecodable, not 8-bit, or has an unusable channel count.
cv::Mat load_grey_file(const std::string& path, const char* role, std::vector<std::string>& notes);

// The design's input pair: the given files cropped to its ROI, or (no files) a seeded test
// pattern of its ROI size. `what` is set to a description of the pair for messages and files.
// Throws InputError when only one file is given, the sizes differ, or the ROI is 'full' without
// files.
void load_pair_or_pattern(const config::PipelineConfig& cfg, const std::string& left_path,
                          const std::string& right_path, std::vector<std::string>& notes, cv::Mat& l, cv::Mat& r,
                          std::string& what);

// The sweep of a store that `name` names, or its only one when `name` is empty; InputError naming
// the store (`db`) otherwise.
search::SweepSpec choose_sweep(search::ResultStore& store, const std::string& db, const std::string& name);

// --- errors ------------------------------------------------------------------------------------

// The one handler of every exception that reaches the top; returns the exit status. User errors
// (UserError, OpenCV and filesystem errors) print one "parallax: error:" line and return 2; out
// of memory returns 1; anything else is a defect of Parallax: 70 with a request for a bug report.
int report_exception(std::exception_ptr ep);

// --- template definitions ----------------------------------------------------------------------

template <class T>
CLI::Validator InRange(T min_value, T max_value) {
  std::ostringstream d;
  d << "in [" << min_value << ", " << max_value << "]";
  return CLI::Validator(
      [min_value, max_value](std::string& input) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(input, v) || !(v >= double(min_value) && v <= double(max_value))) {
          std::ostringstream m;
          m << "value " << input << " is not a number in [" << min_value << ", " << max_value << "]";
          return m.str();
        }
        return {};
      },
      d.str());
}

}  // namespace parallax::cli
