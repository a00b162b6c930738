// KITTI disparity PNGs, PFM disparity maps and disparity pictures.
#include "parallax/eval/disparity_io.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "parallax/eval/input_error.hpp"

namespace parallax::eval {

namespace {

constexpr int kPngCompressionLevel = 9;  // zlib level; fixed so that outputs are reproducible

void require_disparity_and_mask(const cv::Mat& disparity_px, const cv::Mat& valid_mask, const std::string& where) {
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
    throw InputError(file.string() + ": cannot write PNG: " + e.what());
  }
  if (!ok) throw InputError(file.string() + ": cannot write PNG");
}

void write_kitti_disparity(const std::filesystem::path& file, const cv::Mat& disparity_px, const cv::Mat& valid_mask) {
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
        throw std::invalid_argument(file.string() + ": disparity " + std::to_string(d[x]) + " px at (x " +
                                    std::to_string(x) + ", y " + std::to_string(y) +
                                    ") is outside the KITTI range [0, 65535/256]");
      }
      out[x] = static_cast<std::uint16_t>(std::max(1.0, value));  // valid 0 -> 1
    }
  }
  write_png(file, encoded);
}

cv::Mat decode_image_file(const std::filesystem::path& file, const std::string& role) {
  try {
    return cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    if (e.err.find("CV_IO_MAX_IMAGE_PIXELS") != std::string::npos)
      throw InputError(file.string() + ": the " + role +
                       " image's header claims more pixels than the limit (OPENCV_IO_MAX_IMAGE_PIXELS)");
    throw InputError(file.string() + ": cannot decode the " + role + " image: " + e.err);
  }
}

DisparityMap read_kitti_disparity(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) {
    throw InputError(file.string() + ": disparity file not found");
  }
  const cv::Mat encoded = decode_image_file(file, "disparity");
  if (encoded.empty()) throw InputError(file.string() + ": cannot be decoded as an image");
  if (encoded.type() != CV_16UC1) {
    throw InputError(file.string() +
                     ": not a KITTI disparity map (expected a 16-bit "
                     "single-channel PNG, got " +
                     std::to_string(encoded.channels()) + " channel(s) of " + std::to_string(8 * encoded.elemSize1()) +
                     " bits)");
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

cv::Mat read_pfm(const std::filesystem::path& file) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) {
    throw InputError(file.string() + ": is a folder, expected a PFM file");
  }
  if (!std::filesystem::is_regular_file(file, ec)) {
    throw InputError(file.string() + ": PFM file not found");
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot be read");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string bytes = buffer.str();

  // Header: three whitespace-separated fields after the magic, then one whitespace byte.
  std::size_t pos = 0;
  auto skip_space = [&] {
    while (pos < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[pos])) != 0) ++pos;
  };
  auto next_token = [&](const char* field) {
    skip_space();
    const std::size_t start = pos;
    while (pos < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[pos])) == 0 && pos - start < 32) {
      ++pos;
    }
    if (start == pos) {
      throw InputError(file.string() + ": PFM header ends before the " + field + " field");
    }
    return bytes.substr(start, pos - start);
  };
  const std::string magic = bytes.substr(0, 2);
  if (magic == "PF") {
    throw InputError(file.string() +
                     ": colour PFM (header 'PF', 3 channels); a disparity map is a grey PFM "
                     "(header 'Pf')");
  }
  if (magic != "Pf" || bytes.size() < 3 || std::isspace(static_cast<unsigned char>(bytes[2])) == 0) {
    std::string shown = bytes.substr(0, std::min<std::size_t>(bytes.size(), 8));
    for (char& c : shown)
      if (std::isprint(static_cast<unsigned char>(c)) == 0) c = '?';
    throw InputError(file.string() + ": not a PFM file (header starts with '" + shown + "', expected 'Pf')");
  }
  pos = 2;
  auto dimension = [&](const char* field) {
    const std::string token = next_token(field);
    const bool digits = std::all_of(token.begin(), token.end(),
                                    [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
    if (!digits || token.size() > 6 || std::stoi(token) <= 0) {
      throw InputError(file.string() + ": PFM header field " + field + ": '" + token +
                       "' is not a positive integer (at most 6 digits)");
    }
    return std::stoi(token);
  };
  const int width = dimension("width");
  const int height = dimension("height");
  const std::string scale_text = next_token("scale");
  double scale = 0.0;
  try {
    std::size_t used = 0;
    scale = std::stod(scale_text, &used);
    if (used != scale_text.size()) scale = 0.0;
  } catch (const std::exception&) {
    scale = 0.0;
  }
  if (!(scale != 0.0) || !std::isfinite(scale)) {
    throw InputError(file.string() + ": PFM header field scale: '" + scale_text +
                     "' is not a non-zero number (its sign gives the byte order)");
  }
  if (pos >= bytes.size() || std::isspace(static_cast<unsigned char>(bytes[pos])) == 0) {
    throw InputError(file.string() + ": PFM header field scale: no whitespace byte after it");
  }
  ++pos;  // the single whitespace byte that ends the header
  const bool little_endian = scale < 0.0;
  const std::size_t needed = std::size_t(width) * std::size_t(height) * 4u;
  const std::size_t have = bytes.size() - pos;
  if (have < needed) {
    throw InputError(file.string() + ": truncated PFM: " + std::to_string(width) + " x " + std::to_string(height) +
                     " floats need " + std::to_string(needed) + " bytes of pixel data, the file has " +
                     std::to_string(have));
  }
  cv::Mat image(height, width, CV_32FC1);
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data() + pos);
  for (int row = 0; row < height; ++row) {
    float* out = image.ptr<float>(height - 1 - row);  // stored bottom to top
    const unsigned char* in_row = data + std::size_t(row) * std::size_t(width) * 4u;
    for (int x = 0; x < width; ++x) {
      const unsigned char* b = in_row + 4 * x;
      const std::uint32_t bits =
          little_endian
              ? (std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24)
              : (std::uint32_t(b[3]) | std::uint32_t(b[2]) << 8 | std::uint32_t(b[1]) << 16 |
                 std::uint32_t(b[0]) << 24);
      std::memcpy(&out[x], &bits, sizeof bits);
    }
  }
  return image;
}

DisparityMap read_pfm_disparity(const std::filesystem::path& file) {
  const cv::Mat values = read_pfm(file);
  DisparityMap map{cv::Mat(values.size(), CV_32FC1), cv::Mat(values.size(), CV_8UC1)};
  for (int y = 0; y < values.rows; ++y) {
    const float* in = values.ptr<float>(y);
    float* d = map.disparity_px.ptr<float>(y);
    std::uint8_t* ok = map.valid_mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < values.cols; ++x) {
      const bool valid = std::isfinite(in[x]);
      d[x] = valid ? in[x] : 0.0f;
      ok[x] = valid ? 255 : 0;
    }
  }
  return map;
}

cv::Mat colourize_disparity(const cv::Mat& disparity_px, const cv::Mat& valid_mask, double max_disparity_px) {
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

}  // namespace parallax::eval
