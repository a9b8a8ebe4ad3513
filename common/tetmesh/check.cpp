// Geometric conformity check of a mesh (see check_conforming in tetmesh.h).
#include <algorithm>

#include "common/error.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::tet {

void check_conforming(const TetMesh& m) {
  check_mesh(m);
  const std::int32_t N = m.num_cells(), NV = m.num_vertices();
  // exact volume: every level-0 tet has 6*volume = h^3/2 in lattice units
  const i128 S = i128{1} << kLatticeBits;
  i128 vol = 0;
  for (std::int32_t c = 0; c < N; ++c) vol += m.cell_volume6_lattice(c);
  require(vol == i128(m.num_level0) * S * S * S / 2, "mesh: cell volumes do not add up to the domain");
  // bucket grid over the vertices
  const std::int64_t ext[3] = {std::int64_t(m.lat.dims[0]) << kLatticeBits,
                               std::int64_t(m.lat.dims[1]) << kLatticeBits,
                               std::int64_t(m.lat.dims[2]) << kLatticeBits};
  const double per = std::cbrt(double(ext[0]) * ext[1] * ext[2] / std::max<std::int32_t>(NV, 1));
  std::int64_t bs = 1;
  while (bs < per) bs <<= 1;
  int nb[3];
  for (int a = 0; a < 3; ++a) nb[a] = static_cast<int>(ext[a] / bs + 1);
  std::vector<std::int32_t> start(std::size_t(nb[0]) * nb[1] * nb[2] + 1, 0), items(NV);
  auto bucket = [&](std::int32_t v) {
    const std::int64_t i = m.vlat[3 * v] / bs, j = m.vlat[3 * v + 1] / bs, k = m.vlat[3 * v + 2] / bs;
    return (k * nb[1] + j) * nb[0] + i;
  };
  for (std::int32_t v = 0; v < NV; ++v) ++start[bucket(v) + 1];
  for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  {
    std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
    for (std::int32_t v = 0; v < NV; ++v) items[fill[bucket(v)]++] = v;
  }
  std::int64_t bad = -1;
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int32_t c = 0; c < N; ++c) {
    const Tet& t = m.cell_v[c];
    const I3 V[4] = {m.vint(t[0]), m.vint(t[1]), m.vint(t[2]), m.vint(t[3])};
    std::int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      auto cm = [&](const I3& p) { return a == 0 ? p.x : a == 1 ? p.y : p.z; };
      lo[a] = std::min({cm(V[0]), cm(V[1]), cm(V[2]), cm(V[3])}) / bs;
      hi[a] = std::max({cm(V[0]), cm(V[1]), cm(V[2]), cm(V[3])}) / bs;
    }
    for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
      for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
        for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
          const std::int64_t b = (k * nb[1] + j) * nb[0] + i;
          for (std::int32_t s = start[b]; s < start[b + 1]; ++s) {
            const std::int32_t v = items[s];
            if (v == t[0] || v == t[1] || v == t[2] || v == t[3]) continue;
            const I3 P = m.vint(v);
            bool inside = true;
            for (int f = 0; f < 4 && inside; ++f)
              inside = orient_sign(V[kFace[f][0]], V[kFace[f][1]], V[kFace[f][2]], P) <= 0;
            if (inside) {
#pragma omp critical
              bad = std::int64_t(c) * (std::int64_t{1} << 32) + v;
            }
          }
        }
  }
  if (bad >= 0)
    fail("mesh is not conforming: vertex ", bad & 0xffffffff, " lies on or in cell ", bad >> 32);
  // boundary faces: on a side of a ghost pyramid (apex = a cube centre, base = a boundary
  // square) -- all three vertices on the plane through a cube centre and a boundary A edge
  const std::int64_t H = std::int64_t{1} << kLatticeBits;
  for (std::int32_t f = 0; f < m.num_faces(); ++f) {
    if (!m.face_on_boundary(f)) continue;
    const auto fv = m.face_vertices(f);
    const I3 F[3] = {m.vint(fv[0]), m.vint(fv[1]), m.vint(fv[2])};
    // the face's centroid (x3) must be within h/2 of the grid boundary and the face normal
    // must be one of the ghost side normals: (1,+-1,0)-type
    const I3 u = F[1] - F[0], w = F[2] - F[0];
    const i128 n[3] = {i128(u.y) * w.z - i128(u.z) * w.y, i128(u.z) * w.x - i128(u.x) * w.z,
                       i128(u.x) * w.y - i128(u.y) * w.x};
    int zeros = 0;
    for (int a = 0; a < 3; ++a) zeros += n[a] == 0;
    bool ok = zeros == 1;
    for (int a = 0; a < 3 && ok; ++a)
      for (int b2 = a + 1; b2 < 3 && ok; ++b2)
        if (n[a] != 0 && n[b2] != 0) ok = n[a] == n[b2] || n[a] == -n[b2];
    const std::int64_t cen[3] = {F[0].x + F[1].x + F[2].x, F[0].y + F[1].y + F[2].y, F[0].z + F[1].z + F[2].z};
    bool near = false;
    for (int a = 0; a < 3; ++a)
      if (n[a] != 0) near = near || cen[a] <= 3 * H / 2 || cen[a] >= 3 * (ext[a] - H / 2);
    if (!ok || !near) fail("mesh is not conforming: boundary face ", f, " is not on the domain boundary");
  }
}

}  // namespace tetmvs::tet
