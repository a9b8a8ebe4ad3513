#include "common/photoconsist/q_hull.h"

#include <algorithm>

namespace tetmvs::photoconsist {

QHull estimate_q_hull(const Scene& scene, const LeveledPoints& q, const tet::Lattice& lat, const Options& o) {
  QHull h;
  if (!o.q_sil.on || scene.num_silhouettes() > 0 || q.q.size() == 0) return h;
  const std::int32_t top = *std::max_element(q.level.begin(), q.level.end());
  h.sil = estimate_q_silhouettes(scene, q.q, tet::red_edge_length(lat, top), o.q_sil);
  for (const auto& m : h.sil) h.views += !m.empty();
  return h;
}

}  // namespace tetmvs::photoconsist
