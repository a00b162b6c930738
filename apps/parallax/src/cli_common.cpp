// What the `parallax` commands share (cli_common.hpp).
#include "cli_common.hpp"

#include "parallax/sim/func.hpp"

#include <unistd.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <new>
#include <thread>
#include <utility>

#include "parallax/config/user_error.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/disparity_io.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/eval/json.hpp"
#include "parallax/eval/simulate.hpp"

namespace parallax::cli {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace parallax::eval;
using namespace parallax::search;

CLI::Validator OutputFile(const std::string& extension) {
  return CLI::Validator(
      [extension](std::string& path) -> std::string {
        if (path.empty()) return "an empty path";
        if (path.rfind("udp:", 0) == 0) return {};  // a network destination (--mavlink-out)
        const fs::path p(path);
        std::error_code ec;
        if (fs::is_directory(p, ec)) return "'" + path + "' is a folder; give a file name";
        const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
        if (!fs::exists(dir, ec)) return "folder '" + dir.string() + "' (of " + path + ") does not exist";
        if (!fs::is_directory(dir, ec)) return "'" + dir.string() + "' (of " + path + ") is not a folder";
        if (access(dir.c_str(), W_OK) != 0) return "cannot write in folder '" + dir.string() + "'";
        if (fs::exists(p, ec) && access(p.c_str(), W_OK) != 0) return "'" + path + "' is not writable";
        if (!extension.empty()) {
          std::string ext = p.extension().string();
          for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
          if (ext != extension) return "'" + path + "' must end in " + extension;
        }
        return {};
      },
      extension.empty() ? "FILE" : "FILE" + extension);
}

CLI::Validator OutputFolder() {
  return CLI::Validator(
      [](std::string& path) -> std::string {
        if (path.empty()) return "an empty path";
        const fs::path p(path);
        std::error_code ec;
        if (fs::exists(p, ec)) {
          if (!fs::is_directory(p, ec)) return "'" + path + "' is a file, not a folder";
          if (access(p.c_str(), W_OK) != 0) return "cannot write in folder '" + path + "'";
          return {};
        }
        fs::path dir = p.parent_path();
        while (!dir.empty() && !fs::exists(dir, ec)) dir = dir.parent_path();  // folders are created
        if (dir.empty()) dir = ".";
        if (!fs::is_directory(dir, ec)) return "'" + dir.string() + "' (of " + path + ") is not a folder";
        if (access(dir.c_str(), W_OK) != 0)
          return "cannot create '" + path + "': folder '" + dir.string() + "' is not writable";
        return {};
      },
      "DIR");
}

CLI::Validator FrameList() {
  return CLI::Validator(
      [](std::string& arg) -> std::string {
        if (arg.empty() || arg[0] != '@') return {};
        const std::string path = arg.substr(1);
        std::string text;
        try {
          text = config::read_text_file(path, "frame list", std::size_t(1) << 20);
        } catch (const config::ConfigError& e) {
          return e.what();
        }
        std::istringstream in(text);
        std::string line, out;
        int line_no = 0;
        while (std::getline(in, line)) {
          ++line_no;
          const auto hash = line.find('#');
          if (hash != std::string::npos) line.resize(hash);
          const auto b = line.find_first_not_of(" \t\r"), e = line.find_last_not_of(" \t\r");
          if (b == std::string::npos) continue;
          const std::string id = line.substr(b, e - b + 1);
          if (id.find_first_of(" \t,") != std::string::npos)
            return path + ": line " + std::to_string(line_no) + ": one frame id or range per line, got '" + id + "'";
          out += (out.empty() ? "" : ",") + id;
        }
        if (out.empty()) return path + ": no frame id in the file";
        arg = out;
        return {};
      },
      "LIST|@FILE");
}

void add_config_options(CLI::App* cmd, ConfigArgs& a, bool required) {
  auto* opt = cmd->add_option("--config", a.path, "Design configuration (YAML), e.g. configs/ruf2018-census.yaml");
  if (required) opt->required();
  cmd->add_option("--set", a.sets, "Override one field, KEY=VALUE (repeatable), e.g. --set p2=64");
}

void add_engine_option(CLI::App* cmd) {
  cmd->add_option_function<std::string>(
         "--engine",
         [](const std::string& v) {
           sim::FuncEngine e = sim::FuncEngine::fast;
           if (!sim::parse_func_engine(v, e))
             throw CLI::ValidationError("--engine", "expected fast or kernels, got '" + v + "'");
           sim::set_default_func_engine(e);
         },
         "What computes the disparities: fast (whole rows, SIMD; the default) or kernels (the HLS kernels "
         "fired one by one); both give the same bits")
      ->check(CLI::IsMember({"fast", "kernels"}));
}

config::PipelineConfig load_config_args(const ConfigArgs& a) {
  config::PipelineConfig c = config::load_config(a.path);
  std::vector<std::string> problems;
  for (const auto& kv : a.sets) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos) {
      problems.push_back("--set '" + kv + "': expected KEY=VALUE");
      continue;
    }
    try {
      config::set_field(c, kv.substr(0, eq), kv.substr(eq + 1));
    } catch (const config::ConfigError& e) {
      problems.push_back(std::string("--set: ") + e.what());
    }
  }
  for (const auto& fe : config::validate(c)) problems.push_back("field '" + fe.field + "': " + fe.message);
  if (!problems.empty()) {
    std::string msg = a.path + " with overrides: invalid configuration:";
    for (const auto& p : problems) msg += "\n  - " + p;
    throw config::ConfigError(msg);
  }
  return c;
}

