// Tests of silhouette-fix (common/silfix/): the peak analysis on one ray, the projection
// test, and the whole pass on a constructed horn scene: S1 = the cells inside the ground
// truth minus the protrusion, omega = 1 on faces crossing the ground truth outward. Every
// added constraint is checked against the ground truth (inside test by ray parity), and
// re-cutting with the new labels must recover the protrusion.
#include <gtest/gtest.h>

#include <omp.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "common/cut/graph_cut.h"
#include "common/cut/surface.h"
#include "common/label/hull.h"
#include "common/label/labels.h"
#include "common/params.h"
#include "common/silfix/silfix.h"
#include "common/synth/objects.h"
#include "common/synth/scene.h"
#include "common/tetmesh/locate.h"
#include "common/tetmesh/refine.h"
#include "common/trimesh/bvh.h"
#include "common/trimesh/raster.h"

using namespace tetmvs;

namespace {

// The constructed horn case (built once: a few seconds at most).
struct HornCase {
  TriMesh gt;
  MeshBVH bvh;
  Scene scene;
  tet::TetMesh mesh;
  std::vector<std::uint8_t> in_gt, protrusion;
  std::vector<float> omega;
  std::vector<std::int8_t> label;
  std::vector<std::uint8_t> reason;
  std::int64_t num_protrusion = 0;

  HornCase() {
    gt = synth::make_horn(0.04);  // sphere r 1 at the origin, horn along +z to z = 2.1
    bvh = MeshBVH(gt);
    scene.cams = synth::ring_cameras(12, 20, 8.0, Eigen::Vector3d(0, 0, 0.55), 320, 240, 400);
    for (const auto& cam : scene.cams) scene.sil.push_back(rasterize(gt, cam).tri >= 0);
    scene.rgb.assign(scene.cams.size(), cv::Mat());
    scene.grey.assign(scene.cams.size(), cv::Mat());
    const auto [lo, hi] = bounds(gt);
    scene.box = Eigen::AlignedBox3d(lo, hi);
    Eigen::AlignedBox3d box(lo - Eigen::Vector3d::Constant(0.15), hi + Eigen::Vector3d::Constant(0.15));
    mesh = tet::build_bcc(tet::lattice_for_box(box, 8));
    // refine near the surface: cells of ~5.5 px on the body, ~2.7 px on the horn
    for (int level = 0; level < 3; ++level) {
      std::vector<std::uint8_t> active(mesh.num_cells(), 0);
      for (std::int32_t c = 0; c < mesh.num_cells(); ++c) {
        const double edge = tet::red_edge_length(mesh.lat, mesh.node_level[mesh.cell_node[c]]);
        const Eigen::Vector3d x = mesh.cell_centroid(c);
        active[c] = bvh.closest(x).dist() < 0.8 * edge && (level < 2 || x.z() > 0.8);
      }
      mesh = tet::refine(mesh, active);
    }
    const std::int32_t C = mesh.num_cells();
    in_gt.assign(C, 0);
    protrusion.assign(C, 0);
    for (std::int32_t c = 0; c < C; ++c) {
      const Eigen::Vector3d x = mesh.cell_centroid(c);
      in_gt[c] = bvh.inside(x);
      protrusion[c] = in_gt[c] && x.z() > 1.0;
      num_protrusion += protrusion[c];
    }
    omega.assign(2 * static_cast<std::size_t>(mesh.num_faces()), 0.0f);
    for (std::int32_t f = 0; f < mesh.num_faces(); ++f) {
      const std::int32_t a = mesh.face_cell(f, 0), b = mesh.face_cell(f, 1);
      if (b < 0) continue;
      if (in_gt[a] && !in_gt[b]) omega[2 * f] = 1.0f;
      if (in_gt[b] && !in_gt[a]) omega[2 * f + 1] = 1.0f;
    }
    // Hard labels as `label` makes them: box boundary and visual hull exterior; a core of
    // the body interior.
    label.assign(C, 0);
    reason.assign(C, 0);
    for (std::int32_t f = 0; f < mesh.num_faces(); ++f)
      if (mesh.face_on_boundary(f)) {
        label[mesh.face_cell(f, 0)] = -1;
        reason[mesh.face_cell(f, 0)] = kBoundary;
      }
    const auto hull_out = label::outside_visual_hull(mesh, scene);
    for (std::int32_t c = 0; c < C; ++c) {
      if (label[c] == 0 && hull_out[c]) label[c] = -1, reason[c] = kOutsideHull;
      if (label[c] == 0 && in_gt[c] && mesh.cell_centroid(c).norm() < 0.6) label[c] = 1, reason[c] = kHidden;
    }
  }
  // S1 of an "inside" flag per cell.
  TriMesh surface(const std::vector<std::uint8_t>& inside) const { return cut::cut_surface(mesh, inside); }
};

const HornCase& horn() {
  static const HornCase h;
  return h;
}

struct Tally {
  std::int64_t interior = 0, exterior = 0, wrong = 0, interior_on_protrusion = 0;
};
Tally tally(const HornCase& h, const silfix::Result& r) {
  Tally t;
  for (const auto& k : r.constraints) {
    if (k.kind == silfix::kInteriorKind) {
      ++t.interior;
      t.wrong += !h.in_gt[k.cell];
      t.interior_on_protrusion += h.protrusion[k.cell];
    } else {
      ++t.exterior;
      t.wrong += h.in_gt[k.cell];
    }
  }
  return t;
}

}  // namespace

