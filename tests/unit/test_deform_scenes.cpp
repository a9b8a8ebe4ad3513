// deform on rendered synthetic scenes (16 ring cameras, 240 x 180): a faceted start
// surface (the boundary of BCC cells whose centroids lie inside the ground truth, about
// 1.5 px off at the 90th percentile) is refined toward the ground truth; topology,
// closedness and freedom from self-intersections are kept.
#include <gtest/gtest.h>

#include <omp.h>

#include <cstdio>

#include "common/deform/deform.h"
#include "common/deform/forces.h"
#include "common/deform/intersect.h"
#include "common/deform/topology.h"
#include "common/photo/views.h"
#include "common/error.h"
#include "common/photo/options.h"
#include "common/trimesh/check.h"
#include "test_deform_scene.h"

using namespace tetmvs;
using namespace tetmvs::testing;

namespace {

// Test-sized settings: coarser remeshing (5 px edges) and 8 iterations keep each scene
// within a few seconds.
deform::Options test_options() {
  deform::Options o;
  o.iterations = 8;
  o.max_edge_px = 5.0;
  o.min_edge_px = 1.2;
  o.texture_range_px = 2.5;
  o.texture_far_px = 3 * o.texture_range_px;  // the defaults' ratio (15 / 5 px)
  return o;
}

struct Outcome {
  EvalResult before, after;
  deform::Result res;
  MeshCheck start_check, end_check;
  double acc0 = 0, acc1 = 0;  // accuracy (90 %) in pixels
};

Outcome run(const DeformScene& d, const TriMesh& start, const deform::Options& o, const char* what) {
  Outcome out;
  out.start_check = check_mesh(start);
  out.before = evaluate_px(start, d);
  out.res = deform::deform_mesh(start, d.scene, o, photo::Options{});
  out.after = evaluate_px(out.res.mesh, d);
  out.end_check = check_mesh(out.res.mesh);
  out.acc0 = out.before.all.accuracy.at_fraction / d.px;
  out.acc1 = out.after.all.accuracy.at_fraction / d.px;
  const auto& a = out.before.all;
  const auto& b = out.after.all;
  std::printf("  %s: accuracy %.3f -> %.3f px (mean %.3f -> %.3f), completeness(1.25mm) %.4f -> %.4f, (1px) %.4f -> "
              "%.4f, IoU %.4f -> %.4f, faces %zu -> %zu, intersections %lld -> %lld\n",
              what, out.acc0, out.acc1, a.accuracy.mean / d.px, b.accuracy.mean / d.px, a.completeness.within[0],
              b.completeness.within[0], a.completeness.within[1], b.completeness.within[1], out.res.start_iou,
              out.res.final_iou, start.nf(), out.res.mesh.nf(), (long long)out.res.start_intersections,
              (long long)out.res.final_intersections);
  return out;
}

void expect_same_topology(const Outcome& o) {
  EXPECT_TRUE(o.end_check.closed);
  EXPECT_TRUE(o.end_check.edge_manifold);
  EXPECT_TRUE(o.end_check.oriented);
  EXPECT_EQ(o.end_check.degenerate_faces, 0);
  ASSERT_EQ(o.end_check.components.size(), o.start_check.components.size());
  for (size_t i = 0; i < o.end_check.components.size(); ++i)
    EXPECT_EQ(o.end_check.components[i].genus, o.start_check.components[i].genus);
  EXPECT_EQ(o.res.final_intersections, 0);
  EXPECT_TRUE(deform::self_intersections(o.res.mesh.V, o.res.mesh.F).empty());  // independent full check
  EXPECT_EQ(o.res.mesh.N.size(), o.res.mesh.nv());
  EXPECT_EQ(o.res.mesh.C.size(), o.res.mesh.nv());
}

const DeformScene& textured_sphere() {
  static const DeformScene d = make_deform_scene("sphere", 16, 1.0, 240, 180);
  return d;
}

// Every 37th ground-truth vertex of d pushed `out_px` pixels out along its normal (V), with
// the normal (N).
void pushed_out(const DeformScene& d, double out_px, std::vector<Eigen::Vector3d>& V, std::vector<Eigen::Vector3d>& N) {
  const std::vector<Eigen::Vector3d> gn = deform::vertex_normals(d.gt.V, d.gt.F);
  for (size_t v = 0; v < d.gt.nv(); v += 37) {
    V.push_back(d.gt.V[v] + out_px * d.px * gn[v]);
    N.push_back(gn[v]);
  }
}
}  // namespace

