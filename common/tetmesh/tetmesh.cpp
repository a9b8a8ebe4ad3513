// BCC lattice construction, face building, geometry and the consistency check.
#include "common/tetmesh/tetmesh.h"

#include <algorithm>
#include <array>
#include <numeric>

#include "common/error.h"

namespace tetmvs::tet {

Eigen::AlignedBox3d Lattice::grid_box() const {
  const Eigen::Vector3d ext(dims[0] * h, dims[1] * h, dims[2] * h);
  return Eigen::AlignedBox3d(origin, origin + ext);
}

I3 Lattice::to_fixed(const Eigen::Vector3d& x) const {
  const Eigen::Vector3d l = (x - origin) * (std::ldexp(1.0, kFixedBits) / unit());
  return {std::llround(l.x()), std::llround(l.y()), std::llround(l.z())};
}

int TetMesh::max_cell_level() const {
  int L = 0;
  for (std::int32_t c = 0; c < num_cells(); ++c) L = std::max<int>(L, node_level[cell_node[c]]);
  return L;
}

std::array<std::int32_t, 3> TetMesh::face_vertices(std::int32_t f) const { return half_face_vertices(face_half[f][0]); }

std::int32_t TetMesh::neighbour(std::int32_t c, int j) const {
  const std::int32_t f = cell_face[c][j];
  const std::int32_t h = c * 4 + j;
  const std::int32_t o = face_half[f][0] == h ? face_half[f][1] : face_half[f][0];
  return o < 0 ? -1 : o >> 2;
}

i128 TetMesh::cell_volume6_lattice(std::int32_t c) const {
  const Tet& t = cell_v[c];
  const I3 a = vint(t[0]);
  return det3_exact(vint(t[1]) - a, vint(t[2]) - a, vint(t[3]) - a);
}

double TetMesh::cell_volume(std::int32_t c) const {
  // integer differences are exact; one rounding in the determinant
  const Tet& t = cell_v[c];
  const I3 a = vint(t[0]), b = vint(t[1]) - a, d = vint(t[2]) - a, e = vint(t[3]) - a;
  const Eigen::Vector3d u(b.x, b.y, b.z), v(d.x, d.y, d.z), w(e.x, e.y, e.z);
  const double s = lat.unit();
  return u.cross(v).dot(w) * (s * s * s) / 6.0;
}

Eigen::Vector3d TetMesh::cell_centroid(std::int32_t c) const {
  const Tet& t = cell_v[c];
  return 0.25 * (vertex(t[0]) + vertex(t[1]) + vertex(t[2]) + vertex(t[3]));
}

double TetMesh::face_area(std::int32_t f) const {
  const auto v = face_vertices(f);
  return 0.5 * (vertex(v[1]) - vertex(v[0])).cross(vertex(v[2]) - vertex(v[0])).norm();
}

Eigen::Vector3d TetMesh::face_normal(std::int32_t f) const {
  const auto v = face_vertices(f);
  return (vertex(v[1]) - vertex(v[0])).cross(vertex(v[2]) - vertex(v[0])).normalized();
}

Eigen::Vector3d TetMesh::face_centroid(std::int32_t f) const {
  const auto v = face_vertices(f);
  return (vertex(v[0]) + vertex(v[1]) + vertex(v[2])) / 3.0;
}

template <typename V>
static std::size_t cap_bytes(const V& v) {
  return v.capacity() * sizeof(typename V::value_type);
}

std::size_t TetMesh::memory_bytes() const {
  return cap_bytes(vlat) + cap_bytes(vparent) + cap_bytes(node_v) + cap_bytes(node_level) +
         cap_bytes(node_parent) + cap_bytes(node_child) + cap_bytes(node_cell) + cap_bytes(node_ncell) +
         cap_bytes(cell_v) + cap_bytes(cell_node) + cap_bytes(cell_colour) + cap_bytes(cell_new_red) +
         cap_bytes(cell_face) + cap_bytes(face_half) + cap_bytes(face_parent) + cap_bytes(face_sub);
}

Lattice lattice_for_box(const Eigen::AlignedBox3d& box, int cells_longest) {
  require(!box.isEmpty(), "bcc-init: the scene box is empty");
  require(cells_longest >= 1, "bcc-init: mesh.cells must be >= 1, got ", cells_longest);
  const Eigen::Vector3d size = box.sizes();
  const double longest = size.maxCoeff();
  require(std::isfinite(longest) && longest > 0, "bcc-init: the scene box has no extent");
  Lattice lat;
  lat.h = longest / cells_longest;
  Eigen::Vector3d ext;
  for (int a = 0; a < 3; ++a) {
    // the tets cover the cube grid minus pyramids of height h/2 over its boundary
    // squares: at least 0.6 h of margin on each side (strictly more than h/2, so the box
    // faces do not touch the pyramids' apexes), rounded up to whole cubes
    const int n = static_cast<int>(std::ceil(size[a] / lat.h + 1.2 - 1e-9));
    lat.dims[a] = std::max(n, 2);
    require(lat.dims[a] <= kMaxDims, "bcc-init: ", lat.dims[a], " cubes along an axis, at most ",
            kMaxDims, " are supported");
    ext[a] = lat.dims[a] * lat.h;
  }
  lat.origin = box.center() - 0.5 * ext;
  return lat;
}

TetMesh build_bcc(const Lattice& lat) {
  const int nx = lat.dims[0], ny = lat.dims[1], nz = lat.dims[2];
  require(nx >= 2 && ny >= 2 && nz >= 2, "build_bcc: needs at least 2 cubes per axis");
  TetMesh m;
  m.lat = lat;
  const std::int32_t S = std::int32_t{1} << kLatticeBits;
  const std::int64_t NA = std::int64_t(nx + 1) * (ny + 1) * (nz + 1);
  const std::int64_t NB = std::int64_t(nx) * ny * nz;
  auto aid = [&](int i, int j, int k) { return std::int64_t(i) + (nx + 1) * (std::int64_t(j) + (ny + 1) * k); };
  auto bid = [&](int i, int j, int k) { return NA + i + nx * (std::int64_t(j) + std::int64_t(ny) * k); };
  std::vector<std::int32_t> xyz(3 * (NA + NB));
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        const auto id = aid(i, j, k);
        xyz[3 * id] = i * S, xyz[3 * id + 1] = j * S, xyz[3 * id + 2] = k * S;
      }
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const auto id = bid(i, j, k);
        xyz[3 * id] = i * S + S / 2, xyz[3 * id + 1] = j * S + S / 2, xyz[3 * id + 2] = k * S + S / 2;
      }
  const int n[3] = {nx, ny, nz};
  std::vector<Tet> tets;
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int ic = 0; ic < n[c]; ++ic)
      for (int ib = 0; ib < n[b]; ++ib)
        for (int fa = 1; fa < n[a]; ++fa) {
          int lo[3], hi[3];
          lo[a] = fa - 1, hi[a] = fa;
          lo[b] = hi[b] = ib;
          lo[c] = hi[c] = ic;
          const auto c1 = static_cast<std::int32_t>(bid(lo[0], lo[1], lo[2]));
          const auto c2 = static_cast<std::int32_t>(bid(hi[0], hi[1], hi[2]));
          // square corners (db, dc) in quadrant order: low c, high b, high c, low b
          static const int cb[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
          for (int q = 0; q < 4; ++q) {
            std::int32_t e[2];
            for (int s = 0; s < 2; ++s) {
              int p[3];
              p[a] = fa, p[b] = ib + cb[q + s][0], p[c] = ic + cb[q + s][1];
              e[s] = static_cast<std::int32_t>(aid(p[0], p[1], p[2]));
            }
            Tet t{c1, c2, e[0], e[1]};
            auto V = [&](std::int32_t v) { return I3{xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]}; };
            if (orient_sign(V(t[0]), V(t[1]), V(t[2]), V(t[3])) < 0) std::swap(t[2], t[3]);
            tets.push_back(t);
          }
        }
  }
  // compact away unused vertices (the eight grid corners)
  std::vector<std::int32_t> remap(NA + NB, -1);
  for (const Tet& t : tets)
    for (std::int32_t v : t) remap[v] = 0;
  std::int32_t nv = 0;
  for (auto& r : remap)
    if (r == 0) r = nv++;
  m.vlat.resize(3 * std::size_t(nv));
  for (std::int64_t v = 0; v < NA + NB; ++v)
    if (remap[v] >= 0)
      for (int d = 0; d < 3; ++d) m.vlat[3 * remap[v] + d] = xyz[3 * v + d];
  m.vparent.assign(2 * std::size_t(nv), -1);
  for (Tet& t : tets)
    for (auto& v : t) v = remap[v];
  const auto N = static_cast<std::int32_t>(tets.size());
  m.num_level0 = N;
  m.node_v = tets;
  m.node_level.assign(N, 0);
  m.node_parent.assign(N, -1);
  m.node_child.assign(N, -1);
  m.node_cell.resize(N);
  std::iota(m.node_cell.begin(), m.node_cell.end(), 0);
  m.node_ncell.assign(N, 1);
  m.cell_v = std::move(tets);
  m.cell_node.resize(N);
  std::iota(m.cell_node.begin(), m.cell_node.end(), 0);
  m.cell_colour.assign(N, kRed);
  m.cell_new_red.assign(N, 1);
  build_faces(m);
  m.face_parent.assign(m.num_faces(), -1);
  m.face_sub.assign(m.num_faces(), -1);
  return m;
}