void print_notes(const std::vector<std::string>& notes) {
  for (const auto& n : notes) std::fprintf(stderr, "parallax: note: %s\n", n.c_str());
}

std::function<void(int, int, const std::string&)> progress_printer(bool quiet) {
  if (quiet) return {};
  const bool tty = isatty(STDERR_FILENO) != 0;
  return [tty](int done, int total, const std::string& id) {
    if (tty) {
      std::fprintf(stderr, "\r[%d/%d] %s   ", done, total, id.c_str());
      if (done == total) std::fprintf(stderr, "\n");
    } else {
      std::fprintf(stderr, "[%d/%d] %s\n", done, total, id.c_str());
    }
  };
}

std::string command_line(const Invocation& inv) {
  std::string s = "parallax";
  for (int i = 1; i < inv.argc; ++i) {
    const std::string a = inv.argv[i];
    s += " " + (a.find_first_of(" '\"") == std::string::npos ? a : "'" + a + "'");
  }
  return s;
}

void write_text_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw InputError(path + ": cannot write");
  out << text;
  if (!out) throw InputError(path + ": write failed");
  std::fprintf(stderr, "parallax: wrote %s\n", path.c_str());
}

int default_threads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : int(n);
}

EvalOptions eval_options(const std::string& gt, const std::string& frames, int threads, const std::string& save,
                         double colour_max_px, bool quiet) {
  EvalOptions opt;
  opt.gt_kind = parse_gt_kind(gt);
  opt.frames = frames;
  opt.threads = threads;
  opt.save_dir = save;
  opt.colour_max_disparity_px = colour_max_px;
  opt.progress = progress_printer(quiet);
  return opt;
}

namespace {

void print_result_text(const EvalResult& r, const std::string& title) {
  std::printf("%s\n", title.c_str());
  std::printf("%-8s %9s %9s %9s %9s %9s %9s\n", "frame", "density", "dens_gt", "correct", "d1_all", "d1_fill",
              "mae_px");
  auto row = [](const FrameRow& f) {
    const auto& m = f.metrics;
    std::printf("%-8s %8.2f%% %8.2f%% %8.2f%% %8.2f%% %8.2f%% %9.3f\n", f.frame_id.c_str(), m.density_pct,
                m.density_gt_pct, m.correct_3px_pct, m.d1_all_pct, m.d1_all_filled_pct, m.mean_abs_error_px);
  };
  for (const auto& f : r.frames) row(f);
  row(r.pooled);
  std::printf("%zu frames in %.2f s\n", r.frames.size(), r.seconds);
}

}  // namespace

