#include "common/cut/surface.h"

#include <algorithm>
#include <numeric>
#include <unordered_map>

#include "common/error.h"

namespace tetmvs::cut {

namespace {

struct UnionFind {
  std::vector<std::int64_t> p;
  explicit UnionFind(std::size_t n) : p(n) { std::iota(p.begin(), p.end(), 0); }
  std::int64_t find(std::int64_t x) {
    while (p[x] != x) x = p[x] = p[p[x]];
    return x;
  }
  void unite(std::int64_t a, std::int64_t b) {
    a = find(a);
    b = find(b);
    if (a != b) p[std::max(a, b)] = std::min(a, b);  // deterministic representative
  }
};

// Local index (0..3) of vertex v in cell c, or -1.
int local_index(const tet::Tet& t, std::int32_t v) {
  for (int k = 0; k < 4; ++k)
    if (t[k] == v) return k;
  return -1;
}

}  // namespace

TriMesh cut_surface(const tet::TetMesh& m, const std::vector<std::uint8_t>& inside,
                    SurfaceStats* stats, std::vector<std::int32_t>* face_ids) {
  const std::int32_t F = m.num_faces();
  require(static_cast<std::int32_t>(inside.size()) == m.num_cells(), "cut_surface: one flag per cell expected");
  const auto is_in = [&](std::int32_t c) { return c >= 0 && inside[c] != 0; };
  // Cut faces: as half-faces of their inside cell (cell*4 + j), outward = that cell's
  // outward face orientation.
  std::vector<std::int32_t> cut_half;  // per output triangle
  std::vector<std::int32_t> out_of_half;
  std::unordered_map<std::int32_t, std::int32_t> tri_of_half;
  for (std::int32_t f = 0; f < F; ++f) {
    const std::int32_t a = m.face_cell(f, 0), b = m.face_cell(f, 1);
    if (is_in(a) == is_in(b)) continue;
    const std::int32_t h = is_in(a) ? m.face_half[f][0] : m.face_half[f][1];
    tri_of_half.emplace(h, static_cast<std::int32_t>(cut_half.size()));
    cut_half.push_back(h);
  }
  const std::int64_t T = cut_half.size();
  // corner (t, k): triangle t, its k-th vertex. Vertex order of triangle t = kFace[j]
  // of its inside cell.
  const auto tri_vertex = [&](std::int64_t t, int k) {
    const std::int32_t h = cut_half[t];
    return m.cell_v[h >> 2][tet::kFace[h & 3][k]];
  };
  UnionFind uf(static_cast<std::size_t>(T) * 3);
  for (std::int64_t t = 0; t < T; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::int32_t u = tri_vertex(t, k), v = tri_vertex(t, (k + 1) % 3);
      // rotate around edge (u, v) through inside cells until the next cut face
      std::int32_t c = cut_half[t] >> 2, j = cut_half[t] & 3;
      std::int64_t partner = -1;
      for (int guard = 0; guard < 1000; ++guard) {
        // the other face of cell c containing u and v: opposite the vertex that is
        // neither u, v nor the vertex opposite face j
        const tet::Tet& tv = m.cell_v[c];
        const int lu = local_index(tv, u), lv = local_index(tv, v);
        int jn = -1;
        for (int q = 0; q < 4; ++q)
          if (q != lu && q != lv && q != j) jn = q;
        const std::int32_t nb = m.neighbour(c, jn);
        if (!is_in(nb)) {
          partner = tri_of_half.at(c * 4 + jn);
          break;
        }
        // step into the neighbour, through its face shared with c
        const tet::Tet& tn = m.cell_v[nb];
        int jb = -1;
        for (int q = 0; q < 4; ++q)
          if (m.neighbour(nb, q) == c && local_index(tv, tn[q]) < 0) jb = q;
        require(jb >= 0, "cut_surface: inconsistent cell adjacency");
        c = nb;
        j = jb;
      }
      require(partner >= 0, "cut_surface: no partner face around an edge");
      // glue the corners of u and v of both triangles
      for (int q = 0; q < 3; ++q) {
        if (tri_vertex(partner, q) == u) uf.unite(t * 3 + k, partner * 3 + q);
        if (tri_vertex(partner, q) == v) uf.unite(t * 3 + (k + 1) % 3, partner * 3 + q);
      }
    }
  }
  // output vertices: one per union-find class, numbered in order of first corner
  TriMesh out;
  std::vector<std::int64_t> vid(static_cast<std::size_t>(T) * 3, -1);
  std::unordered_map<std::int32_t, int> copies;  // mesh vertex -> copies made
  out.F.resize(T);
  for (std::int64_t t = 0; t < T; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::int64_t r = uf.find(t * 3 + k);
      if (vid[r] < 0) {
        vid[r] = static_cast<std::int64_t>(out.V.size());
        const std::int32_t mv = tri_vertex(t, k);
        out.V.push_back(m.vertex(mv));
        ++copies[mv];
      }
      out.F[t][k] = static_cast<int>(vid[r]);
    }
  if (stats) {
    stats->faces = T;
    stats->split_vertices = static_cast<std::int64_t>(out.V.size()) - static_cast<std::int64_t>(copies.size());
  }
  if (face_ids) {
    face_ids->resize(T);
    for (std::int64_t t = 0; t < T; ++t) (*face_ids)[t] = m.cell_face[cut_half[t] >> 2][cut_half[t] & 3];
  }
  return out;
}

}  // namespace tetmvs::cut
