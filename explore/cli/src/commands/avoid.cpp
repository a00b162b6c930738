// parallax avoid: obstacle detection and avoidance on a design's disparity maps, scored against
// the same stage on the ground truth; optionally MAVLink setpoints to a file or UDP.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/evaluate.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/sim/func.hpp"
#include "parallax/uav/avoid.hpp"

namespace parallax::cli {

namespace {

using nlohmann::json;
using namespace parallax::explore;

struct AvoidOptions {
  ConfigArgs cfg;
  std::string dataset, frames, gt = "noc", calib, mavlink;
  bool json = false;
};

// MAVLink output: a file (binary frames back to back) or udp:HOST:PORT; nothing when empty.
// Throws InputError naming --mavlink-out when the destination cannot be used.
class MavlinkSink {
 public:
  explicit MavlinkSink(const std::string& where) {
    if (where.empty()) return;
    if (where.rfind("udp:", 0) == 0) {
      const auto colon = where.rfind(':');
      const std::string host = where.substr(4, colon - 4);
      const int port = std::atoi(where.substr(colon + 1).c_str());
      fd_ = socket(AF_INET, SOCK_DGRAM, 0);
      addr_.sin_family = AF_INET;
      addr_.sin_port = htons(uint16_t(port));
      if (fd_ < 0 || port <= 0 || inet_pton(AF_INET, host.c_str(), &addr_.sin_addr) != 1)
        throw InputError("--mavlink-out '" + where + "': expected udp:IPv4:PORT");
      return;
    }
    file_.open(where, std::ios::binary);
    if (!file_) throw InputError("--mavlink-out '" + where + "': cannot write");
  }
  ~MavlinkSink() {
    if (fd_ >= 0) close(fd_);
  }
  MavlinkSink(const MavlinkSink&) = delete;
  MavlinkSink& operator=(const MavlinkSink&) = delete;
  void send(const std::vector<uint8_t>& frame) {
    if (file_.is_open()) file_.write(reinterpret_cast<const char*>(frame.data()), std::streamsize(frame.size()));
    if (fd_ >= 0)
      (void)sendto(fd_, frame.data(), frame.size(), 0, reinterpret_cast<const sockaddr*>(&addr_), sizeof addr_);
  }

