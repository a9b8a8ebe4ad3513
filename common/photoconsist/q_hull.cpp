#include "common/photoconsist/q_hull.h"

#include <algorithm>

#include "common/q_silhouettes.h"

namespace tetmvs::photoconsist {

QHull estimate_q_hull(const Scene& scene, const LeveledPoints& q, const tet::Lattice& lat, const Options& o) {
  QHull h;
  if (!o.q_hull || scene.num_silhouettes() > 0 || q.q.size() == 0) return h;
  const std::int32_t top = *std::max_element(q.level.begin(), q.level.end());
  QSilhouetteOptions qo;
  qo.on = o.q_hull;
  qo.splat_cells = o.q_hull_splat_cells;
  qo.close_cells = o.q_hull_close_cells;
  qo.close_px = o.q_hull_close_px;
  qo.margin_px = o.q_hull_margin_px;
  qo.min_points = o.q_hull_min_points;
  h.sil = estimate_q_silhouettes(scene, q.q, tet::red_edge_length(lat, top), qo);
  for (const auto& m : h.sil) h.views += !m.empty();
  return h;
}

}  // namespace tetmvs::photoconsist