TEST(SilFix, ProjectionClearOfMask) {
  Camera cam;
  cam.K << 100, 0, 50, 0, 100, 50, 0, 0, 1;
  cam.width = cam.height = 101;
  // a small triangle around pixel (50, 50) at depth 10: corners within ~2 px
  const Eigen::Vector3d X[3] = {cam.backproject(49, 49, 10), cam.backproject(52, 49, 10), cam.backproject(50, 52, 10)};
  cv::Mat mask(101, 101, CV_8U, cv::Scalar(0));
  EXPECT_TRUE(silfix::projection_clear_of_mask(cam, mask, X, 3, 1.0));
  mask.at<std::uint8_t>(50, 54) = 255;  // 2 px right of the hull (x = 52 at most near y = 50)
  EXPECT_TRUE(silfix::projection_clear_of_mask(cam, mask, X, 3, 1.0));
  EXPECT_FALSE(silfix::projection_clear_of_mask(cam, mask, X, 3, 2.5));  // the pad reaches it
  mask.at<std::uint8_t>(50, 50) = 255;  // inside the triangle
  EXPECT_FALSE(silfix::projection_clear_of_mask(cam, mask, X, 3, 0.0));
  // leaving the image is never clear; neither is a point behind the camera
  cv::Mat empty(101, 101, CV_8U, cv::Scalar(0));
  const Eigen::Vector3d Y[3] = {cam.backproject(0.5, 50, 10), cam.backproject(3, 50, 10), cam.backproject(2, 52, 10)};
  EXPECT_FALSE(silfix::projection_clear_of_mask(cam, empty, Y, 3, 1.0));
  const Eigen::Vector3d Z[2] = {X[0], Eigen::Vector3d(0, 0, -1)};
  EXPECT_FALSE(silfix::projection_clear_of_mask(cam, empty, Z, 2, 1.0));
}

