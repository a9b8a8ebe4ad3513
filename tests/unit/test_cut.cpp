// Tests of the graph cut (Eq. 1, the dual graph, BK max-flow) and of the cut surface.
#include <gtest/gtest.h>

#include <cmath>

#include "common/cut/face_cost.h"
#include "common/cut/graph_cut.h"
#include "common/cut/surface.h"
#include "common/tetmesh/refine.h"
#include "common/tetmesh/tetmesh.h"
#include "common/trimesh/check.h"
#include "cube_mesh.h"

using namespace tetmvs;
using namespace tetmvs::cut;

namespace {

using test::cube_mesh;

// Exterior: cells with a boundary face; interior: the cell containing the origin.
std::vector<std::int8_t> seed_labels(const tet::TetMesh& m) {
  std::vector<std::int8_t> lab(m.num_cells(), kFree);
  for (std::int32_t f = 0; f < m.num_faces(); ++f)
    if (m.face_on_boundary(f)) lab[m.face_cell(f, 0)] = kExterior;
  double best = 1e9;
  std::int32_t centre = 0;
  for (std::int32_t c = 0; c < m.num_cells(); ++c) {
    const double d = m.cell_centroid(c).norm();
    if (d < best) best = d, centre = c;
  }
  lab[centre] = kInterior;
  return lab;
}

}  // namespace

TEST(FaceCost, Eq1Values) {
  // omega = 1: only the area term; omega = 0: (1 - exp(-1/sigma^2)) + lambda
  EXPECT_DOUBLE_EQ(face_cost(1.0, 2.0, 0.5, 0.1), 1.0);
  EXPECT_NEAR(face_cost(0.0, 2.0, 0.5, 0.1), 2.0 * (1 - std::exp(-100.0)) + 1.0, 1e-12);
  EXPECT_NEAR(data_term(0.5, 0.1), 1 - std::exp(-std::pow(std::tan(M_PI / 8), 2) / 0.01), 1e-12);
  // monotone: better photo-consistency never costs more
  double prev = 1e9;
  for (int i = 0; i <= 100; ++i) {
    const double c = face_cost(i / 100.0, 1.0, 0.3, 0.1);
    EXPECT_LE(c, prev + 1e-15);
    prev = c;
  }
}

TEST(GraphCut, UniformCostsGiveTheSeedCellOnly) {
  const auto m = cube_mesh(4, 1);
  const auto lab = seed_labels(m);
  std::vector<float> omega(2 * m.num_faces(), 0.0f);
  const auto r = min_cut(m, omega, lab, {0.5, 0.1});
  std::int64_t inside = 0;
  for (auto v : r.inside) inside += v;
  EXPECT_EQ(inside, 1);  // every extra cell adds surface
  EXPECT_EQ(r.cut_faces, 4);
  EXPECT_NEAR(r.energy, r.max_flow, 1e-9 * r.energy);
}

TEST(GraphCut, OutsideEvidenceCountsHalfAsMuchAsInsideEvidence) {
  // Every free cell holds inside evidence 1 and outside evidence e; with the visibility term
  // far above the face costs, a cell ends inside exactly when its outside evidence's half
  // weighs less than its inside evidence (e < 2).
  const auto m = cube_mesh(4, 1);
  const auto lab = seed_labels(m);
  std::vector<float> omega(2 * m.num_faces(), 0.0f);
  std::int64_t free_cells = 0;
  for (auto l : lab) free_cells += l == kFree;
  for (const float e : {1.9f, 2.1f}) {
    const std::vector<float> in(m.num_cells(), 1.0f), out(m.num_cells(), e);
    CutOptions o{0.5, 0.1};
    o.beta = 1000;
    o.inside_evidence = &in;
    o.outside_evidence = &out;
    const auto r = min_cut(m, omega, lab, o);
    std::int64_t inside = 0;
    for (auto v : r.inside) inside += v;
    EXPECT_EQ(inside, e < 2 ? free_cells + 1 : 1) << "outside evidence " << e;
  }
}

