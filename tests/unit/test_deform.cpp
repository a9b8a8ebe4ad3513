// deform's building blocks: remeshing (red-green splits, collapses, flips), the
// self-intersection test, the signed distance of silhouettes, the smoothness force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <opencv2/imgproc.hpp>

#include "common/deform/forces.h"
#include "common/deform/intersect.h"
#include "common/deform/options.h"
#include "common/deform/photometric.h"
#include "common/deform/remesh.h"
#include "common/deform/topology.h"
#include "common/error.h"
#include "common/params.h"
#include "common/synth/objects.h"
#include "common/trimesh/check.h"

using namespace tetmvs;
using namespace tetmvs::deform;

namespace {
// The faces of an n x n grid of vertices (vertex y * n + x), each square split along its
// diagonal: interior vertices have six neighbours.
std::vector<Eigen::Vector3i> grid_faces(int n) {
  std::vector<Eigen::Vector3i> F;
  for (int y = 0; y + 1 < n; ++y)
    for (int x = 0; x + 1 < n; ++x) {
      const int a = y * n + x;
      F.emplace_back(a, a + 1, a + n + 1);
      F.emplace_back(a, a + n + 1, a + n);
    }
  return F;
}

RemeshMesh from_trimesh(const TriMesh& t, double fp = 1.0) {
  RemeshMesh m;
  m.V = t.V;
  m.F = t.F;
  m.fp.assign(t.V.size(), fp);
  return m;
}
TriMesh to_trimesh(const RemeshMesh& m) {
  TriMesh t;
  t.V = m.V;
  t.F = m.F;
  return t;
}
// The mesh's edge lengths in pixels, ascending.
std::vector<double> sorted_edge_px(const RemeshMesh& m) {
  const Topology topo = build_topology(m.F, static_cast<int>(m.V.size()));
  std::vector<double> len;
  for (const auto& e : topo.edge_v) len.push_back(edge_px(m, e[0], e[1]));
  std::sort(len.begin(), len.end());
  return len;
}
double max_edge(const RemeshMesh& m) {
  const Topology topo = build_topology(m.F, static_cast<int>(m.V.size()));
  double mx = 0;
  for (const auto& e : topo.edge_v) mx = std::max(mx, edge_px(m, e[0], e[1]));
  return mx;
}
void expect_closed_genus(const TriMesh& t, int genus, const char* what) {
  const MeshCheck c = check_mesh(t);
  EXPECT_TRUE(c.closed) << what;
  EXPECT_TRUE(c.edge_manifold) << what;
  EXPECT_TRUE(c.oriented) << what;
  EXPECT_EQ(c.degenerate_faces, 0) << what;
  ASSERT_EQ(c.components.size(), 1u) << what;
  EXPECT_EQ(c.components[0].genus, genus) << what;
  EXPECT_GT(c.components[0].signed_volume, 0) << what;
}
}  // namespace

TEST(DeformTopology, EdgesAndNeighboursOfATetrahedron) {
  std::vector<Eigen::Vector3i> F = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  const Topology t = build_topology(F, 4);
  EXPECT_EQ(t.num_edges(), 6);
  EXPECT_TRUE(t.closed_manifold());
  for (int v = 0; v < 4; ++v) EXPECT_EQ(t.degree(v), 3);
  const int e = t.find_edge(3, 1);
  ASSERT_GE(e, 0);
  EXPECT_EQ(t.edge_f[e][0], 1);
  EXPECT_EQ(t.edge_f[e][1], 2);
  EXPECT_EQ(t.find_edge(0, 0), -1);
}

// The neighbours read from the vertices' faces (untangling's, fold collapses') are the
// topology's, row for row and in order (the umbrella mean sums them in that order).
TEST(DeformTopology, NeighboursFromTheFacesAreTheTopologys) {
  for (const TriMesh& m : {synth::make_sphere(0.2), synth::make_torus(0.15)}) {
    const int nv = static_cast<int>(m.V.size());
    const Topology t = build_topology(m.F, nv);
    const VertexFaces vf(m.F, nv);
    EXPECT_EQ(vf.start, t.vf_start);
    EXPECT_EQ(vf.faces, t.vf);
    std::vector<int> row;
    for (int v = 0; v < nv; ++v) {
      vf.neighbours(m.F, v, row);
      const auto want = t.neighbours(v);
      ASSERT_EQ(row, std::vector<int>(want.begin(), want.end())) << "vertex " << v;
    }
  }
}

TEST(DeformRemesh, RedGreenSplitBoundsEdgesAndKeepsTheSurface) {
  const TriMesh sphere = synth::make_sphere(0.5);
  RemeshMesh m = from_trimesh(sphere, 0.1);  // edges of ~5 "pixels"
  const double vol0 = signed_volume(sphere);
  const std::size_t f0 = m.F.size();
  std::int64_t total = 0;
  for (int pass = 0; pass < 6 && max_edge(m) > 2.0; ++pass) total += split_long_edges(m, 2.0);
  EXPECT_GT(total, 0);
  EXPECT_LE(max_edge(m), 2.0);
  EXPECT_GT(m.F.size(), 4 * f0);
  const TriMesh t = to_trimesh(m);
  expect_closed_genus(t, 0, "after splits");
  // midpoints lie on the old triangles: the volume does not change
  EXPECT_NEAR(signed_volume(t), vol0, 1e-9 * std::abs(vol0));
}