TEST(SilFix, PeakIntervalOnOneRay) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(4, 1, 1));
  const tet::TetMesh m = tet::refine_uniform(tet::build_bcc(tet::lattice_for_box(box, 8)), 1);
  const Eigen::Vector3d org(-10, 0.5123, 0.4871), d(1, 0.0013, -0.0007);
  std::vector<tet::WalkHit> hits;
  tet::walk_ray(m, org, d.normalized(), hits);
  ASSERT_GT(hits.size(), 20u);
  const int n = static_cast<int>(hits.size());
  std::vector<std::uint8_t> outside(n, 0);
  outside[0] = outside[n - 1] = 1;
  // front-facing peak on the face entering hit 5, back-facing peak on the face entering hit 15
  std::vector<float> omega(2 * m.num_faces(), 0.1f);
  auto set = [&](int i, bool front, float w) {
    const std::int32_t f = hits[i].face_in, behind = hits[i].cell;
    const bool first_behind = m.face_cell(f, 0) == behind;
    omega[2 * f + ((first_behind == front) ? 0 : 1)] = w;
  };
  set(5, true, 0.9f);
  set(15, false, 0.85f);
  set(18, false, 0.9f);  // the strongest back peak is further: 0.85 >= 0.8 * 0.9 closes first
  silfix::Options o;
  silfix::RayPeaks pk;
  int k = silfix::interior_hit_on_ray(m, omega, hits, outside, o, pk);
  ASSERT_GE(k, 0);
  EXPECT_FLOAT_EQ(pk.omega_front, 0.9f);
  EXPECT_FLOAT_EQ(pk.omega_back, 0.85f);
  EXPECT_DOUBLE_EQ(pk.t_front, hits[5].t_in);
  EXPECT_DOUBLE_EQ(pk.t_back, hits[15].t_in);
  const double tm = 0.5 * (hits[5].t_in + hits[15].t_in);
  EXPECT_LE(hits[k].t_in, tm);
  EXPECT_GT(hits[k].t_out, tm);
  // a stricter ratio skips the weaker back peak
  o.peak_ratio = 0.99;
  k = silfix::interior_hit_on_ray(m, omega, hits, outside, o, pk);
  ASSERT_GE(k, 0);
  EXPECT_DOUBLE_EQ(pk.t_back, hits[18].t_in);
  o.peak_ratio = 0.8;
  // the front-facing orientation of the same faces does not count as a back peak
  std::vector<float> swapped = omega;
  for (int i : {15, 18}) {
    const std::int32_t f = hits[i].face_in;
    std::swap(swapped[2 * f], swapped[2 * f + 1]);
  }
  EXPECT_LT(silfix::interior_hit_on_ray(m, swapped, hits, outside, o, pk), 0);
  EXPECT_EQ(pk.status, 3);
  // weak peaks
  o.min_peak = 0.95;
  EXPECT_LT(silfix::interior_hit_on_ray(m, omega, hits, outside, o, pk), 0);
  EXPECT_EQ(pk.status, 3);
  o.min_peak = 0.5;
  // a hull gap in the middle makes two segments; all outside makes none
  outside[10] = 1;
  EXPECT_LT(silfix::interior_hit_on_ray(m, omega, hits, outside, o, pk), 0);
  EXPECT_EQ(pk.status, 2);
  // ... unless max_gap_cells joins them: the same interval as without the gap
  o.max_gap_cells = 1;
  k = silfix::interior_hit_on_ray(m, omega, hits, outside, o, pk);
  ASSERT_GE(k, 0);
  EXPECT_DOUBLE_EQ(pk.t_front, hits[5].t_in);
  EXPECT_DOUBLE_EQ(pk.t_back, hits[15].t_in);
  outside[11] = 1;  // a gap of two cells is too wide for 1
  EXPECT_LT(silfix::interior_hit_on_ray(m, omega, hits, outside, o, pk), 0);
  EXPECT_EQ(pk.status, 2);
  o.max_gap_cells = 2;
  EXPECT_GE(silfix::interior_hit_on_ray(m, omega, hits, outside, o, pk), 0);
  o.max_gap_cells = 0;
  std::fill(outside.begin(), outside.end(), 1);
  EXPECT_LT(silfix::interior_hit_on_ray(m, omega, hits, outside, o, pk), 0);
  EXPECT_EQ(pk.status, 1);
}

