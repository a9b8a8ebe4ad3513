// Pictures of silhouette-fix for people (silfix.h).
#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/silhouette/border.h"
#include "common/silfix/silfix.h"

namespace tetmvs::silfix {

cv::Mat view_picture(const cv::Mat& truth, const cv::Mat& s1, const std::vector<Constraint>& constraints,
                     int view, double margin_px) {
  require(truth.type() == CV_8U && s1.type() == CV_8U && truth.size() == s1.size(),
          "view_picture: the two silhouettes must be CV_8U masks of one size");
  // distances to the outline, which the image border is not (common/silhouette/border.h)
  const cv::Mat dist_in = silhouette::distance_inside(truth), dist_out = silhouette::distance_outside(truth);
  cv::Mat img(truth.size(), CV_8UC3, cv::Scalar(0, 0, 0));  // RGB
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) {
      const bool t = truth.at<std::uint8_t>(y, x) != 0, m = s1.at<std::uint8_t>(y, x) != 0;
      cv::Vec3b c(0, 0, 0);
      if (t && m) c = cv::Vec3b(40, 150, 40);                                           // agree: green
      else if (m) c = dist_out.at<float>(y, x) >= margin_px ? cv::Vec3b(230, 40, 40) : cv::Vec3b(110, 30, 30);  // too big: red
      else if (t) c = dist_in.at<float>(y, x) >= margin_px ? cv::Vec3b(50, 90, 255) : cv::Vec3b(30, 45, 120);   // too small: blue
      img.at<cv::Vec3b>(y, x) = c;
    }
  for (const auto& k : constraints) {
    if (k.view != view) continue;
    if (k.kind == kExteriorKind) {
      cv::circle(img, {k.u, k.v}, 1, cv::Scalar(255, 0, 255), cv::FILLED);
    } else {
      const int r = 4;
      cv::line(img, {k.u - r, k.v}, {k.u + r, k.v}, cv::Scalar(255, 255, 0), 1);
      cv::line(img, {k.u, k.v - r}, {k.u, k.v + r}, cv::Scalar(255, 255, 0), 1);
    }
  }
  return img;
}

cv::Mat contact_sheet(const std::vector<cv::Mat>& pictures, const std::vector<std::string>& captions,
                      int tile_width) {
  require(!pictures.empty(), "contact_sheet: no pictures");
  require(captions.size() == pictures.size(), "contact_sheet: one caption per picture");
  require(tile_width >= 16, "contact_sheet: tile width must be at least 16");
  const int n = static_cast<int>(pictures.size());
  const int cols = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  const int rows = (n + cols - 1) / cols;
  const double scale = static_cast<double>(tile_width) / pictures[0].cols;
  const int tile_h = std::max(1, static_cast<int>(std::lround(pictures[0].rows * scale)));
  const int cap_h = 16, legend_h = 20;
  cv::Mat sheet(legend_h + rows * (tile_h + cap_h), cols * tile_width, CV_8UC3, cv::Scalar(25, 25, 25));
  cv::putText(sheet, "green agree, red S1 too big, blue S1 too small, yellow + interior, magenta . exterior",
              {4, 14}, cv::FONT_HERSHEY_PLAIN, 0.8, cv::Scalar(230, 230, 230), 1, cv::LINE_AA);
  for (int i = 0; i < n; ++i) {
    require(pictures[i].type() == CV_8UC3, "contact_sheet: pictures must be RGB");
    cv::Mat tile;
    cv::resize(pictures[i], tile, {tile_width, tile_h}, 0, 0, cv::INTER_AREA);
    const int r = i / cols, c = i % cols;
    const int y = legend_h + r * (tile_h + cap_h), x = c * tile_width;
    tile.copyTo(sheet(cv::Rect(x, y, tile_width, tile_h)));
    cv::putText(sheet, captions[i], {x + 3, y + tile_h + 12}, cv::FONT_HERSHEY_PLAIN, 0.8,
                cv::Scalar(230, 230, 230), 1, cv::LINE_AA);
  }
  return sheet;
}

}  // namespace tetmvs::silfix
