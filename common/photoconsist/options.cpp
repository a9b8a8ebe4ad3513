#include "common/photoconsist/options.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/error.h"
#include "common/params.h"

namespace tetmvs::photoconsist {

std::int64_t CrossingRule::needed(std::int64_t n) const {
  const auto frac = static_cast<std::int64_t>(std::ceil(fraction * static_cast<double>(n) - 1e-9));
  const std::int64_t c = use_max ? std::max<std::int64_t>(frac, points) : std::min<std::int64_t>(frac, points);
  return std::max<std::int64_t>({c, min_points_abs, 1});
}

void CrossingRule::check() const {
  require(fraction >= 0 && fraction <= 1, "photoconsist: photo.cross_fraction = ", fraction,
          " must lie in [0, 1]");
  require(points >= 1, "photoconsist: photo.cross_points = ", points, " must be >= 1");
  require(min_points_abs >= 1, "photoconsist: photo.cross_min = ", min_points_abs, " must be >= 1");
}

void Options::check() const {
  line.check();
  face.check();
  require(lattice_px > 0 && std::isfinite(lattice_px), "photoconsist: photo.lattice_px = ", lattice_px,
          " must be > 0");
  require(hull_margin_px >= 0 && hull_margin_px <= 100, "photoconsist: photo.hull_margin_px = ",
          hull_margin_px, " must lie in [0, 100]");
  require(q_hull_close_px >= 0 && q_hull_close_px <= 100 && q_hull_margin_px >= 0 && q_hull_margin_px <= 100,
          "photoconsist: photo.q_hull_close_px = ", q_hull_close_px, " and photo.q_hull_margin_px = ",
          q_hull_margin_px, " must lie in [0, 100]");
  require(q_hull_splat_cells > 0 && q_hull_splat_cells <= 10 && q_hull_close_cells >= 0 && q_hull_close_cells <= 10,
          "photoconsist: photo.q_hull_splat_cells = ", q_hull_splat_cells, " must lie in (0, 10] and photo.q_hull_close_cells = ",
          q_hull_close_cells, " in [0, 10]");
  require(q_hull_min_points >= 1, "photoconsist: photo.q_hull_min_points = ", q_hull_min_points, " must be >= 1");
  require(std::isfinite(level_cell_px) && level_cell_px >= 0 && level_cell_px <= 64,
          "photoconsist: photo.level_cell_px = ", level_cell_px, " must lie in [0, 64] pixels");
  rule.check();
  occl.check();
}

Options Options::from_params(const Params& p) {
  Options o;
  o.face = photo::Options::from_params(p);
  o.line = o.face;
  const std::string shape = p.s("photo.point_patch");
  require(shape == "line" || shape == "grid", "photoconsist: photo.point_patch = '", shape,
          "' must be 'line' or 'grid'");
  o.line.point_grid = shape == "grid";
  o.line.mu = o.line.point_grid ? p.i("photo.point_grid_mu") : p.i("photo.line_mu");
  if (p.i("photo.point_k") > 0) o.line.k = p.i("photo.point_k");
  o.line.adaptive_k = true;
  o.line.partners = p.i("photo.point_partners");
  o.line.detrend = p.b("photo.point_detrend");
  o.level_cell_px = p.d("photo.level_cell_px");
  o.orientation_prior = p.b("photo.orientation_prior");
  o.line.T = p.d("photo.T");
  o.lattice_px = p.d("photo.lattice_px");
  o.hull_margin_px = p.d("photo.hull_margin_px");
  o.hull_core_px = p.d("label.hull_core_px");
  o.q_hull = p.b("photo.q_hull");
  o.q_hull_close_px = p.d("photo.q_hull_close_px");
  o.q_hull_splat_cells = p.d("photo.q_hull_splat_cells");
  o.q_hull_close_cells = p.d("photo.q_hull_close_cells");
  o.q_hull_margin_px = p.d("photo.q_hull_margin_px");
  o.q_hull_min_points = p.i("photo.q_hull_min_points");
  o.rule.fraction = p.d("photo.cross_fraction");
  o.rule.points = p.i("photo.cross_points");
  o.rule.min_points_abs = p.i("photo.cross_min");
  const std::string r = p.s("photo.cross_rule");
  require(r == "min" || r == "max", "photoconsist: photo.cross_rule = '", r, "' must be 'min' or 'max'");
  o.rule.use_max = r == "max";
  o.occl = OcclusionOptions::from_params(p);
  o.check();
  return o;
}

std::string Options::cache_signature() const {
  std::ostringstream os;
  os.precision(17);
  os << "line_mu=" << line.mu << " k=" << line.k << " cone=" << line.cone_deg << " T=" << line.T
     << " min_std=" << line.min_std << " sil=" << line.use_silhouettes << " adaptive_k=" << line.adaptive_k << " lattice_px=" << lattice_px
     << " hull_margin_px=" << hull_margin_px;
  if (line.detrend) os << " detrend=1";
  if (line.partners > 0) os << " partners=" << line.partners;
  if (orientation_prior) os << " orientation_prior=1";
  if (line.point_grid) os << " grid=1";
  if (hull_core_px > 0) os << " hull_core_px=" << hull_core_px;  // absent when off: caches written before the option stay valid
  // The occlusion options (absent when off). Cached codes of a level scored with other
  // occluders are re-checked point by point (level_pass.cpp), so only the options count.
  if (occl.enabled)
    os << " occl=" << occl.bin_px << "," << occl.support << "," << occl.splat_cells << "," << occl.margin_cells << "," << occl.filter;
  return os.str();
}

}  // namespace tetmvs::photoconsist
