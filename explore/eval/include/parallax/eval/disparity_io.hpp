// Disparity maps on disk (docs/algorithm.md section 6) and as pictures.
//
// Disk format: KITTI 16-bit single-channel PNG, value = round(256 * d), 0 = invalid. A valid
// disparity 0 (a point at infinity) is written as 1 (1/256 px) so that it stays valid.
#pragma once

#include <filesystem>
#include <string>
#include <opencv2/core.hpp>

namespace parallax::eval {

// A disparity map and its validity: disparity_px CV_32FC1 in pixels, valid_mask CV_8UC1 of the
// same size, non-zero = valid. Values under an invalid mask are meaningless.
struct DisparityMap {
  cv::Mat disparity_px;
  cv::Mat valid_mask;
};

// Largest disparity the KITTI format can hold: 65535 / 256 px.
constexpr double kKittiMaxDisparityPx = 65535.0 / 256.0;

// Decodes an image file as stored (depth and channels unchanged), empty when OpenCV cannot decode
// it. A file whose header claims more pixels than OpenCV's limit (OPENCV_IO_MAX_IMAGE_PIXELS; the
// CLI sets 64 Mpx) or that makes the decoder fail throws InputError naming the file and `role`.
cv::Mat decode_image_file(const std::filesystem::path& file, const std::string& role);

// Writes a KITTI disparity PNG. Valid pixels must hold a finite d in [0, 65535/256] (after
// rounding): anything else throws std::invalid_argument naming the file and the pixel. Throws
// InputError naming the file if it cannot be written.
void write_kitti_disparity(const std::filesystem::path& file, const cv::Mat& disparity_px, const cv::Mat& valid_mask);

// Reads a KITTI disparity PNG: d = value / 256, value 0 = invalid (mask 0, d 0); mask 255
// elsewhere. Throws InputError (input_error.hpp) naming the file if it is missing, undecodable or
// not 16-bit single-channel.
DisparityMap read_kitti_disparity(const std::filesystem::path& file);

// Reads a grey PFM (Portable Float Map, header "Pf"): CV_32FC1 with rows top to bottom (the
// file stores them bottom to top), values as stored (inf and nan kept). The byte order is the
// sign of the header's scale: negative = little-endian, positive = big-endian. Trailing bytes
// after the pixels are ignored. Throws InputError naming the file (and the header field) when it
// is missing or a folder, its header is not "Pf W H scale" with W, H positive integers and a
// non-zero scale, it is a colour PFM ("PF"), or it holds fewer pixel bytes than W x H floats.
cv::Mat read_pfm(const std::filesystem::path& file);

// Reads a PFM disparity map (Middlebury 2014/2021 disp0.pfm, disp0GT.pfm): d = value, non-finite
// values (inf = unknown) invalid (mask 0, d 0). Errors as read_pfm.
DisparityMap read_pfm_disparity(const std::filesystem::path& file);

// A picture of a disparity map, CV_8UC3 BGR: HSV hue from 240 deg (blue, d = 0, far) to 0 deg
// (red, d >= max_disparity_px, near), full saturation and value; invalid pixels black.
// max_disparity_px must be > 0 (std::invalid_argument otherwise).
cv::Mat colourize_disparity(const cv::Mat& disparity_px, const cv::Mat& valid_mask, double max_disparity_px);

// Writes any 8- or 16-bit image as PNG (compression level fixed, so runs are reproducible).
// Throws InputError naming the file if it cannot be written.
void write_png(const std::filesystem::path& file, const cv::Mat& image);

}  // namespace parallax::eval
