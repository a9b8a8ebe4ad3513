#include "common/photoconsist/level_scale.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace tetmvs::photoconsist {

double level_cell_px(const photo::Views& full, const tet::Lattice& lat, int level) {
  const Eigen::Vector3d centre = lat.grid_box().center();
  const double edge = tet::red_edge_length(lat, level);
  double best = 0;
  for (int i = 0; i < full.size(); ++i) {
    const double depth = full[i].project_h(centre).z();
    if (depth > 0) best = std::max(best, edge / (depth * full[i].inv_focal));
  }
  return best;
}

int pyramid_level(double cell_px_full, double target_px, int width, int height) {
  require(std::isfinite(cell_px_full) && cell_px_full >= 0 && std::isfinite(target_px) && target_px >= 0,
          "photoconsist: pyramid_level(", cell_px_full, ", ", target_px, ") needs finite values >= 0");
  if (target_px == 0 || cell_px_full == 0) return 0;
  int p = static_cast<int>(std::lround(std::log2(cell_px_full / target_px)));
  int deepest = 0;
  while (std::min(width, height) >> (deepest + 1) >= 16 && deepest < 12) ++deepest;
  return std::clamp(p, 0, deepest);
}

photo::Views level_views(const photo::Views& full, const tet::TetMesh& m, double target_px, int* pyramid) {
  require(full.size() > 0, "photoconsist: no views");
  const int p = pyramid_level(level_cell_px(full, m.lat, m.level), target_px, full[0].width, full[0].height);
  if (pyramid) *pyramid = p;
  return full.reduced(p);
}

}  // namespace tetmvs::photoconsist