TEST(SilFix, HornConstraintsAreCorrectAndRecutRecoversTheProtrusion) {
  const HornCase& h = horn();
  const std::int32_t C = h.mesh.num_cells();
  ASSERT_GT(h.num_protrusion, 30);
  std::vector<std::uint8_t> inside1(C);
  for (std::int32_t c = 0; c < C; ++c) inside1[c] = h.in_gt[c] && !h.protrusion[c];
  const TriMesh s1 = h.surface(inside1);
  const silfix::Result r = silfix::fix_silhouettes(h.mesh, h.scene, s1, h.omega, h.label, h.reason, {});
  const Tally t = tally(h, r);
  std::cout << "horn: " << C << " cells, " << h.num_protrusion << " protrusion cells; S1 mean IoU " << r.mean_iou
            << "; " << t.interior << " interior (" << t.interior_on_protrusion << " on the protrusion), " << t.exterior
            << " exterior, " << r.conflicts << " conflicts, " << r.already << " already\n";
  EXPECT_EQ(t.wrong, 0);
  EXPECT_GE(t.interior_on_protrusion, 10);
  EXPECT_EQ(r.conflicts, 0);
  EXPECT_LT(r.mean_iou, 0.99);
  // labels: only free cells changed, with the new reasons
  for (std::int32_t c = 0; c < C; ++c)
    if (r.label[c] != h.label[c]) {
      ASSERT_EQ(h.label[c], 0);
      ASSERT_EQ(r.reason[c], r.label[c] > 0 ? kSilfixInterior : kSilfixExterior);
    }

  // Re-cut: with lambda large enough that the cut without the constraints drops the horn
  // (cutting it at its base is cheaper than its photo-consistent surface), the constraints
  // bring most of it back.
  // (measured: lambda 0.1 keeps 32 % of the horn without constraints, 0.15 and 0.2 about
  // 7 %; with them all of it; at 0.3 about 58 % comes back, at 0.5 only the constrained cells)
  const cut::CutOptions opt{0.2, 0.1};
  const auto before = cut::min_cut(h.mesh, h.omega, h.label, opt);
  const auto after = cut::min_cut(h.mesh, h.omega, r.label, opt);
  std::int64_t p0 = 0, p1 = 0, wrong0 = 0, wrong1 = 0, constrained = 0;
  for (std::int32_t c = 0; c < C; ++c) {
    p0 += h.protrusion[c] && before.inside[c];
    p1 += h.protrusion[c] && after.inside[c];
    wrong0 += before.inside[c] != h.in_gt[c] && !h.protrusion[c];
    wrong1 += after.inside[c] != h.in_gt[c] && !h.protrusion[c];
    constrained += h.protrusion[c] && r.label[c] > 0;
  }
  std::cout << "protrusion cells inside: before " << p0 << ", after " << p1 << " of " << h.num_protrusion << " ("
            << constrained << " constrained); wrong cells elsewhere " << wrong0 << " -> " << wrong1 << "\n";
  EXPECT_LT(p0, h.num_protrusion / 5);
  EXPECT_GT(p1, h.num_protrusion * 9 / 10);
  EXPECT_GT(p1, 2 * constrained);  // more than the constrained cells themselves
  EXPECT_LE(wrong1, wrong0 + wrong0 / 10 + 5);
  // S2's silhouettes agree better than S1's
  const silfix::Result r2 = silfix::fix_silhouettes(h.mesh, h.scene, h.surface(after.inside), h.omega, r.label, r.reason, {});
  std::cout << "S2 mean IoU " << r2.mean_iou << "\n";
  EXPECT_GT(r2.mean_iou, r.mean_iou);
}

TEST(SilFix, RimBandOptionsAddManyInteriorCellsNoneWrong) {
  // S1 hugging an inner core, as the hull-core prior makes it on untextured objects: the
  // cells inside the ground truth minus their outer layer, so S1's silhouettes miss a band
  // all along the rim. The rim-band options (segments joined over small gaps, the interval
  // searched for a cell that passes the corner check, dense sampling near the boundary) must
  // add no wrong constraint, more interior ones than the paper's rule, and a re-cut that
  // agrees better with the silhouettes.
  const HornCase& h = horn();
  const std::int32_t C = h.mesh.num_cells();
  // (and without the protrusion, as in the test above)
  std::vector<std::uint8_t> inside1(C);
  for (std::int32_t c = 0; c < C; ++c) inside1[c] = h.in_gt[c] && !h.protrusion[c];
  for (std::int32_t f = 0; f < h.mesh.num_faces(); ++f) {
    const std::int32_t a = h.mesh.face_cell(f, 0), b = h.mesh.face_cell(f, 1);
    if (b < 0) continue;
    if (h.in_gt[a] != h.in_gt[b]) inside1[h.in_gt[a] ? a : b] = 0;
  }
  const TriMesh s1 = h.surface(inside1);
  // band: the settings shipped for dinoRing
  Params params = Params::defaults();
  params.merge_file(std::filesystem::path(TETMVS_SOURCE_DIR) / "examples/params/dinoRing.json");
  const silfix::Options paper, band = silfix::Options::from_params(params);
  ASSERT_TRUE(band.search_interval);
  ASSERT_GT(band.max_gap_cells, 0);
  const silfix::Result r0 = silfix::fix_silhouettes(h.mesh, h.scene, s1, h.omega, h.label, h.reason, paper);
  const silfix::Result r1 = silfix::fix_silhouettes(h.mesh, h.scene, s1, h.omega, h.label, h.reason, band);
  const Tally t0 = tally(h, r0), t1 = tally(h, r1);
  auto multi = [](const silfix::Result& r) {
    std::int64_t n = 0;
    for (const auto& v : r.views) n += v.multi_segment;
    return n;
  };
  const cut::CutOptions opt{0.2, 0.1};
  auto s2_iou = [&](const silfix::Result& r) {
    const auto after = cut::min_cut(h.mesh, h.omega, r.label, opt);
    return silfix::fix_silhouettes(h.mesh, h.scene, h.surface(after.inside), h.omega, r.label, r.reason, paper).mean_iou;
  };
  const double iou0 = s2_iou(r0), iou1 = s2_iou(r1);
  std::cout << "shrunken S1: IoU " << r0.mean_iou << "; paper rule " << t0.interior << " interior, S2 IoU " << iou0
            << "; rim-band options " << t1.interior << " interior (" << multi(r1) << " rays with several segments"
            << " against " << multi(r0) << "), S2 IoU " << iou1 << "\n";
  // measured: S1 IoU 0.934; paper rule 44 interior, rim-band options 352; S2 IoU 0.952 and
  // 0.949 (this mesh's 5.5 px body cells leave a rim band no cell fits in: on dinoRing at
  // 2 px the options take S2 from 0.954 to 0.970, docs/architecture.md)
  EXPECT_LT(r0.mean_iou, 0.97);
  EXPECT_EQ(t0.wrong, 0);
  EXPECT_EQ(t1.wrong, 0);
  EXPECT_EQ(r1.conflicts, 0);
  EXPECT_GT(t1.interior, 4 * t0.interior);
  EXPECT_GT(iou1, iou0 - 0.005);
  for (std::int32_t c = 0; c < C; ++c)
    if (r1.label[c] != h.label[c]) {
      ASSERT_EQ(h.label[c], 0);
    }
}

