// Tests of the cut surface's topology (common/cut/surface.h): inside sets that touch
// themselves along an edge or at a vertex must still give a closed surface in which every
// edge has exactly two triangles used in opposite directions and every vertex has one fan
// that is a disk, oriented outward (signed volume = inside volume).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>

#include "common/cut/cleanup.h"
#include "common/cut/surface.h"
#include "common/tetmesh/refine.h"
#include "common/tetmesh/tetmesh.h"
#include "common/trimesh/check.h"
#include "cube_mesh.h"

using namespace tetmvs;
using namespace tetmvs::cut;

namespace {

using test::cube_mesh;

struct SurfaceTopology {
  std::int64_t edges = 0;
  std::int64_t edges_not_two = 0;     // edges with other than two triangles
  std::int64_t misoriented = 0;       // two triangles using an edge in the same direction
  std::int64_t vertices_not_disk = 0; // fan not one cycle of triangles around distinct neighbours
  std::int64_t unused_vertices = 0;
  int euler = 0;
};

// Independent of check_mesh: counts per undirected edge, and per vertex the link (for each
// triangle (v, a, b) in its order the link edge a -> b) must be one simple cycle.
SurfaceTopology surface_topology(const TriMesh& s) {
  SurfaceTopology r;
  std::map<std::pair<int, int>, std::pair<int, int>> edge;  // (lo, hi) -> (lo->hi uses, hi->lo uses)
  std::vector<std::vector<std::pair<int, int>>> link(s.nv());
  for (const auto& f : s.F)
    for (int k = 0; k < 3; ++k) {
      const int a = f[k], b = f[(k + 1) % 3], c = f[(k + 2) % 3];
      auto& e = edge[{std::min(a, b), std::max(a, b)}];
      (a < b ? e.first : e.second) += 1;
      link[a].push_back({b, c});
    }
  r.edges = static_cast<std::int64_t>(edge.size());
  for (const auto& [k, e] : edge) {
    r.edges_not_two += e.first + e.second != 2;
    r.misoriented += e.first + e.second == 2 && e.first != 1;
  }
  for (std::size_t v = 0; v < s.nv(); ++v) {
    const auto& l = link[v];
    if (l.empty()) {
      ++r.unused_vertices;
      continue;
    }
    std::map<int, int> next;
    bool ok = true;
    for (const auto& [a, b] : l) ok = ok && next.emplace(a, b).second;  // each neighbour once as a start
    int steps = 0;
    int x = l[0].first;
    do {
      const auto it = next.find(x);
      if (it == next.end()) {
        ok = false;
        break;
      }
      x = it->second;
      ++steps;
    } while (x != l[0].first && steps <= static_cast<int>(l.size()));
    ok = ok && steps == static_cast<int>(l.size());
    r.vertices_not_disk += !ok;
  }
  r.euler = static_cast<int>(static_cast<std::int64_t>(s.nv()) - r.edges + static_cast<std::int64_t>(s.nf()));
  return r;
}

double inside_volume(const tet::TetMesh& m, const std::vector<std::uint8_t>& inside) {
  double v = 0;
  for (std::int32_t c = 0; c < m.num_cells(); ++c)
    if (inside[c]) v += m.cell_volume(c);
  return v;
}

double cut_area(const tet::TetMesh& m, const std::vector<std::uint8_t>& inside) {
  double a = 0;
  for (std::int32_t f = 0; f < m.num_faces(); ++f) {
    const std::int32_t x = m.face_cell(f, 0), y = m.face_cell(f, 1);
    if ((x >= 0 && inside[x]) != (y >= 0 && inside[y])) a += m.face_area(f);
  }
  return a;
}

// Everything a valid cut surface must satisfy; the Euler characteristic is returned.
int expect_valid(const tet::TetMesh& m, const std::vector<std::uint8_t>& inside, const TriMesh& s,
                 const std::string& what) {
  const SurfaceTopology t = surface_topology(s);
  EXPECT_EQ(t.edges_not_two, 0) << what;
  EXPECT_EQ(t.misoriented, 0) << what;
  EXPECT_EQ(t.vertices_not_disk, 0) << what;
  EXPECT_EQ(t.unused_vertices, 0) << what;
  const MeshCheck chk = check_mesh(s);
  EXPECT_TRUE(chk.closed && chk.edge_manifold && chk.oriented) << what;
  EXPECT_EQ(chk.degenerate_faces, 0) << what;
  for (const auto& c : chk.components) {  // closed orientable surfaces
    EXPECT_EQ(c.euler % 2, 0) << what;
    EXPECT_LE(c.euler, 2) << what;
  }
  const double vol = inside_volume(m, inside);
  EXPECT_NEAR(signed_volume(s), vol, 1e-9 * std::max(1.0, vol)) << what;
  EXPECT_NEAR(total_area(s), cut_area(m, inside), 1e-9) << what;
  return t.euler;
}

std::vector<std::int32_t> shared_vertices(const tet::TetMesh& m, std::int32_t a, std::int32_t b) {
  std::vector<std::int32_t> s;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (m.cell_v[a][i] == m.cell_v[b][j]) s.push_back(m.cell_v[a][i]);
  return s;
}

// An edge far from the domain boundary whose ring has `n` cells, and its ring in rotation
// order (consecutive cells share a face).
std::vector<std::int32_t> interior_ring(const tet::TetMesh& m, std::size_t n) {
  std::map<std::pair<std::int32_t, std::int32_t>, std::vector<std::int32_t>> cells_of_edge;
  for (std::int32_t c = 0; c < m.num_cells(); ++c)
    for (const auto& e : tet::kEdge) {
      const std::int32_t a = m.cell_v[c][e[0]], b = m.cell_v[c][e[1]];
      cells_of_edge[{std::min(a, b), std::max(a, b)}].push_back(c);
    }
  for (const auto& [e, cells] : cells_of_edge) {
    if (cells.size() != n) continue;
    if ((m.vertex(e.first).cwiseAbs().maxCoeff() > 0.5) || (m.vertex(e.second).cwiseAbs().maxCoeff() > 0.5)) continue;
    std::vector<std::int32_t> ring{cells[0]};
    std::vector<std::uint8_t> used(n, 0);
    used[0] = 1;
    while (ring.size() < n) {
      bool found = false;
      for (std::size_t i = 0; i < n && !found; ++i)
        if (!used[i] && shared_vertices(m, ring.back(), cells[i]).size() == 3) {
          used[i] = 1;
          ring.push_back(cells[i]);
          found = true;
        }
      if (!found) break;
    }
    if (ring.size() == n) return ring;
  }
  return {};
}

}  // namespace

