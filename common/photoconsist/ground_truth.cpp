#include "common/photoconsist/ground_truth.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace tetmvs::photoconsist {

GroundTruth::GroundTruth(const TriMesh& gt) : bvh_(gt) {
  require(!gt.F.empty(), "photoconsist: the ground truth must be a triangle mesh");
  const auto [lo, hi] = bounds(gt);
  scale_ = (hi - lo).norm();
}

int GroundTruth::crossings(const Eigen::Vector3d& X, const Eigen::Vector3d& d) const {
  int n = 0;
  double t = 0;
  const double eps = 1e-10 * scale_;
  for (int guard = 0; guard < 100000; ++guard) {
    const RayHit h = bvh_.raycast(X, d, t, std::numeric_limits<double>::infinity());
    if (h.face < 0) break;
    ++n;
    t = h.t + eps;
  }
  return n;
}

bool GroundTruth::inside(const Eigen::Vector3d& X) const {
  static const Eigen::Vector3d dirs[3] = {Eigen::Vector3d(0.5773, 0.5774, 0.5776).normalized(),
                                          Eigen::Vector3d(-0.3121, 0.8121, -0.4931).normalized(),
                                          Eigen::Vector3d(0.1234, -0.4567, 0.8811).normalized()};
  int votes = 0;
  for (const auto& d : dirs) votes += crossings(X, d) % 2;
  return votes >= 2;
}

LevelEval evaluate_level(const tet::TetMesh& m, const LevelResult& r, const GroundTruth& gt, double cell_size) {
  LevelEval E;
  E.near_dist = 2 * cell_size;
  const std::int64_t T = static_cast<std::int64_t>(r.face.size());
  E.tested = T;
  // Inside flags of the vertices the tested faces and cells use.
  std::vector<std::int8_t> in(m.num_vertices(), -1);
  std::vector<std::int32_t> need;
  for (std::int32_t c = 0; c < m.num_cells(); ++c)
    if (m.cell_new_red[c])
      for (int k = 0; k < 4; ++k) need.push_back(m.cell_v[c][k]);
  std::sort(need.begin(), need.end());
  need.erase(std::unique(need.begin(), need.end()), need.end());
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t q = 0; q < static_cast<std::int64_t>(need.size()); ++q)
    in[need[q]] = gt.inside(m.vertex(need[q])) ? 1 : 0;

  E.face_gt_crossed.assign(T, 0);
  E.face_gt_distance.assign(T, 0.f);
#pragma omp parallel for schedule(dynamic, 64)
  for (std::int64_t t = 0; t < T; ++t) {
    const auto fv = m.face_vertices(r.face[t]);
    const int s = in[fv[0]] + in[fv[1]] + in[fv[2]];
    if (s > 0 && s < 3) {
      E.face_gt_crossed[t] = 1;
      continue;
    }
    const Eigen::Vector3d a = m.vertex(fv[0]), b = m.vertex(fv[1]), c = m.vertex(fv[2]);
    const Eigen::Vector3d pts[7] = {a, b, c, (a + b) / 2, (b + c) / 2, (c + a) / 2, (a + b + c) / 3};
    double d = std::numeric_limits<double>::infinity();
    for (const auto& p : pts) d = std::min(d, gt.distance(p));
    E.face_gt_distance[t] = static_cast<float>(d);
  }
  for (std::int64_t t = 0; t < T; ++t) {
    E.gt_crossed += E.face_gt_crossed[t];
    if (E.face_gt_crossed[t] && r.crossing[t]) ++E.found;
    if (r.crossing[t]) {
      ++E.crossing;
      if (E.face_gt_distance[t] <= E.near_dist) ++E.crossing_near;
    }
  }
  for (std::int32_t c = 0; c < m.num_cells(); ++c) {
    if (!m.cell_new_red[c]) continue;
    int s = 0;
    for (int k = 0; k < 4; ++k) s += in[m.cell_v[c][k]];
    if (s > 0 && s < 4) {
      ++E.cells_gt;
      if (r.active[c]) ++E.cells_found;
    }
  }
  // active cells with no tested face near the surface, and of those the ones in free space
  std::vector<std::int64_t> tested_index(m.num_faces(), -1);
  for (std::int64_t t = 0; t < T; ++t) tested_index[r.face[t]] = t;
  std::vector<std::int32_t> far;
  for (std::int32_t c = 0; c < m.num_cells(); ++c) {
    if (!r.active[c]) continue;
    ++E.active;
    bool near = false;
    for (int k = 0; k < 4 && !near; ++k) {
      const std::int64_t t = tested_index[m.cell_face[c][k]];
      near = t >= 0 && (E.face_gt_crossed[t] || E.face_gt_distance[t] <= E.near_dist);
    }
    if (!near) far.push_back(c);
  }
  E.active_far = static_cast<std::int64_t>(far.size());
  std::int64_t air = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : air)
  for (std::int64_t i = 0; i < E.active_far; ++i) air += !gt.inside(m.cell_centroid(far[i]));
  E.active_far_air = air;
  E.points = r.points.size();
  for (std::int64_t p = 0; p < E.points; ++p)
    if (gt.distance(r.points.pos(p)) <= cell_size) ++E.points_near;
  return E;
}

double fraction_within(const QPoints& q, const GroundTruth& gt, double dist) {
  if (q.size() == 0) return 1.0;
  std::int64_t n = 0;
#pragma omp parallel for reduction(+ : n)
  for (std::int64_t p = 0; p < q.size(); ++p) n += gt.distance(q.pos(p)) <= dist;
  return static_cast<double>(n) / q.size();
}

}  // namespace tetmvs::photoconsist
