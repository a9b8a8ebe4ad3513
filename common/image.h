// Image helpers on OpenCV matrices: loading with clear errors, grey conversion,
// bilinear sampling with the brief's pixel convention (centre of pixel (u,v) at (u,v)).
#pragma once
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <opencv2/core.hpp>

namespace tetmvs {

// The pixel size an image file declares in its header, read without decoding it (PNG,
// JPEG, BMP, TIFF, PNM); nullopt for other formats or a header too short to tell.
struct ImageSize {
  std::int64_t width = 0, height = 0;
};
std::optional<ImageSize> read_image_size(const std::filesystem::path& file);

// Loads an 8-bit image as RGB (CV_8UC3) (common/image_read.cpp: OpenCV's decoders, any
// format they read). Throws Error naming the file when it is
// missing, unreadable or not 8-bit, or when its header declares more pixels than the
// stage's memory budget holds (checked before decoding; common/budget.h).
cv::Mat load_rgb(const std::filesystem::path& file);
// Loads a mask (any depth/channels) as CV_8U with 255 where the first channel > 127.
cv::Mat load_mask(const std::filesystem::path& file);
// RGB (CV_8UC3) -> float grey in [0,1] (CV_32F).
cv::Mat rgb_to_grey(const cv::Mat& rgb);
// The PNG file of an 8-bit grey, RGB or RGBA image (libpng; channels in that order, not
// OpenCV's BGR).
std::string encode_png(const cv::Mat& img);
// Writes encode_png(rgb) atomically.
void write_png_rgb(const std::filesystem::path& file, const cv::Mat& rgb);

// Bilinear sample of a CV_32F image at (u, v). Returns false (and leaves out
// untouched) when the 2x2 neighbourhood leaves the image.
inline bool sample_bilinear(const cv::Mat& img, double u, double v, float& out) {
  const int u0 = static_cast<int>(std::floor(u)), v0 = static_cast<int>(std::floor(v));
  if (u0 < 0 || v0 < 0 || u0 + 1 >= img.cols || v0 + 1 >= img.rows) {
    // exact hits on the last row/column are still inside
    if (u0 >= 0 && v0 >= 0 && u0 < img.cols && v0 < img.rows && u == u0 && v == v0) {
      out = img.at<float>(v0, u0);
      return true;
    }
    return false;
  }
  const float a = static_cast<float>(u - u0), b = static_cast<float>(v - v0);
  const float* r0 = img.ptr<float>(v0) + u0;
  const float* r1 = img.ptr<float>(v0 + 1) + u0;
  out = (1 - b) * ((1 - a) * r0[0] + a * r0[1]) + b * ((1 - a) * r1[0] + a * r1[1]);
  return true;
}

}  // namespace tetmvs
