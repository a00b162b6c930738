// KITTI disparity PNGs and disparity pictures.
#include "parallax/explore/disparity_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "parallax/explore/dataset.hpp"

namespace parallax::explore {
namespace {

constexpr int kPngCompressionLevel = 9;  // zlib level; fixed so that outputs are reproducible

void require_disparity_and_mask(const cv::Mat& disparity_px, const cv::Mat& valid_mask,
                                const std::string& where) {
  if (disparity_px.empty() || disparity_px.type() != CV_32FC1) {
    throw std::invalid_argument(where + ": disparity must be a non-empty CV_32FC1 matrix");
  }
  if (valid_mask.type() != CV_8UC1 || valid_mask.size() != disparity_px.size()) {
    throw std::invalid_argument(where + ": validity mask must be CV_8UC1 of the disparity's size");
  }
}

// HSV (h in degrees [0, 360), s = v = 1) to BGR bytes.
cv::Vec3b hue_to_bgr(double hue_deg) {
  const double sector = hue_deg / 60.0;
  const int i = std::min(5, static_cast<int>(std::floor(sector)));
  const double f = sector - i;
  double r = 0.0;
  double g = 0.0;
  double b = 0.0;
  switch (i) {
    case 0:
      r = 1.0;
      g = f;
      b = 0.0;
      break;
    case 1:
      r = 1.0 - f;
      g = 1.0;
      b = 0.0;
      break;
    case 2:
      r = 0.0;
      g = 1.0;
      b = f;
      break;
    case 3:
      r = 0.0;
      g = 1.0 - f;
      b = 1.0;
      break;
    case 4:
      r = f;
      g = 0.0;
      b = 1.0;
      break;
    default:
      r = 1.0;
      g = 0.0;
      b = 1.0 - f;
      break;
  }
  auto byte = [](double c) { return static_cast<std::uint8_t>(std::lround(255.0 * c)); };
  return cv::Vec3b(byte(b), byte(g), byte(r));
}

}  // namespace

void write_png(const std::filesystem::path& file, const cv::Mat& image) {
  const std::vector<int> params = {cv::IMWRITE_PNG_COMPRESSION, kPngCompressionLevel};
  bool ok = false;
  try {
    ok = cv::imwrite(file.string(), image, params);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(file.string() + ": cannot write PNG: " + e.what());
  }
  if (!ok) throw std::runtime_error(file.string() + ": cannot write PNG");
}

void write_kitti_disparity(const std::filesystem::path& file, const cv::Mat& disparity_px,
                           const cv::Mat& valid_mask) {
  require_disparity_and_mask(disparity_px, valid_mask, file.string());
  cv::Mat encoded(disparity_px.size(), CV_16UC1, cv::Scalar(0));
  for (int y = 0; y < disparity_px.rows; ++y) {
    const float* d = disparity_px.ptr<float>(y);
    const std::uint8_t* ok = valid_mask.ptr<std::uint8_t>(y);
    std::uint16_t* out = encoded.ptr<std::uint16_t>(y);
    for (int x = 0; x < disparity_px.cols; ++x) {
      if (ok[x] == 0) continue;  // stays 0 = invalid
      const double scaled = 256.0 * static_cast<double>(d[x]);
      const double value = std::isfinite(scaled) ? std::round(scaled) : -1.0;
      if (!(value >= 0.0 && value <= 65535.0)) {
        throw std::invalid_argument(file.string() + ": disparity " + std::to_string(d[x]) +
                                    " px at (x " + std::to_string(x) + ", y " + std::to_string(y) +
                                    ") is outside the KITTI range [0, 65535/256]");
      }
      out[x] = static_cast<std::uint16_t>(std::max(1.0, value));  // valid 0 -> 1
    }
  }
  write_png(file, encoded);
}

DisparityMap read_kitti_disparity(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) {
    throw InputError(file.string() + ": disparity file not found");
  }
  const cv::Mat encoded = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  if (encoded.empty()) throw InputError(file.string() + ": cannot be decoded as an image");
  if (encoded.type() != CV_16UC1) {
    throw InputError(file.string() +
                     ": not a KITTI disparity map (expected a 16-bit "
                     "single-channel PNG, got " +
                     std::to_string(encoded.channels()) + " channel(s) of " +
                     std::to_string(8 * encoded.elemSize1()) + " bits)");
  }
  DisparityMap map{cv::Mat(encoded.size(), CV_32FC1), cv::Mat(encoded.size(), CV_8UC1)};
  for (int y = 0; y < encoded.rows; ++y) {
    const std::uint16_t* in = encoded.ptr<std::uint16_t>(y);
    float* d = map.disparity_px.ptr<float>(y);
    std::uint8_t* ok = map.valid_mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < encoded.cols; ++x) {
      d[x] = static_cast<float>(in[x]) / 256.0f;  // exact: 16-bit value, power-of-two divisor
      ok[x] = in[x] != 0 ? 255 : 0;
    }
  }
  return map;
}

cv::Mat colourize_disparity(const cv::Mat& disparity_px, const cv::Mat& valid_mask,
                            double max_disparity_px) {
  require_disparity_and_mask(disparity_px, valid_mask, "colourize_disparity");
  if (!(max_disparity_px > 0.0) || !std::isfinite(max_disparity_px)) {
    throw std::invalid_argument("colourize_disparity: max_disparity_px must be > 0");
  }
  cv::Mat picture(disparity_px.size(), CV_8UC3, cv::Scalar(0, 0, 0));
  for (int y = 0; y < disparity_px.rows; ++y) {
    const float* d = disparity_px.ptr<float>(y);
    const std::uint8_t* ok = valid_mask.ptr<std::uint8_t>(y);
    cv::Vec3b* out = picture.ptr<cv::Vec3b>(y);
    for (int x = 0; x < disparity_px.cols; ++x) {
      if (ok[x] == 0 || !std::isfinite(d[x])) continue;  // black
      const double t = std::clamp(static_cast<double>(d[x]) / max_disparity_px, 0.0, 1.0);
      out[x] = hue_to_bgr(240.0 * (1.0 - t));
    }
  }
  return picture;
}

}  // namespace parallax::explore
