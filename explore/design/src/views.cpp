// The views of a design (views.hpp): its maps on one frame, the avoidance stage on them, one
// flight. Everything that runs or flies the design for a report is here; reports/ draws.
#include <string>

#include "parallax/design/result.hpp"
#include "parallax/eval/disparity_io.hpp"
#include "parallax/eval/evaluate.hpp"
#include "parallax/eval/input_error.hpp"
#include "parallax/uav/avoid.hpp"
#include "parallax/uav/fly.hpp"
#include "parallax/uav/scene.hpp"

namespace parallax::design {

// The names this file takes from the other rooms (one namespace per room).
using eval::colourize_disparity;
using eval::crop_to_roi;
using eval::Dataset;
using eval::DisparityMap;
using eval::Frame;
using eval::GtKind;
using eval::InputError;
using eval::list_frames;
using eval::load_frame;
using eval::open_dataset;
using eval::resolve_roi;
using eval::Roi;
using eval::roi_for;
using eval::run_design;
using uav::avoid;
using uav::AvoidResult;
using uav::flight_setup;
using uav::FlightParams;
using uav::FlightResult;
using uav::FlightSetup;
using uav::fly;
using uav::generate_scene;
using uav::kitti_default_rig;
using uav::load_scenario;
using uav::Obstacle;
using uav::render;
using uav::Scenario;
using uav::Scene;
using uav::StereoFrame;

AvoidanceView view_avoidance(const cv::Mat& disparity_px, const cv::Mat& valid_mask, int max_disparity, int roi_x0_px,
                             int roi_y0_px) {
  const AvoidResult a = avoid(disparity_px, valid_mask, max_disparity, kitti_default_rig(roi_x0_px, roi_y0_px));
  AvoidanceView v;
  v.u_map = a.u_map;
  v.v_map = a.v_map;
  for (const Obstacle& o : a.obstacles) v.obstacles.push_back({o.u_box, o.v_box, o.ellipse, o.range_m});
  v.ground_found = a.ground_found;
  v.ground_slope = a.ground_slope;
  v.ground_offset = a.ground_offset;
  v.max_disparity = max_disparity;
  return v;
}

FrameView view_frame(const config::PipelineConfig& cfg, const std::string& dataset, const std::string& frame) {
  const Dataset ds = open_dataset(dataset);
  const auto refs = list_frames(ds, GtKind::noc, frame);
  if (refs.empty()) throw InputError(dataset + ": no frame with ground truth matches '" + frame + "'");
  const Frame f = load_frame(refs.front());
  const Roi r = resolve_roi(roi_for(cfg), f.left.cols, f.left.rows);
  FrameView v;
  v.frame_id = f.id;
  v.left_grey = crop_to_roi(f.left, r).clone();
  const cv::Mat right = crop_to_roi(f.right, r).clone();
  v.gt_px = crop_to_roi(f.gt_disparity_px, r).clone();
  v.gt_mask = crop_to_roi(f.gt_mask, r).clone();
  sim::FuncPipeline pipe;
  const DisparityMap d = run_design(cfg, v.left_grey, right, pipe);
  v.disparity_px = d.disparity_px;
  v.valid_mask = d.valid_mask;
  const double max_d = double(cfg.disparity_end_px());
  v.disparity_colour = colourize_disparity(d.disparity_px, d.valid_mask, max_d);
  v.gt_colour = colourize_disparity(v.gt_px, v.gt_mask, max_d);
  v.avoidance = view_avoidance(d.disparity_px, d.valid_mask, cfg.disparity_end_px(), r.x0, r.y0);
  return v;
}

FlightView view_flight(const config::PipelineConfig& cfg, const std::string& scenario_path, double speed_mps,
                       int size_px) {
  const Scenario sc = load_scenario(scenario_path);
  const Scene scene = generate_scene(sc, 1);
  FlightParams fp;
  fp.speed_mps = speed_mps;
  fp.width_px = size_px;
  const FlightResult r = fly(cfg, sc, scene, fp, 1);
  FlightView v;
  v.scenario = sc.name;
  v.speed_mps = speed_mps;
  v.outcome = to_string(r.outcome);
  v.collided = r.collided;
  v.min_clearance_m = r.min_clearance_m;
  v.goal_z_m = scene.goal_z_m;
  for (const auto& c : scene.cylinders) v.cylinders.push_back({c.x_m, c.z_m, c.radius_m});
  for (const auto& b : scene.boxes) v.boxes.push_back({b.x0_m, b.x1_m, b.z0_m, b.z1_m});
  for (const auto& p : r.trajectory) v.trajectory_xz_m.emplace_back(p.x(), p.z());
  // Three frames of the flight: start, middle, end, with the design's disparity.
  const FlightSetup setup = flight_setup(cfg, sc, fp);
  sim::FuncPipeline pipe;
  if (!r.poses.empty())
    for (std::size_t k : {std::size_t(0), r.poses.size() / 2, r.poses.size() - 1}) {
      const StereoFrame f = render(scene, setup.rig, setup.width_px, setup.height_px, r.poses[k], sc.imaging.antialias);
      const DisparityMap d = run_design(setup.cfg, f.left, f.right, pipe);
      v.frames.push_back(
          {int(k), f.left, colourize_disparity(d.disparity_px, d.valid_mask, double(cfg.disparity_end_px()))});
    }
  return v;
}

}  // namespace parallax::design