TEST(SilFix, FalseBlobGetsCorrectExteriorConstraints) {
  // S1 too big: a blob of cells beside the sphere that label left free (as if the hull
  // labels had missed it). Every exterior constraint must be outside the object, and most
  // of the blob must be labelled.
  const HornCase& h = horn();
  const std::int32_t C = h.mesh.num_cells();
  std::vector<std::uint8_t> inside1(C);
  std::vector<std::int8_t> lab = h.label;
  std::vector<std::uint8_t> rea = h.reason;
  std::int64_t blob = 0;
  for (std::int32_t c = 0; c < C; ++c) {
    const bool in_blob = (h.mesh.cell_centroid(c) - Eigen::Vector3d(1.45, 0, -0.2)).norm() < 0.3 && !h.in_gt[c];
    inside1[c] = h.in_gt[c] || in_blob;
    if (in_blob) {
      blob += 1;
      lab[c] = 0;
      rea[c] = 0;
    }
  }
  ASSERT_GT(blob, 20);
  const TriMesh s1 = h.surface(inside1);
  const silfix::Result r = silfix::fix_silhouettes(h.mesh, h.scene, s1, h.omega, lab, rea, {});
  const Tally t = tally(h, r);
  std::int64_t on_blob = 0;
  for (const auto& k : r.constraints)
    if (k.kind == silfix::kExteriorKind) on_blob += (h.mesh.cell_centroid(k.cell) - Eigen::Vector3d(1.45, 0, -0.2)).norm() < 0.3;
  std::cout << "blob: " << blob << " cells, " << t.exterior << " exterior constraints (" << on_blob
            << " on the blob), " << t.interior << " interior, S1 mean IoU " << r.mean_iou << "\n";
  EXPECT_EQ(t.wrong, 0);
  EXPECT_GT(on_blob, blob / 2);
  // the recut drops the blob
  const auto after = cut::min_cut(h.mesh, h.omega, r.label, {0.2, 0.1});
  std::int64_t blob_left = 0;
  for (std::int32_t c = 0; c < C; ++c)
    blob_left += after.inside[c] && (h.mesh.cell_centroid(c) - Eigen::Vector3d(1.45, 0, -0.2)).norm() < 0.3 && !h.in_gt[c];
  EXPECT_EQ(blob_left, 0);
}

TEST(SilFix, DeterministicWhateverTheThreadCount) {
  const HornCase& h = horn();
  std::vector<std::uint8_t> inside1(h.mesh.num_cells());
  for (std::int32_t c = 0; c < h.mesh.num_cells(); ++c) inside1[c] = h.in_gt[c] && !h.protrusion[c];
  const TriMesh s1 = h.surface(inside1);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const auto a = silfix::fix_silhouettes(h.mesh, h.scene, s1, h.omega, h.label, h.reason, {});
  omp_set_num_threads(3);
  const auto b = silfix::fix_silhouettes(h.mesh, h.scene, s1, h.omega, h.label, h.reason, {});
  omp_set_num_threads(threads);
  ASSERT_EQ(a.constraints.size(), b.constraints.size());
  for (std::size_t i = 0; i < a.constraints.size(); ++i) {
    EXPECT_EQ(a.constraints[i].cell, b.constraints[i].cell);
    EXPECT_EQ(a.constraints[i].u, b.constraints[i].u);
    EXPECT_EQ(a.constraints[i].v, b.constraints[i].v);
  }
  EXPECT_EQ(a.label, b.label);
}