TEST(CutSurface, TwoCellsSharingOnlyAnEdgeGiveTwoTetrahedra) {
  const auto m = cube_mesh(3, 0);
  const auto ring = interior_ring(m, 4);
  ASSERT_EQ(ring.size(), 4u);
  std::vector<std::uint8_t> inside(m.num_cells(), 0);
  inside[ring[0]] = inside[ring[2]] = 1;
  ASSERT_EQ(shared_vertices(m, ring[0], ring[2]).size(), 2u);
  SurfaceStats st;
  const TriMesh s = cut_surface(m, inside, &st);
  EXPECT_EQ(s.nf(), 8u);
  EXPECT_EQ(s.nv(), 8u);
  EXPECT_EQ(st.split_vertices, 2);  // the shared edge's two ends
  EXPECT_EQ(st.nonmanifold_edges, 0);
  EXPECT_EQ(st.split_edges, 0);
  EXPECT_EQ(expect_valid(m, inside, s, "edge"), 4);  // two spheres
  EXPECT_EQ(check_mesh(s).components.size(), 2u);
}

TEST(CutSurface, TwoCellsSharingOnlyAVertexGiveTwoTetrahedra) {
  const auto m = cube_mesh(3, 0);
  std::int32_t a = -1, b = -1;
  for (std::int32_t c = 0; c < m.num_cells() && a < 0; ++c)
    for (std::int32_t d = c + 1; d < m.num_cells(); ++d)
      if (shared_vertices(m, c, d).size() == 1) {
        a = c;
        b = d;
        break;
      }
  ASSERT_GE(a, 0);
  std::vector<std::uint8_t> inside(m.num_cells(), 0);
  inside[a] = inside[b] = 1;
  SurfaceStats st;
  const TriMesh s = cut_surface(m, inside, &st);
  EXPECT_EQ(s.nf(), 8u);
  EXPECT_EQ(s.nv(), 8u);
  EXPECT_EQ(st.split_vertices, 1);
  EXPECT_EQ(expect_valid(m, inside, s, "vertex"), 4);
}

// The whole domain inside except two cells of one edge ring that share only that edge: the
// inside touches itself along the edge (its two other ring cells) and is connected around
// both ends, so gluing through the inside runs gives both gluings the same copies of the two
// ends. Re-gluing through the outside separates the two cavities: outer box + two tetrahedra.
TEST(CutSurface, BlockPinchedAlongAnEdgeIsRegluedIntoSeparateCavities) {
  const auto m = cube_mesh(3, 0);
  const auto ring = interior_ring(m, 4);
  ASSERT_EQ(ring.size(), 4u);
  std::vector<std::uint8_t> inside(m.num_cells(), 1);
  inside[ring[1]] = inside[ring[3]] = 0;
  SurfaceStats st;
  const TriMesh s = cut_surface(m, inside, &st);
  EXPECT_EQ(st.nonmanifold_edges, 1);
  EXPECT_EQ(st.repaired_edges, 1);
  EXPECT_EQ(st.split_edges, 0);
  EXPECT_EQ(st.split_vertices, 2);
  EXPECT_EQ(s.nf(), static_cast<std::size_t>(st.faces));
  EXPECT_EQ(expect_valid(m, inside, s, "edge pinch"), 6);
  EXPECT_EQ(check_mesh(s).components.size(), 3u);
}

