#include "common/label/hull.h"

#include <algorithm>
#include <array>
#include <limits>
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

namespace {

// Whether cell c lies outside the silhouette in the view: the whole projected cell (a disc
// around the mean of its projected vertices, grown by 1.5 px for the pixel rounding) inside
// the image and outside the silhouette (dist: the distance to the nearest silhouette pixel).
bool outside_in_view(const tet::TetMesh& m, const MeshPoints& pts, const Camera& cam, const cv::Mat& dist,
                     std::int32_t c) {
  const tet::Tet& t = m.cell_v[c];
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  std::array<Eigen::Vector2d, 4> px;
  for (int k = 0; k < 4; ++k) {
    if (!(cam.depth(pts.vertex[t[k]]) > 0)) return false;
    px[k] = cam.project(pts.vertex[t[k]]);
    centre += px[k] / 4.0;
  }
  double r2 = 0;  // max of the squared distances: one square root, the same value
  for (int k = 0; k < 4; ++k) r2 = std::max(r2, (px[k] - centre).squaredNorm());
  const double r = std::sqrt(r2) + 1.5;  // pixel rounding of the silhouette and of the distance transform
  if (centre.x() - r < 0 || centre.y() - r < 0 || centre.x() + r > cam.width - 1 || centre.y() + r > cam.height - 1)
    return false;  // partly outside the image: never carves
  return dist.at<float>(round_px(centre.y()), round_px(centre.x())) > r + 0.75;
}

}  // namespace

std::vector<std::uint8_t> outside_visual_hull(const tet::TetMesh& m, const MeshPoints& pts, const Scene& s) {
  const std::int32_t C = m.num_cells();
  std::vector<std::uint8_t> out(C, 0);
  // Cells in chunks of consecutive ones (the mesh's cell order is spatially coherent), each
  // with the box of its vertices: a cell's projected centre lies in the projection of its
  // chunk's box, and a chunk whose box projects (grown by a pixel) wholly inside the
  // silhouette has no cell outside it in that view. Chunks of kChunk cells, then of kSub.
  constexpr std::int32_t kChunk = 256, kSub = 32;
  const std::int32_t subs = (C + kSub - 1) / kSub;
  std::vector<Eigen::AlignedBox3d> sub_box(subs), chunk_box((C + kChunk - 1) / kChunk);
#pragma omp parallel for schedule(static)
  for (std::int32_t i = 0; i < subs; ++i)
    for (std::int32_t c = i * kSub; c < std::min(C, (i + 1) * kSub); ++c)
      for (const std::int32_t x : m.cell_v[c]) sub_box[i].extend(pts.vertex[x]);
  for (std::int32_t i = 0; i < subs; ++i) chunk_box[i * kSub / kChunk].extend(sub_box[i]);
  // per view with a silhouette, the distance (pixels) from each pixel to the nearest
  // silhouette pixel, and the count of pixels outside the silhouette over any rectangle
  // (integral image); computed for a few views at a time, in parallel
  constexpr int kBatch = 8;
  std::vector<cv::Mat> dists(kBatch), outsides(kBatch);
  for (int v0 = 0; v0 < s.size(); v0 += kBatch) {
    const int n = std::min(kBatch, s.size() - v0);
#pragma omp parallel for schedule(dynamic, 1)
    for (int j = 0; j < n; ++j) {
      if (!s.has_silhouette(v0 + j)) continue;
      cv::distanceTransform(s.sil[v0 + j] == 0, dists[j], cv::DIST_L2, cv::DIST_MASK_PRECISE);
      cv::integral(s.sil[v0 + j] == 0, outsides[j], CV_32S);
    }
    for (int j = 0; j < n; ++j) {
      const int v = v0 + j;
      if (!s.has_silhouette(v)) continue;
      const Camera& cam = s.cams[v];
      const cv::Mat &dist = dists[j], &outside = outsides[j];
      // whether no cell in the box can carve: the box projects (grown by a pixel) wholly
      // inside the silhouette or outside the image
      const auto cannot_carve = [&](const Eigen::AlignedBox3d& box) {
        Eigen::Vector2d a = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), b = -a;
        for (int k = 0; k < 8; ++k) {
          const Eigen::Vector3d X = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k));
          if (!(cam.depth(X) > 0)) return false;
          const Eigen::Vector2d p = cam.project(X);
          a = a.cwiseMin(p), b = b.cwiseMax(p);
        }
        if (!a.allFinite() || !b.allFinite()) return false;
        // a centre outside the image never carves: the rectangle ends at the image's border
        const double lo_u = std::max(std::floor(a.x()) - 1, 0.0), hi_u = std::min(std::ceil(b.x()) + 1, cam.width - 1.0);
        const double lo_w = std::max(std::floor(a.y()) - 1, 0.0), hi_w = std::min(std::ceil(b.y()) + 1, cam.height - 1.0);
        if (lo_u > hi_u || lo_w > hi_w) return true;
        const int u0 = static_cast<int>(lo_u), u1 = static_cast<int>(hi_u) + 1;
        const int w0 = static_cast<int>(lo_w), w1 = static_cast<int>(hi_w) + 1;
        return outside.at<std::int32_t>(w1, u1) - outside.at<std::int32_t>(w0, u1) - outside.at<std::int32_t>(w1, u0) +
                   outside.at<std::int32_t>(w0, u0) ==
               0;
      };
      const std::int32_t chunks = static_cast<std::int32_t>(chunk_box.size());
#pragma omp parallel for schedule(dynamic, 16)
      for (std::int32_t i = 0; i < chunks; ++i) {
        if (cannot_carve(chunk_box[i])) continue;
        for (std::int32_t j = i * (kChunk / kSub); j < std::min(subs, (i + 1) * (kChunk / kSub)); ++j) {
          if (cannot_carve(sub_box[j])) continue;
          for (std::int32_t c = j * kSub; c < std::min(C, (j + 1) * kSub); ++c)
            if (!out[c]) out[c] = outside_in_view(m, pts, cam, dist, c);
        }
      }
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
