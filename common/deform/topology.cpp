#include "common/deform/topology.h"

#include <algorithm>

namespace tetmvs::deform {

int Topology::find_edge(int a, int b) const {
  if (a > b) std::swap(a, b);
  const std::array<int, 2> key{a, b};
  auto it = std::lower_bound(edge_v.begin(), edge_v.end(), key);
  if (it == edge_v.end() || *it != key) return -1;
  return static_cast<int>(it - edge_v.begin());
}

bool Topology::closed_manifold() const {
  for (auto c : edge_count)
    if (c != 2) return false;
  return true;
}

Topology build_topology(const std::vector<Eigen::Vector3i>& F, int nv) {
  Topology t;
  t.num_vertices = nv;
  const int nf = static_cast<int>(F.size());
  struct H { int a, b, f, k; };
  // Half-edges in (a, b, f, k) order: a counting sort by the lower vertex a (filled in
  // (f, k) order), then a stable insertion sort by b within each (small) bucket.
  std::vector<H> h(3 * static_cast<size_t>(nf));
  {
    std::vector<int> start(static_cast<size_t>(nv) + 1, 0);
    for (int f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) start[std::min(F[f][k], F[f][(k + 1) % 3]) + 1]++;
    for (int v = 0; v < nv; ++v) start[v + 1] += start[v];
    std::vector<int> pos(start.begin(), start.end() - 1);
    for (int f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = F[f][k], b = F[f][(k + 1) % 3];
        h[pos[std::min(a, b)]++] = {std::min(a, b), std::max(a, b), f, k};
      }
#pragma omp parallel for schedule(static, 4096)
    for (int v = 0; v < nv; ++v)
      for (int i = start[v] + 1; i < start[v + 1]; ++i) {
        const H x = h[i];
        int j = i - 1;
        for (; j >= start[v] && h[j].b > x.b; --j) h[j + 1] = h[j];
        h[j + 1] = x;
      }
  }
  t.face_e.assign(nf, {-1, -1, -1});
  for (size_t i = 0; i < h.size();) {
    size_t j = i;
    while (j < h.size() && h[j].a == h[i].a && h[j].b == h[i].b) ++j;
    const int e = static_cast<int>(t.edge_v.size());
    t.edge_v.push_back({h[i].a, h[i].b});
    t.edge_f.push_back({h[i].f, j - i > 1 ? h[i + 1].f : -1});
    t.edge_count.push_back(static_cast<std::uint8_t>(std::min<size_t>(j - i, 255)));
    for (size_t q = i; q < j; ++q) t.face_e[h[q].f][h[q].k] = e;
    i = j;
  }
  // Vertex neighbours from edges (edges are sorted by (a, b), so each row ends up sorted
  // after a per-row sort).
  t.nbr_start.assign(nv + 1, 0);
  for (const auto& e : t.edge_v) {
    t.nbr_start[e[0] + 1]++;
    t.nbr_start[e[1] + 1]++;
  }
  for (int v = 0; v < nv; ++v) t.nbr_start[v + 1] += t.nbr_start[v];
  t.nbr.resize(t.nbr_start[nv]);
  std::vector<int> fill(t.nbr_start.begin(), t.nbr_start.end() - 1);
  for (const auto& e : t.edge_v) {
    t.nbr[fill[e[0]]++] = e[1];
    t.nbr[fill[e[1]]++] = e[0];
  }
  for (int v = 0; v < nv; ++v) std::sort(t.nbr.begin() + t.nbr_start[v], t.nbr.begin() + t.nbr_start[v + 1]);
  VertexFaces vf(F, nv);
  t.vf_start = std::move(vf.start);
  t.vf = std::move(vf.faces);
  return t;
}

VertexFaces::VertexFaces(const std::vector<Eigen::Vector3i>& F, int nv) : start(static_cast<size_t>(nv) + 1, 0) {
  for (const auto& f : F)
    for (int k = 0; k < 3; ++k) ++start[f[k] + 1];
  for (int v = 0; v < nv; ++v) start[v + 1] += start[v];
  faces.resize(start[nv]);
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (int f = 0; f < static_cast<int>(F.size()); ++f)
    for (int k = 0; k < 3; ++k) faces[fill[F[f][k]]++] = f;  // ascending f
}

void VertexFaces::neighbours(const std::vector<Eigen::Vector3i>& F, int v, std::vector<int>& out) const {
  out.clear();
  for (int f : of(v))
    for (int k = 0; k < 3; ++k)
      if (F[f][k] != v) out.push_back(F[f][k]);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

namespace {
template <class T>
void ring_average_of(std::vector<T>& x, const Topology& topo, int rounds) {
  const int nv = static_cast<int>(x.size());
  std::vector<T> y(nv);
  for (int r = 0; r < rounds; ++r) {
#pragma omp parallel for schedule(static)
    for (int v = 0; v < nv; ++v) {
      T s = x[v];
      for (int q = topo.nbr_start[v]; q < topo.nbr_start[v + 1]; ++q) s += x[topo.nbr[q]];
      y[v] = s / (1.0 + topo.degree(v));
    }
    x.swap(y);
  }
}
}  // namespace

void ring_average(std::vector<double>& x, const Topology& topo, int rounds) { ring_average_of(x, topo, rounds); }
void ring_average(std::vector<Eigen::Vector3d>& x, const Topology& topo, int rounds) { ring_average_of(x, topo, rounds); }

}  // namespace tetmvs::deform
