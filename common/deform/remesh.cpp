#include "common/deform/remesh.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <span>
#include <unordered_set>

#include "common/deform/topology.h"

namespace tetmvs::deform {

double edge_px(const RemeshMesh& m, int a, int b) {
  return (m.V[a] - m.V[b]).norm() / (0.5 * (m.fp[a] + m.fp[b]));
}

namespace {
Eigen::Vector3d tri_cross(const std::vector<Eigen::Vector3d>& V, int a, int b, int c) {
  return (V[b] - V[a]).cross(V[c] - V[a]);
}
// Opposite corner of edge (a, b) in face t.
int opposite(const Eigen::Vector3i& t, int a, int b) {
  for (int k = 0; k < 3; ++k)
    if (t[k] != a && t[k] != b) return t[k];
  return -1;
}
// Number of common entries of two sorted rows: of a's and b's neighbours, the link
// condition of collapsing edge ab on a closed manifold is exactly two (the opposite corners).
int common_count(std::span<const int> x, std::span<const int> y) {
  int common = 0;
  auto i = x.begin(), j = y.begin();
  while (i != x.end() && j != y.end()) {
    if (*i < *j) ++i;
    else if (*j < *i) ++j;
    else { ++common; ++i; ++j; }
  }
  return common;
}

// A batch of edge collapses (collapse_short_edges, collapse_folds): vertex b merges into a,
// the two faces of edge ab die, and both ends and their neighbours are locked for the rest
// of the batch; finish() rewrites the faces and drops unused vertices.
struct CollapseBatch {
  std::vector<char> locked, face_dead, merged;
  std::vector<int> remap;
  std::int64_t count = 0;
  CollapseBatch(int nv, int nf) : locked(nv, 0), face_dead(nf, 0), merged(nv, 0), remap(nv) {
    std::iota(remap.begin(), remap.end(), 0);
  }
  // na, nb: the neighbours of a and b
  void collapse(RemeshMesh& m, int a, int b, int f1, int f2, const Eigen::Vector3d& p, double fp,
                std::span<const int> na, std::span<const int> nb) {
    m.V[a] = p;
    m.fp[a] = fp;
    if (!m.last_step.empty()) m.last_step[a] = 0.5 * (m.last_step[a] + m.last_step[b]);
    remap[b] = a;
    face_dead[f1] = face_dead[f2] = 1;
    merged[a] = merged[b] = 1;
    locked[a] = locked[b] = 1;
    for (int w : na) locked[w] = 1;
    for (int w : nb) locked[w] = 1;
    ++count;
  }
  // Applies the batch; with faces, also what it did to the faces (FoldCollapses).
  std::int64_t finish(RemeshMesh& m, FoldCollapses* faces = nullptr) const {
    if (count == 0) return 0;
    std::vector<Eigen::Vector3i> F;
    std::vector<int> origin;
    F.reserve(m.F.size());
    if (faces) {
      faces->face_to_new.assign(m.F.size(), -1);
      faces->changed.clear();
    }
    for (size_t f = 0; f < m.F.size(); ++f) {
      const auto& t = m.F[f];
      const Eigen::Vector3i r(remap[t[0]], remap[t[1]], remap[t[2]]);
      if (face_dead[f] || r[0] == r[1] || r[1] == r[2] || r[0] == r[2]) continue;
      const bool moved = merged[t[0]] || merged[t[1]] || merged[t[2]];
      if (faces) {
        faces->face_to_new[f] = static_cast<int>(F.size());
        faces->changed.push_back(moved);
      }
      if (!m.origin.empty()) origin.push_back(moved ? -1 : m.origin[f]);
      F.push_back(r);
    }
    m.F.swap(F);
    if (!m.origin.empty()) m.origin.swap(origin);
    compact(m);  // drops the merged-away vertices; keeps every face, in order
    return count;
  }
};
}  // namespace

std::int64_t split_long_edges(RemeshMesh& m, double max_px) {
  const Topology topo = build_topology(m.F, static_cast<int>(m.V.size()));
  const int ne = topo.num_edges(), nf = static_cast<int>(m.F.size());
  std::vector<char> mark(ne, 0);
#pragma omp parallel for schedule(static)
  for (int e = 0; e < ne; ++e) mark[e] = edge_px(m, topo.edge_v[e][0], topo.edge_v[e][1]) > max_px;
  std::vector<int> mid(ne, -1);
  std::int64_t count = 0;
  for (int e = 0; e < ne; ++e)
    if (mark[e]) {
      const int a = topo.edge_v[e][0], b = topo.edge_v[e][1];
      mid[e] = static_cast<int>(m.V.size());
      m.V.push_back(0.5 * (m.V[a] + m.V[b]));
      m.fp.push_back(0.5 * (m.fp[a] + m.fp[b]));
      if (!m.last_step.empty()) m.last_step.push_back(0.5 * (m.last_step[a] + m.last_step[b]));
      ++count;
    }
  if (count == 0) return 0;
  std::vector<Eigen::Vector3i> F;
  std::vector<int> origin;
  const bool track = !m.origin.empty();
  F.reserve(m.F.size() + 3 * static_cast<size_t>(count));
  for (int f = 0; f < nf; ++f) {
    const auto& t = m.F[f];
    const auto& fe = topo.face_e[f];
    const int c = mark[fe[0]] + mark[fe[1]] + mark[fe[2]];
    if (c == 0) {
      F.push_back(t);
    } else if (c == 1) {
      int k = 0;
      while (!mark[fe[k]]) ++k;
      const int a = t[k], b = t[(k + 1) % 3], d = t[(k + 2) % 3], mm = mid[fe[k]];
      F.emplace_back(a, mm, d);
      F.emplace_back(mm, b, d);
    } else if (c == 2) {
      // Green 1:3: k = the unmarked edge (t[k], t[k+1]); the corner between the two
      // marked edges is cut off, the quad left is split by its shorter diagonal.
      int k = 0;
      while (mark[fe[k]]) ++k;
      const int a = t[k], b = t[(k + 1) % 3], d = t[(k + 2) % 3];
      const int mbd = mid[fe[(k + 1) % 3]], mda = mid[fe[(k + 2) % 3]];
      F.emplace_back(mda, mbd, d);
      if ((m.V[a] - m.V[mbd]).squaredNorm() <= (m.V[b] - m.V[mda]).squaredNorm()) {
        F.emplace_back(a, b, mbd);
        F.emplace_back(a, mbd, mda);
      } else {
        F.emplace_back(a, b, mda);
        F.emplace_back(b, mbd, mda);
      }
    } else {
      const int m0 = mid[fe[0]], m1 = mid[fe[1]], m2 = mid[fe[2]];
      F.emplace_back(t[0], m0, m2);
      F.emplace_back(m0, t[1], m1);
      F.emplace_back(m2, m1, t[2]);
      F.emplace_back(m0, m1, m2);
    }
    if (track) origin.resize(F.size(), c == 0 ? m.origin[f] : -1);  // split faces are new
  }
  m.F.swap(F);
  if (track) m.origin.swap(origin);
  return count;
}

void compact(RemeshMesh& m) {
  std::vector<Eigen::Vector3i> F;
  std::vector<int> origin;
  for (size_t f = 0; f < m.F.size(); ++f) {
    const auto& t = m.F[f];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
    F.push_back(t);
    if (!m.origin.empty()) origin.push_back(m.origin[f]);
  }
  if (!m.origin.empty()) m.origin.swap(origin);
  std::vector<int> id(m.V.size(), -1);
  for (const auto& t : F)
    for (int k = 0; k < 3; ++k) id[t[k]] = 0;
  std::vector<Eigen::Vector3d> V;
  std::vector<double> fp, last_step;
  for (size_t v = 0; v < m.V.size(); ++v)
    if (id[v] == 0) {
      id[v] = static_cast<int>(V.size());
      V.push_back(m.V[v]);
      fp.push_back(m.fp[v]);
      if (!m.last_step.empty()) last_step.push_back(m.last_step[v]);
    }
  for (auto& t : F)
    for (int k = 0; k < 3; ++k) t[k] = id[t[k]];
  m.V.swap(V);
  m.F.swap(F);
  m.fp.swap(fp);
  m.last_step.swap(last_step);
}

std::int64_t collapse_short_edges(RemeshMesh& m, double min_px, double needle_ratio, double max_px) {
  const int nv = static_cast<int>(m.V.size()), nf = static_cast<int>(m.F.size());
  const Topology topo = build_topology(m.F, nv);
  const int ne = topo.num_edges();
  std::vector<double> len(ne);
  for (int e = 0; e < ne; ++e) len[e] = edge_px(m, topo.edge_v[e][0], topo.edge_v[e][1]);
  std::vector<char> cand(ne, 0);
  for (int e = 0; e < ne; ++e) cand[e] = len[e] < min_px;
  for (int f = 0; f < nf; ++f) {
    const auto& fe = topo.face_e[f];
    int s = 0, l = 0;
    for (int k = 1; k < 3; ++k) {
      if (len[fe[k]] < len[fe[s]]) s = k;
      if (len[fe[k]] > len[fe[l]]) l = k;
    }
    if (len[fe[s]] < needle_ratio * len[fe[l]]) cand[fe[s]] = 1;
  }
  std::vector<int> order;
  for (int e = 0; e < ne; ++e)
    if (cand[e] && topo.edge_count[e] == 2) order.push_back(e);
  std::sort(order.begin(), order.end(), [&](int x, int y) { return len[x] < len[y] || (len[x] == len[y] && x < y); });

  CollapseBatch batch(nv, nf);
  std::vector<char>& locked = batch.locked;
  const double cos_max_turn = 0.5;
  for (int e : order) {
    const int a = topo.edge_v[e][0], b = topo.edge_v[e][1];
    if (locked[a] || locked[b]) continue;
    if (topo.degree(a) <= 3 || topo.degree(b) <= 3) continue;
    const int f1 = topo.edge_f[e][0], f2 = topo.edge_f[e][1];
    const int c = opposite(m.F[f1], a, b), d = opposite(m.F[f2], a, b);
    if (c < 0 || d < 0 || c == d) continue;
    if (topo.degree(c) <= 3 || topo.degree(d) <= 3) continue;
    if (common_count(topo.neighbours(a), topo.neighbours(b)) != 2) continue;  // link condition: exactly {c, d}
    const Eigen::Vector3d p = 0.5 * (m.V[a] + m.V[b]);
    const double fpp = 0.5 * (m.fp[a] + m.fp[b]);
    bool ok = true;
    for (int end : {a, b}) {
      for (int q = topo.vf_start[end]; q < topo.vf_start[end + 1] && ok; ++q) {
        const int f = topo.vf[q];
        if (f == f1 || f == f2) continue;
        const auto& t = m.F[f];
        const Eigen::Vector3d n0 = tri_cross(m.V, t[0], t[1], t[2]);
        Eigen::Vector3d P[3];
        for (int k = 0; k < 3; ++k) P[k] = (t[k] == end) ? p : m.V[t[k]];
        const Eigen::Vector3d n1 = (P[1] - P[0]).cross(P[2] - P[0]);
        const double l0 = n0.norm(), l1 = n1.norm();
        if (!(l1 > 1e-6 * fpp * fpp) || n0.dot(n1) < cos_max_turn * l0 * l1) ok = false;
      }
      for (int q = topo.nbr_start[end]; q < topo.nbr_start[end + 1] && ok; ++q) {
        const int w = topo.nbr[q];
        if ((m.V[w] - p).norm() / (0.5 * (fpp + m.fp[w])) > max_px) ok = false;
      }
    }
    if (!ok) continue;
    batch.collapse(m, a, b, f1, f2, p, fpp, topo.neighbours(a), topo.neighbours(b));  // b into a
  }
  return batch.finish(m);
}

std::int64_t flip_edges(RemeshMesh& m, double max_dihedral_deg) {
  const int nv = static_cast<int>(m.V.size()), nf = static_cast<int>(m.F.size());
  const Topology topo = build_topology(m.F, nv);
  const int ne = topo.num_edges();
  std::vector<int> degree(nv);
  for (int v = 0; v < nv; ++v) degree[v] = topo.degree(v);
  std::vector<char> face_locked(nf, 0);
  struct PairHash {
    std::size_t operator()(std::uint64_t x) const { return std::hash<std::uint64_t>()(x); }
  };
  std::unordered_set<std::uint64_t, PairHash> created;
  const auto key = [](int x, int y) {
    if (x > y) std::swap(x, y);
    return (static_cast<std::uint64_t>(x) << 32) | static_cast<std::uint32_t>(y);
  };
  const double cos_dihedral = std::cos(max_dihedral_deg * M_PI / 180.0);
  const auto angle = [&](int at, int p, int q) {
    const Eigen::Vector3d u = m.V[p] - m.V[at], w = m.V[q] - m.V[at];
    return std::atan2(u.cross(w).norm(), u.dot(w));
  };
  std::int64_t count = 0;
  for (int e = 0; e < ne; ++e) {
    if (topo.edge_count[e] != 2) continue;
    const int f1 = topo.edge_f[e][0], f2 = topo.edge_f[e][1];
    if (face_locked[f1] || face_locked[f2]) continue;
    const int a0 = topo.edge_v[e][0], b0 = topo.edge_v[e][1];
    // orient: f1 holds a -> b
    const auto& t1 = m.F[f1];
    int a = a0, b = b0;
    {
      int k = 0;
      while (t1[k] != a0) ++k;
      if (t1[(k + 1) % 3] != b0) std::swap(a, b);
    }
    const int c = opposite(m.F[f1], a, b), d = opposite(m.F[f2], a, b);
    if (c < 0 || d < 0 || c == d) continue;
    if (degree[a] <= 3 || degree[b] <= 3) continue;
    if (angle(c, a, b) + angle(d, a, b) <= M_PI + 1e-6) continue;
    const Eigen::Vector3d n1 = tri_cross(m.V, a, b, c), n2 = tri_cross(m.V, b, a, d);
    if (n1.dot(n2) < cos_dihedral * n1.norm() * n2.norm()) continue;
    if (topo.find_edge(c, d) >= 0 || created.count(key(c, d))) continue;
    const Eigen::Vector3d m1 = tri_cross(m.V, c, a, d), m2 = tri_cross(m.V, d, b, c);
    const Eigen::Vector3d ns = n1.normalized() + n2.normalized();
    if (!(m1.dot(ns) > 0) || !(m2.dot(ns) > 0)) continue;
    m.F[f1] = Eigen::Vector3i(c, a, d);
    m.F[f2] = Eigen::Vector3i(d, b, c);
    if (!m.origin.empty()) m.origin[f1] = m.origin[f2] = -1;
    face_locked[f1] = face_locked[f2] = 1;
    created.insert(key(c, d));
    --degree[a];
    --degree[b];
    ++degree[c];
    ++degree[d];
    ++count;
  }
  return count;
}

}  // namespace tetmvs::deform

