#include "common/label/votes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>

#include <omp.h>

#include "common/log.h"
#include "common/tetmesh/locate.h"

namespace tetmvs::label {

namespace {

// The pixels whose centre lies within kReach pixels of the convex hull of the four points
// p (a projected cell): f(w, u0, u1) per image row w of a W x H image, for the columns
// u0..u1. The pixel nearest to a point of the hull lies within sqrt(2) / 2 of it.
constexpr double kReach = 1.0;

template <class F>
void for_pixels_near(const std::array<Eigen::Vector2d, 4>& p, int W, int H, F&& f) {
  Eigen::Vector2d a = p[0], b = p[0];
  for (int k = 1; k < 4; ++k) a = a.cwiseMin(p[k]), b = b.cwiseMax(p[k]);
  // the hull, counter-clockwise (monotone chain over the points sorted by x, then y)
  std::array<Eigen::Vector2d, 4> s = p;
  std::sort(s.begin(), s.end(), [](const Eigen::Vector2d& x, const Eigen::Vector2d& y) {
    return x.x() < y.x() || (x.x() == y.x() && x.y() < y.y());
  });
  const auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& x, const Eigen::Vector2d& y) {
    return (x.x() - o.x()) * (y.y() - o.y()) - (x.y() - o.y()) * (y.x() - o.x());
  };
  std::array<Eigen::Vector2d, 8> h;
  int n = 0;
  for (int i = 0; i < 4; ++i) {  // lower chain
    while (n >= 2 && cross(h[n - 2], h[n - 1], s[i]) <= 0) --n;
    h[n++] = s[i];
  }
  for (int i = 2, lower = n + 1; i >= 0; --i) {  // upper chain
    while (n >= lower && cross(h[n - 2], h[n - 1], s[i]) <= 0) --n;
    h[n++] = s[i];
  }
  --n;  // the first point closes the chain
  // the hull as half-planes nx u + ny w <= c (unit normals, grown by kReach); a degenerate
  // hull (a segment or a point) keeps only the bounding box
  std::array<Eigen::Vector3d, 4> plane;
  int planes = 0;
  if (n >= 3 && (b - a).minCoeff() > 1e-6)
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector2d e = h[(i + 1) % n] - h[i];
      const double len = e.norm();
      if (!(len > 1e-9)) continue;
      const Eigen::Vector2d nrm(e.y() / len, -e.x() / len);
      plane[planes++] = Eigen::Vector3d(nrm.x(), nrm.y(), nrm.dot(h[i]) + kReach);
    }
  const double lo_u = std::max(a.x() - kReach, -1.0), hi_u = std::min(b.x() + kReach, W + 1.0);
  const double lo_w = std::max(a.y() - kReach, -1.0), hi_w = std::min(b.y() + kReach, H + 1.0);
  if (lo_u > hi_u || lo_w > hi_w) return;  // wholly outside the image
  const int w0 = std::max(0, static_cast<int>(std::ceil(lo_w))), w1 = std::min(H - 1, static_cast<int>(std::floor(hi_w)));
  for (int w = w0; w <= w1; ++w) {
    double lo = lo_u, hi = hi_u;
    for (int i = 0; i < planes && lo <= hi; ++i) {
      const double nx = plane[i].x(), c = plane[i].z() - plane[i].y() * w;
      if (nx > 1e-9)
        hi = std::min(hi, c / nx);
      else if (nx < -1e-9)
        lo = std::max(lo, c / nx);
      else if (c < -1e-6)
        lo = hi + 1;
    }
    if (lo > hi) continue;
    const int u0 = std::max(0, static_cast<int>(std::ceil(lo))), u1 = std::min(W - 1, static_cast<int>(std::floor(hi)));
    if (u0 <= u1) f(w, u0, u1);
  }
}

// The exact test of a ray against a cell, with a tolerance: the walk (common/tetmesh/locate.h)
// follows the ray rounded to its fixed-point grid (h / 2^24, h the level-0 edge), with
// symbolic perturbation where it passes through a face, edge or vertex; a ray that passes
// through the cell shrunk by kTolerance x h (16 units of that grid), or misses it grown by
// as much, is crossed or missed by the walk too. The rays between are left to the walk.
constexpr double kTolerance = 1e-6;