// Without the re-gluing the shared edge is split at its midpoint instead: the two cavities
// stay one sphere through the edge's ends.
TEST(CutSurface, BlockPinchedAlongAnEdgeIsSplitAtAMidpointWithoutReglueing) {
  const auto m = cube_mesh(3, 0);
  const auto ring = interior_ring(m, 4);
  ASSERT_EQ(ring.size(), 4u);
  std::vector<std::uint8_t> inside(m.num_cells(), 1);
  inside[ring[1]] = inside[ring[3]] = 0;
  SurfaceStats st;
  std::vector<std::int32_t> ids;
  const TriMesh s = cut_surface(m, inside, &st, &ids, {false});
  EXPECT_EQ(st.nonmanifold_edges, 1);
  EXPECT_EQ(st.repaired_edges, 0);
  EXPECT_EQ(st.split_edges, 1);
  EXPECT_EQ(st.split_vertices, 0);
  EXPECT_EQ(s.nf(), static_cast<std::size_t>(st.faces) + 2);  // two triangles split in two
  EXPECT_EQ(ids.size(), s.nf());
  EXPECT_EQ(expect_valid(m, inside, s, "edge pinch, split"), 4);
  EXPECT_EQ(check_mesh(s).components.size(), 2u);
}

// A six-cell ring with every other cell outside: three cavities meeting along one edge.
TEST(CutSurface, ThreeCavitiesAlongOneEdgeAreSeparated) {
  const auto m = cube_mesh(3, 0);
  const auto ring = interior_ring(m, 6);
  ASSERT_EQ(ring.size(), 6u);
  std::vector<std::uint8_t> inside(m.num_cells(), 1);
  inside[ring[1]] = inside[ring[3]] = inside[ring[5]] = 0;
  for (const bool repair : {true, false}) {
    SurfaceStats st;
    const TriMesh s = cut_surface(m, inside, &st, nullptr, {repair});
    EXPECT_EQ(st.nonmanifold_edges, 2);  // three gluings with the same two copies
    const int euler = expect_valid(m, inside, s, repair ? "three, repair" : "three, split");
    if (repair) {
      EXPECT_EQ(st.split_edges, 0);
      EXPECT_EQ(euler, 8);  // box + three tetrahedra
      EXPECT_EQ(check_mesh(s).components.size(), 4u);
    } else {
      EXPECT_EQ(st.split_edges, 2);
      EXPECT_EQ(euler, 4);
    }
  }
}

// The same with the inside and outside swapped: three tetrahedra meeting along one edge are
// separate from the start (gluing through the inside runs), nothing to repair.
TEST(CutSurface, ThreeCellsAlongOneEdgeAreSeparateSheets) {
  const auto m = cube_mesh(3, 0);
  const auto ring = interior_ring(m, 6);
  ASSERT_EQ(ring.size(), 6u);
  std::vector<std::uint8_t> inside(m.num_cells(), 0);
  inside[ring[0]] = inside[ring[2]] = inside[ring[4]] = 1;
  SurfaceStats st;
  const TriMesh s = cut_surface(m, inside, &st);
  EXPECT_EQ(st.nonmanifold_edges, 0);
  EXPECT_EQ(st.split_vertices, 4);
  EXPECT_EQ(expect_valid(m, inside, s, "three cells"), 6);
}