TEST(DeformRemesh, SplitPatternsOneEdgeAndAllThree) {
  // Two triangles sharing edge (0, 1): only that edge is long -> both split 1:2.
  RemeshMesh m;
  m.V = {{0, 0, 0}, {10, 0, 0}, {5, 1, 0}, {5, -1, 0}};
  m.F = {{0, 1, 2}, {1, 0, 3}};
  m.fp = {1, 1, 1, 1};
  EXPECT_EQ(split_long_edges(m, 6.0), 1);
  EXPECT_EQ(m.F.size(), 4u);
  EXPECT_EQ(m.V.size(), 5u);
  EXPECT_TRUE(m.V[4].isApprox(Eigen::Vector3d(5, 0, 0)));
  // A single big triangle: all three edges long -> 1:4.
  RemeshMesh r;
  r.V = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}};
  r.F = {{0, 1, 2}};
  r.fp = {1, 1, 1};
  EXPECT_EQ(split_long_edges(r, 6.0), 3);
  EXPECT_EQ(r.F.size(), 4u);
  double area = 0;
  for (const auto& t : r.F) area += 0.5 * (r.V[t[1]] - r.V[t[0]]).cross(r.V[t[2]] - r.V[t[0]]).z();
  EXPECT_NEAR(area, 50.0, 1e-12);  // orientation kept (all positive), area kept
}

TEST(DeformRemesh, TwoLongEdgesSplitInThree) {
  // Only two edges are long (10 and 9.49; the third is 3.16): only they are split (no red
  // closure), the corner between them is cut off and the quad left is split by its
  // shorter diagonal (midpoint (5, 0) to (9, 3): 5.0, not (10, 0) to (4.5, 1.5): 5.70).
  RemeshMesh r;
  r.V = {{0, 0, 0}, {10, 0, 0}, {9, 3, 0}};
  r.F = {{0, 1, 2}};
  r.fp = {1, 1, 1};
  EXPECT_EQ(split_long_edges(r, 5.0), 2);
  ASSERT_EQ(r.F.size(), 3u);
  ASSERT_EQ(r.V.size(), 5u);
  double area = 0, longest = 0;
  for (const auto& t : r.F) {
    const double a = 0.5 * (r.V[t[1]] - r.V[t[0]]).cross(r.V[t[2]] - r.V[t[0]]).z();
    EXPECT_GT(a, 0);  // orientation kept
    area += a;
    for (int k = 0; k < 3; ++k) longest = std::max(longest, (r.V[t[k]] - r.V[t[(k + 1) % 3]]).norm());
  }
  EXPECT_NEAR(area, 15.0, 1e-12);
  EXPECT_NEAR(longest, 5.0, 1e-12);  // the chosen diagonal; every edge is now <= 5
}

TEST(DeformRemesh, CollapseRemovesShortEdgesAndKeepsTopology) {
  const TriMesh torus = synth::make_torus(0.12);
  RemeshMesh m = from_trimesh(torus, 0.1);  // edges ~1.2 px
  const std::size_t v0 = m.V.size();
  // collapse the shorter half of the edges
  const Topology topo = build_topology(m.F, static_cast<int>(m.V.size()));
  std::vector<double> len;
  for (const auto& e : topo.edge_v) len.push_back(edge_px(m, e[0], e[1]));
  std::nth_element(len.begin(), len.begin() + len.size() / 2, len.end());
  const double med = len[len.size() / 2];
  const std::int64_t n = collapse_short_edges(m, med, 0.0, 4.0 * med);
  EXPECT_GT(n, 0);
  EXPECT_LT(m.V.size(), v0);
  EXPECT_EQ(m.fp.size(), m.V.size());
  expect_closed_genus(to_trimesh(m), 1, "after collapses");
  EXPECT_NEAR(signed_volume(to_trimesh(m)), signed_volume(torus), 0.05 * signed_volume(torus));
  // repeated passes converge without breaking the mesh
  for (int i = 0; i < 10; ++i) collapse_short_edges(m, med, 0.0, 4.0 * med);
  expect_closed_genus(to_trimesh(m), 1, "after many collapses");
}

TEST(DeformRemesh, CollapseNeedles) {
  // A fan around a centre with one very short spoke: the needle's short edge goes.
  const TriMesh sphere = synth::make_sphere(0.3);
  RemeshMesh m = from_trimesh(sphere, 0.1);
  m.V[0] = 0.1 * m.V[0] + 0.9 * m.V[build_topology(m.F, (int)m.V.size()).nbr[0]];  // pull toward a neighbour
  const std::size_t v0 = m.V.size();
  EXPECT_GE(collapse_short_edges(m, 0.0, 0.2, 10.0), 1);
  EXPECT_LT(m.V.size(), v0);
  expect_closed_genus(to_trimesh(m), 0, "after needle collapse");
}