TEST(DeformScene, TexturedSphereFromBccFacets) {
  const DeformScene& d = textured_sphere();
  const TriMesh start = bcc_start_surface(d.gt, 6 * d.px);
  deform::Options opt = test_options();
  opt.texture_pyramid = 0;  // the full images throughout: the sweep schedule below (a change of level probes every vertex)
  const Outcome o = run(d, start, opt, "textured sphere");
  expect_same_topology(o);
  EXPECT_GT(o.acc0, 1.2);  // the start really is off
  EXPECT_LT(o.acc1, 0.42);  // measured 0.36 (0.44 before the sag correction and the stronger bi-Laplacian)
  EXPECT_LT(o.acc1, o.acc0 / 3);
  EXPECT_GE(o.after.all.completeness.within[1], o.before.all.completeness.within[1]);
  EXPECT_GE(o.after.all.completeness.within[0], o.before.all.completeness.within[0] - 1e-4);
  EXPECT_GT(o.res.final_iou, o.res.start_iou);
  EXPECT_GT(o.res.final_iou, 0.99);
  ASSERT_EQ(o.res.iterations.size(), 8u);
  const auto& last = o.res.iterations.back();
  // iteration 5 is a sweep (texture_start 2, texture_recheck 3): besides the unsettled
  // vertices it probes the settled ones that moved texture_settle_px since their last
  // probe (more than the iterations beside it, not all: 75 % measured); most see a clear
  // peak; the last iteration probes only the vertices that have not settled
  EXPECT_GT(o.res.iterations[5].texture_probed, o.res.iterations[4].texture_probed);
  EXPECT_GT(o.res.iterations[5].texture_probed, o.res.iterations[6].texture_probed);
  EXPECT_LT(o.res.iterations[5].texture_probed, 1.0);
  EXPECT_GT(o.res.iterations[5].texture_applied, 0.5);
  EXPECT_GT(o.res.iterations[5].mean_texture_score, 0.9);
  EXPECT_LT(last.texture_probed, 0.5);
  EXPECT_LT(last.mean_move_px, o.res.iterations[2].mean_move_px);  // settles
  // colours come from the images: only the bottom pole, which no camera of the
  // 20-degree ring faces, keeps the grey of unseen vertices
  int grey = 0;
  for (const auto& c : o.res.mesh.C) grey += c[0] == 128 && c[1] == 128 && c[2] == 128;
  EXPECT_LT(grey, static_cast<int>(o.res.mesh.nv() / 20));
}

TEST(DeformScene, TexturedTorusKeepsItsHole) {
  const DeformScene d = make_deform_scene("torus", 16, 1.0, 240, 180);
  const TriMesh start = bcc_start_surface(d.gt, 6 * d.px);
  const Outcome o = run(d, start, test_options(), "textured torus");
  expect_same_topology(o);
  EXPECT_EQ(o.end_check.components[0].genus, 1);
  EXPECT_LT(o.acc1, 0.58);  // measured 0.49 px (0.74 before #12; the inner side of the ring is seen by few views; 16 views give 2 partners)
  EXPECT_LT(o.acc1, o.acc0 / 1.8);
  EXPECT_GE(o.after.all.completeness.within[1], o.before.all.completeness.within[1]);
}

TEST(DeformScene, TexturelessSphereIsNoWorse) {
  // No texture: the texture force finds no clear peak; silhouettes and smoothing hold the
  // surface. The wide search is on (3x the range); its contrast rule
  // (texture_far_min_contrast 0.1) is what keeps it from false peaks here: with the near
  // search's 0.03 the completeness at 1.25 mm fell 0.99994 -> 0.99953 (measured).
  const DeformScene d = make_deform_scene("sphere", 16, 0.0, 240, 180);
  const TriMesh start = bcc_start_surface(d.gt, 6 * d.px);
  const Outcome o = run(d, start, test_options(), "textureless sphere");
  expect_same_topology(o);
  EXPECT_LE(o.acc1, o.acc0);
  EXPECT_GE(o.after.all.completeness.within[0], o.before.all.completeness.within[0] - 1e-4);
  EXPECT_LT(o.res.iterations.back().texture_applied, 0.1);
}