 private:
  std::ofstream file_;
  int fd_ = -1;
  sockaddr_in addr_{};
};

// The rig of a frame cropped to `roi`: --calib when given, else the frame's own calibration file
// (KITTI calib, Middlebury calib.txt), else KITTI 2015's.
Rig frame_rig(const std::string& calib, const Frame& f, const Roi& roi) {
  Rig rig = kitti_default_rig(roi.x0, roi.y0);
  if (!calib.empty()) {
    rig = load_rig(calib, roi.x0, roi.y0);
  } else if (f.calibration.known) {
    rig.focal_px = f.calibration.focal_px;
    rig.baseline_m = f.calibration.baseline_m;
    rig.cx_px = f.calibration.cx_px - roi.x0;
    rig.cy_px = f.calibration.cy_px - roi.y0;
  }
  return rig;
}

// The accumulated scores as text on stdout.
void print_avoid_text(const config::PipelineConfig& cfg, const AvoidAccumulator& acc,
                      std::map<std::string, double>& m) {
  const AvoidTimings& t = acc.timing_sum();
  const double n = double(acc.frames());
  std::printf(
      "%s on %d frames: obstacle_precision %.1f%%  obstacle_recall %.1f%%  range_error %.2f m  "
      "decision_agreement %.1f%%\n",
      cfg.name.c_str(), acc.frames(), m["obstacle_precision"], m["obstacle_recall"], m["range_error_m"],
      m["decision_agreement_pct"]);
  std::printf(
      "avoidance stage: %.2f ms per frame (U/V maps %.2f, ground + filtering %.2f, contours %.2f, planning %.3f)\n",
      m["mean_ms_per_frame"], t.uv_maps_ms / n, t.filtering_ms / n, t.contours_ms / n, t.planning_ms / n);
}

// The accumulated scores, the stage's time split and the per-frame rows as one JSON object.
json avoid_json(const config::PipelineConfig& cfg, const AvoidAccumulator& acc, const std::map<std::string, double>& m,
                const json& per_frame) {
  const AvoidTimings& t = acc.timing_sum();
  const double n = double(acc.frames());
  json j;
  j["config"] = cfg.name;
  j["frames"] = acc.frames();
  for (const auto& kv : m) j[kv.first] = kv.second;
  j["ms_split"] = {{"uv_maps", t.uv_maps_ms / n},
                   {"filtering", t.filtering_ms / n},
                   {"contours", t.contours_ms / n},
                   {"planning", t.planning_ms / n}};
  j["per_frame"] = per_frame;
  return j;
}

int run_avoid(const AvoidOptions& o, const Invocation&) {
  const config::PipelineConfig cfg = load_config_args(o.cfg);
  if (o.gt != "noc" && o.gt != "occ") throw InputError("--gt '" + o.gt + "': expected noc or occ");
  const Dataset ds = open_dataset(o.dataset);
  const auto refs = list_frames(ds, o.gt == "occ" ? GtKind::occ : GtKind::noc, o.frames);
  if (refs.empty()) throw InputError(o.dataset + ": no frame with ground truth matches '" + o.frames + "'");
  MavlinkSink mav(o.mavlink);
  sim::FuncPipeline pipe;
  AvoidAccumulator acc;
  json per_frame = json::array();
  uint8_t seq = 0;
  for (const auto& ref : refs) {
    Frame f = load_frame(ref);
    const Roi roi = resolve_roi(roi_for(cfg), f.left.cols, f.left.rows);
    const Rig rig = frame_rig(o.calib, f, roi);
    const DisparityMap d = run_design(cfg, crop_to_roi(f.left, roi).clone(), crop_to_roi(f.right, roi).clone(), pipe);
    const AvoidScore s = acc.add(d.disparity_px, d.valid_mask, crop_to_roi(f.gt_disparity_px, roi),
                                 crop_to_roi(f.gt_mask, roi), cfg.disparity_end_px(), rig);
    const AvoidResult& mine = acc.last_design();
    mav.send(mavlink_heartbeat(seq++, 1, 191));
    mav.send(mavlink_velocity_setpoint(seq++, 1, 191, uint32_t(acc.frames() * 100), mine.velocity_mps));
    per_frame.push_back({{"frame", f.id},
                         {"obstacles", s.predicted},
                         {"reference_obstacles", s.reference},
                         {"matched", s.matched},
                         {"decision", to_string(mine.manoeuvre)},
                         {"reference_decision", to_string(acc.last_reference().manoeuvre)},
                         {"nearest_range_m", mine.obstacles.empty() ? 0.0 : mine.obstacles.front().range_m},
                         {"velocity_mps", {mine.velocity_mps.x(), mine.velocity_mps.y(), mine.velocity_mps.z()}}});
  }
  std::map<std::string, double> m;
  for (const auto& kv : acc.metrics()) m[kv.first] = kv.second;
  if (o.json)
    std::cout << avoid_json(cfg, acc, m, per_frame).dump(2) << "\n";
  else
    print_avoid_text(cfg, acc, m);
  return 0;
}

}  // namespace

Command add_avoid(CLI::App& app) {
  auto o = std::make_shared<AvoidOptions>();
  auto* avoidc = app.add_subcommand("avoid",
                                    "Obstacle detection and avoidance on the design's disparity maps, scored against "
                                    "the same stage on the ground truth");
  add_config_options(avoidc, o->cfg, true);
  avoidc->add_option("--dataset", o->dataset, "Dataset folder (KITTI 2015/2012)")->required();
  avoidc->add_option("--frames", o->frames, "Frame filter, e.g. 0-9,15, or @FILE (default: all with ground truth)")
      ->transform(FrameList());
  avoidc->add_option("--gt", o->gt, "Ground truth: noc or occ")->capture_default_str();
  avoidc->add_option(
      "--calib", o->calib,
      "Rig calibration: KITTI calib file (P_rect_02/03 or P2/P3) or OpenCV YAML (default: KITTI 2015's)");
  avoidc
      ->add_option("--mavlink-out", o->mavlink,
                   "Write MAVLink 2 (HEARTBEAT + velocity setpoint per frame) to a file or udp:HOST:PORT")
      ->check(OutputFile());
  avoidc->add_flag("--json", o->json, "Print JSON");
  return bind_command(avoidc, o, run_avoid);
}

}  // namespace parallax::cli
