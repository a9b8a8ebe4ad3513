#include "common/photo/lattice.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.h"

namespace tetmvs::photo {

namespace {
bool inside(const View& v, const Eigen::Vector3d& h) {
  if (!(h.z() > 0)) return false;
  const double u = h.x() / h.z(), w = h.y() / h.z();
  return u >= 0 && w >= 0 && u <= v.width - 1 && w <= v.height - 1;
}
}  // namespace

double finest_footprint(const Views& views, const Eigen::Vector3d& X) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < views.size(); ++i) {
    const Eigen::Vector3d h = views[i].project_h(X);
    if (inside(views[i], h)) best = std::min(best, h.z() * views[i].inv_focal);
  }
  return best;
}

double max_projected_edge_px(const Views& views, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) {
  double best = 0;
  for (int i = 0; i < views.size(); ++i) {
    const View& v = views[i];
    const Eigen::Vector3d ha = v.project_h(a), hb = v.project_h(b), hc = v.project_h(c);
    if (!(ha.z() > 0 && hb.z() > 0 && hc.z() > 0)) continue;
    if (!inside(v, v.project_h((a + b + c) / 3.0))) continue;
    const Eigen::Vector2d pa = ha.head<2>() / ha.z(), pb = hb.head<2>() / hb.z(),
                          pc = hc.head<2>() / hc.z();
    best = std::max({best, (pa - pb).norm(), (pb - pc).norm(), (pc - pa).norm()});
  }
  return best;
}

int lattice_divisions(const Views& views, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                      const Eigen::Vector3d& c, double max_px) {
  require(max_px > 0 && std::isfinite(max_px), "photo::lattice_divisions: max_px = ", max_px,
          " must be > 0");
  const double len = max_projected_edge_px(views, a, b, c);
  const double n = std::ceil(len / max_px);
  require(n < 1e6, "photo::lattice_divisions: a face projects to ", len, " pixels");
  return std::max(1, static_cast<int>(n));
}

void triangle_lattice(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                      int n, std::vector<Eigen::Vector3d>& out) {
  require(n >= 1, "photo::triangle_lattice: n = ", n, " must be >= 1");
  const Eigen::Vector3d e1 = (b - a) / n, e2 = (c - a) / n;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i + j <= n; ++i) out.push_back(a + i * e1 + j * e2);
}

}  // namespace tetmvs::photo
