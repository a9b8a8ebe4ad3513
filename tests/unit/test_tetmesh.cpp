// Tests of the adaptive BCC mesh: M0, red-green refinement, conformity, hierarchy.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <random>
#include <set>

#include "common/tetmesh/locate.h"
#include "common/tetmesh/refine.h"
#include "common/tetmesh/tetmesh.h"

using namespace tetmvs::tet;

namespace {

Lattice test_lattice(int nx = 4, int ny = 3, int nz = 3) {
  Lattice lat;
  lat.origin = Eigen::Vector3d(-0.3, 0.2, 1.1);
  lat.h = 0.37;
  lat.dims = {nx, ny, nz};
  return lat;
}

std::vector<std::int64_t> sorted_sq_edges(const TetMesh& m, const Tet& t) {
  std::vector<std::int64_t> e;
  for (int k = 0; k < 6; ++k) {
    const I3 d = m.vint(t[kEdge[k][0]]) - m.vint(t[kEdge[k][1]]);
    e.push_back(d.x * d.x + d.y * d.y + d.z * d.z);
  }
  std::sort(e.begin(), e.end());
  return e;
}

// A BCC tet of the level-l lattice: two opposite axis-aligned perpendicular edges of length
// s = 2^(16-l), one on the grid Z*s, the other on the grid Z*s + s/2; four edges s*sqrt(3)/2.
bool is_bcc_tet(const TetMesh& m, const Tet& t, int l) {
  const std::int64_t s = std::int64_t{1} << (kLatticeBits - l);
  static const int opp[3][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2}};
  auto axis_edge = [&](const I3& a, const I3& b, int& axis) {
    const I3 d = b - a;
    const int nz = (d.x != 0) + (d.y != 0) + (d.z != 0);
    if (nz != 1) return false;
    axis = d.x != 0 ? 0 : d.y != 0 ? 1 : 2;
    return std::llabs(d.x + d.y + d.z) == s;
  };
  auto on_grid = [&](const I3& p, std::int64_t off) {
    return (p.x - off) % s == 0 && (p.y - off) % s == 0 && (p.z - off) % s == 0;
  };
  for (const auto& o : opp) {
    const I3 a = m.vint(t[o[0]]), b = m.vint(t[o[1]]), c = m.vint(t[o[2]]), d = m.vint(t[o[3]]);
    int ax1, ax2;
    if (!axis_edge(a, b, ax1) || !axis_edge(c, d, ax2) || ax1 == ax2) continue;
    const bool g1 = on_grid(a, 0) && on_grid(b, 0) && on_grid(c, s / 2) && on_grid(d, s / 2);
    const bool g2 = on_grid(a, s / 2) && on_grid(b, s / 2) && on_grid(c, 0) && on_grid(d, 0);
    if (!g1 && !g2) continue;
    const auto e = sorted_sq_edges(m, t);
    const std::int64_t q = 3 * s * s / 4;
    return e[0] == q && e[1] == q && e[2] == q && e[3] == q && e[4] == s * s && e[5] == s * s;
  }
  return false;
}

double total_volume(const TetMesh& m) {
  // compensated sum: half a million terms would otherwise lose ~1e-11 in the sum itself
  double v = 0, comp = 0;
  for (std::int32_t c = 0; c < m.num_cells(); ++c) {
    const double y = m.cell_volume(c) - comp, t = v + y;
    comp = (t - v) - y;
    v = t;
  }
  return v;
}

double domain_volume(const TetMesh& m) { return m.num_level0 * std::pow(m.lat.h, 3) / 12.0; }

// Sum of boundary face areas against the ghost pyramid sides: 4 triangles of area
// h^2 / (2 sqrt 2) per boundary square of the cube grid.
void expect_boundary_area(const TetMesh& m) {
  double area = 0;
  for (std::int32_t f = 0; f < m.num_faces(); ++f)
    if (m.face_on_boundary(f)) area += m.face_area(f);
  const auto& d = m.lat.dims;
  const double squares = 2.0 * (d[0] * d[1] + d[1] * d[2] + d[0] * d[2]);
  // along the grid edges two pyramids of one cube share a side, which is not a face
  const double sides = 4 * squares - 8.0 * (d[0] + d[1] + d[2]);
  const double expect = sides * m.lat.h * m.lat.h / (2 * std::sqrt(2.0));
  EXPECT_NEAR(area / expect, 1.0, 1e-12);
}

