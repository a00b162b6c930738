// Reports of a sweep (`parallax report`): CSV and JSON with one row per design and per frame,
// and a self-contained HTML page (inline CSS, JS and SVG, images as data URIs: nothing is
// fetched when it is viewed). `run` and `sim` write the per-design section as a page of its own.
// docs/reports.md.
#pragma once

#include <map>
#include <ostream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "parallax/design/result.hpp"
#include "parallax/hls_flow/hls_report.hpp"
#include "parallax/search/sweep.hpp"
#include "parallax/resources/model.hpp"
#include "parallax/sim/cycle.hpp"

namespace parallax::reports {

// The names this file takes from the other rooms (one namespace per room).
using design::AvoidanceView;
using design::DesignResult;
using design::FlightView;
using design::FrameView;
using hls_flow::ModelVsSynthesis;
using search::ResultStore;
using search::seed_hash;
using search::SweepSpec;

// Column order of the design CSV: hash, sweep, status, reason, every configuration field (in
// the configuration's own order), then the metrics (metric_columns(), then any other key
// alphabetically). The frame CSV: hash, frame, then the accuracy metrics.
std::vector<std::string> metric_columns();
void write_designs_csv(const std::vector<ResultStore::Row>& rows, std::ostream& out);
void write_frames_csv(const std::vector<ResultStore::Row>& rows, std::ostream& out);
std::string report_json(const std::vector<ResultStore::Row>& rows);

// Everything the per-design section shows; images may be empty (no dataset given).
struct DesignSection {
  std::string title;
  std::string config_yaml;
  std::string config_file;                                     // name the page offers to save the configuration as
  std::string command;                                         // how to reproduce it
  cv::Mat left_grey, disparity_colour, gt_colour, error_map;   // 8-bit grey / BGR
  cv::Mat u_map_image, v_map_image;                            // the avoidance stage, detections drawn
  std::string flight_svg;                                      // top-down flight (empty: none)
  std::vector<std::pair<cv::Mat, std::string>> flight_frames;  // pictures of the flight
  std::string frame_id;
  std::map<std::string, double> metrics;
  sim::CycleReport cycle;  // empty stages: not simulated
  res::Estimate resources;
  const res::Device* device = nullptr;
  std::vector<ModelVsSynthesis> synthesis;  // model beside synthesis (parallax import-hls); empty: none
};
// The pictures of a section, drawn from what explore computed (parallax/design/views.hpp): the
// frame's images and error map with the avoidance stage on them; the avoidance stage's U map
// (obstacle boxes and ellipses) and V map (the ground line and the obstacles' rows); a flight's
// top-down trajectory and frames.
void add_frame_images(DesignSection& s, const FrameView& frame);
void add_avoidance_images(DesignSection& s, const AvoidanceView& avoidance);
void add_flight(DesignSection& s, const FlightView& flight);

// The picture of where a disparity is right (green: within 3 px of the ground truth), wrong
// (red) or unscored (black: no ground truth or no prediction).
cv::Mat error_map(const cv::Mat& disparity_px, const cv::Mat& valid_mask, const cv::Mat& gt_px, const cv::Mat& gt_mask);

// The models' figures of an evaluated design in its section: the cycle report, the per-stage
// resource estimate and its device (the metrics table is the caller's: stored or measured).
void add_figures(DesignSection& s, const DesignResult& r);

std::string design_section_html(const DesignSection& s);
std::string standalone_page(const std::string& title, const std::string& body_html);

struct ReportOptions {
  std::string dataset;  // the dataset the sections' images come from ("" = none): named in their commands
  int details = 6;      // designs on the front that get a section
  // What explore computed for the designs of report_sections(), by hash: timing, resources and
  // views (evaluate_point with view_dataset / view_scenario). A design missing here gets its
  // stored metrics only; a status other than "ok" is named in its title.
  std::map<std::string, DesignResult> sections;
  // Marked in the Pareto plots and listed in the summary: the peers stored beside the sweep
  // (ResultStore::peers) and the seed design (seed_hash, the base design's hash; "" = none).
  std::vector<ResultStore::Row> peers;
  std::string seed_hash;
};
// The designs that get a section: the first `details` of the Pareto front.
std::vector<ResultStore::Row> report_sections(const SweepSpec& spec, const std::vector<ResultStore::Row>& rows,
                                              int details);
std::string html_report(const SweepSpec& spec, const std::vector<ResultStore::Row>& rows, const ReportOptions& opt);

// Outputs never overwrite their inputs: InputError naming the option when an output (option,
// path) is the store (or its journal), one of the dataset folders or a file inside one, or the
// same file as another output. Empty paths are not outputs.
void check_report_outputs(const std::string& store_path, const std::vector<std::string>& dataset_dirs,
                          const std::vector<std::pair<std::string, std::string>>& outputs);
// The dataset the report renders images from when none is given: the folder the sweep ran on
// (ResultStore::sweep_dataset) when it still exists; "" (and a note on stderr) otherwise.
std::string images_dataset(const std::string& swept_dataset);

}  // namespace parallax::reports
