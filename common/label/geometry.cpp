#include "common/label/geometry.h"

namespace tetmvs::label {

MeshPoints::MeshPoints(const tet::TetMesh& m) {
  const std::int32_t V = m.num_vertices(), C = m.num_cells();
  vertex.resize(V);
  centroid.resize(C);
#pragma omp parallel for schedule(static)
  for (std::int32_t v = 0; v < V; ++v) vertex[v] = m.vertex(v);
#pragma omp parallel for schedule(static)
  for (std::int32_t c = 0; c < C; ++c) {
    const tet::Tet& t = m.cell_v[c];
    centroid[c] = 0.25 * (vertex[t[0]] + vertex[t[1]] + vertex[t[2]] + vertex[t[3]]);
  }
}

void VertexProjection::compute(const Camera& cam, const MeshPoints& pts) {
  const std::int32_t V = static_cast<std::int32_t>(pts.vertex.size());
  px.resize(V);
  z.resize(V);
#pragma omp parallel for schedule(static)
  for (std::int32_t v = 0; v < V; ++v) {
    z[v] = cam.depth(pts.vertex[v]);
    px[v] = cam.project(pts.vertex[v]);
  }
}

namespace {
std::int64_t pack(const Eigen::Vector3d& b) {
  const auto f = [](double v) { return static_cast<std::int64_t>(v) & 0x1FFFFF; };
  return f(b.x()) | (f(b.y()) << 21) | (f(b.z()) << 42);
}
}  // namespace

PointProximity::PointProximity(std::vector<Eigen::Vector3d> pts, double radius) : pts_(std::move(pts)), r_(radius) {
  for (std::size_t p = 0; p < pts_.size(); ++p) buckets_[key(pts_[p])].push_back(p);
}

std::int64_t PointProximity::key(const Eigen::Vector3d& X) const { return pack((X / r_).array().floor()); }

bool PointProximity::any_within(const Eigen::Vector3d& X) const {
  const Eigen::Vector3d b = (X / r_).array().floor();
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        const auto it = buckets_.find(pack(b + Eigen::Vector3d(dx, dy, dz)));
        if (it == buckets_.end()) continue;
        for (std::size_t p : it->second)
          if ((pts_[p] - X).squaredNorm() <= r_ * r_) return true;
      }
  return false;
}

}  // namespace tetmvs::label
