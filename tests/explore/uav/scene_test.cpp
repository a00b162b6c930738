// unit: synthetic scenes: exact disparity of the rendered rig (ground plane, a pole, a wall whose
// points land on whole pixels in both cameras), occlusion masks, seeds, scenario files, clearance
// and the KITTI export.
#include <gtest/gtest.h>

#include <algorithm>

#include <filesystem>
#include <fstream>
#include <random>

#include "parallax/config/config.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/evaluate.hpp"
#include "parallax/uav/scene.hpp"

namespace parallax::test {
namespace {

using namespace parallax::eval;
using namespace parallax::uav;

Rig rig640() {
  Rig r;
  r.focal_px = 700;
  r.baseline_m = 0.5;
  r.cx_px = 319.5;
  r.cy_px = 179.5;
  return r;
}
const Eigen::Vector3d kCam(0, -1.6, 0);

TEST(Scene, GroundDisparityIsExact) {
  const Rig r = rig640();
  const StereoFrame f = render(Scene{}, r, 640, 360, kCam);
  for (int v = 185; v < 360; v += 7)
    for (int u = 0; u < 640; u += 53) {
      ASSERT_EQ(f.valid_mask.at<uint8_t>(v, u), 255) << v << "," << u;
      EXPECT_NEAR(f.disparity_px.at<float>(v, u), r.baseline_m * (v - r.cy_px) / 1.6, 1e-3);
    }
  EXPECT_EQ(f.valid_mask.at<uint8_t>(100, 300), 0);  // sky
  // Every ground pixel whose match lies inside the right image is visible from it.
  for (int v = 185; v < 360; v += 5)
    for (int u = 0; u < 640; u += 5)
      if (float(u) - f.disparity_px.at<float>(v, u) >= 1.0f) {
        EXPECT_EQ(f.noc_mask.at<uint8_t>(v, u), 255) << v << "," << u;
      }
}

TEST(Scene, WallPointsLandOnWholePixelsInBothImages) {
  const Rig r = rig640();
  Scene s;
  const double z = r.focal_px * r.baseline_m / 20.0;  // disparity exactly 20 px
  s.boxes.push_back({-30, 30, z, z + 1, 10});
  const StereoFrame f = render(s, r, 640, 360, kCam);
  int compared = 0;
  for (int v = 20; v < 170; v += 3)
    for (int u = 40; u < 600; u += 3) {
      ASSERT_NEAR(f.disparity_px.at<float>(v, u), 20.0f, 1e-3);
      EXPECT_EQ(f.left.at<uint8_t>(v, u), f.right.at<uint8_t>(v, u - 20)) << v << "," << u;
      ++compared;
    }
  EXPECT_GT(compared, 1000);
}

TEST(Scene, PoleRangeAndItsOcclusionShadow) {
  const Rig r = rig640();
  Scene s;
  s.cylinders.push_back({0.0, 10.0, 0.3, 6.0});
  const StereoFrame f = render(s, r, 640, 360, kCam);
  const int uc = int(r.cx_px), vc = 150;
  EXPECT_NEAR(f.disparity_px.at<float>(vc, uc), r.focal_px * r.baseline_m / (10.0 - 0.3), 0.05);
  // The right camera cannot see some background just left of the pole.
  int shadow = 0;
  for (int v = 185; v < 200; ++v)
    for (int u = 0; u < 640; ++u)
      shadow += f.valid_mask.at<uint8_t>(v, u) && !f.noc_mask.at<uint8_t>(v, u) && u > 100 ? 1 : 0;
  EXPECT_GT(shadow, 10);
}

// A shipped scenario by name (compiled in, any working directory) is the same as its file; an
// unknown name is an error naming the shipped ones; a file of that name in the working
// directory wins over the shipped scenario.
TEST(Scene, ScenariosByName) {
  // Every shipped file is a scenario by its name, and the name inside is the file's.
  const std::vector<std::string> shipped = {"corridor",    "corridor-stripes", "forest",
                                            "single-pole", "wall-gap",         "wall-gap-plain"};
  for (const std::string& name : shipped) {
    const Scenario by_name = load_scenario(name);
    const Scenario by_file = load_scenario(std::string(PARALLAX_CONFIG_DIR) + "/scenarios/" + name + ".yaml");
    EXPECT_EQ(by_name.name, by_file.name);
    EXPECT_EQ(by_name.kind, by_file.kind);
    EXPECT_EQ(by_name.density_per_100m2, by_file.density_per_100m2);
    EXPECT_EQ(by_name.length_m, by_file.length_m);
    EXPECT_EQ(by_name.walls, by_file.walls);
    EXPECT_EQ(by_name.name, name);
    EXPECT_EQ(scenario_reference(name), name);
  }
  auto builtin = builtin_scenarios();
  std::sort(builtin.begin(), builtin.end());
  EXPECT_EQ(builtin, shipped);
  try {
    load_scenario("jungle");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("jungle"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("forest"), std::string::npos);
  }
  const auto dir = std::filesystem::temp_directory_path() / "parallax_scene_by_name";
  std::filesystem::create_directories(dir);
  const auto cwd = std::filesystem::current_path();
  std::filesystem::current_path(dir);
  std::ofstream("forest") << "name: mine\nkind: corridor\n";
  EXPECT_EQ(load_scenario("forest").kind, "corridor");
  EXPECT_NE(scenario_reference("forest"), "forest");  // the file's absolute path
  std::filesystem::current_path(cwd);
  std::filesystem::remove_all(dir);
}

TEST(Scene, SeedsAndScenarioFiles) {
  for (const char* name : {"single-pole", "forest", "wall-gap", "corridor"}) {
    const Scenario sc = load_scenario(std::string(PARALLAX_CONFIG_DIR) + "/scenarios/" + name + ".yaml");
    EXPECT_EQ(sc.kind, name);
    const Scene a = generate_scene(sc, 5), b = generate_scene(sc, 5), c = generate_scene(sc, 6);
    EXPECT_GT(a.cylinders.size() + a.boxes.size(), 0u) << name;
    EXPECT_EQ(a.cylinders.size(), b.cylinders.size());
    auto signature = [](const Scene& x) {
      double sum = 0;
      for (const auto& cy : x.cylinders) sum += cy.x_m * 3 + cy.z_m + cy.radius_m;
      for (const auto& bx : x.boxes) sum += bx.x0_m * 3 + bx.z0_m + bx.height_m;
      return sum;
    };
    EXPECT_EQ(signature(a), signature(b)) << name;
    EXPECT_NE(signature(a), signature(c)) << name;
  }
  const auto dir = std::filesystem::temp_directory_path() / "parallax_scene_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "bad.yaml") << "name: x\nkind: maze\n";
  try {
    load_scenario((dir / "bad.yaml").string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("kind"), std::string::npos);
  }
}

TEST(Scene, ClearanceAndKittiExport) {
  Scene s;
  s.cylinders.push_back({0, 10, 0.5, 5});
  s.boxes.push_back({2, 4, 20, 22, 3});
  EXPECT_NEAR(clearance_m(s, Eigen::Vector3d(0, -1, 7)), 2.5, 1e-9);
  EXPECT_LT(clearance_m(s, Eigen::Vector3d(3, -1, 21)), 0.0);  // inside the box
  EXPECT_GT(clearance_m(s, Eigen::Vector3d(0, -7, 10)), 1e6);  // above the pole: nothing
  // What a collision report names: the nearest obstacle, a branch across the pole's side.
  EXPECT_EQ(nearest_obstacle(s, Eigen::Vector3d(0, -1, 7)), "tree r 0.50 m at (x 0.00, z 10.00)");
  EXPECT_EQ(nearest_obstacle(s, Eigen::Vector3d(3, -1, 21)), "wall x 2.0..4.0 z 20.0..22.0");
  s.branches.push_back({0.5, 10, 1.6, M_PI / 2, 2.0, 0.03});
  EXPECT_NEAR(clearance_m(s, Eigen::Vector3d(1.5, -1.6, 10.2)), 0.17, 1e-9);
  EXPECT_EQ(nearest_obstacle(s, Eigen::Vector3d(1.5, -1.6, 10.2)),
            "branch (r 0.030 m, 1.60 m up) from (x 0.50, z 10.00)");
  const auto dir = std::filesystem::temp_directory_path() / "parallax_scene_export";
  std::filesystem::remove_all(dir);
  std::vector<StereoFrame> frames = {render(s, rig640(), 96, 54, kCam),
                                     render(s, rig640(), 96, 54, kCam + Eigen::Vector3d(0, 0, 1))};
  export_kitti(frames, dir.string());
  const Dataset ds = open_dataset(dir);
  EXPECT_EQ(list_frames(ds, GtKind::noc, "").size(), 2u);
  EXPECT_EQ(list_frames(ds, GtKind::occ, "").size(), 2u);
}

// The flights' figures in docs/flight.md were measured on these exact frames: a change of the
// renderer that alters a single bit (of the grey images, the disparity or the masks) changes the
// flights and must come with the figures measured again. Every shipped scenario at its own size
// and at 320 px, at poses off the flight axis with yaw and pitch, through the sensor model, and one
// frame through distorting lenses; FNV-1a over the bytes. GCC 12 at -O3 with FMA (the project's
// native builds, AMD and Intel alike; also -march=x86-64-v3/v4) gives the first digest, builds
// without FMA contraction (-march=x86-64; -O1 as in the debug preset; -O2, measured) the second.
// The digests also rest on libstdc++'s distributions (the noise tables, the scene's layout) and
// glibc's libm: another standard library is another set of frames.
TEST(Scene, RenderedFramesAreThoseTheFlightsWereMeasuredOn) {
  auto fnv = [](uint64_t h, const cv::Mat& m) {
    const cv::Mat c = m.isContinuous() ? m : m.clone();
    for (std::size_t i = 0; i < c.total() * c.elemSize(); ++i) h = (h ^ c.data[i]) * 1099511628211ull;
    return h;
  };
  // {with FMA at -O3, without FMA contraction}: only the stripes' sine differs between the two.
  const std::vector<std::pair<std::string, std::pair<uint64_t, uint64_t>>> expected = {
      {"forest", {0x19346bbd091a4759ull, 0x19346bbd091a4759ull}},
      {"corridor", {0x127912bc765ab5a7ull, 0x127912bc765ab5a7ull}},
      {"wall-gap", {0x2828008a9cbd8badull, 0x2828008a9cbd8badull}},
      {"wall-gap-plain", {0xf13bf20324ae58acull, 0xf13bf20324ae58acull}},
      {"corridor-stripes", {0x47457384f354e514ull, 0x00b2db14523484d3ull}},
      {"single-pole", {0x26bf445e37e9c064ull, 0x26bf445e37e9c064ull}}};
  for (const auto& [name, digests] : expected) {
    const Scenario s = load_scenario(name);
    const Scene scene = generate_scene(s, 1);
    uint64_t h = 1469598103934665603ull;
    for (const int size : {0, 320}) {
      const RigSpec spec = scaled_rig(s.rig, size);
      const Rig rig = rig_of(spec, spec.width_px, spec.height_px);
      std::mt19937 rng(31u + uint32_t(size));
      // Poses as constants (x, height offset, z in metres; yaw, pitch in radians): no arithmetic
      // that a compiler could contract differently in another build.
      const double poses[3][5] = {
          {1.3, 0.2, 0.5, 0.31, -0.08}, {-0.7, -0.25, 6.2, -0.45, 0.12}, {0.2, 0.0, 11.8, 0.05, 0.0}};
      for (const auto& q : poses) {
        CameraPose pose;
        pose.position_m = Eigen::Vector3d(q[0], q[1] - s.rig.altitude_m, q[2]);
        pose.yaw_rad = q[3];
        pose.pitch_rad = q[4];
        StereoFrame f = render(scene, rig, spec.width_px, spec.height_px, pose, s.imaging.antialias);
        apply_sensor(f, s.imaging, rng);
        for (const cv::Mat* m : {&f.left, &f.right, &f.disparity_px, &f.valid_mask, &f.noc_mask}) h = fnv(h, *m);
      }
      if (size == 320) {
        const StereoFrame f = render(scene, rig, spec.width_px, spec.height_px, Eigen::Vector3d(0, -1.6, 3), -0.1);
        for (const cv::Mat* m : {&f.left, &f.right}) h = fnv(h, *m);
      }
    }
    EXPECT_TRUE(h == digests.first || h == digests.second)
        << name << ": the rendered frames changed (digest 0x" << std::hex << h << ", expected 0x" << digests.first
        << " or 0x" << digests.second << "); the flights of docs/flight.md were measured on the previous frames";
  }
}

// The oracle's frames: no right grey image, the same left image and truth, and the sensor's
// generator left where two images would leave it (so the next frame's noise is the same).
TEST(Scene, LeftOnlyFramesKeepTheSensorsGenerator) {
  const Scenario s = load_scenario("forest");
  const Scene scene = generate_scene(s, 3);
  const Rig rig = rig_of(s.rig, s.rig.width_px, s.rig.height_px);
  CameraPose pose;
  pose.position_m = Eigen::Vector3d(0.4, -s.rig.altitude_m, 4.0);
  pose.yaw_rad = 0.2;
  std::mt19937 both(11), left_only(11);
  StereoFrame a = render(scene, rig, s.rig.width_px, s.rig.height_px, pose, true);
  StereoFrame b = render(scene, rig, s.rig.width_px, s.rig.height_px, pose, true, GreyImages::left_only);
  EXPECT_TRUE(b.right.empty());
  apply_sensor(a, s.imaging, both);
  apply_sensor(b, s.imaging, left_only);
  EXPECT_EQ(cv::norm(a.left, b.left, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.disparity_px, b.disparity_px, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.valid_mask, b.valid_mask, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.noc_mask, b.noc_mask, cv::NORM_INF), 0.0);
  EXPECT_TRUE(both == left_only);
  EXPECT_EQ(both(), left_only());
}

// Distorting lenses: the design reads worse images unless its rectify stage undoes the distortion
// with the maps the scene wrote; then it scores nearly as on the undistorted scene.
TEST(Scene, DistortedScenesExerciseTheRectifyStage) {
  const auto dir = std::filesystem::temp_directory_path() / "parallax_scene_distorted";
  std::filesystem::remove_all(dir);
  Rig rig;
  rig.focal_px = 721.5377;
  rig.cx_px = 319.5;
  rig.cy_px = 179.5;
  const Scene scene = generate_scene(load_scenario(std::string(PARALLAX_CONFIG_DIR) + "/scenarios/forest.yaml"), 3);
  export_kitti({render(scene, rig, 640, 360, kCam, -0.15)}, dir.string());
  write_rectification_maps(rig, 640, 360, -0.15, (dir / "maps.yml").string());
  config::PipelineConfig cfg = config::load_config(std::string(PARALLAX_CONFIG_DIR) + "/ruf2018-census.yaml");
  const Dataset ds = open_dataset(dir);
  EvalOptions eo;
  const double raw = evaluate_design(cfg, ds, eo).pooled.metrics.correct_3px_pct;
  cfg.rectify = "bilinear";
  cfg.rectify_rows = 64;
  cfg.rectify_maps_left = cfg.rectify_maps_right = (dir / "maps.yml").string();
  const double rectified = evaluate_design(cfg, ds, eo).pooled.metrics.correct_3px_pct;
  EXPECT_GT(rectified, raw + 3.0) << raw << " -> " << rectified;
  EXPECT_GT(rectified, 90.0);
}

}  // namespace
}  // namespace parallax::test