namespace tetmvs::deform {

FoldCollapses collapse_folds(RemeshMesh& m, const std::vector<std::pair<int, int>>& pairs) {
  FoldCollapses out;
  if (pairs.empty()) return out;
  const int nv = static_cast<int>(m.V.size()), nf = static_cast<int>(m.F.size());
  // the adjacency of the few vertices around the pairs, read from each vertex's faces (a
  // whole Topology would cost more than the collapses on a mesh of millions)
  const VertexFaces vf(m.F, nv);
  const auto neighbours = [&](int v) {
    std::vector<int> r;
    vf.neighbours(m.F, v, r);
    return r;
  };
  // candidate edges: those at a corner of an intersecting face, shortest first (in world
  // units: the fold is sub-pixel, the edge of a vertex pushed past its neighbour is short
  // and need not belong to the intersecting faces); ties in (lower, upper) vertex order
  std::vector<std::array<int, 2>> cand;
  for (const auto& p : pairs)
    for (int f : {p.first, p.second})
      for (int k = 0; k < 3; ++k) {
        const int v = m.F[f][k];
        for (int w : neighbours(v)) cand.push_back({std::min(v, w), std::max(v, w)});
      }
  std::sort(cand.begin(), cand.end());
  cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
  const auto len = [&](const std::array<int, 2>& e) { return (m.V[e[0]] - m.V[e[1]]).squaredNorm(); };
  std::sort(cand.begin(), cand.end(),
            [&](const auto& x, const auto& y) { return len(x) < len(y) || (len(x) == len(y) && x < y); });
  CollapseBatch batch(nv, nf);
  std::vector<char>& locked = batch.locked;
  std::vector<char> pair_done(pairs.size(), 0);
  // the pairs at each vertex (a corner of either face), compressed rows
  std::vector<int> vp_start(nv + 1, 0), vp;
  for (const auto& p : pairs)
    for (int f : {p.first, p.second})
      for (int k = 0; k < 3; ++k) ++vp_start[m.F[f][k] + 1];
  for (int v = 0; v < nv; ++v) vp_start[v + 1] += vp_start[v];
  vp.resize(vp_start[nv]);
  {
    std::vector<int> fill(vp_start.begin(), vp_start.end() - 1);
    for (size_t i = 0; i < pairs.size(); ++i)
      for (int f : {pairs[i].first, pairs[i].second})
        for (int k = 0; k < 3; ++k) vp[fill[m.F[f][k]]++] = static_cast<int>(i);
  }
  for (const auto& [a, b] : cand) {
    if (locked[a] || locked[b]) continue;
    std::vector<int> edge_faces;  // the faces of a that hold b, ascending
    for (int f : vf.of(a))
      if (m.F[f][0] == b || m.F[f][1] == b || m.F[f][2] == b) edge_faces.push_back(f);
    if (edge_faces.size() != 2) continue;
    const int f1 = edge_faces[0], f2 = edge_faces[1];
    const int c = opposite(m.F[f1], a, b), d = opposite(m.F[f2], a, b);
    if (c < 0 || d < 0 || c == d) continue;
    const std::vector<int> na = neighbours(a), nb = neighbours(b);
    if (na.size() <= 3 || nb.size() <= 3 || neighbours(c).size() <= 3 || neighbours(d).size() <= 3) continue;
    if (common_count(na, nb) != 2) continue;
    // one collapse per intersecting pair: skip edges whose ends touch no pair left
    std::vector<int> touched;
    for (int end : {a, b})
      for (int q = vp_start[end]; q < vp_start[end + 1]; ++q)
        if (!pair_done[vp[q]]) touched.push_back(vp[q]);
    if (touched.empty()) continue;
    // The merged vertex goes where its fan is flattest: at a, at b or at the midpoint,
    // whichever maximises the smallest cosine between a surrounding triangle's normal and
    // the fan's mean normal before the collapse (a vertex pushed past its neighbour folds
    // its fan over the neighbour's: merged at the midpoint the fold would stay). No
    // triangle may become degenerate.
    Eigen::Vector3d nref = Eigen::Vector3d::Zero();
    for (int end : {a, b})
      for (int f : vf.of(end))
        if (f != f1 && f != f2) nref += tri_cross(m.V, m.F[f][0], m.F[f][1], m.F[f][2]);
    if (!(nref.norm() > 0)) continue;
    nref.normalize();
    const Eigen::Vector3d options[3] = {0.5 * (m.V[a] + m.V[b]), m.V[a], m.V[b]};
    double best = -2;
    Eigen::Vector3d p = options[0];
    for (const Eigen::Vector3d& x : options) {
      double worst = 2;
      for (int end : {a, b})
        for (int f : vf.of(end)) {
          if (f == f1 || f == f2) continue;
          const auto& t = m.F[f];
          Eigen::Vector3d P[3];
          for (int k = 0; k < 3; ++k) P[k] = (t[k] == a || t[k] == b) ? x : m.V[t[k]];
          const Eigen::Vector3d n = (P[1] - P[0]).cross(P[2] - P[0]);
          const double l2 = std::max({(P[1] - P[0]).squaredNorm(), (P[2] - P[1]).squaredNorm(), (P[0] - P[2]).squaredNorm()});
          worst = std::min(worst, n.norm() > 1e-9 * l2 ? n.normalized().dot(nref) : -2.0);
        }
      if (worst > best) best = worst, p = x;
    }
    if (!(best > -1.5)) continue;
    for (int i : touched) pair_done[i] = 1;
    batch.collapse(m, a, b, f1, f2, p, 0.5 * (m.fp[a] + m.fp[b]), na, nb);
  }
  out.count = batch.finish(m, &out);
  return out;
}

}  // namespace tetmvs::deform