TEST(DeformScene, WithoutSilhouettesTextureAloneImproves) {
  DeformScene d = textured_sphere();
  for (int i = 0; i < d.scene.size(); ++i)
    if (i % 2 == 0) d.scene.sil[i] = cv::Mat();  // half the views have none
  const TriMesh start = bcc_start_surface(d.gt, 6 * d.px);
  const Outcome half = run(d, start, test_options(), "half the silhouettes");
  expect_same_topology(half);
  EXPECT_LT(half.acc1, 0.48);  // measured 0.41 (0.50 before #12)
  for (auto& s : d.scene.sil) s = cv::Mat();
  const Outcome none = run(d, start, test_options(), "no silhouettes");
  expect_same_topology(none);
  EXPECT_EQ(none.res.final_iou, -1.0);
  EXPECT_EQ(none.res.iterations[0].rim_vertices, 0);
  EXPECT_LT(none.acc1, 0.36);  // measured 0.28 (0.47 before #12)
}

TEST(DeformScene, TextureForceFindsAKnownOffset) {
  // Ground-truth vertices pushed 2 px out along the normal: the plane sweep must point
  // back by about -2 px where it sees a clear peak.
  const DeformScene& d = textured_sphere();
  std::vector<Eigen::Vector3d> V, N;
  pushed_out(d, 2.0, V, N);
  const std::vector<double> fp = deform::vertex_footprints(V, d.scene.cams, d.px);
  const photo::Views views(d.scene.cams, d.scene.grey);
  deform::Options o;
  std::vector<deform::TextureProbe> probes;
  const auto f = deform::texture_force(V, N, fp, views, {}, {}, o, photo::Options{}, probes);
  int applied = 0, close = 0;
  for (size_t v = 0; v < V.size(); ++v) {
    EXPECT_TRUE(probes[v].probed);
    if (!probes[v].applied) continue;
    ++applied;
    close += std::abs(probes[v].offset_px + 2.0 * d.px / fp[v]) < 0.5;
    EXPECT_NEAR(f[v].dot(N[v]), probes[v].offset_px * fp[v], 1e-5 * d.px);  // offset_px is a float
  }
  std::printf("  texture probe: %d of %zu applied, %d within 0.5 px of the true offset\n", applied, V.size(), close);
  EXPECT_GT(applied, static_cast<int>(V.size() / 2));
  EXPECT_GT(close, static_cast<int>(0.9 * applied));
  // inactive vertices are not probed and get no force
  std::vector<std::uint8_t> active(V.size(), 0);
  active[0] = 1;
  const auto g = deform::texture_force(V, N, fp, views, {}, active, o, photo::Options{}, probes);
  for (size_t v = 1; v < V.size(); ++v) {
    EXPECT_FALSE(probes[v].probed);
    EXPECT_EQ(g[v], Eigen::Vector3d::Zero());
  }
}

TEST(DeformScene, SagCorrectionRemovesTheConvexBias) {
  // Vertices on the true sphere: the planar patch's best match lies inside a convex
  // surface by its mean sag; with the curvature the mean offset is about zero.
  const DeformScene& d = textured_sphere();
  const std::vector<Eigen::Vector3d> gn = deform::vertex_normals(d.gt.V, d.gt.F);
  const deform::Topology topo = deform::build_topology(d.gt.F, static_cast<int>(d.gt.nv()));
  const std::vector<double> Hall = deform::mean_curvature(d.gt.V, gn, topo, 4);
  std::vector<Eigen::Vector3d> V, N;
  std::vector<double> H;
  for (size_t v = 0; v < d.gt.nv(); v += 23) {
    V.push_back(d.gt.V[v]);
    N.push_back(gn[v]);
    H.push_back(Hall[v]);
  }
  double radius = 0;  // the sphere's radius from its vertices
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& x : d.gt.V) c += x;
  c /= static_cast<double>(d.gt.nv());
  for (const auto& x : d.gt.V) radius += (x - c).norm() / static_cast<double>(d.gt.nv());
  double hsum = 0;
  for (double h : H) hsum += h;
  EXPECT_NEAR(hsum / H.size() * radius, 1.0, 0.05);  // H = 1 / radius
  const std::vector<double> fp = deform::vertex_footprints(V, d.scene.cams, d.px);
  const photo::Views views(d.scene.cams, d.scene.grey);
  deform::Options o;
  std::vector<deform::TextureProbe> plain, sag;
  deform::texture_force(V, N, fp, views, {}, {}, o, photo::Options{}, plain);
  deform::texture_force(V, N, fp, views, {}, {}, o, photo::Options{}, sag, H);
  double m0 = 0, m1 = 0;
  int n = 0;
  for (size_t v = 0; v < V.size(); ++v)
    if (plain[v].applied && sag[v].applied) {
      m0 += plain[v].offset_px;
      m1 += sag[v].offset_px;
      ++n;
    }
  ASSERT_GT(n, static_cast<int>(V.size() / 2));
  m0 /= n;
  m1 /= n;
  std::printf("  mean offset on the true sphere: %.3f px planar, %.3f px with the sag correction (%d vertices)\n", m0, m1, n);
  EXPECT_LT(m0, -0.15);  // the planar patch's inward bias (measured -0.27 px)
  EXPECT_LT(std::abs(m1), std::abs(m0) / 3);  // measured -0.05 px
}