void expect_valid(const TetMesh& m) {
  ASSERT_NO_THROW(check_conforming(m));
  EXPECT_NEAR(total_volume(m) / domain_volume(m), 1.0, 1e-12);
  expect_boundary_area(m);
  // every interior face in exactly two cells with opposite orientation, and the face
  // normal points from its first cell out
  for (std::int32_t f = 0; f < m.num_faces(); ++f) {
    const Eigen::Vector3d n = m.face_normal(f), c = m.face_centroid(f);
    EXPECT_GT(n.dot(c - m.cell_centroid(m.face_cell(f, 0))), 0.0);
    if (!m.face_on_boundary(f)) {
      EXPECT_LT(n.dot(c - m.cell_centroid(m.face_cell(f, 1))), 0.0);
    }
  }
}

}  // namespace

TEST(TetMesh, PerturbationIsGeneric) {
  // no integer direction with components up to 64 is orthogonal to kSoS1, kSoS2 or
  // kSoS1 x kSoS2 (face normals and edge directions of the mesh are such directions)
  const I3 v1 = kSoS1, v2 = kSoS2;
  const i128 w[3] = {i128(v1.y) * v2.z - i128(v1.z) * v2.y, i128(v1.z) * v2.x - i128(v1.x) * v2.z,
                     i128(v1.x) * v2.y - i128(v1.y) * v2.x};
  int zero = 0;
  for (int x = -64; x <= 64; ++x)
    for (int y = -64; y <= 64; ++y)
      for (int z = -64; z <= 64; ++z) {
        if (!x && !y && !z) continue;
        zero += (x * v1.x + y * v1.y + z * v1.z) == 0;
        zero += (x * v2.x + y * v2.y + z * v2.z) == 0;
        zero += (w[0] * x + w[1] * y + w[2] * z) == 0;
      }
  EXPECT_EQ(zero, 0);
}

TEST(TetMesh, LatticeCoversBox) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-1, 0, 2), Eigen::Vector3d(1, 0.5, 3));
  const Lattice lat = lattice_for_box(box, 16);
  EXPECT_DOUBLE_EQ(lat.h, 2.0 / 16);
  EXPECT_EQ(lat.dims[0], 18);
  EXPECT_EQ(lat.dims[1], 6);
  EXPECT_EQ(lat.dims[2], 10);
  const TetMesh m = build_bcc(lat);
  // every point of the box is in a cell (the ghost pyramids stay outside the box)
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> U(0, 1);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d p = box.min() + box.sizes().cwiseProduct(Eigen::Vector3d(U(rng), U(rng), U(rng)));
    ASSERT_GE(locate(m, p), 0) << p.transpose();
  }
  for (int k = 0; k < 8; ++k) ASSERT_GE(locate(m, box.corner(Eigen::AlignedBox3d::CornerType(k))), 0);
}

TEST(TetMesh, Level0IsCongruentBcc) {
  const TetMesh m = build_bcc(test_lattice());
  const int nx = 4, ny = 3, nz = 3;
  EXPECT_EQ(m.num_cells(), 4 * ((nx - 1) * ny * nz + nx * (ny - 1) * nz + nx * ny * (nz - 1)));
  EXPECT_EQ(m.num_vertices(), (nx + 1) * (ny + 1) * (nz + 1) - 8 + nx * ny * nz);
  const auto ref = sorted_sq_edges(m, m.cell_v[0]);
  for (std::int32_t c = 0; c < m.num_cells(); ++c) {
    EXPECT_EQ(sorted_sq_edges(m, m.cell_v[c]), ref);
    EXPECT_TRUE(is_bcc_tet(m, m.cell_v[c], 0));
    EXPECT_EQ(m.cell_new_red[c], 1);
    EXPECT_EQ(m.cell_colour[c], kRed);
  }
  EXPECT_NEAR(m.cell_volume(0), std::pow(0.37, 3) / 12, 1e-15);
  expect_valid(m);
  // faces: 4 per cell, interior counted twice
  std::int32_t boundary = 0;
  for (std::int32_t f = 0; f < m.num_faces(); ++f) boundary += m.face_on_boundary(f);
  EXPECT_EQ(2 * m.num_faces() - boundary, 4 * m.num_cells());
  EXPECT_EQ(boundary, 8 * (nx * ny + ny * nz + nx * nz) - 8 * (nx + ny + nz));
}

