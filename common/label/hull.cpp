#include "common/label/hull.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace tetmvs::label {

std::vector<cv::Mat> silhouette_distances(const Scene& s) {
  std::vector<cv::Mat> dist(s.size());
  for (int v = 0; v < s.size(); ++v)
    if (s.has_silhouette(v)) cv::distanceTransform(s.sil[v], dist[v], cv::DIST_L2, cv::DIST_MASK_PRECISE);
  return dist;
}

std::vector<std::uint8_t> outside_visual_hull(const tet::TetMesh& m, const Scene& s) {
  return outside_visual_hull(m, MeshPoints(m), s);
}

std::vector<std::uint8_t> outside_visual_hull(const tet::TetMesh& m, const MeshPoints& pts, const Scene& s) {
  const std::int32_t C = m.num_cells();
  std::vector<std::uint8_t> out(C, 0);
  VertexProjection proj;
  for (int v = 0; v < s.size(); ++v) {
    if (!s.has_silhouette(v)) continue;
    // distance (pixels) from each pixel to the nearest silhouette pixel
    cv::Mat dist;
    cv::distanceTransform(s.sil[v] == 0, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    const Camera& cam = s.cams[v];
    proj.compute(cam, pts);
#pragma omp parallel for schedule(static, 4096)
    for (std::int32_t c = 0; c < C; ++c) {
      if (out[c]) continue;
      const tet::Tet& t = m.cell_v[c];
      Eigen::Vector2d centre = Eigen::Vector2d::Zero();
      bool front = true;
      for (int k = 0; k < 4; ++k) {
        front = front && proj.z[t[k]] > 0;
        centre += proj.px[t[k]] / 4.0;
      }
      if (!front) continue;
      double r2 = 0;  // max of the squared distances: one square root, the same value
      for (int k = 0; k < 4; ++k) r2 = std::max(r2, (proj.px[t[k]] - centre).squaredNorm());
      const double r = std::sqrt(r2) + 1.5;  // pixel rounding of the silhouette and of the distance transform
      if (centre.x() - r < 0 || centre.y() - r < 0 || centre.x() + r > cam.width - 1 || centre.y() + r > cam.height - 1)
        continue;  // partly outside the image: never carves
      if (dist.at<float>(round_px(centre.y()), round_px(centre.x())) > r + 0.75) out[c] = 1;
    }
  }
  return out;
}

std::vector<std::uint8_t> hull_core_cells(const tet::TetMesh& m, const MeshPoints& pts, const Scene& s,
                                          const std::vector<cv::Mat>& dist, const std::vector<std::uint8_t>& skip,
                                          double core_px, int min_views) {
  const std::int32_t C = m.num_cells();
  std::vector<std::uint8_t> ok(C, 1);
  std::vector<std::int32_t> deep(C, 0);
  for (std::int32_t c = 0; c < C; ++c) ok[c] = !skip[c];
  VertexProjection proj;
  for (int v = 0; v < s.size(); ++v) {
    if (dist[v].empty()) continue;
    const Camera& cam = s.cams[v];
    proj.compute(cam, pts);
#pragma omp parallel for schedule(static, 4096)
    for (std::int32_t c = 0; c < C; ++c) {
      if (!ok[c]) continue;
      const Eigen::Vector3d& X = pts.centroid[c];
      if (cam.depth(X) <= 0) continue;
      const Eigen::Vector2d p = cam.project(X);
      const int u = round_px(p.x()), w = round_px(p.y());
      if (u < 0 || w < 0 || u >= cam.width || w >= cam.height) continue;
      // projected radius of the cell around its centre, in pixels
      double rad = 0;
      for (int k = 0; k < 4; ++k) {
        const std::int32_t i = m.cell_v[c][k];
        rad = proj.z[i] > 0 ? std::max(rad, (proj.px[i] - p).norm()) : 1e30;
      }
      ok[c] = dist[v].at<float>(w, u) >= rad + 1.0 + core_px;  // +1: pixel rounding
      ++deep[c];
    }
  }
  std::vector<std::uint8_t> core(C, 0);
  for (std::int32_t c = 0; c < C; ++c) core[c] = ok[c] && deep[c] >= min_views;
  return core;
}

std::vector<std::uint8_t> vertices_in_silhouettes(const MeshPoints& pts, const Scene& s) {
  const std::int32_t V = static_cast<std::int32_t>(pts.vertex.size());
  std::vector<std::uint8_t> in(V, 1);
  for (int v = 0; v < s.size(); ++v) {
    if (!s.has_silhouette(v)) continue;
    const Camera& cam = s.cams[v];
#pragma omp parallel for schedule(static, 4096)
    for (std::int32_t i = 0; i < V; ++i) {
      if (!in[i] || cam.depth(pts.vertex[i]) <= 0) continue;
      const Eigen::Vector2d p = cam.project(pts.vertex[i]);
      in[i] = s.in_silhouette(v, p.x(), p.y(), true);
    }
  }
  return in;
}

bool deep_in_hull(const Scene& s, const std::vector<cv::Mat>& dist, const Eigen::Vector3d& X, double depth_px) {
  for (int v = 0; v < s.size(); ++v) {
    double z;
    int u, w;
    if (dist[v].empty() || !nearest_pixel(s.cams[v], X, z, u, w)) continue;
    if (dist[v].at<float>(w, u) < depth_px) return false;
  }
  return true;
}

double pixel_size(const Scene& s) {
  std::vector<double> size;
  for (const Camera& cam : s.cams) {
    const double z = cam.depth(s.box.center());
    if (z > 0) size.push_back(z / cam.focal());
  }
  if (size.empty()) return 0;
  std::nth_element(size.begin(), size.begin() + size.size() / 2, size.end());
  return size[size.size() / 2];
}

bool in_hull_core(const Scene& s, const std::vector<cv::Mat>& dist, const Eigen::Vector3d& X, double margin) {
  int views = 0;
  for (int v = 0; v < s.size(); ++v) {
    double z;
    int u, w;
    if (dist[v].empty() || !nearest_pixel(s.cams[v], X, z, u, w)) continue;
    if (dist[v].at<float>(w, u) < margin) return false;
    ++views;
  }
  return views > 0;
}

}  // namespace tetmvs::label