TEST(DeformRemesh, FlipsImproveTheSmallestAngle) {
  // Green (1:2) splits leave thin triangles on a sphere; Delaunay flips fatten them.
  TriMesh s = synth::make_sphere(0.4);
  RemeshMesh q = from_trimesh(s, 0.1);
  split_long_edges(q, 0.4 / 0.1 * 0.9);
  auto min_angle = [](const RemeshMesh& r) {
    double mn = M_PI;
    for (const auto& t : r.F)
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d a = r.V[t[(k + 1) % 3]] - r.V[t[k]], b = r.V[t[(k + 2) % 3]] - r.V[t[k]];
        mn = std::min(mn, std::atan2(a.cross(b).norm(), a.dot(b)));
      }
    return mn;
  };
  const double before = min_angle(q);
  std::int64_t flips = 0;
  for (int i = 0; i < 5; ++i) flips += flip_edges(q, 30.0);
  EXPECT_GT(flips, 0);
  EXPECT_GE(min_angle(q), before);
  expect_closed_genus(to_trimesh(q), 0, "after flips");
}

TEST(DeformIntersect, SegmentTriangle) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_TRUE(segment_crosses_triangle({0.2, 0.2, -1}, {0.2, 0.2, 1}, a, b, c));
  EXPECT_FALSE(segment_crosses_triangle({0.8, 0.8, -1}, {0.8, 0.8, 1}, a, b, c));
  EXPECT_FALSE(segment_crosses_triangle({0.2, 0.2, 0.1}, {0.2, 0.2, 1}, a, b, c));
  // touching at a vertex does not count
  EXPECT_FALSE(segment_crosses_triangle({0, 0, 0}, {0.2, 0.2, 1}, a, b, c));
}

TEST(DeformIntersect, CleanMeshesHaveNoneAndAPushedVertexMakesSome) {
  const TriMesh torus = synth::make_torus(0.1);
  EXPECT_TRUE(self_intersections(torus.V, torus.F).empty());
  // two spheres touching at no point, then overlapping
  TriMesh two = synth::make_two(0.15);
  EXPECT_TRUE(self_intersections(two.V, two.F).empty());
  // push one vertex of a sphere through the opposite side
  TriMesh s = synth::make_sphere(0.2);
  int top = 0;
  for (int v = 0; v < (int)s.nv(); ++v)
    if (s.V[v].z() > s.V[top].z()) top = v;
  s.V[top] = Eigen::Vector3d(0.01, 0.02, -1.5);
  const auto pairs = self_intersections(s.V, s.F);
  EXPECT_GT(pairs.size(), 0u);
  for (const auto& p : pairs) EXPECT_LT(p.first, p.second);
  // filtered: exactly the full result's pairs that touch a flagged face (deform rechecks
  // only the faces it changed and keeps the rest); strides 13 and 29 flag fewer than an
  // eighth of the faces: the grid then holds the flagged faces only and every face is
  // looked up in it
  std::size_t some = 0;
  for (int stride : {1, 2, 7, 13, 29}) {
    std::vector<char> only(s.nf(), 0);
    for (size_t f = 0; f < s.nf(); f += stride) only[f] = 1;
    std::vector<std::pair<int, int>> expect;
    for (const auto& p : pairs)
      if (only[p.first] || only[p.second]) expect.push_back(p);
    EXPECT_EQ(self_intersections(s.V, s.F, only), expect) << stride;
    if (stride > 8) some += expect.size();
  }
  EXPECT_GT(some, 0u);  // the sparse strides did meet intersecting pairs
  std::vector<char> none(s.nf(), 0);
  EXPECT_TRUE(self_intersections(s.V, s.F, none).empty());
}

TEST(DeformIntersect, MotionPairsFindWhatTheGridFindsAtEveryScaleOfTheStep) {
  // a sphere whose top vertex moves through the opposite side: every state on the way
  // (the step halved as by retries) gives the grid's pairs, filtered or not
  const TriMesh s = synth::make_sphere(0.2);
  int top = 0;
  for (int v = 0; v < (int)s.nv(); ++v)
    if (s.V[v].z() > s.V[top].z()) top = v;
  std::vector<Eigen::Vector3d> V1 = s.V;
  V1[top] = Eigen::Vector3d(0.01, 0.02, -1.5);
  for (auto& x : V1) x += Eigen::Vector3d(0.003, -0.002, 0.001);  // every vertex moves
  const MotionPairs cand(s.V, V1, s.F);
  EXPECT_GT(cand.size(), s.nf());  // every face has neighbours sharing a vertex only
  std::size_t met = 0;
  for (double scale : {1.0, 0.5, 0.25, 0.0}) {
    std::vector<Eigen::Vector3d> V(s.nv());
    for (size_t v = 0; v < s.nv(); ++v) V[v] = s.V[v] + scale * (V1[v] - s.V[v]);
    const auto expect = self_intersections(V, s.F);
    EXPECT_EQ(cand.intersections(V), expect) << scale;
    met += expect.size();
    std::vector<char> only(s.nf(), 0);
    for (size_t f = 0; f < s.nf(); f += 7) only[f] = 1;
    EXPECT_EQ(cand.intersections(V, only), self_intersections(V, s.F, only)) << scale;
  }
  EXPECT_GT(met, 0u);
}

