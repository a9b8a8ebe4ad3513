// Red-green refinement (see refine.h for the rules).
#include "common/tetmesh/refine.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "common/error.h"

namespace tetmvs::tet {
namespace {

inline I3 vI(const std::vector<std::int32_t>& vlat, std::int32_t v) {
  return {vlat[3 * v], vlat[3 * v + 1], vlat[3 * v + 2]};
}

inline void fix_orientation(Tet& t, const std::vector<std::int32_t>& vlat) {
  const int s = orient_sign(vI(vlat, t[0]), vI(vlat, t[1]), vI(vlat, t[2]), vI(vlat, t[3]));
  if (s < 0) std::swap(t[2], t[3]);
}

inline Tet with(Tet t, int i, std::int32_t v) {
  t[i] = v;
  return t;
}

// Working state of one refinement step.
struct Refiner {
  TetMesh& m;
  EdgeMap& E;
  std::vector<std::uint8_t> touched;  // per vertex: end point of an edge split this round

  std::int32_t midpoint(std::int32_t a, std::int32_t b) {
    const std::int32_t f = E.find(a, b);
    if (f >= 0) return f;
    const auto v = m.num_vertices();
    for (int d = 0; d < 3; ++d) {
      const std::int64_t s = std::int64_t{m.vlat[3 * a + d]} + m.vlat[3 * b + d];
      if (s & 1) fail("refine: edge (", a, ", ", b, ") cannot be bisected on the lattice (level > ",
                      kMaxLevel, ")");
      m.vlat.push_back(static_cast<std::int32_t>(s / 2));
    }
    m.vparent.push_back(a);
    m.vparent.push_back(b);
    touched.push_back(0);
    E.insert(a, b, v);
    return v;
  }

  void red_refine(std::int32_t n) {
    require(m.node_level[n] < kMaxLevel, "refine: a cell would be refined beyond level ", kMaxLevel);
    const Tet v = m.node_v[n];
    std::int32_t mid[6];
    for (int k = 0; k < 6; ++k) mid[k] = midpoint(v[kEdge[k][0]], v[kEdge[k][1]]);
    for (int k = 0; k < 4; ++k) touched[v[k]] = 1;
    for (int k = 0; k < 6; ++k) touched[mid[k]] = 1;
    Tet ch[8];
    for (int i = 0; i < 4; ++i) {
      Tet t = v;
      for (int j = 0; j < 4; ++j)
        if (j != i) t[j] = mid[kEdgeIndex[i][j]];
      ch[i] = t;
    }
    // octahedron: diagonals (m01,m23), (m02,m13), (m03,m12); take the shortest
    static const int diag[3][2] = {{0, 5}, {1, 4}, {2, 3}};
    int best = 0;
    std::int64_t bestlen = -1;
    for (int d = 0; d < 3; ++d) {
      const I3 e = vI(m.vlat, mid[diag[d][0]]) - vI(m.vlat, mid[diag[d][1]]);
      const std::int64_t len = e.x * e.x + e.y * e.y + e.z * e.z;
      if (bestlen < 0 || len < bestlen) bestlen = len, best = d;
    }
    const int i = kEdge[diag[best][0]][0], j = kEdge[diag[best][0]][1];
    const int k = kEdge[diag[best][1]][0], l = kEdge[diag[best][1]][1];
    const std::int32_t a = mid[diag[best][0]], b = mid[diag[best][1]];
    const std::int32_t cyc[4] = {mid[kEdgeIndex[i][k]], mid[kEdgeIndex[i][l]], mid[kEdgeIndex[j][l]],
                                 mid[kEdgeIndex[j][k]]};
    for (int t = 0; t < 4; ++t) {
      ch[4 + t] = Tet{a, b, cyc[t], cyc[(t + 1) & 3]};
      fix_orientation(ch[4 + t], m.vlat);
    }
    const auto first = m.num_nodes();
    m.node_child[n] = first;
    m.node_cell[n] = -1;
    m.node_ncell[n] = 0;
    for (int c = 0; c < 8; ++c) {
      m.node_v.push_back(ch[c]);
      m.node_level.push_back(static_cast<std::int8_t>(m.node_level[n] + 1));
      m.node_parent.push_back(n);
      m.node_child.push_back(-1);
      m.node_cell.push_back(-1);
      m.node_ncell.push_back(1);
    }
  }

