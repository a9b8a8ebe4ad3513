#include "common/photo/views.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/silhouette/border.h"

namespace tetmvs::photo {

namespace {
cv::Mat inside_px_of(const cv::Mat& sil) {
  cv::Mat out;
  silhouette::distance_inside(sil).convertTo(out, CV_8U);  // saturating: at most 255
  return out;
}
}  // namespace

bool View::in_silhouette(double u, double v) const {
  if (sil.empty()) return true;
  const int x = static_cast<int>(std::lround(u)), y = static_cast<int>(std::lround(v));
  if (x < 0 || y < 0 || x >= sil.cols || y >= sil.rows) return false;
  return sil.at<unsigned char>(y, x) != 0;
}

Views::Views(const std::vector<Camera>& cams, const std::vector<cv::Mat>& grey,
             const std::vector<cv::Mat>& sil, bool outline_distances)
    : outline_distances_(outline_distances) {
  require(grey.size() == cams.size(), "photo::Views: ", grey.size(), " grey images for ", cams.size(),
          " cameras");
  require(sil.empty() || sil.size() == cams.size(), "photo::Views: ", sil.size(),
          " silhouettes for ", cams.size(), " cameras");
  views_.resize(cams.size());
  for (size_t i = 0; i < cams.size(); ++i) {
    const Camera& c = cams[i];
    View& v = views_[i];
    const cv::Mat& g = grey[i];
    require(!g.empty() && g.type() == CV_32F && g.channels() == 1, "photo::Views: grey image of view ",
            i, " (", c.name, ") must be a non-empty CV_32F single-channel image");
    require((c.width == 0 || c.width == g.cols) && (c.height == 0 || c.height == g.rows),
            "photo::Views: grey image of view ", i, " (", c.name, ") is ", g.cols, "x", g.rows,
            ", camera says ", c.width, "x", c.height);
    require(c.K(2, 0) == 0.0 && c.K(2, 1) == 0.0 && c.K(2, 2) > 0.0 && c.K.allFinite() &&
                c.R.allFinite() && c.t.allFinite(),
            "photo::Views: camera ", i, " (", c.name, ") needs a finite K with last row (0, 0, k33 > 0)");
    v.P = c.P() / c.K(2, 2);
    v.centre = c.centre();
    const double f = 0.5 * (c.K(0, 0) + c.K(1, 1)) / c.K(2, 2);
    require(f > 0.0, "photo::Views: camera ", i, " (", c.name, ") has focal length ", f);
    v.inv_focal = 1.0 / f;
    v.grey = g;
    v.width = g.cols;
    v.height = g.rows;
    if (!sil.empty() && !sil[i].empty()) {
      require(sil[i].type() == CV_8U && sil[i].cols == g.cols && sil[i].rows == g.rows,
              "photo::Views: silhouette of view ", i, " (", c.name, ") must be CV_8U of size ", g.cols,
              "x", g.rows);
      v.sil = sil[i];
      if (outline_distances_) v.inside_px = inside_px_of(v.sil);
      has_sil_ = true;
    }
  }
}

Views Views::reduced(int level) const {
  require(level >= 0 && level <= 12, "photo::Views::reduced: pyramid level ", level, " must lie in [0, 12]");
  Views out = *this;
  if (level == 0) return out;
  for (View& v : out.views_) {
    cv::Mat g = v.grey;
    for (int l = 0; l < level; ++l) {
      require(g.cols >= 2 && g.rows >= 2, "photo::Views::reduced: a ", v.width, "x", v.height,
              " image has no pyramid level ", level);
      cv::Mat d;
      cv::pyrDown(g, d);
      g = d;
    }
    const double s = 1.0 / static_cast<double>(1 << level);
    v.P.topRows<2>() *= s;
    v.inv_focal /= s;
    if (!v.sil.empty()) {
      cv::Mat m(g.rows, g.cols, CV_8U);
      const int f = 1 << level;
      for (int y = 0; y < g.rows; ++y)
        for (int x = 0; x < g.cols; ++x)
          m.at<unsigned char>(y, x) = v.sil.at<unsigned char>(std::min(y * f, v.sil.rows - 1), std::min(x * f, v.sil.cols - 1));
      v.sil = m;
      if (outline_distances_) v.inside_px = inside_px_of(v.sil);
    }
    v.grey = g;
    v.width = g.cols;
    v.height = g.rows;
  }
  return out;
}

}  // namespace tetmvs::photo
