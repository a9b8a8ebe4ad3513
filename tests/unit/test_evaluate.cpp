#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/synth/objects.h"
#include "common/synth/scene.h"
#include "common/label/truth.h"
#include "common/tetmesh/tetmesh.h"
#include "common/trimesh/evaluate.h"

using namespace tetmvs;

namespace {
// Dino-scale scene: a 7 cm box at the origin, 12 ring cameras at 0.65 m, 320 x 240.
struct EvalScene {
  Eigen::AlignedBox3d box{Eigen::Vector3d::Constant(-0.035), Eigen::Vector3d::Constant(0.035)};
  std::vector<Camera> cams;
  Eigen::Vector3d up;
  EvalScene() {
    cams = synth::ring_cameras(12, 20, 0.65, box.center(), 320, 240, 1600);
    up = synth::scene_up(cams, box.center());
  }
  TriMesh object(const std::string& name, double edge = 6e-4) const {
    return synth::make_placed_object(name, box, up, 0.85, edge);
  }
};
EvalOptions opts() {
  EvalOptions o;
  o.spacing = 5e-4;
  o.thresholds = {0.00125, 0.0005, 0.002};
  return o;
}
const RegionResult* region(const EvalResult& r, const std::string& name) {
  for (const auto& x : r.regions)
    if (x.name == name) return &x;
  return nullptr;
}
}  // namespace

TEST(Evaluate, GroundTruthAgainstItself) {
  const EvalScene s;
  const TriMesh gt = s.object("sphere");
  const EvalResult r = evaluate(gt, gt, s.cams, opts());
  EXPECT_LT(r.all.accuracy.at_fraction, 1e-12);
  EXPECT_LT(r.all.accuracy.max, 1e-12);
  EXPECT_EQ(r.all.completeness.within[0], 1.0);
  EXPECT_GT(r.all.completeness.visible_samples, 10000);
  EXPECT_TRUE(r.rec_check.closed);
  EXPECT_EQ(r.rec_check.components.size(), 1u);
  EXPECT_EQ(r.rec_check.components[0].genus, 0);
  // Ring cameras at 20 degrees elevation miss the bottom of the sphere.
  EXPECT_LT(r.all.completeness.visible_samples, r.all.completeness.gt_samples);
  const nlohmann::json j = to_json(r);
  EXPECT_EQ(j["completeness"]["value"], 1.0);
  EXPECT_EQ(j["completeness"]["by_threshold"].size(), 3u);
  EXPECT_EQ(j["regions"][0]["name"], "body");
  EXPECT_EQ(j["reconstruction"]["check"]["closed"], true);
}

TEST(Evaluate, MovedOneMillimetreAlongNormals) {
  const EvalScene s;
  const TriMesh gt = s.object("sphere");
  TriMesh moved = gt;
  for (std::size_t i = 0; i < moved.V.size(); ++i) moved.V[i] += 1e-3 * moved.N[i].cast<double>();
  const EvalResult r = evaluate(moved, gt, s.cams, opts());
  EXPECT_NEAR(r.all.accuracy.at_fraction, 1e-3, 0.03e-3);
  EXPECT_NEAR(r.all.accuracy.p50, 1e-3, 0.03e-3);
  EXPECT_NEAR(r.all.accuracy.mean, 1e-3, 0.03e-3);
  EXPECT_EQ(r.all.completeness.within[0], 1.0);  // 1 mm < 1.25 mm
  EXPECT_EQ(r.all.completeness.within[1], 0.0);  // 1 mm > 0.5 mm
  EXPECT_EQ(r.all.completeness.within[2], 1.0);
  // Inward works the same.
  TriMesh in = gt;
  for (std::size_t i = 0; i < in.V.size(); ++i) in.V[i] -= 1e-3 * in.N[i].cast<double>();
  EXPECT_NEAR(evaluate(in, gt, s.cams, opts()).all.accuracy.at_fraction, 1e-3, 0.03e-3);
}