TEST(GraphCut, FollowsPhotoConsistentSphereAndSurfaceIsClosedManifoldOutward) {
  const auto m = cube_mesh(6, 2);
  const double R = 0.6;
  const auto in_sphere = [&](std::int32_t c) { return m.cell_centroid(c).norm() < R; };
  auto lab = seed_labels(m);
  for (std::int32_t c = 0; c < m.num_cells(); ++c)  // interior: a core well inside
    if (m.cell_centroid(c).norm() < 0.5 * R) lab[c] = kInterior;
  // omega = 1 for the outward orientation of faces between a cell inside the sphere and
  // one outside it; 0 elsewhere.
  std::vector<float> omega(2 * m.num_faces(), 0.0f);
  double truth_volume = 0;
  for (std::int32_t c = 0; c < m.num_cells(); ++c)
    if (in_sphere(c)) truth_volume += m.cell_volume(c);
  for (std::int32_t f = 0; f < m.num_faces(); ++f) {
    const std::int32_t a = m.face_cell(f, 0), b = m.face_cell(f, 1);
    if (b < 0) continue;
    if (in_sphere(a) && !in_sphere(b)) omega[2 * f] = 1.0f;
    if (in_sphere(b) && !in_sphere(a)) omega[2 * f + 1] = 1.0f;
  }
  const auto r = min_cut(m, omega, lab, {0.05, 0.1});
  double vol = 0;
  std::int64_t wrong = 0;
  for (std::int32_t c = 0; c < m.num_cells(); ++c) {
    if (r.inside[c]) vol += m.cell_volume(c);
    wrong += (r.inside[c] != 0) != in_sphere(c);
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_NEAR(vol, truth_volume, 1e-9);
  EXPECT_NEAR(r.energy, r.max_flow, 1e-9 * r.energy);
  EXPECT_NEAR(r.area_energy, 0.05 * r.cut_area, 1e-12);
  EXPECT_NEAR(r.data_energy, 0.0, 1e-12);  // every cut face has omega = 1

  SurfaceStats st;
  const TriMesh s = cut_surface(m, r.inside, &st);
  const MeshCheck chk = check_mesh(s);
  EXPECT_TRUE(chk.closed);
  EXPECT_TRUE(chk.edge_manifold);
  EXPECT_TRUE(chk.oriented);
  ASSERT_EQ(chk.components.size(), 1u);
  EXPECT_EQ(chk.components[0].genus, 0);
  EXPECT_NEAR(signed_volume(s), truth_volume, 1e-9);  // outward: positive enclosed volume
  EXPECT_NEAR(total_area(s), r.cut_area, 1e-9);
}

TEST(GraphCut, ReversedScoresMakeTheSphereCostly) {
  // The same sphere but omega rewards only the inward orientation: the cut must not
  // take the sphere (it pays the full data term there) and shrinks to the seed.
  const auto m = cube_mesh(6, 1);
  const double R = 0.6;
  const auto in_sphere = [&](std::int32_t c) { return m.cell_centroid(c).norm() < R; };
  std::vector<float> omega(2 * m.num_faces(), 0.0f);
  for (std::int32_t f = 0; f < m.num_faces(); ++f) {
    const std::int32_t a = m.face_cell(f, 0), b = m.face_cell(f, 1);
    if (b < 0) continue;
    if (in_sphere(a) && !in_sphere(b)) omega[2 * f + 1] = 1.0f;
    if (in_sphere(b) && !in_sphere(a)) omega[2 * f] = 1.0f;
  }
  const auto r = min_cut(m, omega, seed_labels(m), {0.05, 0.1});
  std::int64_t inside = 0;
  for (auto v : r.inside) inside += v;
  EXPECT_EQ(inside, 1);
}

TEST(CutSurface, TwoCellsMeetingAtAnEdgeAreSplitIntoTwoClosedSheets) {
  const auto m = cube_mesh(3, 0);
  // find two cells sharing exactly one edge (two vertices) and no face
  std::int32_t a = -1, b = -1;
  for (std::int32_t c = 0; c < m.num_cells() && a < 0; ++c)
    for (std::int32_t d = c + 1; d < m.num_cells(); ++d) {
      int shared = 0;
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) shared += m.cell_v[c][i] == m.cell_v[d][j];
      if (shared == 2) {
        a = c;
        b = d;
        break;
      }
    }
  ASSERT_GE(a, 0);
  std::vector<std::uint8_t> inside(m.num_cells(), 0);
  inside[a] = inside[b] = 1;
  SurfaceStats st;
  const TriMesh s = cut_surface(m, inside, &st);
  const MeshCheck chk = check_mesh(s);
  EXPECT_EQ(s.nf(), 8u);
  EXPECT_EQ(s.nv(), 8u);  // 4 + 4: the shared edge's two vertices are duplicated
  EXPECT_EQ(st.split_vertices, 2);
  EXPECT_TRUE(chk.edge_manifold);
  EXPECT_TRUE(chk.closed);
  EXPECT_EQ(chk.components.size(), 2u);
  EXPECT_NEAR(signed_volume(s), m.cell_volume(a) + m.cell_volume(b), 1e-12);
}