// Tile size (pixels) of the per-view map of the deepest ray origins.
constexpr int kTile = 8;

// A cell as the four half-spaces n . X <= h of its faces (unit outward normals).
struct CellPlanes {
  std::array<Eigen::Vector3d, 4> n;
  std::array<double, 4> h;
};

CellPlanes cell_planes(const MeshPoints& pts, const tet::Tet& t) {
  CellPlanes c;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d& a = pts.vertex[t[(k + 1) % 4]];
    const Eigen::Vector3d& b = pts.vertex[t[(k + 2) % 4]];
    const Eigen::Vector3d& d = pts.vertex[t[(k + 3) % 4]];
    Eigen::Vector3d n = (b - a).cross(d - a).normalized();
    if (n.dot(pts.vertex[t[k]] - a) > 0) n = -n;  // away from the opposite vertex
    c.n[k] = n;
    c.h[k] = n.dot(a);
  }
  return c;
}

// Whether the ray origin + t dir (t >= 0) passes through the cell shrunk by `tol` (world
// units), 2, or only through the cell grown by as much, 1, or neither, 0. Through the cell
// grown by g (negative: shrunk): at some t > -g inside all four half-spaces.
int ray_meets(const CellPlanes& c, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double tol) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double lo_in = -kInf, hi_in = kInf, lo_out = -kInf, hi_out = kInf;  // shrunk, grown
  bool in = true, out = true;
  for (int k = 0; k < 4; ++k) {
    const double base = c.n[k].dot(origin) - c.h[k], sd = c.n[k].dot(dir);
    const double s_in = base + tol, s_out = base - tol;
    if (sd > 0) {
      hi_in = std::min(hi_in, -s_in / sd);
      hi_out = std::min(hi_out, -s_out / sd);
    } else if (sd < 0) {
      lo_in = std::max(lo_in, -s_in / sd);
      lo_out = std::max(lo_out, -s_out / sd);
    } else {
      in = in && !(s_in > 0);
      out = out && !(s_out > 0);
    }
  }
  if (in && lo_in < hi_in && hi_in > tol) return 2;
  return out && lo_out < hi_out && hi_out > -tol ? 1 : 0;
}

// The smallest depth in cam of a point of the box (at one of its corners); infinity for an
// empty box.
double min_depth(const Camera& cam, const Eigen::AlignedBox3d& box) {
  double z = std::numeric_limits<double>::infinity();
  if (box.isEmpty()) return z;
  for (int k = 0; k < 8; ++k) z = std::min(z, cam.depth(box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k))));
  return z;
}

// Per view, the rays of the view by the pixel nearest to their projection (the rays of a
// view pass through its camera centre: each projects to one point).
struct RayBuckets {
  std::vector<std::int32_t> offset, ray;  // rays of pixel i: ray[offset[i] .. offset[i + 1])
};

}  // namespace

