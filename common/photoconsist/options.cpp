#include "common/photoconsist/options.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/error.h"

namespace tetmvs::photoconsist {

std::int64_t CrossingRule::needed(std::int64_t n) const {
  const auto frac = static_cast<std::int64_t>(std::ceil(fraction * static_cast<double>(n) - 1e-9));
  const std::int64_t c = combine == "max" ? std::max<std::int64_t>(frac, points) : std::min<std::int64_t>(frac, points);
  return std::max<std::int64_t>({c, min_points_abs, 1});
}

void CrossingRule::check() const { check_param_ranges(*this); }

void PointMeasure::check() const { check_param_ranges(*this); }

void PointMeasure::check_with(const photo::Options& face) const {
  check();
  const int cameras = k > 0 ? k : face.k;
  if (k > 0)
    require(partners <= cameras - 1, "photo.point_partners = ", partners, " must be at most photo.point_k - 1 = ",
            cameras - 1, " (a reference view's partners are the other cameras of its patch)");
  else
    require(partners <= cameras - 1, "photo.point_partners = ", partners, " must be at most ", cameras - 1,
            ": photo.point_k = 0 gives the lattice points photo.k = ", cameras,
            " cameras (a reference view's partners are the other cameras of its patch)");
}

photo::Options PointMeasure::applied_to(const photo::Options& face) const {
  photo::Options line = face;
  line.point_grid = patch == "grid";
  line.mu = line.point_grid ? grid_mu : line_mu;
  if (k > 0) line.k = k;
  line.adaptive_k = true;
  line.partners = partners;
  line.detrend = detrend;
  line.outline_fill = outline_fill;
  return line;
}

void Options::check() const {
  check_param_ranges(*this);
  line.check();
  face.check();
  q_sil.check();
  rule.check();
  occl.check();
}

Options Options::from_params(const Params& p) {
  Options o;
  read_params(p, o);
  read_params(p, o.face);
  read_params(p, o.q_sil);
  read_params(p, o.rule);
  read_params(p, o.occl);
  PointMeasure point;
  read_params(p, point);
  point.check_with(o.face);
  o.line = point.applied_to(o.face);
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
  if (line.outline_fill) os << " outline_fill=1";
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
