// A PFM writer for tests, independent of the library's reader: grey "Pf" files, rows bottom to
// top, either byte order (the sign of the scale), optional custom header text.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <string>

namespace parallax::test {

// The PFM bytes of a CV_32FC1 image: header (default "Pf\nW H\n-1\n" for little-endian,
// "Pf\nW H\n1\n" for big-endian), then the rows bottom to top.
inline std::string pfm_bytes(const cv::Mat& values, bool little_endian, const std::string& header = "") {
  std::string out = header.empty() ? "Pf\n" + std::to_string(values.cols) + " " + std::to_string(values.rows) + "\n" +
                                         (little_endian ? "-1" : "1") + "\n"
                                   : header;
  for (int row = values.rows - 1; row >= 0; --row) {
    for (int x = 0; x < values.cols; ++x) {
      const float v = values.at<float>(row, x);
      std::uint32_t bits = 0;
      std::memcpy(&bits, &v, sizeof bits);
      char b[4];
      for (int k = 0; k < 4; ++k) {
        const int shift = little_endian ? 8 * k : 8 * (3 - k);
        b[k] = static_cast<char>((bits >> shift) & 0xffu);
      }
      out.append(b, 4);
    }
  }
  return out;
}

inline void write_bytes(const std::filesystem::path& file, const std::string& bytes) {
  std::filesystem::create_directories(file.parent_path());
  std::ofstream out(file, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(static_cast<bool>(out)) << file;
}

inline void write_pfm(const std::filesystem::path& file, const cv::Mat& values, bool little_endian) {
  write_bytes(file, pfm_bytes(values, little_endian));
}

}  // namespace parallax::test
