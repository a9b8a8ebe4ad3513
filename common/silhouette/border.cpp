#include "common/silhouette/border.h"

#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace tetmvs::silhouette {

namespace {
void check_mask(const cv::Mat& mask, const char* what) {
  require(!mask.empty() && mask.type() == CV_8U, "silhouette::", what, ": expected a non-empty CV_8U mask");
}

// Distance of every non-zero pixel of `from` to the nearest zero pixel inside the image.
// (OpenCV's transform already leaves the border out: pixels beyond it count as neither.
// A mask without any zero pixel gets a distance larger than the image.)
cv::Mat distance_to_zero(const cv::Mat& from) {
  cv::Mat d;
  if (cv::countNonZero(from) == static_cast<int>(from.total())) {
    d = cv::Mat(from.size(), CV_32F, cv::Scalar(static_cast<float>(from.cols + from.rows)));
    return d;
  }
  cv::distanceTransform(from, d, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  return d;
}
}  // namespace

cv::Mat outline(const cv::Mat& mask) {
  check_mask(mask, "outline");
  cv::Mat out(mask.size(), CV_8U, cv::Scalar(0));
  const int W = mask.cols, H = mask.rows;
  for (int y = 0; y < H; ++y) {
    const std::uint8_t* r = mask.ptr<std::uint8_t>(y);
    const std::uint8_t* up = y > 0 ? mask.ptr<std::uint8_t>(y - 1) : nullptr;
    const std::uint8_t* dn = y + 1 < H ? mask.ptr<std::uint8_t>(y + 1) : nullptr;
    std::uint8_t* o = out.ptr<std::uint8_t>(y);
    for (int x = 0; x < W; ++x) {
      if (!r[x]) continue;
      // only neighbours inside the image count: the border is not an outline
      const bool bg = (x > 0 && !r[x - 1]) || (x + 1 < W && !r[x + 1]) || (up && !up[x]) || (dn && !dn[x]);
      if (bg) o[x] = 255;
    }
  }
  return out;
}

cv::Mat distance_inside(const cv::Mat& mask) {
  check_mask(mask, "distance_inside");
  return distance_to_zero(mask != 0);
}

cv::Mat distance_outside(const cv::Mat& mask) {
  check_mask(mask, "distance_outside");
  return distance_to_zero(mask == 0);
}

bool touches_border(const cv::Mat& mask) {
  check_mask(mask, "touches_border");
  const int W = mask.cols, H = mask.rows;
  return cv::countNonZero(mask.row(0)) > 0 || cv::countNonZero(mask.row(H - 1)) > 0 ||
         cv::countNonZero(mask.col(0)) > 0 || cv::countNonZero(mask.col(W - 1)) > 0;
}

}  // namespace tetmvs::silhouette