// Middlebury leaves out the reconstruction's points nearest to the ground truth's unobserved
// parts: a bottom no camera sees, bulged by 3 mm, counts in `accuracy` and not in
// `accuracy_seen`.
TEST(Evaluate, AnUnseenBottomCountsOnlyInTheAccuracyOverAll) {
  const EvalScene s;
  const TriMesh gt = s.object("sphere");
  const auto [lo, hi] = bounds(gt);
  const Eigen::Vector3d c = 0.5 * (lo + hi);
  const double radius = 0.5 * (hi.x() - lo.x());
  TriMesh bulged = gt;
  std::size_t moved = 0;
  for (std::size_t i = 0; i < bulged.V.size(); ++i)
    if ((bulged.V[i] - c).dot(s.up) < -std::sin(75 * M_PI / 180) * radius) {  // below 75 degrees south
      bulged.V[i] += 3e-3 * bulged.N[i].cast<double>();
      ++moved;
    }
  ASSERT_GT(moved, 10u);
  const EvalResult r = evaluate(bulged, gt, s.cams, opts());
  EXPECT_GT(r.all.accuracy.max, 2.5e-3);
  EXPECT_LT(r.all.accuracy_seen.max, 1e-4);
  EXPECT_LT(r.all.accuracy_seen.samples, r.all.accuracy.samples);
  EXPECT_GT(r.all.accuracy_seen.samples, r.all.accuracy.samples * 9 / 10);
  const nlohmann::json j = to_json(r);
  EXPECT_EQ(j["accuracy"]["samples_seen"], r.all.accuracy_seen.samples);
  EXPECT_LT(j["accuracy"]["value_seen"].get<double>(), 1e-4);
  // Seen everywhere, the two agree.
  const EvalResult same = evaluate(gt, gt, s.cams, opts());
  EXPECT_LT(same.all.accuracy_seen.max, 1e-12);
}

TEST(Evaluate, HalfTheSurfaceRemoved) {
  const EvalScene s;
  const TriMesh gt = s.object("sphere");
  std::vector<char> keep(gt.F.size());
  for (std::size_t f = 0; f < gt.F.size(); ++f) keep[f] = gt.V[gt.F[f][0]].x() < s.box.center().x();
  const TriMesh half = submesh(gt, keep);
  const EvalResult r = evaluate(half, gt, s.cams, opts());
  EXPECT_NEAR(r.all.completeness.within[0], 0.5, 0.05);
  EXPECT_LT(r.all.accuracy.at_fraction, 1e-12);  // what is there is exact
  EXPECT_FALSE(r.rec_check.closed);
  EXPECT_EQ(r.rec_check.components[0].boundary_loops, 1);
  // A box region around the kept half: complete there.
  EvalOptions o = opts();
  o.region_box = Eigen::AlignedBox3d(s.box.min(), Eigen::Vector3d(s.box.center().x() - 2e-3, s.box.max().y(), s.box.max().z()));
  const EvalResult rb = evaluate(half, gt, s.cams, o);
  ASSERT_NE(region(rb, "box"), nullptr);
  EXPECT_EQ(region(rb, "box")->completeness.within[0], 1.0);
}

TEST(Evaluate, ConvexLidOfTheCupMissesTheCavity) {
  const EvalScene s;
  const TriMesh cup = s.object("cup");
  // The cup closed by a flat lid at its rim: what a visual hull / minimal surface gives.
  const TriMesh lid = s.object("cup_filled");
  const EvalResult r = evaluate(lid, cup, s.cams, opts());
  const RegionResult* cav = region(r, "cavity");
  const RegionResult* body = region(r, "body");
  ASSERT_NE(cav, nullptr);
  ASSERT_NE(body, nullptr);
  EXPECT_GT(cav->completeness.visible_samples, 1000);
  // The cameras see into the cavity only partly (20 degrees elevation).
  EXPECT_LT(cav->completeness.visible_samples, cav->completeness.gt_samples / 2);
  EXPECT_LT(cav->completeness.within[0], 0.2);
  // The body is complete but for the inner half of the rounded rim, up to 3.9 mm under the lid.
  EXPECT_GT(body->completeness.within[0], 0.95);
  // The lid is far from the ground truth: the accuracy tail shows it.
  EXPECT_GT(r.all.accuracy.p95, 3e-3);
  EXPECT_LT(r.all.accuracy.p50, 1e-4);
  const EvalResult self = evaluate(cup, cup, s.cams, opts());
  EXPECT_EQ(region(self, "cavity")->completeness.within[0], 1.0);
  // Over all of the cavity (unseen samples too): the ground truth itself is complete, the lid
  // is not; the JSON also gives the seen share (the ceiling of value_all for any method).
  EXPECT_EQ(region(self, "cavity")->completeness.within_all, 1.0);
  EXPECT_LT(cav->completeness.within_all, 0.2);
  const nlohmann::json j = to_json(r);
  EXPECT_NEAR(j["regions"][1]["completeness"]["visible_share"].get<double>(),
              double(cav->completeness.visible_samples) / cav->completeness.gt_samples, 1e-12);
  EXPECT_EQ(j["regions"][1]["completeness"]["value_all"].get<double>(), cav->completeness.within_all);
}