void build_faces(TetMesh& m) {
  const std::int32_t N = m.num_cells(), NV = m.num_vertices();
  const std::int64_t H = std::int64_t(N) * 4;
  require(H < (std::int64_t{1} << 31), "build_faces: too many cells (", N, ")");
  // bucket half-faces by their smallest vertex (counting sort)
  std::vector<std::int32_t> start(NV + 1, 0);
  auto sorted_face = [&](std::int32_t h) {
    std::array<std::int32_t, 3> k = m.half_face_vertices(h);
    if (k[0] > k[1]) std::swap(k[0], k[1]);
    if (k[1] > k[2]) std::swap(k[1], k[2]);
    if (k[0] > k[1]) std::swap(k[0], k[1]);
    return k;
  };
  for (std::int32_t h = 0; h < H; ++h) ++start[sorted_face(h)[0] + 1];
  for (std::int32_t v = 0; v < NV; ++v) start[v + 1] += start[v];
  std::vector<std::int32_t> order(H);
  {
    std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
    for (std::int32_t h = 0; h < H; ++h) order[fill[sorted_face(h)[0]]++] = h;
  }
  std::vector<std::int32_t> partner(H, -1);
  std::int64_t bad = -1;
#pragma omp parallel for schedule(dynamic, 4096)
  for (std::int32_t v = 0; v < NV; ++v) {
    const std::int32_t b = start[v], e = start[v + 1];
    if (e - b < 2) continue;
    // small bucket: sort by (second, third, half-face)
    std::vector<std::pair<std::int64_t, std::int32_t>> keys;
    keys.reserve(e - b);
    for (std::int32_t i = b; i < e; ++i) {
      const auto k = sorted_face(order[i]);
      keys.emplace_back((std::int64_t(k[1]) << 32) | std::uint32_t(k[2]), order[i]);
    }
    std::sort(keys.begin(), keys.end());
    for (std::size_t i = 0; i < keys.size();) {
      std::size_t j = i + 1;
      while (j < keys.size() && keys[j].first == keys[i].first) ++j;
      if (j - i == 2) {
        partner[keys[i].second] = keys[i + 1].second;
        partner[keys[i + 1].second] = keys[i].second;
      } else if (j - i > 2) {
#pragma omp critical
        bad = keys[i].second;
      }
      i = j;
    }
  }
  if (bad >= 0)
    fail("mesh is not conforming: a face of cell ", bad >> 2, " is shared by more than two cells");
  m.cell_face.assign(N, {-1, -1, -1, -1});
  m.face_half.clear();
  m.face_half.reserve(H / 2 + H / 8);
  for (std::int32_t h = 0; h < H; ++h) {
    const std::int32_t p = partner[h];
    if (p >= 0 && p < h) continue;
    const auto f = static_cast<std::int32_t>(m.face_half.size());
    m.face_half.push_back({h, p});
    m.cell_face[h >> 2][h & 3] = f;
    if (p >= 0) {
      m.cell_face[p >> 2][p & 3] = f;
      // the two cells must see the face with opposite orientations
      const auto a = m.half_face_vertices(h), b = m.half_face_vertices(p);
      // same cyclic order => same orientation => overlapping cells
      const bool same = (a[0] == b[0] && a[1] == b[1]) || (a[0] == b[1] && a[1] == b[2]) || (a[0] == b[2] && a[1] == b[0]);
      if (same) fail("mesh is not conforming: cells ", h >> 2, " and ", p >> 2, " overlap across a face");
    }
  }
}