TEST(DeformSilhouette, SignedDistanceIsZeroOnTheBoundary) {
  cv::Mat m = cv::Mat::zeros(40, 40, CV_8U);
  m(cv::Rect(10, 10, 20, 20)).setTo(255);  // object pixels 10..29
  const cv::Mat sd = signed_distance(m);
  EXPECT_NEAR(sd.at<float>(20, 10), -0.5f, 1e-4);  // first object pixel
  EXPECT_NEAR(sd.at<float>(20, 9), 0.5f, 1e-4);    // first background pixel
  EXPECT_NEAR(sd.at<float>(20, 20), -9.5f, 0.05);  // 10 px to the pixel 30
  EXPECT_NEAR(sd.at<float>(20, 2), 7.5f, 0.05);
}

TEST(DeformSilhouette, SignedDistanceNearIsExactWithinItsReach) {
  // a disc, a ring with a hole and a blob cut by the image border
  cv::Mat m = cv::Mat::zeros(60, 80, CV_8U);
  cv::circle(m, cv::Point(20, 20), 12, cv::Scalar(255), -1);
  cv::circle(m, cv::Point(55, 35), 15, cv::Scalar(255), -1);
  cv::circle(m, cv::Point(55, 35), 5, cv::Scalar(0), -1);
  cv::circle(m, cv::Point(2, 58), 9, cv::Scalar(255), -1);
  const cv::Mat exact = signed_distance(m);
  for (int reach : {1, 3, 6, 20}) {  // 20: the whole-image transform, clamped
    const cv::Mat near = signed_distance_near(m, reach);
    int within = 0;
    for (int y = 0; y < m.rows; ++y)
      for (int x = 0; x < m.cols; ++x) {
        const float e = exact.at<float>(y, x), n = near.at<float>(y, x);
        if (std::abs(e) + 0.5f <= reach + 1e-4f) {
          EXPECT_NEAR(n, e, 1e-4) << reach << " " << x << " " << y;
          ++within;
        } else {
          EXPECT_EQ(n, std::copysign(reach + 0.5f, e)) << reach << " " << x << " " << y;
        }
      }
    EXPECT_GT(within, 100);
  }
  // one side only: everything beyond reach
  const cv::Mat all = signed_distance_near(cv::Mat(10, 10, CV_8U, cv::Scalar(255)), 2);
  EXPECT_EQ(cv::countNonZero(all != -2.5f), 0);
}

TEST(DeformSilhouette, ViewRasterEqualsTheWholeImageComputation) {
  // rasterize_view works in the covered box grown past the reach: the same signed distance and
  // IoU counts as over the whole image, for a sphere inside the image and one cut by its border
  const TriMesh s = synth::make_sphere(0.1);  // radius 1, 30 px at depth 10
  Camera c;
  c.K << 300, 0, 79.5, 0, 300, 59.5, 0, 0, 1;
  c.width = 160;
  c.height = 120;
  for (const double shift : {0.0, 3.0}) {
    c.t = Eigen::Vector3d(shift, 0, 10.0);
    cv::Mat sil = cv::Mat::zeros(120, 160, CV_8U);
    cv::circle(sil, cv::Point(70, 60), 25, cv::Scalar(255), -1);
    const ViewRaster v = rasterize_view(s, c, sil, 8);
    const cv::Mat covered = v.raster.tri >= 0;
    ASSERT_GT(cv::countNonZero(covered), 500);
    const cv::Mat whole = signed_distance_near(covered, 8);
    EXPECT_EQ(cv::countNonZero(v.sd != whole), 0) << shift;
    EXPECT_EQ(v.covered, cv::countNonZero(covered));
    EXPECT_EQ(v.agree, cv::countNonZero(covered & sil));
    EXPECT_EQ(v.either, cv::countNonZero(covered | sil));
  }
}

TEST(DeformSmooth, BilaplacianDoesNotShrinkASphereButUmbrellaDoes) {
  const TriMesh s = synth::make_sphere(0.1);
  const Topology topo = build_topology(s.F, (int)s.nv());
  const auto N = vertex_normals(s.V, s.F);
  Options o;
  o.smooth_tangent = 0;
  o.smooth_normal = 0;
  o.smooth_bilaplacian = 0.2;
  const auto bi = smooth_force(s.V, topo, N, o);
  o.smooth_bilaplacian = 0;
  o.smooth_normal = 0.2;
  const auto um = smooth_force(s.V, topo, N, o);
  double mb = 0, mu = 0;
  for (size_t v = 0; v < s.nv(); ++v) {
    mb += bi[v].dot(N[v]);
    mu += um[v].dot(N[v]);
  }
  mb /= s.nv();
  mu /= s.nv();
  EXPECT_LT(mu, 0);                    // umbrella moves inward
  EXPECT_LT(std::abs(mb), 0.2 * std::abs(mu));  // bi-Laplacian: far less net normal motion
}

