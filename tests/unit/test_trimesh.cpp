#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"
#include "common/synth/objects.h"
#include "common/trimesh/bvh.h"
#include "common/trimesh/check.h"
#include "common/trimesh/rng.h"
#include "common/trimesh/roughness.h"
#include "common/trimesh/sample.h"

using namespace tetmvs;

TEST(TriMesh, ObjectsAreClosedOutwardWithTheRightGenus) {
  struct Want { const char* name; int comps; int genus; };
  for (const Want w : {Want{"sphere", 1, 0}, Want{"torus", 1, 1}, Want{"cup", 1, 0}, Want{"cup_filled", 1, 0},
                       Want{"two", 2, 0}, Want{"horn", 1, 0}, Want{"relief", 1, 0}}) {
    const TriMesh m = synth::make_object(w.name, 0.05);
    const MeshCheck c = check_mesh(m);
    SCOPED_TRACE(w.name);
    EXPECT_TRUE(c.closed);
    EXPECT_TRUE(c.edge_manifold);
    EXPECT_TRUE(c.oriented);
    EXPECT_EQ(c.degenerate_faces, 0);
    EXPECT_EQ(c.unreferenced_vertices, 0);
    ASSERT_EQ(static_cast<int>(c.components.size()), w.comps);
    for (const auto& k : c.components) {
      EXPECT_EQ(k.genus, w.genus);
      EXPECT_GT(k.signed_volume, 0);  // outward normals
    }
    // Edge lengths near the requested 0.05.
    double emax = 0;
    for (const auto& f : m.F)
      for (int k = 0; k < 3; ++k) emax = std::max(emax, (m.V[f[k]] - m.V[f[(k + 1) % 3]]).norm());
    EXPECT_LT(emax, 0.05 * 1.6);
    ASSERT_NE(m.fprop("region"), nullptr);
  }
}

TEST(TriMesh, SphereAreaAndVolumeConverge) {
  const TriMesh m = synth::make_sphere(0.02);
  const double pi = 3.14159265358979;
  EXPECT_NEAR(total_area(m), 4 * pi, 4 * pi * 2e-3);
  EXPECT_NEAR(signed_volume(m), 4 * pi / 3, 4 * pi / 3 * 2e-3);
  for (std::size_t i = 0; i < m.V.size(); ++i) EXPECT_NEAR(m.V[i].norm(), 1.0, 1e-12);
}

TEST(TriMesh, CupRegionsLabelTheCavity) {
  const TriMesh m = synth::make_cup(0.05);
  const auto& reg = *m.fprop("region");
  double cav = 0, body = 0;
  for (std::size_t f = 0; f < m.F.size(); ++f) {
    const Eigen::Vector3d c = (m.V[m.F[f][0]] + m.V[m.F[f][1]] + m.V[m.F[f][2]]) / 3;
    const double r = std::hypot(c.x(), c.y());
    if (reg[f] == static_cast<float>(synth::kCavity)) {
      cav += face_area(m, f);
      EXPECT_LE(r, 0.75 + 1e-9);  // inner wall radius
      EXPECT_GE(c.z(), 0.3 - 1e-3);
    } else {
      body += face_area(m, f);
    }
  }
  const double pi = 3.14159265358979;
  // inner wall 2 pi 0.75 (2 - 0.125 - 0.4) + bottom pi 0.65^2 + corner ~ pi/2*0.1*2pi*0.7
  EXPECT_NEAR(cav, 2 * pi * 0.75 * 1.475 + pi * 0.65 * 0.65 + 0.5 * pi * 0.1 * 2 * pi * 0.70, 0.1);
  EXPECT_GT(body, cav);
}

