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

}  // namespace tetmvs::label