TEST(DeformSmooth, FairingRemovesJitterWithoutShrinkingASphere) {
  // the smooth sphere: unlike the umbrella, the fairing hardly moves it; the sphere with its
  // vertices jittered along their normals (a fixed pattern of +1 % and -0.5 % of the radius):
  // the fairing's normal motion is against the jitter at nearly every vertex
  const TriMesh s = synth::make_sphere(0.1);
  const Topology topo = build_topology(s.F, (int)s.nv());
  const auto N0 = vertex_normals(s.V, s.F);
  Options o;
  o.smooth_tangent = 0;
  o.smooth_normal = 0;
  o.smooth_bilaplacian = 0;  // the fairing alone
  o.smooth_fairing = 1.2;
  const auto smooth = smooth_force(s.V, topo, N0, o, true);
  o.smooth_fairing = 0;
  o.smooth_normal = 1.2;
  const auto umbrella = smooth_force(s.V, topo, N0, o, true);
  double mf = 0, mu = 0;
  for (size_t v = 0; v < s.nv(); ++v) {
    mf += smooth[v].dot(N0[v]);
    mu += umbrella[v].dot(N0[v]);
  }
  EXPECT_LT(mu / s.nv(), 0);                                   // the umbrella shrinks the sphere
  EXPECT_LT(std::abs(mf / s.nv()), 0.05 * std::abs(mu / s.nv()));  // the fairing does not

  std::vector<Eigen::Vector3d> V = s.V;
  std::vector<double> jitter(s.nv());
  for (size_t v = 0; v < s.nv(); ++v) {
    jitter[v] = ((v * 2654435761u) % 3 == 0 ? 1.0 : -0.5) * 0.001;  // 1 % of the radius, mean ~0
    V[v] += jitter[v] * N0[v];
  }
  const auto N = vertex_normals(V, s.F);
  o.smooth_normal = 0;
  o.smooth_fairing = 1.2;
  const auto f = smooth_force(V, topo, N, o, true);
  int against = 0;
  double before = 0, after = 0;
  for (size_t v = 0; v < s.nv(); ++v) {
    const double m = f[v].dot(N[v]);
    against += m * jitter[v] < 0;
    before += jitter[v] * jitter[v];
    after += (jitter[v] + m) * (jitter[v] + m);
  }
  EXPECT_GT(against, 0.9 * s.nv());
  EXPECT_LT(after, 0.5 * before);  // one step removes most of the jitter
  // off the full images (fairing = false) the bi-Laplacian acts, as before
  o.smooth_bilaplacian = 0.4;
  const auto b = smooth_force(V, topo, N, o, false);
  const auto b0 = smooth_force(V, topo, N, [&] { Options p = o; p.smooth_fairing = 0; return p; }(), false);
  for (size_t v = 0; v < s.nv(); ++v) ASSERT_EQ(b[v], b0[v]);
}

TEST(DeformSilhouette, SpreadMovesTheVerticesAroundAnOutwardPullAndFades) {
  // a flat grid of 21 x 21 vertices 1 unit apart (footprint 1: units are pixels), normals +z
  const int n = 21;
  std::vector<Eigen::Vector3d> V, N(n * n, Eigen::Vector3d::UnitZ());
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) V.emplace_back(x, y, 0);
  const std::vector<Eigen::Vector3i> F = grid_faces(n);
  const Topology topo = build_topology(F, n * n);
  const std::vector<double> fp(n * n, 1.0);
  const int centre = 10 * n + 10;
  std::vector<Eigen::Vector3d> fsil(n * n, Eigen::Vector3d::Zero());
  fsil[centre] = Eigen::Vector3d(0.3, 0, 1.0);  // a pull of 1 px outward (and across)
  const SpreadOptions o{4.0, 1.0, 2.5};
  const std::vector<double> s = silhouette_spread(V, N, fp, topo, fsil, o);
  EXPECT_EQ(s[centre], 0.0);                          // the corrected vertex moves by its own correction
  EXPECT_NEAR(s[centre + 1], 1.0 * (1 - 1.0 / 4), 1e-12);  // one pixel away: 3/4 of the pull's normal part
  EXPECT_NEAR(s[centre + 2], 1.0 * (1 - 2.0 / 4), 1e-12);
  EXPECT_NEAR(s[centre + 3], 1.0 * (1 - 3.0 / 4), 1e-12);
  EXPECT_EQ(s[centre + 4], 0.0);                      // out of reach
  EXPECT_EQ(s[centre - 5 * n], 0.0);
  EXPECT_NEAR(s[centre + n + 1], 1.0 * (1 - std::sqrt(2.0) / 4), 1e-12);  // along a diagonal edge
  // in the pixels of images reduced four times the grid's edges are a quarter pixel long
  EXPECT_NEAR(silhouette_spread(V, N, fp, topo, fsil, {4.0, 4.0, 2.5})[centre + 4], 1.0 * (1 - 1.0 / 4), 1e-12);
  // inward pushes and pulls of max_source_px or more do not spread; no reach, no spread
  fsil[centre].z() = -1.0;
  for (double x : silhouette_spread(V, N, fp, topo, fsil, o)) EXPECT_EQ(x, 0.0);
  fsil[centre].z() = 2.6;
  for (double x : silhouette_spread(V, N, fp, topo, fsil, o)) EXPECT_EQ(x, 0.0);
  fsil[centre].z() = 1.0;
  for (double x : silhouette_spread(V, N, fp, topo, fsil, {0.0, 1.0, 2.5})) EXPECT_EQ(x, 0.0);
  // two pulls: a vertex between them takes their mean
  fsil[centre + 4] = Eigen::Vector3d(0, 0, 2.0);
  EXPECT_NEAR(silhouette_spread(V, N, fp, topo, fsil, o)[centre + 2], 1.5 * (1 - 2.0 / 4), 1e-12);
}