TEST(Evaluate, ProtrusionShavedOff) {
  const EvalScene s;
  const TriMesh horn = s.object("horn");
  const TriMesh ball = s.object("horn");
  // Remove the horn, cap nothing: the protrusion's completeness drops, the body's does not.
  const auto& reg = *horn.fprop("region");
  std::vector<char> keep(horn.F.size());
  for (std::size_t f = 0; f < horn.F.size(); ++f) keep[f] = reg[f] != 2.0f;
  const EvalResult r = evaluate(submesh(horn, keep), horn, s.cams, opts());
  ASSERT_NE(region(r, "protrusion"), nullptr);
  EXPECT_LT(region(r, "protrusion")->completeness.within[0], 0.3);
  EXPECT_GT(region(r, "body")->completeness.within[0], 0.99);
}

TEST(Evaluate, PointCloudReconstruction) {
  const EvalScene s;
  const TriMesh gt = s.object("torus");
  TriMesh pc;
  pc.V = gt.V;  // vertices 0.6 mm apart: every surface point within 1.25 mm
  EvalOptions o = opts();
  o.thresholds = {0.00125, 0.0001};
  const EvalResult r = evaluate(pc, gt, s.cams, o);
  EXPECT_TRUE(r.rec_is_point_cloud);
  EXPECT_LT(r.all.accuracy.max, 1e-12);
  EXPECT_EQ(r.all.completeness.within[0], 1.0);
  EXPECT_LT(r.all.completeness.within[1], 0.3);  // but few within 0.1 mm
}

TEST(Evaluate, VisibleCapOfASphereFromOneCamera) {
  const EvalScene s;
  const TriMesh gt = s.object("sphere", 3e-4);
  const SurfaceSamples smp = sample_surface(gt, 3e-4, 2);
  const std::vector<Camera> one = {s.cams[0]};
  const std::vector<int> n = count_visible_views(gt, smp, one, 2.0);
  double vis = 0;
  for (int k : n) vis += k;
  // The cap seen from distance d of a sphere of radius r covers (1 - r/d) / 2 of it.
  const double r = 0.5 * (bounds(gt).second.x() - bounds(gt).first.x()), d = 0.65;
  EXPECT_NEAR(vis / smp.size(), 0.5 * (1 - r / d), 0.01);
}

TEST(Evaluate, ErrorPictureShowsTheError) {
  const EvalScene s;
  const TriMesh gt = s.object("sphere");
  TriMesh moved = gt;
  for (std::size_t i = 0; i < moved.V.size(); ++i)
    if (moved.V[i].x() > 0) moved.V[i] += 2.5e-3 * moved.N[i].cast<double>();
  const cv::Mat img = error_picture(moved, MeshBVH(gt), s.cams, 4, 2.5e-3);
  EXPECT_EQ(img.cols, 640);
  EXPECT_EQ(img.rows, 480 + 40);
  // Red (large error) and blue (no error) pixels both present.
  int red = 0, blue = 0;
  for (int y = 0; y < 480; ++y)
    for (int x = 0; x < 640; ++x) {
      const cv::Vec3b p = img.at<cv::Vec3b>(y, x);
      red += p[0] > 80 && p[1] < 40 && p[2] < 40;
      blue += p[2] > 80 && p[0] < 40 && p[1] < 40;
    }
  EXPECT_GT(red, 500);
  EXPECT_GT(blue, 500);
}

TEST(Evaluate, RejectsBadOptions) {
  const EvalScene s;
  const TriMesh gt = s.object("sphere", 2e-3);
  EvalOptions o = opts();
  o.spacing = 0;
  EXPECT_THROW(evaluate(gt, gt, s.cams, o), Error);
  o = opts();
  o.accuracy_fraction = 1.5;
  EXPECT_THROW(evaluate(gt, gt, s.cams, o), Error);
  o = opts();
  TriMesh empty;
  EXPECT_THROW(evaluate(empty, gt, s.cams, o), Error);
}

