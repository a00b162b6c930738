// parallax scene: render a seeded synthetic scene along the flight axis as a KITTI-layout stereo
// dataset, optionally with radial lens distortion and the maps that rectify it.
#include <Eigen/Core>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "commands.hpp"
#include "parallax/uav/scene.hpp"
#include "parallax/uav/truth.hpp"

namespace parallax::cli {

namespace {

namespace fs = std::filesystem;
using namespace parallax::eval;
using namespace parallax::uav;
using namespace parallax::search;

struct SceneOptions {
  std::string scenario, out;
  uint32_t seed = 1;
  int frames = 10, width = 0;
  double step = 2.0, k1 = 0.0;
};

int run_scene(const SceneOptions& o, const Invocation&) {
  const Scenario s = load_scenario(o.scenario);
  const Scene scene = generate_scene(s, o.seed);
  const RigSpec spec = scaled_rig(s.rig, o.width);
  const int width = spec.width_px, height = spec.height_px;
  const Rig rig = rig_of(spec, width, height);
  std::vector<StereoFrame> frames;
  std::vector<std::vector<TruthObstacle>> truth;
  const auto start = std::chrono::steady_clock::now();
  std::mt19937 rng(o.seed * 7919u + 17u);
  for (int i = 0; i < o.frames; ++i) {
    CameraPose pose;
    pose.position_m = Eigen::Vector3d(0, -s.rig.altitude_m, i * o.step);
    pose.pitch_rad = s.rig.mount_pitch_deg * M_PI / 180.0;
    frames.push_back(o.k1 != 0.0 ? render(scene, rig, width, height, pose.position_m, o.k1)
                                 : render(scene, rig, width, height, pose, s.imaging.antialias));
    apply_sensor(frames.back(), s.imaging, rng);
    truth.push_back(obstacles_in_view(scene, rig, width, pose.position_m, 40.0));
  }
  const double render_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / o.frames;
  std::fprintf(stderr, "parallax: rendered %d stereo pairs, %.1f ms per pair\n", o.frames, render_ms);
  export_kitti(frames, o.out);
  write_kitti_calibration(rig, o.frames, o.out);
  write_truth((fs::path(o.out) / "obstacles.json").string(), truth);
  if (o.k1 != 0.0) {
    for (const char* side : {"maps_left.yml", "maps_right.yml"})
      write_rectification_maps(rig, width, height, o.k1, (fs::path(o.out) / side).string());
    std::printf(
        "distortion k1 = %g: rectify with --set rectify=bilinear --set rectify_maps_left=%s/maps_left.yml "
        "--set rectify_maps_right=%s/maps_right.yml\n",
        o.k1, o.out.c_str(), o.out.c_str());
  }
  std::printf(
      "%s (seed %u): %zu poles/trees, %zu boxes; %d frames of %dx%d written to %s/training with their "
      "calibration (f = %.1f px, B = %.4f m, camera %.1f m above the ground) and the obstacles in view "
      "(obstacles.json, read by avoid)\n",
      s.name.c_str(), o.seed, scene.cylinders.size(), scene.boxes.size(), o.frames, width, height, o.out.c_str(),
      rig.focal_px, rig.baseline_m, s.rig.altitude_m);
  return 0;
}

}  // namespace

Command add_scene(CLI::App& app) {
  auto o = std::make_shared<SceneOptions>();
  auto* scenec = app.add_subcommand(
      "scene", "Render a seeded synthetic scene along the flight axis as a KITTI-layout stereo dataset");
  scenec->add_option("--scenario", o->scenario, scenario_option_help())->required();
  scenec->add_option("--seed", o->seed, "Scene seed")->capture_default_str();
  scenec->add_option("--frames", o->frames, "Frames, one every --step-m along the flight axis")
      ->capture_default_str()
      ->check(InRange(1, 10000));
  scenec->add_option("--step-m", o->step, "Distance between frames")
      ->capture_default_str()
      ->check(InRange(0.01, 100.0));
  scenec->add_option("--size", o->width, "Scale the scenario's rig to this image width (0: its sensor as given)")
      ->capture_default_str()
      ->check(CLI::Range(0, 0) | InRange(32, 4096));
  scenec->add_option("--out", o->out, "Output folder (KITTI layout: training/image_2, image_3, disp_noc_0, disp_occ_0)")
      ->required()
      ->check(OutputFolder());
  scenec
      ->add_option("--distortion-k1", o->k1,
                   "Radial lens distortion: images distorted, OUT/maps_left.yml and maps_right.yml rectify them")
      ->check(InRange(-0.5, 0.5));
  return bind_command(scenec, o, run_scene);
}

}  // namespace parallax::cli