TEST(DeformSilhouette, ACorrectionAlongAContourIsSharedWithTheRowsBesideIt) {
  // The silhouette corrections of one iteration are averaged over each vertex's one-ring
  // (deform.cpp): a contour generator's row of rim vertices pulled out by 1 px does not rise
  // alone as a crease; the rows beside it take a share and the total pull is kept.
  const int n = 21;
  const Topology topo = build_topology(grid_faces(n), n * n);
  std::vector<Eigen::Vector3d> f(n * n, Eigen::Vector3d::Zero());
  for (int x = 0; x < n; ++x) f[10 * n + x] = Eigen::Vector3d(0, 0, 1.0);  // the rim row y = 10
  ring_average(f, topo, 1);
  for (int x = 1; x + 1 < n; ++x) {  // interior vertices: six neighbours, two of them on the row
    EXPECT_NEAR(f[10 * n + x].z(), 3.0 / 7, 1e-12);
    EXPECT_NEAR(f[9 * n + x].z(), 2.0 / 7, 1e-12);
    EXPECT_NEAR(f[11 * n + x].z(), 2.0 / 7, 1e-12);
    EXPECT_EQ(f[8 * n + x].z(), 0.0);
    EXPECT_EQ(f[12 * n + x].z(), 0.0);
    // the crease (the row above the rows beside it) drops from 1 px to 1/7; the column's sum stays 1
    EXPECT_NEAR(f[10 * n + x].z() - f[9 * n + x].z(), 1.0 / 7, 1e-12);
    EXPECT_NEAR(f[9 * n + x].z() + f[10 * n + x].z() + f[11 * n + x].z(), 1.0, 1e-12);
  }
  for (const Eigen::Vector3d& d : f) EXPECT_EQ(d.head<2>().squaredNorm(), 0.0);  // the direction is kept
}