// Labels against the ground truth (evaluate --labels): a unit sphere in a BCC mesh of cells
// 0.1 wide, labelled by the exact test on the centroid (nothing wrong), then with known mistakes.
TEST(Evaluate, LabelsAgainstTheTruth) {
  const TriMesh sphere = synth::make_object("sphere", 0.03);
  const MeshBVH gt(sphere);
  const tet::TetMesh m = tet::build_bcc(tet::lattice_for_box(
      Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-1.3), Eigen::Vector3d::Constant(1.3)), 26));
  const double cell = tet::red_edge_length(m.lat, m.max_cell_level());
  std::vector<std::int8_t> lab(m.num_cells(), 0);
  std::vector<std::uint8_t> why(m.num_cells(), 0);
  std::int32_t deep = -1, straddle = -1, far = -1;
  std::int64_t in = 0, out = 0;
  for (std::int32_t c = 0; c < m.num_cells(); ++c) {
    const double r = m.cell_centroid(c).norm();
    if (r < 0.7) lab[c] = 1, why[c] = 4, ++in;           // hidden (interior)
    else if (r > 1.2) lab[c] = -1, why[c] = 2, ++out;    // outside the hull
    if (deep < 0 && r < 0.4) deep = c;
    if (straddle < 0 && std::abs(r - 0.99) < 0.005) straddle = c;
    if (far < 0 && r > 1.25) far = c;
  }
  ASSERT_GE(deep, 0);
  ASSERT_GE(straddle, 0);
  ASSERT_GE(far, 0);
  label::LabelTruth t = label::check_labels(m, lab, why, gt);
  EXPECT_DOUBLE_EQ(t.cell, cell);
  EXPECT_EQ(t.interior.cells, in);
  EXPECT_EQ(t.exterior.cells, out);
  EXPECT_EQ(t.interior.wrong + t.exterior.wrong, 0);
  ASSERT_EQ(t.by_reason.size(), 2u);
  EXPECT_EQ(t.by_reason.at(4).cells, in);

  // mistakes: a deep cell voted out, a cell just inside the surface (its corners outside) voted
  // out, a cell far outside labelled interior by the hull core
  lab[deep] = -1, why[deep] = 3;
  lab[straddle] = -1, why[straddle] = 3;
  lab[far] = 1, why[far] = 7;
  t = label::check_labels(m, lab, why, gt);
  EXPECT_EQ(t.exterior.wrong, 2);
  EXPECT_EQ(t.exterior.wrong_whole, 1);  // the straddling cell is only partly inside
  EXPECT_EQ(t.exterior.deeper_than[0], 1);
  EXPECT_NEAR(t.exterior.deepest, (1 - m.cell_centroid(deep).norm()) / cell, 0.05);
  EXPECT_GT(t.exterior.deepest, 5);
  EXPECT_EQ(t.by_reason.at(3).wrong, 2);
  EXPECT_EQ(t.interior.wrong, 1);
  EXPECT_EQ(t.interior.wrong_whole, 1);
  EXPECT_EQ(t.by_reason.at(7).wrong, 1);
  EXPECT_EQ(t.by_reason.at(4).wrong, 0);
  const nlohmann::json j = label::to_json(t);
  EXPECT_EQ(j["exterior"]["wrong"], 2);
  EXPECT_EQ(j["by_reason"][1]["name"], "voted_out");
  EXPECT_EQ(j["by_reason"][1]["wrong_whole"], 1);
  std::vector<std::int32_t> listed = {deep, straddle, far};
  std::sort(listed.begin(), listed.end());
  EXPECT_EQ(t.wrong_cells, listed);
  EXPECT_EQ(j["wrong_cells"].get<std::vector<std::int32_t>>(), listed);
  EXPECT_FALSE(j["wrong_cells_truncated"].get<bool>());
  std::vector<std::int32_t> whole = {deep, far};
  std::sort(whole.begin(), whole.end());
  EXPECT_EQ(j["wrong_whole_cells"].get<std::vector<std::int32_t>>(), whole);

  EXPECT_THROW(label::check_labels(m, std::vector<std::int8_t>(3, 0), {}, gt), Error);
}
