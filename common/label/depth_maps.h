// Per-view depth maps of the points Q, the evidence behind label's free-space and occlusion
// tests. Splats are discs of about one finest cell (Q's points are about a cell apart).
#pragma once
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "common/qpoints.h"
#include "common/scene.h"

namespace tetmvs::label {

// Per view (CV_32F, 0 = no point there):
//   front  the smallest depth of the points photo-consistent in the view (Q's visible side);
//   back   the largest depth of the points facing away from the view (the object's far side,
//          seen by other cameras);
//   near / far  front / back taken to their extreme over a window of about one finest cell:
//          the free-space and beyond tests use them, so a gap between the splats of Q (a
//          crossing face without a point) never lets a cell behind the surface pass for free
//          space seen through the gap.
// With exits (the seen-free-space rule) also:
//   exit   the nearest point facing away from the view at least the depth margin behind
//          `front` (where the ray leaves the matter it met);
//   entry  the nearest point facing the view at least the margin behind that exit (where
//          it meets matter again).
struct DepthMaps {
  std::vector<cv::Mat> front, back, near, far, exit, entry;
};
// margin: the depth margin (world units) of exit and entry.
DepthMaps q_depth_maps(const Scene& s, const QPoints& q, double cell, bool with_exits, double margin = 0);
// Only `front` and `near` (the free-space test of Q's points).
DepthMaps q_visible_side(const Scene& s, const QPoints& q, double cell);

// q_depth_maps for the evidence of the free cells: in a scene without any silhouette the
// visible side `front` is taken from Q's per-pixel median depth where at least 3 splats give
// one (false matches in front of the surface must not hide the air behind them).
DepthMaps visible_side_maps(const Scene& s, const QPoints& q, double cell, bool with_exits, double margin);

// Per view, the per-pixel `quantile` (0 the nearest, 0.5 the median, 1 the farthest) of the
// depths of the splats of the points of q photo-consistent in it; 0 where fewer than 3
// splats cover the pixel.
std::vector<cv::Mat> quantile_depth_maps(const Scene& s, const QPoints& q, double cell, double quantile);

// Per view, the points of q photo-consistent in it, ascending.
std::vector<std::vector<std::int64_t>> points_by_view(const QPoints& q, int views);

// The points of q whose drop flag is 0, in order.
QPoints keep_points(const QPoints& q, const std::vector<std::uint8_t>& drop);

}  // namespace tetmvs::label
