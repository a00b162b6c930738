// parallax crop-dataset: the centred ROI crop of a KITTI 2015 dataset (images and ground truth)
// written as a new dataset.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.hpp"
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/input_error.hpp"

namespace parallax::cli {

namespace {

using namespace parallax::eval;
using namespace parallax::search;

struct CropOptions {
  std::string src, out, frames, roi = "640x360";
};

int run_crop_dataset(const CropOptions& o, const Invocation&) {
  int w = 640, h = 360;
  const RoiSize rs = parse_roi_size(o.roi);
  if (rs.full) throw InputError("--roi: crop-dataset needs a size WxH, not full");
  w = rs.width_px;
  h = rs.height_px;
  const CropSummary s = crop_dataset(o.src, o.frames, {GtKind::noc, GtKind::occ}, w, h, o.out);
  std::printf("wrote %zu frames (%zu files) to %s\n", s.frame_ids.size(), s.files_written.size(), o.out.c_str());
  return 0;
}

}  // namespace

Command add_crop_dataset(CLI::App& app) {
  auto o = std::make_shared<CropOptions>();
  auto* crop = app.add_subcommand(
      "crop-dataset", "Write the centred ROI crop of a KITTI 2015 dataset (images and GT) as a new dataset");
  crop->add_option("--dataset", o->src, "Source dataset")->required();
  crop->add_option("--frames", o->frames, "Frames, e.g. 1-5,7, or @FILE (default: all)")->transform(FrameList());
  crop->add_option("--roi", o->roi, "ROI WxH")->capture_default_str();
  crop->add_option("--out", o->out, "Output folder")->required()->check(OutputFolder());
  return bind_command(crop, o, run_crop_dataset);
}

}  // namespace parallax::cli
