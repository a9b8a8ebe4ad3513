#include "common/q_silhouettes.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace tetmvs {

void QSilhouetteOptions::check() const { check_param_ranges(*this); }

QSilhouetteOptions QSilhouetteOptions::from_params(const Params& p) {
  QSilhouetteOptions o;
  read_params(p, o);
  o.check();
  return o;
}

std::vector<cv::Mat> estimate_q_silhouettes(const Scene& s, const QPoints& q, double cell, const QSilhouetteOptions& o) {
  if (!o.on || s.num_silhouettes() > 0 || q.size() == 0) return std::vector<cv::Mat>(s.size());
  // the cell in pixels at the median depth of Q over the views (one value: the closing
  // radius is one for all)
  std::vector<double> px;
  for (std::int64_t p = 0; p < q.size(); p += std::max<std::int64_t>(1, q.size() / 2000))
    for (int v = 0; v < s.size(); ++v) {
      const double z = s.cams[v].depth(q.pos(p));
      if (z > 0) px.push_back(cell * s.cams[v].focal() / z);
    }
  double cell_px = 0;
  if (!px.empty()) {
    std::nth_element(px.begin(), px.begin() + px.size() / 2, px.end());
    cell_px = px[px.size() / 2];
  }
  const double close = std::max(o.close_px, o.close_cells * cell_px);
  return q_silhouettes(s, q, o.splat_cells * cell, close, o.margin_px, o.min_points);
}

std::vector<cv::Mat> q_silhouettes(const Scene& s, const QPoints& q, double splat, double close_px, double margin_px,
                                   int min_points) {
  require(splat > 0 && close_px >= 0 && margin_px >= 0, "q_silhouettes needs splat > 0, close_px >= 0, margin_px >= 0");
  std::vector<cv::Mat> out(s.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (int v = 0; v < s.size(); ++v) {
    if (s.has_silhouette(v)) continue;
    const Camera& cam = s.cams[v];
    cv::Mat m = cv::Mat::zeros(cam.height, cam.width, CV_8U);
    int n = 0;
    for (std::int64_t p = 0; p < q.size(); ++p) {
      bool consistent = false;
      for (std::int64_t k = q.cam_offsets[p]; k < q.cam_offsets[p + 1] && !consistent; ++k) consistent = q.cams[k] == v;
      if (!consistent) continue;
      const Eigen::Vector3d X = q.pos(p);
      const double z = cam.depth(X);
      if (z <= 0) continue;
      const Eigen::Vector2d px = cam.project(X);
      const int u = static_cast<int>(std::lround(px.x())), w = static_cast<int>(std::lround(px.y()));
      if (u < 0 || w < 0 || u >= cam.width || w >= cam.height) continue;
      const int r = std::max(1, static_cast<int>(std::lround(splat * cam.focal() / z)));
      cv::circle(m, cv::Point(u, w), r, cv::Scalar(255), cv::FILLED);
      ++n;
    }
    if (n < min_points) continue;  // too few points to outline the object: no estimate
    const int c = static_cast<int>(std::lround(close_px));
    if (c > 0)
      cv::morphologyEx(m, m, cv::MORPH_CLOSE, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * c + 1, 2 * c + 1)),
                       cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    // fill holes: background is what the image border reaches through unmarked pixels
    cv::Mat pad;
    cv::copyMakeBorder(m, pad, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    cv::floodFill(pad, cv::Point(0, 0), cv::Scalar(128));
    m = pad(cv::Rect(1, 1, cam.width, cam.height)) != 128;
    const int g = static_cast<int>(std::lround(margin_px));
    if (g > 0) cv::dilate(m, m, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * g + 1, 2 * g + 1)));
    out[v] = m;
  }
  return out;
}

}  // namespace tetmvs
