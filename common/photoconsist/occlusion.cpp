#include "common/photoconsist/occlusion.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace tetmvs::photoconsist {

void OcclusionOptions::check() const { check_param_ranges(*this); }

OcclusionOptions OcclusionOptions::from_params(const Params& p) {
  OcclusionOptions o;
  read_params(p, o);
  o.check();
  return o;
}

OcclusionMaps::OcclusionMaps(const photo::Views& views, const QPoints& q, const std::vector<std::int32_t>& level,
                             const std::vector<double>& cell_size, const OcclusionOptions& o) {
  o.check();
  require(static_cast<std::int64_t>(level.size()) == q.size(), "photoconsist: occlusion: ", q.size(),
          " points but ", level.size(), " levels");
  for (auto l : level)
    require(l >= 0 && l < static_cast<std::int32_t>(cell_size.size()), "photoconsist: occlusion: point level ", l,
            " has no cell size");
  views_ = views.size();
  support_ = o.support;
  bin_px_ = o.bin_px;
  used_.assign(q.size(), 1);
  splat(views, q, level, cell_size, o);
  if (o.filter) {
    // Points hidden in most of their own cameras are left out.
    std::vector<std::uint8_t> keep(q.size(), 1);
#pragma omp parallel
    {
      std::vector<std::uint8_t> mask(views_);
#pragma omp for schedule(static)
      for (std::int64_t p = 0; p < q.size(); ++p) {
        hidden_views(views, q.pos(p), mask.data());
        std::int64_t n = 0, h = 0;
        for (std::int64_t c = q.cam_offsets[p]; c < q.cam_offsets[p + 1]; ++c, ++n) h += mask[q.cams[c]];
        keep[p] = !(2 * h > n);
      }
    }
    for (auto k : keep) dropped_ += !k;
    if (dropped_ > 0) {
      used_ = keep;
      splat(views, q, level, cell_size, o);
    }
  }
}

void OcclusionMaps::splat(const photo::Views& views, const QPoints& q, const std::vector<std::int32_t>& level,
                          const std::vector<double>& cell_size, const OcclusionOptions& o) {
  points_ = 0;
  for (auto u : used_) points_ += u;
  grid_.assign(views_, Grid{});
  const float inf = std::numeric_limits<float>::infinity();
  const int K = support_;
#pragma omp parallel for schedule(dynamic, 1)
  for (int v = 0; v < views_; ++v) {
    const photo::View& view = views[v];
    Grid& g = grid_[v];
    g.nx = static_cast<int>(std::ceil(view.width / bin_px_));
    g.ny = static_cast<int>(std::ceil(view.height / bin_px_));
    g.depth.assign(static_cast<std::size_t>(g.nx) * g.ny * K, inf);
    for (std::int64_t p = 0; p < q.size(); ++p) {
      if (!used_[p]) continue;
      const Eigen::Vector3d h = view.project_h(q.pos(p));
      const double d = h.z();
      if (!(d > 0)) continue;
      const double u = h.x() / d, w = h.y() / d;
      const double cell = cell_size[level[p]];
      const double r = o.splat_cells * cell / (d * view.inv_focal);  // disc radius, pixels
      const float value = static_cast<float>(d + o.margin_cells * cell);
      // Bins whose centre lies within r of (u, w), and the bin of (u, w) itself.
      const double cu = (u + 0.5) / bin_px_, cw = (w + 0.5) / bin_px_;  // bin coordinates
      const double rb = std::min(r / bin_px_, static_cast<double>(g.nx + g.ny));  // finite, bounded
      if (!(cu + rb >= 0 && cw + rb >= 0 && cu - rb < g.nx && cw - rb < g.ny)) continue;  // misses the image
      const int x0 = std::max(0, static_cast<int>(std::floor(cu - rb)));
      const int x1 = std::min(g.nx - 1, static_cast<int>(std::floor(cu + rb)));
      const int y0 = std::max(0, static_cast<int>(std::floor(cw - rb)));
      const int y1 = std::min(g.ny - 1, static_cast<int>(std::floor(cw + rb)));
      const double fx = std::floor(cu), fy = std::floor(cw);  // the bin of (u, w) (may lie outside)
      const int own_x = fx >= 0 && fx < g.nx ? static_cast<int>(fx) : -1;
      const int own_y = fy >= 0 && fy < g.ny ? static_cast<int>(fy) : -1;
      for (int by = y0; by <= y1; ++by)
        for (int bx = x0; bx <= x1; ++bx) {
          const double du = bx + 0.5 - cu, dw = by + 0.5 - cw;
          if (du * du + dw * dw > rb * rb && !(bx == own_x && by == own_y)) continue;
          float* s = &g.depth[(static_cast<std::size_t>(by) * g.nx + bx) * K];
          if (!(value < s[K - 1])) continue;
          int k = K - 1;
          while (k > 0 && s[k - 1] > value) s[k] = s[k - 1], --k;
          s[k] = value;
        }
    }
  }
}

int OcclusionMaps::hidden_views(const photo::Views& views, const Eigen::Vector3d& X, std::uint8_t* mask) const {
  int n = 0;
  for (int v = 0; v < views_; ++v) {
    mask[v] = 0;
    const photo::View& view = views[v];
    const Eigen::Vector3d h = view.project_h(X);
    const double d = h.z();
    if (!(d > 0)) continue;
    const double u = h.x() / d, w = h.y() / d;
    if (!(u >= 0 && w >= 0 && u <= view.width - 1 && w <= view.height - 1)) continue;
    if (d > limit(v, u, w)) mask[v] = 1, ++n;
  }
  return n;
}

std::int64_t OcclusionMaps::occluding_bins() const {
  std::int64_t n = 0;
  for (const Grid& g : grid_)
    for (std::size_t b = 0; b < g.depth.size(); b += support_) n += std::isfinite(g.depth[b + support_ - 1]);
  return n;
}

}  // namespace tetmvs::photoconsist
