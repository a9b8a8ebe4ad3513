#include "common/trimesh/check.h"

#include <algorithm>
#include <numeric>

namespace tetmvs {

namespace {
struct UnionFind {
  std::vector<int> p;
  explicit UnionFind(std::size_t n) : p(n) { std::iota(p.begin(), p.end(), 0); }
  int find(int x) {
    while (p[x] != x) x = p[x] = p[p[x]];
    return x;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) p[std::max(a, b)] = std::min(a, b);
  }
};
}  // namespace

MeshCheck check_mesh(const TriMesh& m) {
  MeshCheck r;
  r.vertices = m.V.size();
  r.faces = m.F.size();
  const int nv = static_cast<int>(m.V.size());
  std::vector<char> used(nv, 0);
  UnionFind uf(nv);
  for (std::size_t f = 0; f < m.F.size(); ++f) {
    const auto& t = m.F[f];
    for (int k = 0; k < 3; ++k) used[t[k]] = 1;
    uf.unite(t[0], t[1]);
    uf.unite(t[0], t[2]);
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || !(face_area(m, f) > 0)) ++r.degenerate_faces;
  }
  for (int v = 0; v < nv; ++v) r.unreferenced_vertices += !used[v];

  // Components: by shared vertices, numbered by size.
  std::vector<int> root_comp(nv, -1);
  std::vector<int> order;
  for (int v = 0; v < nv; ++v)
    if (used[v] && uf.find(v) == v) {
      root_comp[v] = static_cast<int>(order.size());
      order.push_back(v);
    }
  const int nc = static_cast<int>(order.size());
  std::vector<ComponentCheck> comps(nc);
  std::vector<int> fc(m.F.size());
  for (std::size_t f = 0; f < m.F.size(); ++f) {
    const int c = root_comp[uf.find(m.F[f][0])];
    fc[f] = c;
    comps[c].faces++;
    comps[c].area += face_area(m, f);
    const auto& t = m.F[f];
    comps[c].signed_volume += m.V[t[0]].dot(m.V[t[1]].cross(m.V[t[2]])) / 6.0;
  }
  for (int v = 0; v < nv; ++v)
    if (used[v]) comps[root_comp[uf.find(v)]].vertices++;

  // Edges: (lo, hi, +1/-1 direction), sorted.
  struct E { int a, b; int dir; };
  std::vector<E> e;
  e.reserve(3 * m.F.size());
  for (const auto& t : m.F)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (a == b) continue;
      e.push_back({std::min(a, b), std::max(a, b), a < b ? 1 : -1});
    }
  std::sort(e.begin(), e.end(), [](const E& x, const E& y) { return x.a != y.a ? x.a < y.a : (x.b != y.b ? x.b < y.b : x.dir < y.dir); });
  std::vector<int> comp_nonmanifold(nc, 0), comp_misoriented(nc, 0);
  UnionFind bl(nv);
  std::vector<char> on_boundary(nv, 0);
  for (std::size_t i = 0; i < e.size();) {
    std::size_t j = i;
    int sum = 0;
    while (j < e.size() && e[j].a == e[i].a && e[j].b == e[i].b) sum += e[j++].dir;
    const int n = static_cast<int>(j - i);
    const int c = root_comp[uf.find(e[i].a)];
    r.edges++;
    comps[c].edges++;
    if (n == 1) {
      r.boundary_edges++;
      comps[c].boundary_edges++;
      bl.unite(e[i].a, e[i].b);
      on_boundary[e[i].a] = on_boundary[e[i].b] = 1;
    } else if (n > 2) {
      r.nonmanifold_edges++;
      comp_nonmanifold[c]++;
    } else if (sum != 0) {
      r.misoriented_edges++;
      comp_misoriented[c]++;
    }
    i = j;
  }
  for (int v = 0; v < nv; ++v)
    if (on_boundary[v] && bl.find(v) == v) comps[root_comp[uf.find(v)]].boundary_loops++;
  for (int c = 0; c < nc; ++c) {
    ComponentCheck& k = comps[c];
    k.euler = static_cast<int>(k.vertices - k.edges + k.faces);
    k.edge_manifold = comp_nonmanifold[c] == 0;
    k.closed = k.edge_manifold && k.boundary_edges == 0;
    k.oriented = k.edge_manifold && comp_misoriented[c] == 0;
    if (k.edge_manifold && k.oriented) {
      const int g2 = 2 - k.euler - static_cast<int>(k.boundary_loops);
      k.genus = g2 >= 0 && g2 % 2 == 0 ? g2 / 2 : -1;
    }
  }
  // Sort components by face count (largest first), stable on first appearance.
  std::vector<int> perm(nc);
  std::iota(perm.begin(), perm.end(), 0);
  std::stable_sort(perm.begin(), perm.end(), [&](int a, int b) { return comps[a].faces > comps[b].faces; });
  std::vector<int> rank(nc);
  for (int i = 0; i < nc; ++i) {
    rank[perm[i]] = i;
    r.components.push_back(comps[perm[i]]);
  }
  for (auto& c : fc) c = rank[c];
  r.face_component = std::move(fc);
  r.edge_manifold = r.nonmanifold_edges == 0;
  r.closed = r.edge_manifold && r.boundary_edges == 0 && r.faces > 0;
  r.oriented = r.edge_manifold && r.misoriented_edges == 0;
  return r;
}

nlohmann::json to_json(const MeshCheck& c) {
  nlohmann::json j;
  j["vertices"] = c.vertices;
  j["faces"] = c.faces;
  j["edges"] = c.edges;
  j["unreferenced_vertices"] = c.unreferenced_vertices;
  j["degenerate_faces"] = c.degenerate_faces;
  j["boundary_edges"] = c.boundary_edges;
  j["nonmanifold_edges"] = c.nonmanifold_edges;
  j["misoriented_edges"] = c.misoriented_edges;
  j["edge_manifold"] = c.edge_manifold;
  j["closed"] = c.closed;
  j["oriented"] = c.oriented;
  j["num_components"] = c.components.size();
  nlohmann::json comps = nlohmann::json::array();
  for (const auto& k : c.components) {
    comps.push_back({{"vertices", k.vertices}, {"faces", k.faces}, {"edges", k.edges},
                     {"boundary_edges", k.boundary_edges}, {"boundary_loops", k.boundary_loops},
                     {"euler", k.euler}, {"closed", k.closed}, {"edge_manifold", k.edge_manifold},
                     {"oriented", k.oriented}, {"genus", k.genus}, {"area", k.area},
                     {"signed_volume", k.signed_volume}});
  }
  j["components"] = comps;
  return j;
}

}  // namespace tetmvs
