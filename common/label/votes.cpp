#include "common/label/votes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include <omp.h>

#include "common/log.h"
#include "common/tetmesh/locate.h"

namespace tetmvs::label {

namespace {

// Per view, over tiles of kTile x kTile pixels, the smallest depth of a counted cell whose
// projection (its bounding box, grown by a pixel and a half) reaches into the tile. A ray from
// a point to a camera projects to one point in that camera's image, so every cell it crosses
// covers that point: the counted cells it crosses lie no nearer to the camera than the tile's
// depth, and the ray can stop where it passes that depth (a ray whose point is nearer than
// any such cell meets none at all).
class NearestCounted {
 public:
  static constexpr int kTile = 4;
  NearestCounted(const tet::TetMesh& m, const MeshPoints& pts, const Scene& s, const std::vector<std::uint8_t>& counted)
      : s_(s), depth_(s.size()), bounded_(s.size(), 1) {
    const Eigen::AlignedBox3d box = m.lat.grid_box();
    VertexProjection proj;
    for (int v = 0; v < s.size(); ++v) {
      const Camera& cam = s.cams[v];
      const int tw = (cam.width + kTile - 1) / kTile, th = (cam.height + kTile - 1) / kTile;
      std::vector<float>& d = depth_[v];
      d.assign(static_cast<std::size_t>(tw) * th, std::numeric_limits<float>::infinity());
      // a camera inside the grid: its rays go on past it (no stop)
      if (box.contains(cam.centre())) {
        bounded_[v] = 0;
        continue;
      }
      proj.compute(cam, pts);
      for (std::int32_t c = 0; c < m.num_cells() && bounded_[v]; ++c) {
        if (!counted[c]) continue;
        const tet::Tet& t = m.cell_v[c];
        double zmin = proj.z[t[0]];
        Eigen::Vector2d a = proj.px[t[0]], b = a;
        for (int k = 1; k < 4; ++k) {
          zmin = std::min(zmin, proj.z[t[k]]);
          a = a.cwiseMin(proj.px[t[k]]);
          b = b.cwiseMax(proj.px[t[k]]);
        }
        if (!(zmin > 0)) {  // a counted cell reaching behind the camera: no stop in this view
          bounded_[v] = 0;
          break;
        }
        const double lo_u = std::max(a.x() - 1.5, -1.0), hi_u = std::min(b.x() + 1.5, cam.width + 1.0);
        const double lo_w = std::max(a.y() - 1.5, -1.0), hi_w = std::min(b.y() + 1.5, cam.height + 1.0);
        if (lo_u > hi_u || lo_w > hi_w) continue;  // wholly outside the image
        const int u0 = std::max(0, static_cast<int>(std::floor(lo_u)) / kTile);
        const int u1 = std::min(tw - 1, std::max(0, static_cast<int>(std::ceil(hi_u))) / kTile);
        const int w0 = std::max(0, static_cast<int>(std::floor(lo_w)) / kTile);
        const int w1 = std::min(th - 1, std::max(0, static_cast<int>(std::ceil(hi_w))) / kTile);
        const float zf = std::nextafter(static_cast<float>(zmin), 0.0f);  // rounded down
        for (int w = w0; w <= w1; ++w)
          for (int u = u0; u <= u1; ++u) {
            float& cur = d[static_cast<std::size_t>(w) * tw + u];
            cur = std::min(cur, zf);
          }
      }
    }
  }

  // The parameter t (origin + t * dir, dir a unit vector toward camera v) beyond which the
  // ray crosses no counted cell, plus `margin`; infinity when the view gives no bound.
  double stop(int v, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double margin) const {
    if (!bounded_[v]) return std::numeric_limits<double>::infinity();
    const Camera& cam = s_.cams[v];
    double z;
    int u, w;
    if (!nearest_pixel(cam, origin, z, u, w)) return std::numeric_limits<double>::infinity();
    const int tw = (cam.width + kTile - 1) / kTile;
    const double zmin = depth_[v][static_cast<std::size_t>(w / kTile) * tw + u / kTile];
    const double rate = -cam.R.row(2).dot(dir);  // depth lost per unit of t
    if (!(rate > 0)) return std::numeric_limits<double>::infinity();
    if (!std::isfinite(zmin)) return -1;  // no counted cell there at all
    return (z - zmin) / rate + margin;
  }

 private:
  const Scene& s_;
  std::vector<std::vector<float>> depth_;
  std::vector<std::uint8_t> bounded_;
};

}  // namespace

std::vector<std::int32_t> visibility_votes(const tet::TetMesh& m, const Scene& s, const QPoints& q, double offset,
                                           std::int64_t* rays, const std::vector<std::uint8_t>* counted,
                                           const MeshPoints* pts) {
  std::vector<std::int32_t> votes(m.num_cells(), 0);
  std::unique_ptr<MeshPoints> own;
  if (counted && !pts) pts = (own = std::make_unique<MeshPoints>(m)).get();
  std::unique_ptr<NearestCounted> nearest;
  if (counted) nearest = std::make_unique<NearestCounted>(m, *pts, s, *counted);
  const double margin = 2 * tet::red_edge_length(m.lat, m.max_cell_level());
  // Rays in camera order, each camera's in the order of Q: consecutive rays are nearly
  // parallel neighbours that cross the same cells (votes are counts: the order changes nothing).
  std::vector<std::vector<std::int64_t>> by_view(s.size());
  for (std::int64_t p = 0; p < q.size(); ++p)
    for (std::int64_t k = q.cam_offsets[p]; k < q.cam_offsets[p + 1]; ++k) by_view[q.cams[k]].push_back(p);
  std::int64_t nrays = 0;
  Progress prog("label: votes", s.size());
  std::vector<std::vector<std::int32_t>> partial(omp_get_max_threads());  // per thread: no atomics, sums exact
#pragma omp parallel reduction(+ : nrays)
  {
    std::vector<std::int32_t>& mine = partial[omp_get_thread_num()];
    mine.assign(m.num_cells(), 0);
    std::vector<tet::WalkHit> hits;
    std::int32_t start = -1;  // the previous ray's start cell
    for (int v = 0; v < s.size(); ++v) {
      const Eigen::Vector3d centre = s.cams[v].centre();
      const std::vector<std::int64_t>& points = by_view[v];
#pragma omp for schedule(dynamic, 256) nowait
      for (std::size_t i = 0; i < points.size(); ++i) {
        const Eigen::Vector3d X = q.pos(points[i]);
        const Eigen::Vector3d dir = (centre - X).normalized();
        const Eigen::Vector3d origin = X + offset * dir;
        ++nrays;
        const double t_stop = nearest ? nearest->stop(v, origin, dir, margin) : std::numeric_limits<double>::infinity();
        if (t_stop <= 0) continue;  // no counted cell on this ray
        tet::walk_ray(m, origin, dir, hits, t_stop, &start);
        for (const auto& h : hits) ++mine[h.cell];
      }
#pragma omp master
      prog.tick();
    }
  }
  for (const auto& part : partial)
    for (std::size_t c = 0; c < part.size(); ++c) votes[c] += part[c];
  prog.done();
  if (rays) *rays = nrays;
  return votes;
}

double percentile(std::vector<std::int32_t> v, double pct) {
  if (v.empty()) return 0;
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(std::floor(pct / 100.0 * (v.size() - 1) + 0.5)));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

}  // namespace tetmvs::label
