#include "common/photoconsist/sight_lines.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.h"

namespace tetmvs::photoconsist {

namespace {

// The bin of image point (u, w), or false when it lies outside the map.
bool bin_of(double u, double w, int nx, int ny, int& bx, int& by) {
  const double fx = std::floor((u + 0.5) / SightLines::kBinPx), fy = std::floor((w + 0.5) / SightLines::kBinPx);
  if (!(fx >= 0 && fy >= 0 && fx < nx && fy < ny)) return false;
  bx = static_cast<int>(fx), by = static_cast<int>(fy);
  return true;
}

}  // namespace

SightLines::SightLines(const photo::Views& views, const QPoints& q, double margin_px, int min_views)
    : margin_px_(margin_px), min_views_(min_views), points_(q.size()) {
  require(min_views >= 1, "photoconsist: lines of sight need at least 1 view, got ", min_views);
  require(margin_px >= 0, "photoconsist: lines of sight: margin ", margin_px, " px must be >= 0");
  const int V = views.size();
  // Per view the points of Q seen in it (cameras lists), in point order.
  std::vector<std::vector<std::int64_t>> seen(V);
  for (std::int64_t p = 0; p < q.size(); ++p)
    for (std::int64_t c = q.cam_offsets[p]; c < q.cam_offsets[p + 1]; ++c)
      if (q.cams[c] >= 0 && q.cams[c] < V) seen[q.cams[c]].push_back(p);
  maps_.assign(V, Map{});
  const float none = -std::numeric_limits<float>::infinity();
#pragma omp parallel for schedule(dynamic, 1)
  for (int v = 0; v < V; ++v) {
    const photo::View& view = views[v];
    Map& m = maps_[v];
    m.nx = static_cast<int>(std::ceil(view.width / kBinPx)) + 1;
    m.ny = static_cast<int>(std::ceil(view.height / kBinPx)) + 1;
    m.depth.assign(static_cast<std::size_t>(m.nx) * m.ny, none);
    for (const std::int64_t p : seen[v]) {
      const Eigen::Vector3d h = view.project_h(q.pos(p));
      const double d = h.z();
      if (!(d > 0)) continue;
      int bx, by;
      if (!bin_of(h.x() / d, h.y() / d, m.nx, m.ny, bx, by)) continue;
      const float z = static_cast<float>(d);
      static constexpr int kPlus[5][2] = {{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}};
      for (const auto& o : kPlus) {
        const int x = bx + o[0], y = by + o[1];
        if (x < 0 || y < 0 || x >= m.nx || y >= m.ny) continue;
        float& s = m.depth[static_cast<std::size_t>(y) * m.nx + x];
        s = std::max(s, z);
      }
    }
  }
}

int SightLines::free_views(const photo::Views& views, const Eigen::Vector3d& X) const {
  int n = 0;
  for (int v = 0; v < static_cast<int>(maps_.size()); ++v) {
    const photo::View& view = views[v];
    const Eigen::Vector3d h = view.project_h(X);
    const double d = h.z();
    if (!(d > 0)) continue;
    const Map& m = maps_[v];
    int bx, by;
    if (!bin_of(h.x() / d, h.y() / d, m.nx, m.ny, bx, by)) continue;
    const double deepest = m.depth[static_cast<std::size_t>(by) * m.nx + bx];
    n += d < deepest - margin_px_ * d * view.inv_focal;
  }
  return n;
}

}  // namespace tetmvs::photoconsist