TEST(TriMesh, CheckFindsBoundaryNonManifoldAndMisorientation) {
  TriMesh m = synth::make_sphere(0.2);
  std::vector<char> keep(m.F.size(), 1);
  keep[0] = 0;
  const MeshCheck open = check_mesh(submesh(m, keep));
  EXPECT_FALSE(open.closed);
  EXPECT_TRUE(open.edge_manifold);
  EXPECT_EQ(open.boundary_edges, 3);
  EXPECT_EQ(open.components[0].boundary_loops, 1);
  EXPECT_EQ(open.components[0].genus, 0);  // a disc
  TriMesh flipped = m;
  std::swap(flipped.F[5][1], flipped.F[5][2]);
  EXPECT_EQ(check_mesh(flipped).misoriented_edges, 3);
  EXPECT_FALSE(check_mesh(flipped).oriented);
  TriMesh fin = m;
  fin.V.push_back({5, 5, 5});
  fin.F.push_back({m.F[0][0], m.F[0][1], static_cast<int>(fin.V.size()) - 1});
  const MeshCheck c = check_mesh(fin);
  EXPECT_EQ(c.nonmanifold_edges, 1);
  EXPECT_FALSE(c.edge_manifold);
  EXPECT_FALSE(c.closed);
  fin.V.push_back({7, 7, 7});
  EXPECT_EQ(check_mesh(fin).unreferenced_vertices, 1);
}

TEST(TriMesh, SamplingIsAreaWeightedAndDeterministic) {
  const TriMesh m = synth::make_cup(0.05);
  const double spacing = 0.01;
  const SurfaceSamples s = sample_surface(m, spacing, 7);
  const double expect = total_area(m) / (spacing * spacing);
  EXPECT_NEAR(static_cast<double>(s.size()), expect, 4 * std::sqrt(expect));
  // Same seed, same samples; samples lie on their faces.
  const SurfaceSamples s2 = sample_surface(m, spacing, 7);
  ASSERT_EQ(s.size(), s2.size());
  for (std::size_t i = 0; i < s.size(); i += 97) {
    EXPECT_EQ(s.P[i], s2.P[i]);
    const auto& f = m.F[s.face[i]];
    const Eigen::Vector3d n = (m.V[f[1]] - m.V[f[0]]).cross(m.V[f[2]] - m.V[f[0]]).normalized();
    EXPECT_NEAR(n.dot(s.P[i] - m.V[f[0]]), 0, 1e-12);
    EXPECT_NEAR(s.N[i].dot(n), 1, 1e-12);
  }
  // Area weighting: the share of samples in the cavity matches its share of the area.
  const auto& reg = *m.fprop("region");
  double acav = 0;
  for (std::size_t f = 0; f < m.F.size(); ++f) acav += reg[f] == 1 ? face_area(m, f) : 0;
  std::size_t ncav = 0;
  for (int f : s.face) ncav += reg[f] == 1;
  EXPECT_NEAR(static_cast<double>(ncav) / s.size(), acav / total_area(m), 0.01);
}

TEST(TriMesh, BvhClosestPointMatchesBruteForce) {
  const TriMesh m = synth::make_torus(0.1);
  const MeshBVH bvh(m);
  Rng rng(3);
  for (int q = 0; q < 300; ++q) {
    const Eigen::Vector3d p(rng.uniform() * 4 - 2, rng.uniform() * 4 - 2, rng.uniform() * 4 - 2);
    double best = 1e300;
    for (std::size_t f = 0; f < m.F.size(); ++f) {
      const auto& t = m.F[f];
      best = std::min(best, (closest_point_on_triangle(p, m.V[t[0]], m.V[t[1]], m.V[t[2]]) - p).squaredNorm());
    }
    const ClosestHit h = bvh.closest(p);
    EXPECT_DOUBLE_EQ(h.dist2, best);
    EXPECT_NEAR((h.point - p).squaredNorm(), h.dist2, 1e-12);
    // Range-limited query: found exactly when within range.
    const ClosestHit lim = bvh.closest(p, 0.3);
    EXPECT_EQ(lim.prim >= 0, best <= 0.09);
  }
  // Point cloud: nearest vertex.
  TriMesh pc;
  pc.V = m.V;
  const MeshBVH pb(pc);
  EXPECT_TRUE(pb.points_only());
  const ClosestHit h = pb.closest(m.V[17] + Eigen::Vector3d(1e-4, 0, 0));
  EXPECT_EQ(h.prim, 17);
  EXPECT_NEAR(h.dist(), 1e-4, 1e-12);
}