void print_evaluation(const EvalResult& r, bool as_json, const json& extra, const std::string& title) {
  if (as_json) {
    json j = r;  // parallax/eval/json.hpp
    j.update(extra);
    std::cout << j.dump(2) << "\n";
  } else {
    print_result_text(r, title);
  }
}

cv::Mat load_grey_file(const std::string& path, const char* role, std::vector<std::string>& notes) {
  if (!fs::exists(path)) throw InputError(path + ": " + role + " image not found");
  const cv::Mat raw = decode_image_file(path, role);
  if (raw.empty())
    throw InputError(path + ": cannot read the " + std::string(role) + " image (not an image OpenCV can decode)");
  if (raw.depth() != CV_8U) throw InputError(path + ": " + role + " image must have 8-bit samples");
  cv::Mat grey;
  if (raw.channels() == 1) {
    grey = raw;
  } else if (raw.channels() == 3 || raw.channels() == 4) {
    cv::cvtColor(raw, grey, raw.channels() == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
    notes.push_back(path + ": colour input converted to grey as OpenCV's cvtColor does (0.299 R + 0.587 G + 0.114 B)");
  } else {
    throw InputError(path + ": " + role + " image has " + std::to_string(raw.channels()) + " channels");
  }
  return grey;
}

void load_pair_or_pattern(const config::PipelineConfig& cfg, const std::string& left_path,
                          const std::string& right_path, std::vector<std::string>& notes, cv::Mat& l, cv::Mat& r,
                          std::string& what) {
  if (left_path.empty() != right_path.empty()) throw InputError("--left and --right go together");
  if (!left_path.empty()) {
    const cv::Mat left = load_grey_file(left_path, "left", notes), right = load_grey_file(right_path, "right", notes);
    if (left.size() != right.size()) throw InputError(right_path + ": size differs from the left image " + left_path);
    const Roi roi = resolve_roi(roi_for(cfg), left.cols, left.rows);
    l = crop_to_roi(left, roi).clone();
    r = crop_to_roi(right, roi).clone();
    what = left_path + " and " + right_path;
    if (roi.width_px != left.cols || roi.height_px != left.rows)
      what += " (centred " + std::to_string(roi.width_px) + "x" + std::to_string(roi.height_px) + " crop)";
    return;
  }
  if (cfg.roi_full) throw InputError("--left/--right are needed when the config's roi is 'full'");
  test_pattern(cfg.roi_width_px, cfg.roi_height_px, cfg.disparities, 1, l, r);
  what = "a generated " + std::to_string(l.cols) + "x" + std::to_string(l.rows) + " test pattern (seed 1)";
  notes.push_back("no pair given: used " + what);
}

SweepSpec choose_sweep(ResultStore& store, const std::string& db, const std::string& name) {
  const std::vector<SweepSpec> sweeps = store.sweeps();
  if (sweeps.empty()) throw InputError(db + ": no sweep in this store");
  std::string names;
  for (const auto& s : sweeps) {
    names += (names.empty() ? "" : ", ") + s.name;
    if (s.name == name) return s;
  }
  if (name.empty() && sweeps.size() == 1) return sweeps.front();
  throw InputError(name.empty() ? db + ": several sweeps (" + names + "): choose one with --sweep"
                                : "--sweep '" + name + "': not in " + db + " (" + names + ")");
}

int report_exception(std::exception_ptr ep) {
  auto user = [](const std::string& msg) {
    std::fprintf(stderr, "parallax: error: %s\n", msg.c_str());
    return kExitUserError;
  };
  auto internal = [](const std::string& what) {
    std::fprintf(stderr,
                 "parallax: internal error: %s\n"
                 "parallax: this is a defect of Parallax, not of your input: please report it with the command line "
                 "and the files it names\n",
                 what.c_str());
    return kExitInternalError;
  };
  try {
    std::rethrow_exception(std::move(ep));
  } catch (const UserError& e) {
    return user(e.what());
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "parallax: error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    return internal(e.what());
  } catch (...) {
    return internal("an exception of unknown type");
  }
}

}  // namespace parallax::cli