std::vector<std::int32_t> visibility_votes(const tet::TetMesh& m, const Scene& s, const QPoints& q, double offset,
                                           std::int64_t* rays, const std::vector<std::uint8_t>* counted,
                                           const MeshPoints* pts) {
  const std::int32_t C = m.num_cells();
  std::vector<std::int32_t> votes(C, 0);
  std::unique_ptr<MeshPoints> own;
  if (!pts) pts = (own = std::make_unique<MeshPoints>(m)).get();
  // the counted cells (all without `counted`) and their faces' planes
  std::vector<std::int32_t> cells;
  for (std::int32_t c = 0; c < C; ++c)
    if (!counted || (*counted)[c]) cells.push_back(c);
  const std::int32_t N = static_cast<std::int32_t>(cells.size());
  // the counted cells' vertices, each projected once per view: slot[4 i + k] is corner k of
  // counted cell i in the list `corners`
  std::vector<std::int32_t> corners, slot(static_cast<std::size_t>(N) * 4);
  {
    std::vector<std::int32_t> at(m.num_vertices(), -1);
    for (std::int32_t i = 0; i < N; ++i)
      for (int k = 0; k < 4; ++k) {
        std::int32_t& a = at[m.cell_v[cells[i]][k]];
        if (a < 0) a = static_cast<std::int32_t>(corners.size()), corners.push_back(m.cell_v[cells[i]][k]);
        slot[4 * static_cast<std::size_t>(i) + k] = a;
      }
  }
  const std::int32_t NV = static_cast<std::int32_t>(corners.size());
  std::vector<CellPlanes> planes(N);
#pragma omp parallel for schedule(static)
  for (std::int32_t i = 0; i < N; ++i) planes[i] = cell_planes(*pts, m.cell_v[cells[i]]);
  const double tol = kTolerance * tet::red_edge_length(m.lat, 0);
  Eigen::AlignedBox3d counted_box;
  for (const std::int32_t c : cells)
    for (const std::int32_t x : m.cell_v[c]) counted_box.extend(pts->vertex[x]);
  const Eigen::AlignedBox3d box = m.lat.grid_box();
  std::vector<std::vector<std::int64_t>> by_view(s.size());
  for (std::int64_t p = 0; p < q.size(); ++p)
    for (std::int64_t k = q.cam_offsets[p]; k < q.cam_offsets[p + 1]; ++k) by_view[q.cams[k]].push_back(p);
  std::int64_t nrays = 0;
  Progress prog("label: votes", s.size());
  std::vector<std::vector<std::int32_t>> partial(omp_get_max_threads());  // per thread: no atomics, sums exact
#pragma omp parallel reduction(+ : nrays)
  {
    std::vector<std::int32_t>& mine = partial[omp_get_thread_num()];
    mine.assign(C, 0);
    std::vector<tet::WalkHit> hits;
    std::vector<Eigen::Vector3d> origin, dir;
    std::vector<double> depth, tile_depth, corner_depth(NV);
    std::vector<Eigen::Vector2d> corner_px(NV);
    std::vector<std::int32_t> pixel, outside;  // outside: the rays projecting outside the image
    RayBuckets b;
#pragma omp for schedule(dynamic, 1) nowait
    for (int v = 0; v < s.size(); ++v) {
      const Camera& cam = s.cams[v];
      const int W = cam.width, H = cam.height;
      const Eigen::Vector3d centre = cam.centre();
      const std::vector<std::int64_t>& points = by_view[v];
      const std::int32_t R = static_cast<std::int32_t>(points.size());
      nrays += R;
      origin.resize(R), dir.resize(R), depth.resize(R), pixel.resize(R);
      for (std::int32_t i = 0; i < R; ++i) {
        const Eigen::Vector3d X = q.pos(points[i]);
        dir[i] = (centre - X).normalized();
        origin[i] = X + offset * dir[i];
      }
      // The walk of every ray where the projection cannot stand for it: a camera inside the
      // grid (its rays go on past it) or a counted cell reaching behind it.
      bool project = !box.contains(centre);
      if (project)
        for (std::int32_t j = 0; j < NV; ++j) {
          corner_depth[j] = cam.depth(pts->vertex[corners[j]]);
          corner_px[j] = cam.project(pts->vertex[corners[j]]);
        }
      if (project && !(min_depth(cam, counted_box) > tol))  // else every vertex lies in front
        for (std::int32_t j = 0; j < NV && project; ++j) project = corner_depth[j] > 0;
      if (!project) {
        for (std::int32_t i = 0; i < R; ++i) {
          std::int32_t start = -1;
          tet::walk_ray(m, origin[i], dir[i], hits, std::numeric_limits<double>::infinity(), &start);
          for (const auto& h : hits) ++mine[h.cell];
        }
        continue;
      }
      // the rays by pixel (those projecting outside the image meet no cell that stays inside it:
      // they are walked)
      b.offset.assign(static_cast<std::size_t>(W) * H + 1, 0);
      for (std::int32_t i = 0; i < R; ++i) {
        double z;
        int u, w;
        depth[i] = cam.depth(origin[i]);
        pixel[i] = nearest_pixel(cam, origin[i], z, u, w) ? w * W + u : -1;
        if (pixel[i] >= 0) ++b.offset[pixel[i] + 1];
      }
      outside.clear();
      for (std::int32_t i = 0; i < R; ++i)
        if (pixel[i] < 0) outside.push_back(i);
      for (std::size_t k = 1; k < b.offset.size(); ++k) b.offset[k] += b.offset[k - 1];
      b.ray.resize(b.offset.back());
      {
        std::vector<std::int32_t> fill(b.offset.begin(), b.offset.end() - 1);
        for (std::int32_t i = 0; i < R; ++i)
          if (pixel[i] >= 0) b.ray[fill[pixel[i]]++] = i;
      }
      // per tile of kTile x kTile pixels, the largest depth of a ray's origin there (a cell
      // nearer to no ray's origin than its tiles' depths is crossed by none of their rays)
      const int TW = (W + kTile - 1) / kTile, TH = (H + kTile - 1) / kTile;
      tile_depth.assign(static_cast<std::size_t>(TW) * TH, -std::numeric_limits<double>::infinity());
      for (std::int32_t i = 0; i < R; ++i)
        if (pixel[i] >= 0) {
          double& d = tile_depth[static_cast<std::size_t>(pixel[i] / W / kTile) * TW + pixel[i] % W / kTile];
          d = std::max(d, depth[i]);
        }
      // each counted cell against the rays near its projection
      std::array<Eigen::Vector2d, 4> corner;
      for (std::int32_t i = 0; i < N; ++i) {
        double zmin = std::numeric_limits<double>::infinity();
        bool inside = true;  // the projection wholly inside the image (kReach from its border)
        for (int k = 0; k < 4; ++k) {
          const std::int32_t j = slot[4 * static_cast<std::size_t>(i) + k];
          zmin = std::min(zmin, corner_depth[j]);
          corner[k] = corner_px[j];
          inside = inside && corner[k].x() >= kReach && corner[k].y() >= kReach && corner[k].x() <= W - 1 - kReach &&
                   corner[k].y() <= H - 1 - kReach;
        }
        // the tiles of the pixels near the projection: is a ray's origin there deep enough?
        Eigen::Vector2d a = corner[0], c = corner[0];
        for (int k = 1; k < 4; ++k) a = a.cwiseMin(corner[k]), c = c.cwiseMax(corner[k]);
        const int tu0 = std::max(0, static_cast<int>(std::floor(a.x() - kReach)) / kTile);
        const int tu1 = std::min(TW - 1, std::max(0, static_cast<int>(std::ceil(c.x() + kReach))) / kTile);
        const int tw0 = std::max(0, static_cast<int>(std::floor(a.y() - kReach)) / kTile);
        const int tw1 = std::min(TH - 1, std::max(0, static_cast<int>(std::ceil(c.y() + kReach))) / kTile);
        bool deep = false;
        for (int tw = tw0; tw <= tw1 && !deep; ++tw)
          for (int tu = tu0; tu <= tu1 && !deep; ++tu) deep = tile_depth[static_cast<std::size_t>(tw) * TW + tu] >= zmin - tol;
        const auto test = [&](std::int32_t r) {
          if (depth[r] < zmin - tol) return;  // the cell lies wholly behind the ray's origin
          const int meets = ray_meets(planes[i], origin[r], dir[r], tol);
          if (meets == 2)
            ++mine[cells[i]];
          else if (meets == 1) {
            std::int32_t start = -1;
            tet::walk_ray(m, origin[r], dir[r], hits, std::numeric_limits<double>::infinity(), &start);
            for (const auto& h : hits) mine[cells[i]] += h.cell == cells[i];
          }
        };
        if (deep)
          for_pixels_near(corner, W, H, [&](int w, int u0, int u1) {
            for (std::int32_t k = b.offset[w * W + u0]; k < b.offset[w * W + u1 + 1]; ++k) test(b.ray[k]);
          });
        if (!inside)
          for (const std::int32_t r : outside) test(r);
      }
      prog.tick();
    }
  }
  for (const auto& part : partial)
    for (std::int32_t c = 0; c < C; ++c) votes[c] += part[c];
  if (counted)  // the projected walks of unbounded views count every cell they cross
    for (std::int32_t c = 0; c < C; ++c)
      if (!(*counted)[c]) votes[c] = 0;
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