TEST(SilFix, ViewPictureColoursAndSheet) {
  cv::Mat truth(40, 60, CV_8U, cv::Scalar(0)), s1(40, 60, CV_8U, cv::Scalar(0));
  cv::rectangle(truth, cv::Rect(10, 10, 20, 20), cv::Scalar(255), cv::FILLED);
  cv::rectangle(s1, cv::Rect(15, 10, 30, 20), cv::Scalar(255), cv::FILLED);
  silfix::Constraint k;
  k.view = 0, k.u = 12, k.v = 20, k.kind = silfix::kInteriorKind;
  const cv::Mat pic = silfix::view_picture(truth, s1, {k}, 0, 2.0);
  ASSERT_EQ(pic.type(), CV_8UC3);
  EXPECT_EQ(pic.at<cv::Vec3b>(15, 20), cv::Vec3b(40, 150, 40));   // both: green
  EXPECT_EQ(pic.at<cv::Vec3b>(15, 40), cv::Vec3b(230, 40, 40));   // S1 only, far: red
  EXPECT_EQ(pic.at<cv::Vec3b>(15, 30), cv::Vec3b(110, 30, 30));   // S1 only, within the margin
  EXPECT_EQ(pic.at<cv::Vec3b>(20, 12), cv::Vec3b(255, 255, 0));   // the constraint's cross
  EXPECT_EQ(pic.at<cv::Vec3b>(13, 12), cv::Vec3b(50, 90, 255));   // true only, beyond the margin: blue
  EXPECT_EQ(pic.at<cv::Vec3b>(5, 5), cv::Vec3b(0, 0, 0));
  const cv::Mat sheet = silfix::contact_sheet({pic, pic, pic}, {"a", "b", "c"}, 120);
  EXPECT_EQ(sheet.cols, 2 * 120);
  EXPECT_GT(sheet.rows, 2 * 80);
}

// label's optional hull-core prior (label.hull_core_px): on the horn scene (12 ring views,
// exact silhouettes) the cells deep inside every silhouette are labelled interior, none of
// them outside the ground truth, most of the object's volume is covered, and a point of Q
// inside the core is dropped while one on the surface is kept.
TEST(LabelHullCore, CoreCellsAreInsideAndFalseMatchesAreDropped) {
  const HornCase& h = horn();
  QPoints q;
  const std::vector<std::int32_t> cams{0, 1, 2, 3};
  q.add(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), 0.95f, cams, -1);      // deep inside
  q.add(Eigen::Vector3d(1.0, 0, 0), Eigen::Vector3d(1, 0, 0), 0.95f, cams, -1);    // on the sphere
  label::Options o;
  o.hull_core_px = 0;
  const label::Result off = label::label_cells(h.mesh, h.scene, q, o);
  EXPECT_EQ(off.count(label::Rule::kHullCore), 0);
  EXPECT_EQ(off.count(label::Filter::kInHullCore), 0);
  o.hull_core_px = 2;
  const label::Result on = label::label_cells(h.mesh, h.scene, q, o);
  EXPECT_EQ(on.count(label::Filter::kInHullCore), 1);
  std::int64_t core = 0, wrong = 0;
  double core_volume = 0, gt_volume = 0;
  for (std::int32_t c = 0; c < h.mesh.num_cells(); ++c) {
    if (h.in_gt[c]) gt_volume += h.mesh.cell_volume(c);
    if (on.reason[c] != kHullCore) continue;
    ++core;
    EXPECT_EQ(on.label[c], 1);
    wrong += !h.in_gt[c];
    core_volume += h.mesh.cell_volume(c);
  }
  std::printf("hull core: %lld cells, %lld outside the object, %.3f of its volume\n", (long long)core,
              (long long)wrong, core_volume / gt_volume);
  EXPECT_EQ(on.count(label::Rule::kHullCore), core);
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(core_volume, 0.5 * gt_volume);
}