TEST(TetMesh, UniformRefinementIsFinerBcc) {
  const TetMesh m0 = build_bcc(test_lattice(3, 2, 2));
  TetMesh m = m0;
  for (int k = 1; k <= 2; ++k) {
    RefineStats st;
    m = refine(m, std::vector<std::uint8_t>(m.num_cells(), 1), &st);
    EXPECT_EQ(m.num_cells(), m0.num_cells() * (k == 1 ? 8 : 64));
    EXPECT_EQ(st.green_cells, 0);
    EXPECT_EQ(st.red_closure, 0);
    std::set<std::array<std::int32_t, 4>> seen;
    for (std::int32_t c = 0; c < m.num_cells(); ++c) {
      ASSERT_TRUE(is_bcc_tet(m, m.cell_v[c], k)) << "cell " << c;
      EXPECT_EQ(m.node_level[m.cell_node[c]], k);
      auto t = m.cell_v[c];
      std::sort(t.begin(), t.end());
      EXPECT_TRUE(seen.insert(t).second);
    }
    expect_valid(m);
  }
}

TEST(TetMesh, RedChildrenHaveParentShapeAtHalfSize) {
  TetMesh m = build_bcc(test_lattice(2, 2, 3));
  m = refine_uniform(m, 2);
  for (std::int32_t n = 0; n < m.num_nodes(); ++n) {
    if (m.node_child[n] < 0) continue;
    auto pe = sorted_sq_edges(m, m.node_v[n]);
    for (auto& e : pe) e /= 4;
    const double pv = double(m.cell_volume6_lattice(0));  // unused placeholder
    (void)pv;
    for (int k = 0; k < 8; ++k) {
      const std::int32_t ch = m.node_child[n] + k;
      EXPECT_EQ(sorted_sq_edges(m, m.node_v[ch]), pe);
      const Tet& t = m.node_v[ch];
      const I3 a = m.vint(t[0]);
      const i128 v6 = det3_exact(m.vint(t[1]) - a, m.vint(t[2]) - a, m.vint(t[3]) - a);
      const Tet& p = m.node_v[n];
      const I3 b = m.vint(p[0]);
      const i128 p6 = det3_exact(m.vint(p[1]) - b, m.vint(p[2]) - b, m.vint(p[3]) - b);
      EXPECT_TRUE(v6 * 8 == p6);
    }
  }
}

// Random sequences of refinement, with active green cells: conforming at every step, the
// face parents are right, the new-red flags are right.
TEST(TetMesh, RandomRefinementStaysConforming) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 3; ++trial) {
    TetMesh m = build_bcc(test_lattice(3, 3, 2));
    std::uniform_real_distribution<double> U(-0.3, 0.3);
    const Eigen::Vector3d p = m.lat.grid_box().center() + Eigen::Vector3d(U(rng), U(rng), U(rng));
    for (int level = 1; level <= 4; ++level) {
      std::vector<std::uint8_t> act(m.num_cells(), 0);
      // activate a few cells, including green ones, clustered around a point
      std::bernoulli_distribution coin(0.3);
      for (std::int32_t c = 0; c < m.num_cells(); ++c)
        act[c] = (m.cell_centroid(c) - p).norm() < 0.35 && coin(rng);
      RefineStats st;
      const TetMesh old = m;
      m = refine(old, act, &st);
      ASSERT_EQ(m.level, level);
      expect_valid(m);
      // every active cell's region is now finer: the cell holding its centroid is smaller
      for (std::int32_t c = 0; c < old.num_cells(); ++c) {
        if (!act[c]) continue;
        const std::int32_t d = locate(m, old.cell_centroid(c));
        ASSERT_GE(d, 0);
        EXPECT_LT(m.cell_volume(d), old.cell_volume(c) * 0.99);
      }
      // new-red flag: exactly the cells whose node is new
      for (std::int32_t c = 0; c < m.num_cells(); ++c)
        EXPECT_EQ(m.cell_new_red[c], m.cell_node[c] >= old.num_nodes() ? 1 : 0);
      // face parents: the new face lies in the old face (area ratios 1, 1/4, or a part)
      std::int64_t whole = 0, quarter = 0, part = 0, none = 0;
      for (std::int32_t f = 0; f < m.num_faces(); ++f) {
        const std::int32_t g = m.face_parent[f];
        if (g < 0) {
          ++none;
          // no old face contains it: its centroid is not on an old face of the old cell
          // holding it (checked through areas: an interior face is never an old face)
          continue;
        }
        const double r = m.face_area(f) / old.face_area(g);
        const Eigen::Vector3d n = old.face_normal(g);
        for (std::int32_t v : m.face_vertices(f))
          EXPECT_NEAR(n.dot(m.vertex(v) - old.face_centroid(g)), 0.0, 1e-12);
        if (m.face_sub[f] == kSubWhole) {
          ++whole;
          EXPECT_NEAR(r, 1.0, 1e-12);
        } else if (m.face_sub[f] >= 0) {
          ++quarter;
          EXPECT_NEAR(r, 0.25, 1e-12);
          const Eigen::Vector3d expect =
              m.face_sub[f] == 3 ? old.face_centroid(g)
                                 : (old.face_centroid(g) + old.vertex(old.face_vertices(g)[m.face_sub[f]])) / 2;
          EXPECT_NEAR((m.face_centroid(f) - expect).norm(), 0.0, 1e-12);
        } else {
          ++part;
          EXPECT_LT(r, 0.999);
        }
      }
      EXPECT_GT(whole, 0);
      EXPECT_GT(quarter, 0);
      EXPECT_GT(none, 0);
      (void)part;
      // old faces are covered: sum of areas of new faces with parent g == area of g
      std::vector<double> cover(old.num_faces(), 0.0);
      for (std::int32_t f = 0; f < m.num_faces(); ++f)
        if (m.face_parent[f] >= 0) cover[m.face_parent[f]] += m.face_area(f);
      for (std::int32_t g = 0; g < old.num_faces(); ++g) {
        // a face of an old green cell can be crossed by the new green closure (then part of
        // it has no parent); every other old face is tiled exactly
        const bool green_side = old.cell_colour[old.face_cell(g, 0)] == kGreen ||
                                (!old.face_on_boundary(g) && old.cell_colour[old.face_cell(g, 1)] == kGreen);
        if (!green_side) {
          EXPECT_NEAR(cover[g] / old.face_area(g), 1.0, 1e-12) << "face " << g;
        }
        else EXPECT_LE(cover[g] / old.face_area(g), 1.0 + 1e-12);
      }
    }
    EXPECT_GT(m.max_cell_level(), 1);
  }
}