  // Midpoints of a node's six edges and the split mask.
  int mids(std::int32_t n, std::int32_t mid[6]) const {
    const Tet& v = m.node_v[n];
    int mask = 0;
    for (int k = 0; k < 6; ++k) {
      mid[k] = E.find(v[kEdge[k][0]], v[kEdge[k][1]]);
      if (mid[k] >= 0) mask |= 1 << k;
    }
    return mask;
  }

  // True when the red-tree leaf n cannot stay unsplit or green. *split = mask != 0.
  // Returns 0 (stays), or the reason for red: 1 an edge split twice, 2 not a green
  // pattern, 3 an edge of a would-be green cell is split.
  int needs_red(std::int32_t n, bool* split) const {
    std::int32_t mid[6];
    const int mask = mids(n, mid);
    *split = mask != 0;
    if (!mask) return 0;
    const Tet& v = m.node_v[n];
    for (int k = 0; k < 6; ++k)
      if (mid[k] >= 0 && (E.has(v[kEdge[k][0]], mid[k]) || E.has(mid[k], v[kEdge[k][1]]))) return 1;
    Tet out[4];
    const int nc = green_split(v, mid, m.vlat, out);
    if (nc == 0) return 2;
    for (int c = 0; c < nc; ++c)
      for (int k = 0; k < 6; ++k) {
        const std::int32_t x = out[c][kEdge[k][0]], y = out[c][kEdge[k][1]];
        if (E.has(x, y)) return 3;
      }
    return 0;
  }
};

// Exact test: the triangle f (three lattice points) lies in the closed triangle g.
bool triangle_inside(const I3 f[3], const I3 g[3]) {
  for (int i = 0; i < 3; ++i)
    if (orient_sign(g[0], g[1], g[2], f[i]) != 0) return false;
  const I3 u = g[1] - g[0], w = g[2] - g[0];
  const i128 nx = i128(u.y) * w.z - i128(u.z) * w.y, ny = i128(u.z) * w.x - i128(u.x) * w.z,
             nz = i128(u.x) * w.y - i128(u.y) * w.x;
  const i128 ax = nx < 0 ? -nx : nx, ay = ny < 0 ? -ny : ny, az = nz < 0 ? -nz : nz;
  // project along the dominant normal axis
  int drop = 2;
  if (ax >= ay && ax >= az) drop = 0;
  else if (ay >= az) drop = 1;
  auto p2 = [&](const I3& p) -> std::pair<std::int64_t, std::int64_t> {
    if (drop == 0) return {p.y, p.z};
    if (drop == 1) return {p.z, p.x};
    return {p.x, p.y};
  };
  auto o2 = [&](const I3& a, const I3& b, const I3& c) {
    const auto A = p2(a), B = p2(b), C = p2(c);
    return sign_of(i128(B.first - A.first) * (C.second - A.second) -
                   i128(B.second - A.second) * (C.first - A.first));
  };
  const int s = o2(g[0], g[1], g[2]);
  for (int i = 0; i < 3; ++i)
    for (int e = 0; e < 3; ++e)
      if (o2(g[e], g[(e + 1) % 3], f[i]) * s < 0) return false;
  return true;
}

}  // namespace

int green_split(const Tet& v, const std::int32_t mid[6], const std::vector<std::int32_t>& vlat,
                Tet out[4]) {
  int mask = 0;
  for (int k = 0; k < 6; ++k)
    if (mid[k] >= 0) mask |= 1 << k;
  const int count = std::popcount(static_cast<unsigned>(mask));
  if (count == 0) {
    out[0] = v;
    return 1;
  }
  if (count == 1) {
    const int k = std::countr_zero(static_cast<unsigned>(mask));
    const int i = kEdge[k][0], j = kEdge[k][1];
    out[0] = with(v, j, mid[k]);
    out[1] = with(v, i, mid[k]);
    return 2;
  }
  if (count == 2) {
    if (mask != (1 | 32) && mask != (2 | 16) && mask != (4 | 8)) {
      // two adjacent edges (v,a), (v,b): 1:3. The face (v,a,b) is cut into the corner
      // triangle (v, m_va, m_vb) and a quad split along a diagonal chosen from the face
      // alone (shorter diagonal, ties by vertex ids), so both cells sharing the face agree.
      const int k1 = std::countr_zero(static_cast<unsigned>(mask));
      const int k2 = std::countr_zero(static_cast<unsigned>(mask & (mask - 1)));
      int vv = -1;
      for (int x : {kEdge[k1][0], kEdge[k1][1]})
        if (x == kEdge[k2][0] || x == kEdge[k2][1]) vv = x;
      const int ia = kEdge[k1][0] == vv ? kEdge[k1][1] : kEdge[k1][0];
      const int ib = kEdge[k2][0] == vv ? kEdge[k2][1] : kEdge[k2][0];
      const std::int32_t ma = mid[k1], mb = mid[k2];
      auto len2 = [&](std::int32_t x, std::int32_t y) {
        const I3 d = vI(vlat, x) - vI(vlat, y);
        return d.x * d.x + d.y * d.y + d.z * d.z;
      };
      const std::int64_t la = len2(ma, v[ib]), lb = len2(mb, v[ia]);
      bool use_a = la < lb;  // diagonal (m_va, b)
      if (la == lb) use_a = EdgeMap::key(ma, v[ib]) < EdgeMap::key(mb, v[ia]);
      out[0] = with(with(v, ia, ma), ib, mb);  // corner at v
      if (use_a) {
        out[1] = with(v, vv, ma);                 // (m_va, a, b, d)
        out[2] = with(with(v, vv, ma), ia, mb);  // (m_va, m_vb, b, d) in a's slot
      } else {
        out[1] = with(v, vv, mb);                 // (m_vb, a, b, d)
        out[2] = with(with(v, vv, mb), ib, ma);  // (m_vb, a, m_va, d) in b's slot
      }
      fix_orientation(out[1], vlat);
      fix_orientation(out[2], vlat);
      return 3;
    }
    const int k1 = std::countr_zero(static_cast<unsigned>(mask)), k2 = 5 - k1;
    const int i = kEdge[k1][0], j = kEdge[k1][1], k = kEdge[k2][0], l = kEdge[k2][1];
    const Tet t1 = with(v, j, mid[k1]), t2 = with(v, i, mid[k1]);
    out[0] = with(t1, l, mid[k2]);
    out[1] = with(t1, k, mid[k2]);
    out[2] = with(t2, l, mid[k2]);
    out[3] = with(t2, k, mid[k2]);
    return 4;
  }
  if (count == 3) {
    for (int d = 0; d < 4; ++d) {
      int o[3], n = 0;
      for (int x = 0; x < 4; ++x)
        if (x != d) o[n++] = x;
      const int fm = (1 << kEdgeIndex[o[0]][o[1]]) | (1 << kEdgeIndex[o[1]][o[2]]) | (1 << kEdgeIndex[o[0]][o[2]]);
      if (mask != fm) continue;
      const int i = o[0], j = o[1], k = o[2];
      const std::int32_t mij = mid[kEdgeIndex[i][j]], mjk = mid[kEdgeIndex[j][k]], mik = mid[kEdgeIndex[i][k]];
      out[0] = with(with(v, j, mij), k, mik);
      out[1] = with(with(v, i, mij), k, mjk);
      out[2] = with(with(v, i, mik), j, mjk);
      out[3] = with(with(with(v, i, mij), j, mjk), k, mik);
      fix_orientation(out[3], vlat);
      return 4;
    }
    return 0;
  }
  return 0;
}

EdgeMap edge_midpoints(const TetMesh& m) {
  EdgeMap E(static_cast<std::size_t>(m.num_vertices()) + 16);
  for (std::int32_t v = 0; v < m.num_vertices(); ++v)
    if (m.vparent[2 * v] >= 0) E.insert(m.vparent[2 * v], m.vparent[2 * v + 1], v);
  return E;
}

TetMesh refine(const TetMesh& old, const std::vector<std::uint8_t>& active, RefineStats* stats) {
  require(active.size() == static_cast<std::size_t>(old.num_cells()), "refine: ", active.size(),
          " active flags for a mesh of ", old.num_cells(), " cells");
  RefineStats st;
  const bool timing = std::getenv("TETMVS_REFINE_TIMING") != nullptr;
  auto t_last = std::chrono::steady_clock::now();
  auto lap = [&](const char* what) {
    if (!timing) return;
    const auto now = std::chrono::steady_clock::now();
    std::fprintf(stderr, "refine: %-12s %8.3f s\n", what, std::chrono::duration<double>(now - t_last).count());
    t_last = now;
  };
  TetMesh m;
  m.lat = old.lat;
  m.level = old.level + 1;
  m.vlat = old.vlat;
  m.vparent = old.vparent;
  m.node_v = old.node_v;
  m.node_level = old.node_level;
  m.node_parent = old.node_parent;
  m.node_child = old.node_child;
  m.node_cell = old.node_cell;
  m.node_ncell = old.node_ncell;
  m.num_level0 = old.num_level0;
  const std::int32_t old_nodes = old.num_nodes();

  EdgeMap E = edge_midpoints(old);
  lap("copy+map");
  Refiner R{m, E, std::vector<std::uint8_t>(old.num_vertices(), 0)};

  // nodes to red-refine first: the red nodes of the active cells (a green cell's node)
  std::vector<std::uint8_t> flag(old_nodes, 0);
  for (std::int32_t c = 0; c < old.num_cells(); ++c)
    if (active[c]) flag[old.cell_node[c]] = 1;
  std::vector<std::int32_t> todo;
  for (std::int32_t n = 0; n < old_nodes; ++n)
    if (flag[n]) todo.push_back(n);
  st.red_active = static_cast<std::int64_t>(todo.size());
  // Room for the active nodes' children and a quarter more for the closure's (the arrays are
  // large at fine levels: growing them by doubling copies and faults every page again).
  const std::size_t grow = todo.size() + todo.size() / 4, nodes = old_nodes + 8 * grow;
  m.node_v.reserve(nodes);
  m.node_level.reserve(nodes);
  m.node_parent.reserve(nodes);
  m.node_child.reserve(nodes);
  m.node_cell.reserve(nodes);
  m.node_ncell.reserve(nodes);
  m.vlat.reserve(m.vlat.size() + 3 * 4 * grow);
  m.vparent.reserve(m.vparent.size() + 2 * 4 * grow);
  // green[n]: leaf n had split edges at its last check
  std::vector<std::uint8_t> green(old_nodes);
  for (std::int32_t n = 0; n < old_nodes; ++n) green[n] = old.node_ncell[n] > 1;

  while (!todo.empty()) {
    std::fill(R.touched.begin(), R.touched.end(), 0);
    for (std::int32_t n : todo) R.red_refine(n);
    ++st.rounds;
    const std::int32_t NN = m.num_nodes();
    green.resize(NN, 0);
    flag.assign(NN, 0);
#pragma omp parallel for schedule(static, 4096)
    for (std::int32_t n = 0; n < NN; ++n) {
      if (m.node_child[n] >= 0) continue;
      const Tet& v = m.node_v[n];
      if (!R.touched[v[0]] && !R.touched[v[1]] && !R.touched[v[2]] && !R.touched[v[3]]) {
        // A leaf passed its last check (or the previous refinement's closure). Every edge
        // split since was an edge of a red-refined node, whose corners are all touched; so
        // the leaf's answer can change only when a corner or, for a green leaf, one of its
        // edge midpoints is touched.
        if (!green[n]) continue;
        std::int32_t mid[6];
        R.mids(n, mid);
        bool near = false;
        for (int k = 0; k < 6; ++k) near = near || (mid[k] >= 0 && R.touched[mid[k]]);
        if (!near) continue;
      }
      bool split = false;
      flag[n] = static_cast<std::uint8_t>(R.needs_red(n, &split));
      green[n] = split;
    }
    todo.clear();
    for (std::int32_t n = 0; n < NN; ++n)
      if (flag[n]) {
        todo.push_back(n);
        ++st.red_reason[flag[n] - 1];
      }
    st.red_closure += static_cast<std::int64_t>(todo.size());
  }

  lap("closure");
  // After the closure green[n] is exact for every leaf: a leaf not checked in a round had no
  // corner touched, so none of its edges was split in that round.
  // cells: every red-tree leaf, unsplit or green-split, in node order
  const std::int32_t NN = m.num_nodes();
  std::vector<std::int32_t> count(NN + 1, 0);
#pragma omp parallel for schedule(static, 4096)
  for (std::int32_t n = 0; n < NN; ++n) {
    if (m.node_child[n] >= 0) continue;
    if (!green[n]) {
      count[n + 1] = 1;
      continue;
    }
    std::int32_t mid[6];
    R.mids(n, mid);
    Tet out[4];
    count[n + 1] = green_split(m.node_v[n], mid, m.vlat, out);
  }
  for (std::int32_t n = 0; n < NN; ++n) {
    require(m.node_child[n] >= 0 || count[n + 1] > 0, "refine: internal error, node ", n,
            " has no valid split pattern after the closure");
    count[n + 1] += count[n];
  }
  const std::int32_t NC = count[NN];
  m.cell_v.resize(NC);
  m.cell_node.resize(NC);
  m.cell_colour.resize(NC);
  m.cell_new_red.resize(NC);
  std::int64_t green_nodes = 0;
#pragma omp parallel for schedule(static, 4096) reduction(+ : green_nodes)
  for (std::int32_t n = 0; n < NN; ++n) {
    if (m.node_child[n] >= 0) continue;
    Tet out[4] = {m.node_v[n]};
    int nc = 1;
    if (green[n]) {
      std::int32_t mid[6];
      R.mids(n, mid);
      nc = green_split(m.node_v[n], mid, m.vlat, out);
    }
    const std::int32_t first = count[n];
    m.node_cell[n] = first;
    m.node_ncell[n] = static_cast<std::uint8_t>(nc);
    green_nodes += nc > 1;
    for (int c = 0; c < nc; ++c) {
      m.cell_v[first + c] = out[c];
      m.cell_node[first + c] = n;
      m.cell_colour[first + c] = nc > 1 ? kGreen : kRed;
      m.cell_new_red[first + c] = n >= old_nodes;
    }
  }
  st.green_nodes = green_nodes;
  st.green_cells = 0;
  for (std::int32_t c = 0; c < NC; ++c) st.green_cells += m.cell_colour[c] == kGreen;
  lap("cells");
  build_faces(m);
  lap("faces");

  // faces of the previous mesh each new face lies in
  const std::int32_t NF = m.num_faces();
  m.face_parent.assign(NF, -1);
  m.face_sub.assign(NF, -1);
#pragma omp parallel for schedule(static, 4096)
  for (std::int32_t f = 0; f < NF; ++f) {
    // fast path: a face of a cell that is the same in both meshes (an unsplit old node)
    bool done = false;
    for (int k = 0; k < 2 && !done; ++k) {
      const std::int32_t h = m.face_half[f][k];
      if (h < 0) continue;
      const std::int32_t nd = m.cell_node[h >> 2];
      if (nd < old_nodes && old.node_ncell[nd] == 1 && m.node_ncell[nd] == 1) {
        m.face_parent[f] = old.cell_face[old.node_cell[nd]][h & 3];
        m.face_sub[f] = kSubWhole;
        done = true;
      }
    }
    if (done) continue;
    // fast path: a face inside one new node (between its red children or its green parts)
    // whose old ancestor was an unsplit cell lies inside that old cell
    if (m.face_half[f][1] >= 0) {
      const std::int32_t c0 = m.face_half[f][0] >> 2, c1 = m.face_half[f][1] >> 2;
      std::int32_t n0 = m.cell_node[c0], n1 = m.cell_node[c1];
      if (m.cell_colour[c0] == kRed) n0 = m.node_parent[n0];
      if (m.cell_colour[c1] == kRed) n1 = m.node_parent[n1];
      if (n0 == n1 && n0 >= 0) {
        std::int32_t a = n0;
        while (a >= old_nodes) a = m.node_parent[a];
        if (old.node_ncell[a] == 1) continue;  // stays -1 / -1
      }
    }
    std::int32_t n = m.cell_node[m.face_half[f][0] >> 2];
    while (n >= old_nodes) n = m.node_parent[n];
    const auto fv = m.face_vertices(f);
    const I3 F[3] = {m.vint(fv[0]), m.vint(fv[1]), m.vint(fv[2])};
    for (std::int32_t oc = old.node_cell[n]; oc < old.node_cell[n] + old.node_ncell[n]; ++oc) {
      bool found = false;
      for (int j = 0; j < 4 && !found; ++j) {
        const std::int32_t g = old.cell_face[oc][j];
        const auto gv = old.face_vertices(g);
        const I3 G[3] = {old.vint(gv[0]), old.vint(gv[1]), old.vint(gv[2])};
        if (!triangle_inside(F, G)) continue;
        found = true;
        m.face_parent[f] = g;
        auto sorted = [](std::array<std::int32_t, 3> a) {
          std::sort(a.begin(), a.end());
          return a;
        };
        const auto sf = sorted(fv);
        if (sf == sorted(gv)) {
          m.face_sub[f] = kSubWhole;
          break;
        }
        const std::int32_t m01 = E.find(gv[0], gv[1]), m12 = E.find(gv[1], gv[2]), m20 = E.find(gv[2], gv[0]);
        if (sf == sorted({gv[0], m01, m20})) m.face_sub[f] = 0;
        else if (sf == sorted({gv[1], m12, m01})) m.face_sub[f] = 1;
        else if (sf == sorted({gv[2], m20, m12})) m.face_sub[f] = 2;
        else if (sf == sorted({m01, m12, m20})) m.face_sub[f] = 3;
      }
      if (found) break;
    }
  }
  lap("face-parents");
  m.vlat.shrink_to_fit();
  m.vparent.shrink_to_fit();
  m.node_v.shrink_to_fit();
  m.node_level.shrink_to_fit();
  m.node_parent.shrink_to_fit();
  m.node_child.shrink_to_fit();
  m.node_cell.shrink_to_fit();
  m.node_ncell.shrink_to_fit();
  m.face_half.shrink_to_fit();
  if (stats) *stats = st;
  return m;
}

TetMesh refine_uniform(const TetMesh& m, int times) {
  TetMesh r = m;
  for (int i = 0; i < times; ++i) r = refine(r, std::vector<std::uint8_t>(r.num_cells(), 1));
  return r;
}

}  // namespace tetmvs::tet
