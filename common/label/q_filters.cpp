#include "common/label/q_filters.h"

#include "common/label/depth_maps.h"
#include "common/label/geometry.h"
#include "common/label/hull.h"

namespace tetmvs::label {

namespace {

// Applies one filter's drop flags: counts them and keeps the rest.
void apply(QPoints& q, const std::vector<std::uint8_t>& drop, Filter f, std::array<std::int64_t, kNumFilters>& dropped) {
  std::int64_t n = 0;
  for (const auto d : drop) n += d;
  dropped[static_cast<int>(f)] = n;
  if (n > 0) q = keep_points(q, drop);
}

// Points in front of Q's visible side (the `near` depth maps) by margin in views_needed views.
std::vector<std::uint8_t> in_free_space(const Scene& s, const QPoints& q, const DepthMaps& d, double margin,
                                        int views_needed) {
  const std::int64_t P = q.size();
  std::vector<std::uint8_t> drop(P, 0);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int64_t p = 0; p < P; ++p) {
    const Eigen::Vector3d X = q.pos(p);
    int free_space = 0;
    for (int v = 0; v < s.size() && free_space < views_needed; ++v) {
      double z;
      int u, w;
      if (!nearest_pixel(s.cams[v], X, z, u, w)) continue;
      const float dn = d.near[v].at<float>(w, u);
      free_space += dn != 0 && z < dn - margin;
    }
    drop[p] = free_space >= views_needed;
  }
  return drop;
}

}  // namespace

std::vector<std::uint8_t> in_front_of_median(const Scene& s, const QPoints& q, double cell, double margin,
                                             int views_needed) {
  const std::int64_t P = q.size();
  const auto depth = quantile_depth_maps(s, q, cell, 0.5);
  std::vector<std::uint8_t> drop(P, 0);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int64_t p = 0; p < P; ++p) {
    int in_front = 0;
    for (int v = 0; v < s.size() && in_front < views_needed; ++v) {
      double z;
      int u, w;
      if (!nearest_pixel(s.cams[v], q.pos(p), z, u, w)) continue;
      const float d = depth[v].at<float>(w, u);
      in_front += d != 0 && z < d - margin;
    }
    drop[p] = in_front >= views_needed;
  }
  return drop;
}

QPoints filter_points(const Scene& s, const QPoints& q_in, const FilterOptions& o, const std::vector<cv::Mat>& hull_dist,
                      const std::vector<cv::Mat>& q_sil, std::array<std::int64_t, kNumFilters>& dropped) {
  QPoints q = q_in;
  dropped.fill(0);
  if (o.hull_core_px > 0) {
    std::vector<std::uint8_t> drop(q.size());
#pragma omp parallel for schedule(dynamic, 1024)
    for (std::int64_t p = 0; p < q.size(); ++p) drop[p] = in_hull_core(s, hull_dist, q.pos(p), o.hull_core_px);
    apply(q, drop, Filter::kInHullCore, dropped);
  }
  bool estimated = false;
  for (const auto& m : q_sil) estimated = estimated || !m.empty();
  if (estimated) {
    std::vector<std::uint8_t> drop(q.size());
#pragma omp parallel for schedule(dynamic, 1024)
    for (std::int64_t p = 0; p < q.size(); ++p) {
      bool inside = true;
      for (int v = 0; v < s.size() && inside; ++v) {
        double z;
        int u, w;
        if (!q_sil[v].empty() && nearest_pixel(s.cams[v], q.pos(p), z, u, w)) inside = q_sil[v].at<std::uint8_t>(w, u) != 0;
      }
      drop[p] = !inside;
    }
    apply(q, drop, Filter::kOutsideQHull, dropped);
  }
  if (s.num_silhouettes() == 0)
    apply(q, in_front_of_median(s, q, o.cell, o.margin, o.min_views), Filter::kInFrontOfMedian, dropped);
  apply(q, in_free_space(s, q, q_visible_side(s, q, o.cell), o.margin, o.min_views), Filter::kInFreeSpace,
        dropped);
  return q;
}

}  // namespace tetmvs::label