void link_faces(TetMesh& m) {
  const std::int32_t N = m.num_cells();
  const std::int64_t H = std::int64_t(N) * 4;
  require(H < (std::int64_t{1} << 31), "mesh: too many cells (", N, ")");
  require(m.cell_face.size() == std::size_t(N), "mesh: cell_face has the wrong size");
  m.face_half.clear();
  m.face_half.reserve(H / 2 + H / 8);
  for (std::int32_t h = 0; h < H; ++h) {
    const std::int32_t f = m.cell_face[h >> 2][h & 3], next = m.num_faces();
    if (f == next) {
      m.face_half.push_back({h, -1});
      continue;
    }
    require(f >= 0 && f < next, "mesh: cell ", h >> 2, " names face ", f, " out of order (the next new face is ",
            next, ")");
    require(m.face_half[f][1] < 0, "mesh: face ", f, " is named by more than two cells");
    m.face_half[f][1] = h;
  }
  const auto sorted = [](std::array<std::int32_t, 3> k) {
    std::sort(k.begin(), k.end());
    return k;
  };
  const std::int32_t F = m.num_faces();
  std::vector<std::array<std::int32_t, 3>> open;  // corners of the faces of one cell
  for (std::int32_t f = 0; f < F; ++f)
    if (m.face_half[f][1] < 0) open.push_back(sorted(m.face_vertices(f)));
  std::sort(open.begin(), open.end());
  for (std::size_t i = 1; i < open.size(); ++i)
    require(open[i] != open[i - 1], "mesh: two faces of one cell each have the same corners (", open[i][0], ", ",
            open[i][1], ", ", open[i][2], ")");
  std::int64_t bad = -1;
#pragma omp parallel for schedule(static, 4096) reduction(max : bad)
  for (std::int32_t f = 0; f < F; ++f) {
    const std::int32_t h = m.face_half[f][0], p = m.face_half[f][1];
    if (p < 0) continue;
    const auto a = m.half_face_vertices(h), b = m.half_face_vertices(p);
    // the same corners, in the opposite cyclic order
    const bool opposite = (a[0] == b[0] && a[1] == b[2] && a[2] == b[1]) ||
                          (a[0] == b[1] && a[1] == b[0] && a[2] == b[2]) ||
                          (a[0] == b[2] && a[1] == b[1] && a[2] == b[0]);
    if (!opposite || std::binary_search(open.begin(), open.end(), sorted(a))) bad = std::max<std::int64_t>(bad, f);
  }
  require(bad < 0, "mesh: face ", bad, " is not the same triangle in opposite orientations in its two cells, or a face of one cell repeats its corners");
}

