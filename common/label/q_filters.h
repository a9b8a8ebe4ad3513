// The Q filters: points of Q that cannot lie on the surface, dropped before votes and depth
// maps, in this order (each sees the points the ones before kept):
//   in_hull_core        inside the hull core (hull-core prior on): the prior says matter, so
//                       they are false matches, whose rays would carve tunnels through it;
//   outside_q_hull      outside a silhouette estimated from Q (scenes without any): another
//                       view sees background there;
//   in_front_of_median  in front of Q's per-pixel median depth in min_views views (scenes
//                       without silhouettes): false matches crowd in front of the surface
//                       near occluding contours, where no silhouette bounds them;
//   in_free_space       in front of Q's visible side in min_views views: a point on the
//                       surface is never in front of what a camera sees there, a false match
//                       floating in the air (in a cup's cavity) is.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "common/qpoints.h"
#include "common/scene.h"

namespace tetmvs::label {

enum class Filter : std::uint8_t { kInHullCore, kOutsideQHull, kInFrontOfMedian, kInFreeSpace };
inline constexpr int kNumFilters = 4;
inline constexpr std::array<const char*, kNumFilters> kFilterNames = {"in_hull_core", "outside_q_hull",
                                                                      "in_front_of_median", "in_free_space"};

struct FilterOptions {
  double hull_core_px = 0;  // in_hull_core (0 = off)
  int min_views = 3;        // in_front_of_median, in_free_space
  double margin = 0;        // depth margin of both, world units
  double cell = 0;          // finest cell size (the depth maps' splats)
};

// The filters above. hull_dist: silhouette_distances() of the scene (in_hull_core); q_sil: the
// silhouettes estimated from Q, one per view (empty: none). dropped: per filter.
QPoints filter_points(const Scene& s, const QPoints& q, const FilterOptions& o, const std::vector<cv::Mat>& hull_dist,
                      const std::vector<cv::Mat>& q_sil, std::array<std::int64_t, kNumFilters>& dropped);

// Per point of q: 1 when it lies in front of the per-pixel median depth of Q (the splats of
// the points consistent in a view) by `margin` (world units) in at least views_needed views.
std::vector<std::uint8_t> in_front_of_median(const Scene& s, const QPoints& q, double cell, double margin,
                                             int views_needed);

}  // namespace tetmvs::label