TEST(DeformOptions, DefaultsAreValidAndBadValuesRejected) {
  const Options o = Options::from_params(Params::defaults());
  // (that the fields' defaults are defaults.json's values: test_param_binding.cpp)
  const auto rejected = [&](auto change) {
    Options bad = o;
    change(bad);
    try {
      bad.check();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(rejected([](Options& b) { b.min_edge_px = 1.5; }).find("max_edge_px"), std::string::npos);
  EXPECT_NE(rejected([](Options& b) { b.smooth_bilaplacian = 0.6; }).find("smooth_bilaplacian"), std::string::npos);
  EXPECT_NE(rejected([](Options& b) { b.photo_window = 8; }).find("photo_window"), std::string::npos);  // even
  EXPECT_NE(rejected([](Options& b) { b.photo_window = 1; }).find("photo_window"), std::string::npos);
  EXPECT_NE(rejected([](Options& b) { b.photo_partners = 0; }).find("photo_partners"), std::string::npos);
  EXPECT_NE(rejected([](Options& b) { b.photo_baseline_max_deg = b.photo_baseline_min_deg - 1; }).find("baselines"),
            std::string::npos);
  EXPECT_NE(rejected([](Options& b) { b.photo_coarsest_level = 7; }).find("photo_coarsest_level"), std::string::npos);
  EXPECT_NE(rejected([](Options& b) { b.photo_level_iterations = 0; }).find("photo_level_iterations"),
            std::string::npos);
  EXPECT_NE(rejected([](Options& b) { b.w_photo = 1.5; }).find("w_photo"), std::string::npos);
  EXPECT_NE(rejected([](Options& b) { b.sil_tolerance_px = -1; }).find("sil_tolerance_px"), std::string::npos);
}

// 14 iterations: 2 without the photometric force, 3 on each of the levels 3, 2, 1, then 3
// on the full images
static Options schedule_options() {
  Options o;
  o.iterations = 14;
  o.photo_start = 2;
  o.photo_coarsest_level = 3;
  o.photo_level_iterations = 3;
  return o;
}

TEST(DeformOptions, PhotometricForceRunsCoarseToFine) {
  Options o = schedule_options();
  std::vector<int> levels;
  for (int it = 0; it < o.iterations; ++it) levels.push_back(o.photo_level(it));
  EXPECT_EQ(levels, (std::vector<int>{-1, -1, 3, 3, 3, 2, 2, 2, 1, 1, 1, 0, 0, 0}));
  o.photo_coarsest_level = 0;
  for (int it = 2; it < o.iterations; ++it) EXPECT_EQ(o.photo_level(it), 0);
}

TEST(DeformOptions, TheMeshFollowsTheImagesInUse) {
  // edge lengths in pixels of the photometric level's images: the coarsest before the force
  // starts, the full images after the last iteration (the remesh that ends it)
  const Options o = schedule_options();
  std::vector<int> levels;
  for (int it = 0; it <= o.iterations; ++it) levels.push_back(o.mesh_level(it));
  EXPECT_EQ(levels, (std::vector<int>{3, 3, 3, 3, 3, 2, 2, 2, 1, 1, 1, 0, 0, 0, 0}));
}

// Remeshing keeps, per face, the face it was (deform carries the intersecting pairs of the
// faces it leaves alone over and retests only the others): a face with an origin has that
// face's corners, in order, at the same positions, and no face claims an origin twice.
TEST(DeformRemesh, RemeshingTracksTheFacesItLeavesAlone) {
  const TriMesh s = synth::make_sphere(0.15);
  RemeshMesh m = from_trimesh(s, 0.1);
  const std::vector<double> len = sorted_edge_px(m);
  const std::vector<Eigen::Vector3d> V0 = m.V;
  const std::vector<Eigen::Vector3i> F0 = m.F;
  m.origin.resize(F0.size());
  std::iota(m.origin.begin(), m.origin.end(), 0);
  const std::int64_t splits = split_long_edges(m, len[len.size() * 9 / 10]);
  const std::int64_t collapses = collapse_short_edges(m, len[len.size() / 10], 0.2, 1e9);
  const std::int64_t flips = flip_edges(m, 30);
  compact(m);
  EXPECT_GT(splits, 0);
  EXPECT_GT(collapses, 0);
  EXPECT_GT(flips, 0);
  ASSERT_EQ(m.origin.size(), m.F.size());
  std::vector<char> claimed(F0.size(), 0);
  std::int64_t kept = 0;
  for (size_t f = 0; f < m.F.size(); ++f) {
    const int o = m.origin[f];
    if (o < 0) continue;
    ++kept;
    ASSERT_LT(o, static_cast<int>(F0.size()));
    EXPECT_FALSE(claimed[o]) << "face " << o << " claimed twice";
    claimed[o] = 1;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.V[m.F[f][k]], V0[F0[o][k]]) << "face " << f;
  }
  EXPECT_GT(kept, static_cast<std::int64_t>(F0.size()) / 4);
  EXPECT_LT(kept, static_cast<std::int64_t>(m.F.size()));
  expect_closed_genus(to_trimesh(m), 0, "after remeshing with tracking");
}

TEST(DeformRemesh, RemeshingCarriesTheLastStepsWithTheVertices) {
  // A value linear in the position (here x) stays so: splits put their vertex at the
  // midpoint and collapses merge there, and both take the mean of the ends' values.
  const TriMesh s = synth::make_sphere(0.15);
  RemeshMesh m = from_trimesh(s, 0.1);
  const std::vector<double> len = sorted_edge_px(m);
  for (const auto& x : m.V) m.last_step.push_back(x.x());
  const std::size_t v0 = m.V.size();
  EXPECT_GT(split_long_edges(m, len[len.size() * 9 / 10]), 0);
  EXPECT_GT(m.V.size(), v0);
  EXPECT_GT(collapse_short_edges(m, len[len.size() / 10], 0.2, 1e9), 0);
  flip_edges(m, 30);
  compact(m);
  ASSERT_EQ(m.last_step.size(), m.V.size());
  for (std::size_t v = 0; v < m.V.size(); ++v) EXPECT_NEAR(m.last_step[v], m.V[v].x(), 1e-12) << "vertex " << v;
  // without values nothing is carried
  RemeshMesh plain = from_trimesh(s, 0.1);
  split_long_edges(plain, len[len.size() * 9 / 10]);
  compact(plain);
  EXPECT_TRUE(plain.last_step.empty());
}

TEST(DeformTopology, RingAverageKeepsConstantsAndSpreadsASpike) {
  const TriMesh s = synth::make_sphere(0.15);
  const int nv = static_cast<int>(s.V.size());
  const Topology topo = build_topology(s.F, nv);
  std::vector<double> c(nv, 2.5);
  ring_average(c, topo, 5);
  for (double x : c) EXPECT_NEAR(x, 2.5, 1e-12);
  std::vector<double> spike(nv, 0.0);
  spike[0] = 1.0;
  ring_average(spike, topo, 1);
  EXPECT_NEAR(spike[0], 1.0 / (1 + topo.degree(0)), 1e-12);
  for (int w : topo.neighbours(0)) EXPECT_NEAR(spike[w], 1.0 / (1 + topo.degree(w)), 1e-12);
  ring_average(spike, topo, 11);
  double sum = 0, peak = 0;
  for (double x : spike) sum += x, peak = std::max(peak, x);
  EXPECT_LT(peak, 0.05);  // a single vertex's value is spread over 12 rings
  EXPECT_GT(sum, 0.5);
}

TEST(DeformRemesh, CollapseFoldsRemovesAFoldOverInAVertexFan) {
  // A vertex pushed past one of its neighbours (onto the tangent plane there):
  // its fan folds over that neighbour's, a sub-pixel pleat of triangles sharing a vertex
  // like those deform's smoothing left on dinoRing. Collapsing the short edge removes it.
  const TriMesh s = synth::make_sphere(0.2);
  RemeshMesh m = from_trimesh(s, 0.1);
  const Topology topo = build_topology(m.F, static_cast<int>(m.V.size()));
  const int v = 0, u = topo.nbr[topo.nbr_start[0]];
  m.V[v] = m.V[u] + 0.3 * (m.V[u] - m.V[v]);
  const auto before = self_intersections(m.V, m.F);
  ASSERT_FALSE(before.empty());
  int sharing = 0;  // pairs of faces with a common vertex: the fan fold-over
  for (const auto& p : before) {
    int c = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) c += m.F[p.first][i] == m.F[p.second][j];
    sharing += c == 1;
  }
  EXPECT_GT(sharing, 0);
  const size_t nv0 = m.V.size();
  const size_t nf0 = m.F.size();
  const std::vector<Eigen::Vector3i> F0 = m.F;
  const std::vector<Eigen::Vector3d> V0 = m.V;
  const FoldCollapses fc = collapse_folds(m, before);
  EXPECT_EQ(fc.count, 1);
  EXPECT_EQ(m.V.size(), nv0 - 1);  // one collapse for the whole pleat
  // the face map: the edge's two faces removed, the others kept in order; the faces that
  // lost a corner to the merge are flagged changed, and only they
  ASSERT_EQ(fc.face_to_new.size(), nf0);
  ASSERT_EQ(fc.changed.size(), m.F.size());
  EXPECT_EQ(std::count(fc.face_to_new.begin(), fc.face_to_new.end(), -1), 2);
  int last = -1, changed = 0;
  for (size_t f = 0; f < nf0; ++f) {
    const int g = fc.face_to_new[f];
    if (g < 0) continue;
    EXPECT_EQ(g, last + 1);
    last = g;
    // a face not flagged keeps its corners and their positions
    if (!fc.changed[g]) {
      for (int k = 0; k < 3; ++k) EXPECT_EQ(m.V[m.F[g][k]], V0[F0[f][k]]);
    }
    changed += fc.changed[g];
  }
  EXPECT_GE(changed, 6);
  EXPECT_LE(changed, 20);
  EXPECT_EQ(m.fp.size(), m.V.size());
  EXPECT_TRUE(self_intersections(m.V, m.F).empty());
  expect_closed_genus(to_trimesh(m), 0, "after collapsing the fold");
  // nothing to do on a clean mesh
  EXPECT_EQ(collapse_folds(m, {}).count, 0);
}