TEST(TetMesh, SphereShellStaysConformingAndAdaptive) {
  // refine toward a sphere shell 4 times; report the count against a uniform mesh
  Lattice lat = lattice_for_box(Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1)), 6);
  TetMesh m = build_bcc(lat);
  const int levels = 4;
  const double R = 0.7;
  for (int l = 0; l < levels; ++l) {
    std::vector<std::uint8_t> act(m.num_cells(), 0);
    for (std::int32_t c = 0; c < m.num_cells(); ++c) {
      double lo = 1e30, hi = 0;
      for (std::int32_t v : m.cell_v[c]) {
        const double r = m.vertex(v).norm();
        lo = std::min(lo, r), hi = std::max(hi, r);
      }
      // the vertices straddle the sphere, or the cell is close to it
      act[c] = (lo <= R && hi >= R) || std::abs(m.cell_centroid(c).norm() - R) < 0.3 * lat.h / (1 << l);
      act[c] = act[c] && m.node_level[m.cell_node[c]] == l;
    }
    m = refine(m, act);
  }
  expect_valid(m);
  EXPECT_EQ(m.max_cell_level(), levels);
  const double uniform = double(m.num_level0) * std::pow(8.0, levels);
  std::printf("[ sphere   ] %d levels: %d cells, uniform %.0f (%.1f%%)\n", levels, m.num_cells(), uniform,
              100.0 * m.num_cells() / uniform);
  EXPECT_LT(m.num_cells(), 0.3 * uniform);
  // the finest cells are all near the shell
  for (std::int32_t c = 0; c < m.num_cells(); ++c)
    if (m.node_level[m.cell_node[c]] == levels) {
      EXPECT_NEAR(m.cell_centroid(c).norm(), R, 0.6 * lat.h);
    }
}

// The green closure must stay local: random sparse active cells make only a few extra red
// refinements (with only the 1:2 / 1:4 patterns the whole mesh would be refined).
TEST(TetMesh, ClosureStaysLocal) {
  Lattice lat;
  lat.dims = {8, 8, 8};
  const TetMesh m = build_bcc(lat);
  std::mt19937 rng(11);
  std::int64_t active = 0, extra = 0;
  int max_rounds = 0;
  for (int trial = 0; trial < 10; ++trial) {
    std::vector<std::uint8_t> act(m.num_cells(), 0);
    const Eigen::Vector3d p(4, 4, 4);
    for (std::int32_t c = 0; c < m.num_cells(); ++c)
      act[c] = (m.cell_centroid(c) - p).norm() < 2.0 && rng() % 4 == 0;
    RefineStats st;
    const TetMesh r = refine(m, act, &st);
    active += st.red_active;
    extra += st.red_closure;
    max_rounds = std::max(max_rounds, st.rounds);
  }
  std::printf("[ closure  ] %ld active cells -> %ld extra red by closure, <= %d passes\n", long(active),
              long(extra), max_rounds);
  EXPECT_LT(extra, 4 * active);
  EXPECT_LE(max_rounds, 8);
}
