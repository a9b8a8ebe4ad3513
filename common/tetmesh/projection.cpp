// Projected cell sizes (see projection.h).
#include "common/tetmesh/projection.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace tetmvs::tet {

double max_projected_cell_size(const TetMesh& m, const std::vector<Camera>& cams) {
  const int L = m.max_cell_level();
  const double edge = red_edge_length(m.lat, L);
  double best = 0;
#pragma omp parallel for schedule(static, 4096) reduction(max : best)
  for (std::int32_t c = 0; c < m.num_cells(); ++c) {
    if (m.node_level[m.cell_node[c]] != L) continue;
    const Eigen::Vector3d X = m.cell_centroid(c);
    for (const Camera& cam : cams) {
      const double d = cam.depth(X);
      if (d <= 0) continue;
      if (cam.width > 0 && !cam.sees(X)) continue;
      best = std::max(best, edge * cam.focal() / d);
    }
  }
  return best;
}

int levels_for_pixels(const Lattice& lat, const Eigen::AlignedBox3d& box, const std::vector<Camera>& cams,
                      double target_px) {
  require(target_px > 0 && std::isfinite(target_px), "levels_for_pixels: the pixel target must be > 0, got ",
          target_px);
  const Eigen::Vector3d X = box.center();
  double worst = 0;
  for (const Camera& cam : cams) {
    const double d = cam.depth(X);
    if (d <= 0) continue;
    worst = std::max(worst, lat.h * cam.focal() / d);
  }
  require(worst > 0, "levels_for_pixels: no camera has the box centre in front of it");
  int L = 0;
  while (std::ldexp(worst, -L) > target_px) ++L;
  return L;
}

}  // namespace tetmvs::tet
