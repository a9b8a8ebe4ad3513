// Occlusion-aware camera selection of photoconsist (docs/photoconsist.md, "Occlusion").
//
// From level 1 on, the points of Q found at the previous levels are splatted into every
// view as discs (radius photo.occl_splat_cells cells of the point's level, at the point's
// depth plus photo.occl_margin_cells cells of its level) on a grid of bins of
// photo.occl_bin_px pixels. Each bin keeps its photo.occl_support smallest splatted
// depths; the largest of them is the bin's depth limit (+inf with fewer splats), so a
// single stray point of Q never blinds a view: it takes `support` points in front.
// A lattice point X is hidden in view v when its depth there exceeds the limit of the bin
// it projects to; hidden views are not usable for X (photo::Scratch::hidden), so a point
// in the air of a cavity is not scored "consistent" in views that see the outer wall in
// front of it, and a point on the cavity's floor is scored with the views that see it.
// Occluders are checked first (photo.occl_filter): a point of Q hidden, by the maps of
// all points, in more than half of the cameras it was found consistent in cannot have
// been seen by them (a false point in the air of a cavity, consistent in views that see
// the wall in front of it); it is left out of the final maps, so false points do not
// hide the surface behind them. Level 0 has no Q: today's behaviour. Deterministic (each view is built by one thread,
// points in order).
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/param_binding.h"
#include "common/photo/views.h"
#include "common/qpoints.h"

namespace tetmvs {
class Params;

namespace photoconsist {

struct OcclusionOptions {
  bool enabled = false;      // photo.occlusion (off by default: docs/photoconsist.md)
  double bin_px = 2;         // photo.occl_bin_px: bin size of the depth maps, pixels
  int support = 2;           // photo.occl_support: splats a bin needs before it occludes
  double splat_cells = 0.5;  // photo.occl_splat_cells: disc radius, cells of the point's level
  double margin_cells = 1;   // photo.occl_margin_cells: depth margin, cells of the point's level
  bool filter = true;        // photo.occl_filter: drop occluders hidden in most of their own cameras
  void check() const;  // throws Error on a value outside its documented range
  static OcclusionOptions from_params(const Params& p);

  static constexpr auto params() {  // the fields that hold parameters (common/param_binding.h)
    return std::to_array<ParamField<OcclusionOptions>>({
        {"photo.occlusion", &OcclusionOptions::enabled},
        {"photo.occl_bin_px", &OcclusionOptions::bin_px},
        {"photo.occl_support", &OcclusionOptions::support},
        {"photo.occl_splat_cells", &OcclusionOptions::splat_cells},
        {"photo.occl_margin_cells", &OcclusionOptions::margin_cells},
        {"photo.occl_filter", &OcclusionOptions::filter},
    });
  }
};

class OcclusionMaps {
 public:
  OcclusionMaps() = default;
  // q: the occluders; level[p]: the level point p was found at; cell_size[l]: the red
  // edge length of level l (every level[p] must index it).
  OcclusionMaps(const photo::Views& views, const QPoints& q, const std::vector<std::int32_t>& level,
                const std::vector<double>& cell_size, const OcclusionOptions& o);

  bool empty() const { return views_ == 0; }
  int num_views() const { return views_; }
  // Depth limit of view v at pixel (u, w); +inf when the bin has fewer than `support`
  // splats or (u, w) lies outside the image.
  float limit(int v, double u, double w) const {
    const Grid& g = grid_[v];
    const double bu = (u + 0.5) / bin_px_, bw = (w + 0.5) / bin_px_;
    if (!(bu >= 0 && bw >= 0 && bu < g.nx && bw < g.ny)) return std::numeric_limits<float>::infinity();
    const std::int64_t b = static_cast<std::int64_t>(bw) * g.nx + static_cast<std::int64_t>(bu);
    return g.depth[b * support_ + support_ - 1];
  }
  // mask[v] = 1 for every view v in which X is hidden (in front of the camera, inside the
  // image, deeper than the limit), else 0; returns their number. mask: num_views() flags.
  int hidden_views(const photo::Views& views, const Eigen::Vector3d& X, std::uint8_t* mask) const;

  // Statistics: bins with a finite limit, over all views; points splatted.
  std::int64_t occluding_bins() const;
  std::int64_t points() const { return points_; }
  // Per point of q: 1 when it was used as an occluder (not dropped by the filter).
  const std::vector<std::uint8_t>& used() const { return used_; }
  std::int64_t dropped() const { return dropped_; }

 private:
  struct Grid {
    int nx = 0, ny = 0;
    std::vector<float> depth;  // nx * ny * support, ascending per bin, +inf = empty
  };
  void splat(const photo::Views& views, const QPoints& q, const std::vector<std::int32_t>& level,
             const std::vector<double>& cell_size, const OcclusionOptions& o);
  std::vector<Grid> grid_;
  std::vector<std::uint8_t> used_;
  std::int64_t dropped_ = 0;
  int views_ = 0, support_ = 1;
  double bin_px_ = 1;
  std::int64_t points_ = 0;
};

}  // namespace photoconsist
}  // namespace tetmvs