// Random inside sets (many pinches of every kind, cells on the domain boundary, green cells
// of a refined mesh) with and without re-gluing: always a valid closed manifold surface.
TEST(CutSurface, RandomInsideSetsGiveClosedManifoldOutwardSurfaces) {
  const tet::TetMesh coarse = cube_mesh(2, 0);
  std::vector<std::uint8_t> active(coarse.num_cells(), 0);
  for (std::int32_t c = 0; c < coarse.num_cells(); ++c) active[c] = coarse.cell_centroid(c).x() < 0;
  const tet::TetMesh meshes[2] = {coarse, tet::refine(coarse, active)};  // red and green cells
  ASSERT_GT(std::count(meshes[1].cell_colour.begin(), meshes[1].cell_colour.end(), tet::kGreen), 0);
  std::mt19937 rng(7);
  std::int64_t repaired = 0, split = 0, pinched = 0;
  for (const auto& m : meshes)
    for (int trial = 0; trial < 16; ++trial) {
      std::vector<std::uint8_t> inside(m.num_cells());
      const double p = 0.2 + 0.6 * (trial % 4) / 3.0;
      std::bernoulli_distribution in(p);
      for (auto& x : inside) x = in(rng);
      if (std::count(inside.begin(), inside.end(), 1) == 0) inside[0] = 1;
      for (const bool repair : {true, false}) {
        SurfaceStats st;
        std::vector<std::int32_t> ids;
        const TriMesh s = cut_surface(m, inside, &st, &ids, {repair});
        expect_valid(m, inside, s, "random trial " + std::to_string(trial));
        EXPECT_EQ(ids.size(), s.nf());
        EXPECT_EQ(s.nf(), static_cast<std::size_t>(st.faces + 2 * st.split_edges));  // a split adds one triangle on either side
        repaired += st.repaired_edges;
        split += st.split_edges;
        pinched += st.nonmanifold_edges;
      }
    }
  // the random sets must actually exercise both repairs
  EXPECT_GT(pinched, 20);
  EXPECT_GT(repaired, 10);
  EXPECT_GT(split, 10);
}

// clean_up_regions (common/cut/cleanup.h): an enclosed void becomes inside even when it holds
// an exterior label (counted), a void open to the mesh boundary stays, an unseeded speck is
// removed and a seeded one kept. The surface afterwards is one closed shell of positive volume.
TEST(CutCleanup, FillsEnclosedVoidsRemovesSpecks) {
  const tet::TetMesh m = cube_mesh(6, 0);
  const std::int32_t C = m.num_cells();
  const auto centre = [&](std::int32_t c) {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) x += m.vertex(m.cell_v[c][k]);
    return Eigen::Vector3d(x / 4);
  };
  std::vector<std::uint8_t> inside(C, 0);
  std::vector<std::int8_t> labels(C, 0);
  std::int32_t void_cell = -1, speck_cell = -1, seeded_speck = -1;
  for (std::int32_t c = 0; c < C; ++c) {
    const Eigen::Vector3d x = centre(c);
    const double r = (x - Eigen::Vector3d(-0.2, 0, 0)).norm();
    inside[c] = r < 0.6 && r > 0.2;  // a thick shell around an enclosed void
    if (r <= 0.2 && void_cell < 0) void_cell = c;
    if (inside[c] && labels[c] == 0 && r > 0.4) labels[c] = 1;  // seeds in the shell
  }
  ASSERT_GE(void_cell, 0);
  labels[void_cell] = -1;  // free-space evidence inside the enclosed void
  // two one-cell specks far from the shell, one with an interior label
  for (std::int32_t c = 0; c < C && (speck_cell < 0 || seeded_speck < 0); ++c) {
    const Eigen::Vector3d x = centre(c);
    if (x.x() > 0.75 && std::abs(x.y()) < 0.5 && std::abs(x.z()) < 0.5) {
      bool isolated = true;
      for (int j = 0; j < 4; ++j) {
        const std::int32_t d = m.neighbour(c, j);
        isolated = isolated && (d < 0 || (!inside[d] && d != speck_cell));
        for (int q = 0; d >= 0 && q < 4; ++q) isolated = isolated && m.neighbour(d, q) != speck_cell;
      }
      if (!isolated) continue;
      if (speck_cell < 0) {
        speck_cell = c;
      } else {
        seeded_speck = c;
        labels[c] = 1;
      }
      inside[c] = 1;
    }
  }
  ASSERT_GE(speck_cell, 0);
  ASSERT_GE(seeded_speck, 0);
  std::vector<std::uint8_t> before = inside;
  const CleanupStats st = clean_up_regions(m, labels, inside, 0.01);
  EXPECT_EQ(st.voids_filled, 1);
  EXPECT_GT(st.void_cells, 0);
  EXPECT_EQ(st.void_exterior_cells, 1);
  EXPECT_EQ(inside[void_cell], 1);
  EXPECT_EQ(st.specks_removed, 1);
  EXPECT_EQ(inside[speck_cell], 0);
  EXPECT_EQ(inside[seeded_speck], 1);
  EXPECT_EQ(st.inside_regions, 2);
  // Outside cells connected to the boundary are untouched.
  for (std::int32_t c = 0; c < C; ++c)
    if (!before[c] && c != void_cell && centre(c).norm() > 0.9) {
      EXPECT_EQ(inside[c], 0);
    }
  const TriMesh s = cut_surface(m, inside);
  const SurfaceTopology t = surface_topology(s);
  EXPECT_EQ(t.edges_not_two, 0);
  EXPECT_EQ(t.euler, 4);  // two spheres: the filled ball and the seeded speck
}
