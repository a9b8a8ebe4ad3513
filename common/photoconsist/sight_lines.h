// Lines of sight (photo.sight_views, photo.sight_margin_px; docs/photoconsist.md, "Lines
// of sight"): a point of Q was found photo-consistent in each of its cameras, so the
// segment from such a camera to the point is air. Per view, a map on bins of kBinPx
// pixels keeps the depth of the deepest point of Q seen in that view (a point covers its
// bin and the four next to it). A position is free in a view when it lies in front of
// that depth by more than margin_px pixels at its own depth. A crossing face whose three
// vertices are each free in at least min_views views lies in the air the cameras saw
// through: a band of agreement in front of a surface (a cavity's far wall seen over its
// rim), not the surface, and it is not crossing.
#pragma once
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "common/photo/views.h"
#include "common/qpoints.h"

namespace tetmvs::photoconsist {

class SightLines {
 public:
  static constexpr double kBinPx = 2;
  SightLines() = default;
  // q: the points of Q with their cameras; views: full resolution. min_views >= 1.
  SightLines(const photo::Views& views, const QPoints& q, double margin_px, int min_views);
  // Views in which X lies in front of the deepest point of Q seen there, by the margin.
  int free_views(const photo::Views& views, const Eigen::Vector3d& X) const;
  bool free(const photo::Views& views, const Eigen::Vector3d& X) const { return free_views(views, X) >= min_views_; }
  std::int64_t points() const { return points_; }

 private:
  struct Map {
    int nx = 0, ny = 0;
    std::vector<float> depth;  // deepest seen point per bin, -inf where none
  };
  std::vector<Map> maps_;
  double margin_px_ = 0;
  int min_views_ = 1;
  std::int64_t points_ = 0;
};

}  // namespace tetmvs::photoconsist
