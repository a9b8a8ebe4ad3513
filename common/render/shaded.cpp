#include "common/render/shaded.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/silhouette/border.h"
#include "common/trimesh/raster.h"

namespace tetmvs {

cv::Mat render_shaded(const TriMesh& m, const Camera& cam, const cv::Mat* photo) {
  const Raster r = rasterize(m, cam, {});
  cv::Mat out(cam.height, cam.width, CV_8UC3, cv::Scalar(0, 0, 0));
  if (photo && !photo->empty()) out = *photo * 0.35;
  const Eigen::Vector3d C = cam.centre();
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const int t = r.tri.at<int>(y, x);
      if (t < 0) continue;
      const Eigen::Vector3d n = face_cross(m, t).normalized();
      const Eigen::Vector3d X = m.V[m.F[t][0]];
      const double c = n.dot((C - X).normalized());
      const double shade = 0.15 + 0.85 * std::abs(c);
      const auto v = [](double a) { return static_cast<std::uint8_t>(std::clamp(a, 0.0, 255.0)); };
      out.at<cv::Vec3b>(y, x) = c >= 0 ? cv::Vec3b(v(235 * shade), v(225 * shade), v(200 * shade))
                                       : cv::Vec3b(v(255 * shade), v(60 * shade), v(60 * shade));
    }
  return out;
}

std::vector<int> spread_views(int n, int count) {
  std::vector<int> v;
  for (int k = 0; k < std::min(n, count); ++k) v.push_back(static_cast<int>(std::floor((k + 0.5) * n / count)));
  return v;
}

cv::Mat render_sheet(const TriMesh& m, const Scene& s, std::vector<int> views, int width) {
  if (views.empty()) views = spread_views(s.size());
  std::vector<cv::Mat> tiles;
  for (int v : views) {
    cv::Mat img = render_shaded(m, s.cams[v]);
    cv::Mat small;
    const double sc = double(width) / img.cols;
    cv::resize(img, small, {width, int(std::round(img.rows * sc))}, 0, 0, cv::INTER_AREA);
    cv::putText(small, s.cams[v].name, {4, 14}, cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(200, 200, 200), 1, cv::LINE_AA);
    tiles.push_back(small);
  }
  cv::Mat sheet;
  cv::hconcat(tiles, sheet);
  return sheet;
}

SilhouetteAgreement silhouette_agreement(const TriMesh& m, const Scene& s) {
  SilhouetteAgreement a;
  std::vector<double> bd;
  for (int v = 0; v < s.size(); ++v) {
    if (!s.has_silhouette(v)) continue;
    const Raster r = rasterize(m, s.cams[v], {});
    cv::Mat mine = r.tri >= 0;
    const cv::Mat& truth = s.sil[v];
    const double inter = cv::countNonZero(mine & truth), uni = cv::countNonZero(mine | truth);
    a.views.push_back(v);
    a.iou.push_back(uni > 0 ? inter / uni : 1.0);
    a.cut_by_border.push_back(silhouette::touches_border(truth));
    // boundary distance: pixels of my silhouette's boundary, distance to the true boundary
    // (the morphological gradient leaves the image border out, as silhouette::outline does)
    cv::Mat tb, mb;
    cv::morphologyEx(truth, tb, cv::MORPH_GRADIENT, cv::getStructuringElement(cv::MORPH_RECT, {3, 3}));
    cv::morphologyEx(mine, mb, cv::MORPH_GRADIENT, cv::getStructuringElement(cv::MORPH_RECT, {3, 3}));
    cv::Mat dist;
    cv::distanceTransform(tb == 0, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    for (int y = 0; y < mb.rows; ++y)
      for (int x = 0; x < mb.cols; ++x)
        if (mb.at<std::uint8_t>(y, x)) bd.push_back(dist.at<float>(y, x));
  }
  if (!a.iou.empty()) {
    double sum = 0;
    for (double x : a.iou) sum += x;
    a.mean_iou = sum / a.iou.size();
    double in_sum = 0;
    int in_views = 0;
    for (std::size_t k = 0; k < a.iou.size(); ++k)
      if (!a.cut_by_border[k]) in_sum += a.iou[k], ++in_views;
    if (in_views > 0) a.mean_iou_inside = in_sum / in_views;
  }
  if (!bd.empty()) {
    double sum = 0;
    for (double x : bd) sum += x;
    a.mean_boundary_px = sum / bd.size();
    const std::size_t k = static_cast<std::size_t>(0.95 * (bd.size() - 1));
    std::nth_element(bd.begin(), bd.begin() + k, bd.end());
    a.p95_boundary_px = bd[k];
  }
  return a;
}

}  // namespace tetmvs