TEST(DeformScene, FarSearchReachesOffsetsBeyondTheRange) {
  // Vertices 4 px outside the sphere with a search range of 2 px: only the wide search
  // (texture_far_px) finds the way back. First with the near search's contrast rule, then
  // with the wide search's own (texture_far_min_contrast 0.1): this test sphere's texture
  // is coarse (the profile stays high for pixels around the peak), so fewer peaks pass,
  // but those that do are right.
  const DeformScene& d = textured_sphere();
  std::vector<Eigen::Vector3d> V, N;
  pushed_out(d, 4.0, V, N);
  const std::vector<double> fp = deform::vertex_footprints(V, d.scene.cams, d.px);
  const photo::Views views(d.scene.cams, d.scene.grey);
  deform::Options o;
  o.texture_range_px = 2;
  const double default_contrast = o.texture_far_min_contrast;
  o.texture_far_min_contrast = o.texture_min_contrast;
  const auto count = [&](double far, int& close) {
    o.texture_far_px = far;
    std::vector<deform::TextureProbe> probes;
    deform::texture_force(V, N, fp, views, {}, {}, o, photo::Options{}, probes);
    int applied = 0;
    close = 0;
    for (size_t v = 0; v < V.size(); ++v) {
      if (!probes[v].applied) continue;
      ++applied;
      close += std::abs(probes[v].offset_px + 4.0 * d.px / fp[v]) < 0.5;
    }
    return applied;
  };
  int close_near = 0, close_far = 0;
  const int near = count(2, close_near), far = count(8, close_far);
  std::printf("  4 px out, range 2 px: %d applied (%d close) without, %d (%d close) with the far search, of %zu\n",
              near, close_near, far, close_far, V.size());
  EXPECT_LT(close_near, static_cast<int>(V.size() / 10));
  EXPECT_GT(close_far, static_cast<int>(V.size() / 2));
  EXPECT_GT(close_far, static_cast<int>(0.85 * far));  // measured 0.90
  o.texture_far_min_contrast = default_contrast;
  int close_strict = 0;
  const int strict = count(8, close_strict);
  std::printf("  with texture_far_min_contrast %.2f: %d applied (%d close)\n", default_contrast, strict, close_strict);
  EXPECT_GT(close_strict, static_cast<int>(V.size() / 5));  // measured 356 of 663 (151 at 0.2)
  EXPECT_GT(close_strict, static_cast<int>(0.8 * strict));  // measured 0.92 (0.85 at 0.2)
}

TEST(DeformScene, SameResultForAnyThreadCount) {
  const DeformScene& d = textured_sphere();
  const TriMesh start = bcc_start_surface(d.gt, 8 * d.px);
  deform::Options o = test_options();
  o.iterations = 3;
  o.texture_start = 1;
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const deform::Result a = deform::deform_mesh(start, d.scene, o, photo::Options{});
  omp_set_num_threads(3);
  const deform::Result b = deform::deform_mesh(start, d.scene, o, photo::Options{});
  omp_set_num_threads(saved);
  ASSERT_EQ(a.mesh.nv(), b.mesh.nv());
  ASSERT_EQ(a.mesh.nf(), b.mesh.nf());
  for (size_t v = 0; v < a.mesh.nv(); ++v) ASSERT_EQ(a.mesh.V[v], b.mesh.V[v]) << v;
  for (size_t f = 0; f < a.mesh.nf(); ++f) ASSERT_EQ(a.mesh.F[f], b.mesh.F[f]) << f;
  EXPECT_EQ(a.iterations.back().mean_texture_score, b.iterations.back().mean_texture_score);
}

TEST(DeformScene, RejectsAnOpenMesh) {
  const DeformScene& d = textured_sphere();
  TriMesh start = bcc_start_surface(d.gt, 8 * d.px);
  start.F.pop_back();
  EXPECT_THROW(deform::deform_mesh(start, d.scene, test_options(), photo::Options{}), Error);
  TriMesh inward = bcc_start_surface(d.gt, 8 * d.px);
  flip_orientation(inward);
  EXPECT_THROW(deform::deform_mesh(inward, d.scene, test_options(), photo::Options{}), Error);
}
