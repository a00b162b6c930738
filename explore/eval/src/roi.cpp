// The region of interest (ROI) of dataset frames: centred and full ROIs, the "full" / WxH size
// setting, and cropping an image to a ROI.
#include "parallax/eval/dataset.hpp"
#include "parallax/eval/text_util.hpp"

#include <stdexcept>

#include "dataset_internal.hpp"

namespace parallax::eval {
using dataset_detail::all_digits;
using dataset_detail::size_text;
using detail::trim;

Roi centred_roi(int image_w, int image_h, int roi_w, int roi_h) {
  if (roi_w <= 0 || roi_h <= 0) {
    throw InputError("ROI " + size_text(roi_w, roi_h) + ": width and height must be > 0");
  }
  if (roi_w > image_w || roi_h > image_h) {
    throw InputError("ROI " + size_text(roi_w, roi_h) + " is larger than the image (" + size_text(image_w, image_h) +
                     "); use --roi full, or --set roi=WxH with a smaller size");
  }
  return Roi{(image_w - roi_w) / 2, (image_h - roi_h) / 2, roi_w, roi_h};
}

Roi full_roi(int image_w, int image_h) {
  return Roi{0, 0, image_w, image_h};
}

RoiSize parse_roi_size(const std::string& text) {
  const std::string t = trim(text);
  if (t == "full") return RoiSize{};
  const std::size_t x = t.find_first_of("xX");
  if (x != std::string::npos) {
    const std::string w = t.substr(0, x);
    const std::string h = t.substr(x + 1);
    if (all_digits(w) && all_digits(h) && w.size() <= 6 && h.size() <= 6) {
      const int width_px = std::stoi(w);
      const int height_px = std::stoi(h);
      if (width_px > 0 && height_px > 0) return RoiSize{false, width_px, height_px};
    }
  }
  throw InputError("ROI '" + text + "': expected 'full' or WIDTHxHEIGHT, e.g. 640x360");
}

std::string to_string(const RoiSize& size) {
  return size.full ? "full" : size_text(size.width_px, size.height_px);
}

Roi resolve_roi(const RoiSize& size, int image_w, int image_h) {
  if (size.full) return full_roi(image_w, image_h);
  return centred_roi(image_w, image_h, size.width_px, size.height_px);
}

cv::Mat crop_to_roi(const cv::Mat& image, const Roi& roi) {
  if (roi.x0 < 0 || roi.y0 < 0 || roi.width_px <= 0 || roi.height_px <= 0 || roi.x0 + roi.width_px > image.cols ||
      roi.y0 + roi.height_px > image.rows) {
    throw std::invalid_argument("crop_to_roi: ROI " + size_text(roi.width_px, roi.height_px) + " at (" +
                                std::to_string(roi.x0) + ", " + std::to_string(roi.y0) + ") does not fit in a " +
                                size_text(image) + " image");
  }
  return image(cv::Rect(roi.x0, roi.y0, roi.width_px, roi.height_px));
}

}  // namespace parallax::eval
