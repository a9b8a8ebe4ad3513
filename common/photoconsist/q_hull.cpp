#include "common/photoconsist/q_hull.h"

#include <algorithm>

#include "common/label/labels.h"

namespace tetmvs::photoconsist {

QHull estimate_q_hull(const Scene& scene, const LeveledPoints& q, const tet::Lattice& lat, const Options& o) {
  QHull h;
  if (!o.q_hull || scene.num_silhouettes() > 0 || q.q.size() == 0) return h;
  const std::int32_t top = *std::max_element(q.level.begin(), q.level.end());
  const double cell = tet::red_edge_length(lat, top);
  // Q's points are about a cell apart: small splats joined by a closing of about a cell
  // fill the object's outline without growing it by the splat size. The cell in pixels at
  // the median depth of Q over the views (one value: the closing radius is one for all).
  std::vector<double> px;
  for (std::int64_t p = 0; p < q.q.size(); p += std::max<std::int64_t>(1, q.q.size() / 2000))
    for (int v = 0; v < scene.size(); ++v) {
      const double z = scene.cams[v].depth(q.q.pos(p));
      if (z > 0) px.push_back(cell * scene.cams[v].focal() / z);
    }
  double cell_px = 0;
  if (!px.empty()) {
    std::nth_element(px.begin(), px.begin() + px.size() / 2, px.end());
    cell_px = px[px.size() / 2];
  }
  const double close = std::max(o.q_hull_close_px, o.q_hull_close_cells * cell_px);
  h.sil = label::q_silhouettes(scene, q.q, o.q_hull_splat_cells * cell, close, o.q_hull_margin_px, o.q_hull_min_points);
  for (const auto& m : h.sil) h.views += !m.empty();
  return h;
}

}  // namespace tetmvs::photoconsist