// The noise floor on the full images: windows with little image gradient (h small for their
// pixel pairs) get their steps cut, textured ones keep theirs; the reduced levels ignore it.
TEST(DeformPhotometric, TheNoiseFloorDampsWeakWindowsOnTheFullImagesOnly) {
  const TriMesh m = synth::make_object("sphere", 0.3);
  const int nv = static_cast<int>(m.V.size());
  const deform::Topology topo = deform::build_topology(m.F, nv);
  const std::vector<double> fp(nv, 1.0);
  const auto steps = [&](double grad, double hess, int level, double floor) {
    deform::PhotometricGradient g;
    g.grad.assign(nv, grad);
    g.hess.assign(nv, hess);
    g.pairs.assign(nv, 100.0);  // floor 0.001: 0.1 added to the curvature
    return deform::photometric_steps(g, topo, level, level, fp, floor)[0];
  };
  // textured: curvature 100 for 100 pairs; the floor changes the step by under 0.1 %
  EXPECT_NEAR(steps(-1.0, 100.0, 0, 0.001), steps(-1.0, 100.0, 0, 0.0), 1e-3 * steps(-1.0, 100.0, 0, 0.0));
  // weak: curvature 0.01 for 100 pairs; the step shrinks tenfold (0.001 / 0.011 -> 0.001 / 0.111)
  EXPECT_NEAR(steps(-0.001, 0.01, 0, 0.0), 0.001 / 0.011, 1e-9);
  EXPECT_NEAR(steps(-0.001, 0.01, 0, 0.001), 0.001 / 0.111, 1e-9);
  // on a reduced level the floor does nothing
  EXPECT_EQ(steps(-0.001, 0.01, 1, 0.001), steps(-0.001, 0.01, 1, 0.0));
}

// The damping on the reduced images is per pixel pair: a cap that few views see (a tenth of
// the pairs, the same windows) takes the same step as the rest of the surface; on the full
// images, damped by a share of the median curvature, its step is cut short.
TEST(DeformPhotometric, OnTheReducedImagesTheDampingIsPerPixelPair) {
  const TriMesh m = synth::make_object("sphere", 0.3);
  const int nv = static_cast<int>(m.V.size());
  const deform::Topology topo = deform::build_topology(m.F, nv);
  const std::vector<double> fp(nv, 1.0);
  int top = 0, bottom = 0;
  for (int v = 0; v < nv; ++v) {
    if (m.V[v].z() > m.V[top].z()) top = v;
    if (m.V[v].z() < m.V[bottom].z()) bottom = v;
  }
  const double zmin = m.V[bottom].z(), zmax = m.V[top].z();
  deform::PhotometricGradient g;
  for (int v = 0; v < nv; ++v) {
    // the lowest fifth is seen by a tenth of the pairs; gradient and curvature per pair the same
    const double pairs = m.V[v].z() < zmin + 0.2 * (zmax - zmin) ? 10.0 : 100.0;
    g.pairs.push_back(pairs);
    g.hess.push_back(pairs * 1.0);
    g.grad.push_back(pairs * -0.01);
  }
  const auto reduced = deform::photometric_steps(g, topo, 1, 1, fp);
  EXPECT_NEAR(reduced[top], 0.01 / 1.2, 1e-9);  // damping 0.2 of the curvature per pair
  EXPECT_NEAR(reduced[bottom], 0.01 / 1.2, 1e-9);
  const auto full = deform::photometric_steps(g, topo, 0, 0, fp);
  EXPECT_NEAR(full[top], 1.0 / 110.0, 1e-9);    // damping 0.1 of the median curvature (100)
  EXPECT_NEAR(full[bottom], 0.1 / 20.0, 1e-9);  // the same damping on a tenth of the curvature
}
