#include "common/photoconsist/hull.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/silhouette/border.h"

namespace tetmvs::photoconsist {

HullTest::HullTest(const photo::Views& views, const std::vector<cv::Mat>& sil, double margin_px, double core_px)
    : views_(&views) {
  require(core_px >= 0, "photoconsist: hull core margin ", core_px, " must be >= 0");
  require(sil.empty() || static_cast<int>(sil.size()) == views.size(), "photoconsist: ", sil.size(),
          " silhouettes for ", views.size(), " views");
  require(margin_px >= 0, "photoconsist: hull margin ", margin_px, " must be >= 0");
  const int r = static_cast<int>(std::ceil(margin_px));
  const cv::Mat kernel =
      r > 0 ? cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1)) : cv::Mat();
  for (int v = 0; v < static_cast<int>(sil.size()); ++v) {
    if (sil[v].empty()) continue;
    require(sil[v].type() == CV_8U && sil[v].cols == views[v].width && sil[v].rows == views[v].height,
            "photoconsist: silhouette of view ", v, " does not match its image");
    cv::Mat d;
    if (r > 0)
      cv::dilate(sil[v], d, kernel);
    else
      d = sil[v];
    idx_.push_back(v);
    const std::size_t words = (static_cast<std::size_t>(d.cols) + 63) / 64;
    std::vector<std::uint64_t> bits(words * d.rows, 0);
    for (int y = 0; y < d.rows; ++y) {
      const std::uint8_t* row = d.ptr<std::uint8_t>(y);
      for (int x = 0; x < d.cols; ++x)
        if (row[x]) bits[y * words + (x >> 6)] |= std::uint64_t{1} << (x & 63);
    }
    bits_.push_back(std::move(bits));
    words_.push_back(words);
    cv::Mat bin = d != 0, ii;
    bin.convertTo(bin, CV_8U, 1.0 / 255.0);
    cv::integral(bin, ii, CV_32S);
    integral_.push_back(ii);
    if (core_px > 0) {
      core_.push_back(silhouette::distance_inside(sil[v]) >= core_px);
    }
  }
}

bool HullTest::in_core(const Eigen::Vector3d& X) const {
  if (core_.empty()) return false;
  int views = 0;
  for (std::size_t s = 0; s < idx_.size(); ++s) {
    int x, y;
    if (!pixel(s, X, x, y)) continue;
    if (core_[s].at<std::uint8_t>(y, x) == 0) return false;
    ++views;
  }
  return views > 0;
}

bool HullTest::pixel(std::size_t s, const Eigen::Vector3d& X, int& x, int& y) const {
  return pixel_of(s, (*views_)[idx_[s]].project_h(X), x, y);
}

bool HullTest::pixel_of(std::size_t s, const Eigen::Vector3d& h, int& x, int& y) const {
  const photo::View& v = (*views_)[idx_[s]];
  if (!(h.z() > 0)) return false;
  return silhouette::nearest_pixel_in_image(Eigen::Vector2d(h.x() / h.z(), h.y() / h.z()), v.width, v.height, x, y);
}


bool HullTest::inside(const Eigen::Vector3d& X) const {
  for (std::size_t s = 0; s < idx_.size(); ++s) {
    int x, y;
    if (pixel(s, X, x, y) && !in_dilated(s, x, y)) return false;
  }
  return true;
}

bool HullTest::triangle_outside(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                const Eigen::Vector3d& c) const {
  for (std::size_t s = 0; s < idx_.size(); ++s) {
    const photo::View& v = (*views_)[idx_[s]];
    const Eigen::Vector3d h[3] = {v.project_h(a), v.project_h(b), v.project_h(c)};
    if (!(h[0].z() > 0 && h[1].z() > 0 && h[2].z() > 0)) continue;
    double u0 = 1e300, u1 = -1e300, w0 = 1e300, w1 = -1e300;
    for (const auto& p : h) {
      const double u = p.x() / p.z(), w = p.y() / p.z();
      u0 = std::min(u0, u), u1 = std::max(u1, u), w0 = std::min(w0, w), w1 = std::max(w1, w);
    }
    // Pixels whose nearest-pixel rounding any point of the box can hit.
    const long x0 = std::lround(std::floor(u0 - 0.5)), x1 = std::lround(std::ceil(u1 + 0.5));
    const long y0 = std::lround(std::floor(w0 - 0.5)), y1 = std::lround(std::ceil(w1 + 0.5));
    if (x0 < 0 || y0 < 0 || x1 >= v.width || y1 >= v.height) continue;  // not all inside the image
    // a silhouette pixel at the box's centre: no need to count them
    if (in_dilated(s, static_cast<int>((x0 + x1) / 2), static_cast<int>((y0 + y1) / 2))) continue;
    const cv::Mat& ii = integral_[s];
    const int X0 = static_cast<int>(x0), X1 = static_cast<int>(x1) + 1, Y0 = static_cast<int>(y0),
              Y1 = static_cast<int>(y1) + 1;
    const int sum = ii.at<int>(Y1, X1) - ii.at<int>(Y0, X1) - ii.at<int>(Y1, X0) + ii.at<int>(Y0, X0);
    if (sum == 0) return true;
  }
  return false;
}

}  // namespace tetmvs::photoconsist