TEST(TriMesh, ClosestPointOnTriangleRegions) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_EQ(closest_point_on_triangle({-1, -1, 1}, a, b, c), a);
  EXPECT_EQ(closest_point_on_triangle({2, -1, 0}, a, b, c), b);
  EXPECT_EQ(closest_point_on_triangle({0.5, -1, 0}, a, b, c), Eigen::Vector3d(0.5, 0, 0));
  EXPECT_TRUE(closest_point_on_triangle({1, 1, 0}, a, b, c).isApprox(Eigen::Vector3d(0.5, 0.5, 0)));
  EXPECT_LT((closest_point_on_triangle({0.2, 0.3, 5}, a, b, c) - Eigen::Vector3d(0.2, 0.3, 0)).norm(), 1e-15);
  // Degenerate (collinear) triangle.
  EXPECT_TRUE(closest_point_on_triangle({0.5, 1, 0}, a, b, Eigen::Vector3d(2, 0, 0)).isApprox(Eigen::Vector3d(0.5, 0, 0)));
}

TEST(TriMesh, RaycastHitsTheSphere) {
  const TriMesh m = synth::make_sphere(0.05);
  const MeshBVH bvh(m);
  const RayHit h = bvh.raycast({0.1, 0.2, -5}, {0, 0, 1});
  ASSERT_GE(h.face, 0);
  EXPECT_NEAR(h.t, 5 - std::sqrt(1 - 0.05), 2e-3);
  EXPECT_LT(bvh.raycast({0, 0, -5}, {0, 0, 1}, 0, 3.9).face, 0);  // stops before the sphere
  EXPECT_LT(bvh.raycast({2, 0, -5}, {0, 0, 1}).face, 0);          // misses
}

TEST(TriMesh, RoughnessOfASmoothAndANoisySphere) {
  // unit sphere, edges of 0.02; a ball of radius 0.1 holds ~90 vertices
  TriMesh m = synth::make_sphere(0.02);
  const double r = 0.1;
  const Roughness smooth = surface_roughness(m, r);
  const double cap = r * r / (4 * std::sqrt(3.0));  // RMS of a sphere cap about its plane (R = 1)
  EXPECT_GT(smooth.samples, 1000);
  EXPECT_NEAR(smooth.median, cap, 0.15 * cap);
  // vertices moved along their normal by uniform noise in [-a, a]: RMS a / sqrt(3) more
  const double a = 0.01;
  for (std::size_t v = 0; v < m.nv(); ++v) {
    Rng g(7, v);
    m.V[v] *= 1 + a * (2 * g.uniform() - 1);
  }
  const Roughness noisy = surface_roughness(m, r);
  const double want = std::hypot(cap, a / std::sqrt(3.0));
  EXPECT_NEAR(noisy.median, want, 0.1 * want);
  EXPECT_GT(noisy.p90, noisy.median);
  // the same answer again (deterministic) and at most max_samples samples
  EXPECT_EQ(surface_roughness(m, r).median, noisy.median);
  EXPECT_LE(surface_roughness(m, r, 100).samples, 100);
  EXPECT_THROW(surface_roughness(m, 0), Error);
}

TEST(TriMesh, RoughnessRadiusInPixelsAtTheObject) {
  const TriMesh m = synth::make_sphere(0.2);
  std::vector<Camera> cams(3);
  const double dist[3] = {4, 5, 9};
  for (int i = 0; i < 3; ++i) {
    cams[i].R = Eigen::Matrix3d::Identity();
    cams[i].t = Eigen::Vector3d(0, 0, dist[i]);  // centre (0, 0, -dist)
    cams[i].K << 1000, 0, 320, 0, 1000, 240, 0, 0, 1;
  }
  EXPECT_NEAR(pixel_footprint(cams, Eigen::Vector3d::Zero()), 5.0 / 1000, 1e-9);  // the median camera
  Eigen::AlignedBox3d box;
  for (const auto& p : m.V) box.extend(p);
  EXPECT_DOUBLE_EQ(surface_roughness_px(m, cams, 40).radius, 40 * pixel_footprint(cams, box.center()));
}
