#include "common/image.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/fileio.h"

namespace tetmvs {
namespace fs = std::filesystem;

cv::Mat load_rgb(const fs::path& file) {
  if (!fs::exists(file)) fail(file.string(), ": image file is missing");
  cv::Mat m = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  if (m.empty()) fail(file.string(), ": cannot decode image (corrupt or unsupported format)");
  if (m.depth() != CV_8U) fail(file.string(), ": image must be 8-bit per channel");
  cv::Mat rgb;
  if (m.channels() == 1) cv::cvtColor(m, rgb, cv::COLOR_GRAY2RGB);
  else if (m.channels() == 3) cv::cvtColor(m, rgb, cv::COLOR_BGR2RGB);
  else if (m.channels() == 4) cv::cvtColor(m, rgb, cv::COLOR_BGRA2RGB);
  else fail(file.string(), ": unsupported channel count ", m.channels());
  return rgb;
}

cv::Mat load_mask(const fs::path& file) {
  if (!fs::exists(file)) fail(file.string(), ": mask file is missing");
  cv::Mat m = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  if (m.empty()) fail(file.string(), ": cannot decode mask image");
  std::vector<cv::Mat> ch;
  cv::split(m, ch);
  cv::Mat first;
  ch[0].convertTo(first, CV_32F, m.depth() == CV_16U ? 1.0 / 257.0 : 1.0);
  cv::Mat out = first > 127.0f;
  return out;
}

cv::Mat rgb_to_grey(const cv::Mat& rgb) {
  require(rgb.type() == CV_8UC3, "rgb_to_grey: expected an 8-bit RGB image");
  cv::Mat g(rgb.rows, rgb.cols, CV_32F);
  for (int y = 0; y < rgb.rows; ++y) {
    const auto* s = rgb.ptr<cv::Vec3b>(y);
    float* d = g.ptr<float>(y);
    for (int x = 0; x < rgb.cols; ++x)
      d[x] = (0.299f * s[x][0] + 0.587f * s[x][1] + 0.114f * s[x][2]) / 255.0f;
  }
  return g;
}

void write_png_rgb(const fs::path& file, const cv::Mat& rgb) {
  cv::Mat out;
  if (rgb.channels() == 3) cv::cvtColor(rgb, out, cv::COLOR_RGB2BGR);
  else out = rgb;
  std::vector<uchar> buf;
  if (!cv::imencode(".png", out, buf)) fail(file.string(), ": PNG encoding failed");
  write_text_atomic(file, std::string(buf.begin(), buf.end()));
}

}  // namespace tetmvs