void check_mesh(const TetMesh& m) {
  const std::int32_t N = m.num_cells(), NV = m.num_vertices(), NN = m.num_nodes();
  require(m.vparent.size() == 2 * std::size_t(NV), "mesh: vparent has the wrong size");
  require(m.cell_node.size() == std::size_t(N) && m.cell_colour.size() == std::size_t(N) &&
              m.cell_new_red.size() == std::size_t(N),
          "mesh: cell arrays disagree in length");
  require(m.node_level.size() == std::size_t(NN) && m.node_parent.size() == std::size_t(NN) &&
              m.node_child.size() == std::size_t(NN) && m.node_cell.size() == std::size_t(NN) &&
              m.node_ncell.size() == std::size_t(NN),
          "mesh: tree arrays disagree in length");
  for (std::int32_t c = 0; c < N; ++c) {
    for (std::int32_t v : m.cell_v[c])
      require(v >= 0 && v < NV, "mesh: cell ", c, " has vertex ", v, " out of range");
    require(m.cell_volume6_lattice(c) > 0, "mesh: cell ", c, " is not positively oriented");
    const std::int32_t nd = m.cell_node[c];
    require(nd >= 0 && nd < NN, "mesh: cell ", c, " has node ", nd, " out of range");
    require(m.node_child[nd] < 0 && c >= m.node_cell[nd] && c < std::int64_t{m.node_cell[nd]} + m.node_ncell[nd],
            "mesh: cell ", c, " and node ", nd, " do not point at each other");
    require((m.node_ncell[nd] == 1) == (m.cell_colour[c] == kRed), "mesh: cell ", c,
            " has the wrong colour");
  }
  for (std::int32_t n = 0; n < NN; ++n) {
    const std::int32_t ch = m.node_child[n];
    if (ch >= 0) {
      require(std::int64_t{ch} + 8 <= NN && m.node_ncell[n] == 0, "mesh: node ", n, " has bad children");
      for (int k = 0; k < 8; ++k)
        require(m.node_parent[ch + k] == n && m.node_level[ch + k] == m.node_level[n] + 1,
                "mesh: node ", ch + k, " does not point back at its parent ", n);
    } else {
      require(m.node_ncell[n] >= 1 && m.node_ncell[n] <= 4, "mesh: leaf node ",
              n, " has ", int(m.node_ncell[n]), " cells");
    }
  }
  require(m.cell_face.size() == std::size_t(N), "mesh: cell_face has the wrong size");
  for (std::int32_t f = 0; f < m.num_faces(); ++f) {
    for (int k = 0; k < 2; ++k) {
      const std::int32_t h = m.face_half[f][k];
      if (k == 1 && h < 0) continue;
      require(h >= 0 && (h >> 2) < N && m.cell_face[h >> 2][h & 3] == f, "mesh: face ", f,
              " and its cells do not point at each other");
    }
  }
}

}  // namespace tetmvs::tet
