// Tests of the photo-consistency measure (common/photo/) on synthetic images rendered
// here: a textured plane seen by 8 pinhole cameras in a cone around its normal.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>

#include "common/error.h"
#include "common/image.h"
#include "common/photo/camera_select.h"
#include "common/photo/ncc.h"
#include "common/photo/face_score.h"
#include "common/photo/lattice.h"
#include "common/photo/oriented_point.h"
#include "common/photo/patch.h"
#include "test_photo_scene.h"

using namespace tetmvs;
using namespace tetmvs::photo;
using tetmvs::testing::PlaneScene;

namespace {
const std::vector<double> kPolar = {20, 32, 24, 35, 20, 30, 26, 34};

Eigen::Vector3d rotate(const Eigen::Vector3d& v, const Eigen::Vector3d& axis, double deg) {
  return Eigen::AngleAxisd(deg * std::numbers::pi / 180, axis.normalized()) * v;
}

// One scene per normal, rendered once for the whole test binary.
const PlaneScene& scene(int which) {
  static const PlaneScene s0(Eigen::Vector3d(0, 0, 1), kPolar);
  static const PlaneScene s1(rotate(Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(1, -1, 0), 9), kPolar);
  static const PlaneScene s2(rotate(Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 1), 14), kPolar);
  return which == 0 ? s0 : which == 1 ? s1 : s2;
}
const Views& views(int which) {
  static const Views v0(scene(0).cams, scene(0).grey), v1(scene(1).cams, scene(1).grey),
      v2(scene(2).cams, scene(2).grey);
  return which == 0 ? v0 : which == 1 ? v1 : v2;
}

// Points on the plane of scene s near its centre (offsets of a few texture cells).
std::vector<Eigen::Vector3d> surface_points(const PlaneScene& s) {
  const Eigen::Vector3d e1 = stable_perpendicular(s.N), e2 = s.N.cross(e1);
  std::vector<Eigen::Vector3d> p;
  for (double a : {-0.17, 0.0, 0.11})
    for (double b : {-0.13, 0.07}) p.push_back(s.O + a * e1 + b * e2);
  return p;
}
// Normals of mesh faces crossing the surface at those points. The 1 x mu line lies
// along n_X x n_f: for a face whose normal is in the plane of N and the nearest
// orientation n_c (eps = 0), the lines of every orientation in that plane lie on the
// surface and the orientation is not observable. Turning the face by eps about N
// tilts each orientation's line off the surface by about eps * sin(angle(n_X, N)):
// the nearest orientation's line stays on the surface, the others' leave it.
std::vector<Eigen::Vector3d> crossing_face_normals(const Eigen::Vector3d& N) {
  const Eigen::Vector3d nc = orientations()[nearest_orientation(N)];
  Eigen::Vector3d q = N.cross(nc);
  if (q.norm() < 1e-9) q = stable_perpendicular(N);
  const Eigen::Vector3d p = q.normalized(), u = p.cross(N);
  std::vector<Eigen::Vector3d> out;
  for (double eps : {30.0, -30.0, 50.0, 150.0}) {
    const double e = eps * std::numbers::pi / 180;
    out.push_back(std::cos(e) * u + std::sin(e) * p);
  }
  return out;
}
std::vector<Eigen::Vector3d> face_normals() {
  return {Eigen::Vector3d(0.8, 0.3, 0.52).normalized(), Eigen::Vector3d(-0.2, 0.9, 0.4).normalized(),
          Eigen::Vector3d(0.45, -0.55, -0.7).normalized()};
}
}  // namespace

TEST(PhotoViews, RejectsBadInputs) {
  const PlaneScene& s = scene(0);
  std::vector<cv::Mat> g = s.grey;
  g.pop_back();
  EXPECT_THROW(Views(s.cams, g), Error);
  g = s.grey;
  g[2] = cv::Mat(10, 10, CV_32F, cv::Scalar(0));
  EXPECT_THROW(Views(s.cams, g), Error);
  g = s.grey;
  cv::Mat u8;
  g[1].convertTo(u8, CV_8U, 255);
  g[1] = u8;
  EXPECT_THROW(Views(s.cams, g), Error);
  const Views v(s.cams, s.grey);
  EXPECT_EQ(v.size(), 8);
  // The stored projection gives the camera's pixel, and z = depth.
  const Eigen::Vector3d X(0.1, -0.2, 0.05);
  for (int i = 0; i < v.size(); ++i) {
    const Eigen::Vector3d h = v[i].project_h(X);
    EXPECT_NEAR((h.head<2>() / h.z() - s.cams[i].project(X)).norm(), 0.0, 1e-9);
    EXPECT_NEAR(h.z(), s.cams[i].depth(X), 1e-12);
  }
}

TEST(CameraSelect, ConeOrderAndTies) {
  constexpr double kDeg = std::numbers::pi / 180;
  const PlaneScene& s = scene(0);
  const Views& v = views(0);
  Options o;
  // Straight up: every camera is within 35 deg of +z; sorted by angle, ties by index.
  auto c = select_cameras(v, s.O, Eigen::Vector3d(0, 0, 1), o);
  ASSERT_EQ(c.size(), 8u);
  for (size_t i = 1; i < c.size(); ++i) EXPECT_TRUE(better_candidate(c[i - 1], c[i]));
  // Cameras 0 and 4 are both at polar 20 deg (exact tie by symmetry up to rounding).
  EXPECT_TRUE((c[0].view == 0 && c[1].view == 4) || (c[0].view == 4 && c[1].view == 0));
  for (const auto& x : c) {
    const Eigen::Vector3d d = (s.cams[x.view].centre() - s.O).normalized();
    EXPECT_NEAR(x.cos, d.z(), 1e-12);
  }
  // A narrow cone keeps only the cameras at polar <= 25 deg.
  o.cone_deg = 25;
  c = select_cameras(v, s.O, Eigen::Vector3d(0, 0, 1), o);
  std::set<int> got;
  for (const auto& x : c) got.insert(x.view);
  EXPECT_EQ(got, (std::set<int>{0, 2, 4}));
  // Downward normal: nothing within 60 deg.
  EXPECT_TRUE(select_cameras(v, s.O, Eigen::Vector3d(0, 0, -1), Options{}).empty());
  // A normal tilted 50 deg from the cameras' axis: the default cone admits cameras up to
  // 75 deg from it, which a 60 deg cone (the paper's) leaves out, and no camera beyond.
  const Eigen::Vector3d tilted(std::sin(50 * kDeg), 0, std::cos(50 * kDeg));
  const auto wide = select_cameras(v, s.O, tilted, Options{});
  Options paper;
  paper.cone_deg = 60;
  const auto narrow = select_cameras(v, s.O, tilted, paper);
  EXPECT_GT(wide.size(), narrow.size());
  for (const auto& x : wide) EXPECT_GE(x.cos, std::cos(75 * kDeg) - 1e-12);
  for (const auto& x : narrow) EXPECT_GE(x.cos, std::cos(60 * kDeg) - 1e-12);
  // Exact ties resolve by index: two identical cameras.
  std::vector<Camera> cams = {s.cams[1], s.cams[1], s.cams[3]};  // polar 32, 32, 35 deg
  std::vector<cv::Mat> grey = {s.grey[1], s.grey[1], s.grey[3]};
  const Views tie(cams, grey);
  c = select_cameras(tie, s.O, Eigen::Vector3d(0, 0, 1), Options{});
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0].cos, c[1].cos);
  EXPECT_EQ(c[0].view, 0);
  EXPECT_EQ(c[1].view, 1);
  EXPECT_EQ(c[2].view, 2);
}

TEST(CameraSelect, PointOutsideImageOrSilhouetteDropsTheView) {
  const PlaneScene& s = scene(0);
  // A point far to the side projects outside some images.
  const Eigen::Vector3d X(1.3, 0.0, 0.0);
  const auto c = select_cameras(views(0), X, Eigen::Vector3d(0, 0, 1), Options{});
  int inside = 0;
  for (const auto& cam : s.cams) inside += cam.sees(X);
  EXPECT_LT(inside, 8);
  EXPECT_EQ(static_cast<int>(c.size()), inside);
  // Silhouettes: view 2's silhouette excludes everything -> dropped when asked.
  std::vector<cv::Mat> sil(8);
  sil[2] = cv::Mat(s.grey[2].size(), CV_8U, cv::Scalar(0));
  sil[5] = cv::Mat(s.grey[5].size(), CV_8U, cv::Scalar(255));
  const Views vs(s.cams, s.grey, sil);
  EXPECT_TRUE(vs.has_silhouettes());
  Options o;
  EXPECT_EQ(select_cameras(vs, s.O, Eigen::Vector3d(0, 0, 1), o).size(), 8u);
  o.use_silhouettes = true;
  const auto cs = select_cameras(vs, s.O, Eigen::Vector3d(0, 0, 1), o);
  EXPECT_EQ(cs.size(), 7u);
  for (const auto& x : cs) EXPECT_NE(x.view, 2);
}

TEST(PointScore, OnSurfaceHighWithNearestOrientation) {
  Options o;
  o.mu = 11;  // the paper's 1 x 11 line and 60 degree cone
  o.cone_deg = 60;
  Scratch scratch;
  for (int w = 0; w < 3; ++w) {
    const PlaneScene& s = scene(w);
    const int expect = nearest_orientation(s.N);
    for (const auto& X : surface_points(s))
      for (const auto& nf : crossing_face_normals(s.N)) {
        std::array<float, kNumOrientations> per;
        const PointResult r = score_point(views(w), X, nf, o, scratch, &per);
        ASSERT_TRUE(r.valid());
        EXPECT_GT(r.score, 0.9f) << "scene " << w << " X " << X.transpose();
        EXPECT_TRUE(r.consistent(o));
        EXPECT_EQ(r.orientation, expect) << "scene " << w << " X " << X.transpose() << " nf "
                                         << nf.transpose() << " score " << r.score << " vs "
                                         << per[expect];
        EXPECT_EQ(r.score, per[r.orientation]);
        EXPECT_EQ(r.num_partners, o.k_prime());
        EXPECT_EQ(r.num_views, o.k);
        // The reference and its partners are distinct views within the cone.
        std::set<int> cams = {r.ref};
        for (int i = 0; i < r.num_partners; ++i) cams.insert(r.partners[i]);
        EXPECT_EQ(static_cast<int>(cams.size()), 1 + o.k_prime());
        for (int c : cams) {
          const Eigen::Vector3d d = (s.cams[c].centre() - X).normalized();
          EXPECT_GE(d.dot(r.normal()), std::cos(60 * std::numbers::pi / 180) - 1e-12);
        }
        // Samples one pixel apart in the finest view.
        EXPECT_NEAR(r.spacing, s.footprint, 0.1 * s.footprint);
        // Orientations facing away from every camera have no score.
        for (int i = 0; i < kNumOrientations; ++i)
          if (orientations()[i].dot(s.N) < -0.2) {
            EXPECT_EQ(per[i], kNoScore);
          }
      }
  }
}

TEST(PointScore, OffSurfaceLow) {
  // The 1 x 11 line sees only a few independent texture values, and the score is a
  // maximum over 14 orientations and k references: away from the surface it is a
  // chance value (mean ~0.5 here, docs/photo.md), not ~0. So this test checks the
  // distribution over 100 points, and the 2-D patch (121 samples) point by point.
  Options o;
  o.mu = 11;  // the paper's mu and cone
  o.cone_deg = 60;
  Scratch scratch;
  for (int w = 0; w < 3; ++w) {
    const PlaneScene& s = scene(w);
    const Eigen::Vector3d e1 = stable_perpendicular(s.N), e2 = s.N.cross(e1);
    double on_sum = 0, off_sum = 0;
    int on_n = 0, off_n = 0, off_above_08 = 0, on_above_09 = 0;
    for (int i = 0; i < 100; ++i) {
      const double a = -0.4 + 0.8 * ((i * 37) % 100) / 100.0, b = -0.3 + 0.6 * ((i * 61) % 100) / 100.0;
      const Eigen::Vector3d nf(std::sin(i * 1.3), std::cos(i * 2.1), std::sin(i * 0.7 + 1));
      const Eigen::Vector3d X0 = s.O + a * e1 + b * e2;
      const PointResult on = score_point(views(w), X0, nf, o, scratch);
      ASSERT_TRUE(on.valid());
      on_sum += on.score, ++on_n, on_above_09 += on.score > 0.9f;
      const double px = (i % 2 ? 1 : -1) * (i % 4 < 2 ? 10.0 : 20.0);
      const PointResult off = score_point(views(w), X0 + px * s.footprint * s.N, nf, o, scratch);
      ASSERT_TRUE(off.valid());
      off_sum += off.score, ++off_n, off_above_08 += off.score > 0.8f;
    }
    EXPECT_GE(on_above_09, 97) << "scene " << w;
    EXPECT_GT(on_sum / on_n, 0.95) << "scene " << w;
    EXPECT_LT(off_sum / off_n, 0.6) << "scene " << w;
    EXPECT_LE(off_above_08, 10) << "scene " << w;
    // The 2-D patch separates point by point.
    for (double px : {-8.0, 8.0, 15.0})
      for (const auto& X0 : surface_points(s)) {
        const PatchResult r = score_patch(views(w), X0 + px * s.footprint * s.N, s.N, o, scratch);
        ASSERT_TRUE(r.valid());
        EXPECT_LT(r.score, 0.4f) << "scene " << w << " offset " << px << " px, X " << X0.transpose();
        EXPECT_GT(score_patch(views(w), X0, s.N, o, scratch).score, 0.95f);
      }
  }
}

// score_offset re-scores the best orientation in the same views: at offset 0 it is the
// point's own score, and on a textured plane the score falls off either way along the normal
// (the crest band_probe counts).
TEST(PointScore, ScoreOffsetIsTheSameMeasureMovedAlongTheNormal) {
  Options o;
  o.mu = 11;
  Scratch scratch;
  const PlaneScene& s = scene(0);
  for (const auto& X : surface_points(s))
    for (const auto& nf : crossing_face_normals(s.N)) {
      const PointResult r = score_point(views(0), X, nf, o, scratch);
      ASSERT_TRUE(r.valid());
      EXPECT_NEAR(score_offset(views(0), X, nf, r, 0.0, o, scratch), r.score, 1e-6f);
      EXPECT_LT(score_offset(views(0), X, nf, r, -4.0, o, scratch), r.score);
      EXPECT_LT(score_offset(views(0), X, nf, r, 4.0, o, scratch), r.score);
    }
  EXPECT_EQ(score_offset(views(0), s.O, s.N, PointResult{}, 1.0, o, scratch), kNoScore);
}

TEST(PointScore, TooFewCamerasMeansNoScore) {
  const PlaneScene& s = scene(0);
  std::vector<Camera> cams(s.cams.begin(), s.cams.begin() + 3);
  std::vector<cv::Mat> grey(s.grey.begin(), s.grey.begin() + 3);
  const Views v(cams, grey);
  Scratch scratch;
  const PointResult r = score_point(v, s.O, face_normals()[0], Options{}, scratch);
  EXPECT_FALSE(r.valid());
  EXPECT_EQ(r.score, kNoScore);
  EXPECT_EQ(r.orientation, -1);
  EXPECT_FALSE(r.consistent(Options{}));
  // Four cameras are enough for k' = 3.
  cams.push_back(s.cams[3]);
  grey.push_back(s.grey[3]);
  const Views v4(cams, grey);
  const PointResult r4 = score_point(v4, s.O, face_normals()[0], Options{}, scratch);
  ASSERT_TRUE(r4.valid());
  EXPECT_EQ(r4.num_views, 4);
  EXPECT_GT(r4.score, 0.9f);
}

TEST(PointScore, PatchLeavingTheImageDropsTheView) {
  // A point near the border of some images: its centre is inside them but the
  // 11-sample line is not; those views are skipped and the next candidates used.
  const PlaneScene& s = scene(0);
  Options o;
  o.k = 4;
  Scratch scratch;
  int tested = 0;
  for (double x = 0.5; x < 1.6 && !tested; x += 0.01) {
    const Eigen::Vector3d X(x, 0.0, 0.0);
    // Views whose centre test passes but whose border margin is < 5 px.
    int edge = 0;
    for (const auto& c : s.cams)
      if (c.sees(X, 0.0) && !c.sees(X, 6.0)) ++edge;
    if (edge == 0) continue;
    const PatchResult r = score_line(views(0), X, Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 1, 0), o, scratch);
    if (!r.valid()) continue;
    ++tested;
    for (int i = 0; i < r.num_views; ++i) {
      EXPECT_TRUE(s.cams[r.views[i]].sees(X, 4.0)) << "view " << r.views[i] << " x " << x;
    }
    EXPECT_GT(r.score, 0.9f);
  }
  EXPECT_EQ(tested, 1);
}

TEST(PointScore, DeterministicAndBatchMatches) {
  const PlaneScene& s = scene(1);
  std::vector<double> X, nf;
  for (const auto& p : surface_points(s))
    for (const auto& n : face_normals())
      for (double off : {0.0, 0.03}) {
        const Eigen::Vector3d q = p + off * s.N;
        X.insert(X.end(), {q.x(), q.y(), q.z()});
        nf.insert(nf.end(), {n.x(), n.y(), n.z()});
      }
  const long n = static_cast<long>(X.size() / 3);
  std::vector<PointResult> batch(n);
  score_points(views(1), X.data(), nf.data(), n, Options{}, batch.data());
  Scratch scratch;
  for (long i = 0; i < n; ++i) {
    const PointResult r = score_point(views(1), Eigen::Vector3d(X[3 * i], X[3 * i + 1], X[3 * i + 2]),
                                      Eigen::Vector3d(nf[3 * i], nf[3 * i + 1], nf[3 * i + 2]), Options{},
                                      scratch);
    EXPECT_EQ(r.score, batch[i].score);
    EXPECT_EQ(r.orientation, batch[i].orientation);
    EXPECT_EQ(r.ref, batch[i].ref);
    EXPECT_EQ(r.partners, batch[i].partners);
  }
}

TEST(FaceScore, OutwardHighInwardZero) {
  Options o;
  Scratch scratch;
  for (int w = 0; w < 3; ++w) {
    const PlaneScene& s = scene(w);
    const Eigen::Vector3d e1 = stable_perpendicular(s.N), e2 = s.N.cross(e1);
    for (double size : {0.5, 3.0, 20.0}) {  // triangle size in pixels (patch is 11 px)
      const double h = size * s.footprint;
      const Eigen::Vector3d a = s.O + 0.05 * e1, b = a + h * e1, c = a + h * (0.5 * e1 + 0.9 * e2);
      ASSERT_GT(triangle_normal(a, b, c).dot(s.N), 0.99);
      const PatchResult out = face_patch(views(w), a, b, c, o, scratch);
      ASSERT_TRUE(out.valid());
      EXPECT_GT(out.omega(), 0.9f) << "scene " << w << " size " << size;
      EXPECT_EQ(face_score(views(w), a, b, c, o, scratch), out.omega());
      // The inward orientation (b, c swapped) faces away from all cameras.
      const PatchResult in = face_patch(views(w), a, c, b, o, scratch);
      EXPECT_FALSE(in.valid());
      EXPECT_EQ(in.omega(), 0.0f);
      EXPECT_EQ(face_score(views(w), a, c, b, o, scratch), 0.0f);
    }
  }
}

TEST(FaceScore, BothOrientationsAtOnceMatchTwoPatches) {
  Options o;
  Scratch scratch;
  for (int w = 0; w < 3; ++w) {
    const PlaneScene& s = scene(w);
    const Eigen::Vector3d e1 = stable_perpendicular(s.N), e2 = s.N.cross(e1);
    for (double tilt : {0.0, 0.4, -0.7}) {  // faces across the plane too: both sides may see views
      const double h = 5.0 * s.footprint;
      const Eigen::Vector3d a = s.O + 0.03 * e2, b = a + h * e1 + tilt * h * s.N, c = a + h * (0.3 * e1 + e2);
      PatchResult front, back;
      face_patches(views(w), a, b, c, o, scratch, front, back);
      const PatchResult f1 = face_patch(views(w), a, b, c, o, scratch), b1 = face_patch(views(w), a, c, b, o, scratch);
      EXPECT_EQ(front.valid(), f1.valid());
      EXPECT_EQ(back.valid(), b1.valid());
      EXPECT_NEAR(front.omega(), f1.omega(), 1e-5f) << w << " " << tilt;
      EXPECT_NEAR(back.omega(), b1.omega(), 1e-5f) << w << " " << tilt;
      EXPECT_EQ(front.ref, f1.ref);
      EXPECT_EQ(back.ref, b1.ref);
    }
  }
  PatchResult front, back;
  face_patches(views(0), scene(0).O, scene(0).O, scene(0).O + Eigen::Vector3d(0.1, 0, 0), o, scratch, front, back);
  EXPECT_FALSE(front.valid());
  EXPECT_FALSE(back.valid());
}

TEST(FaceScore, TiltedOrOffsetFacesScoreLower) {
  Options o;
  o.mu = 11;  // the paper's 11 x 11 (the default 7 x 7 leaves the surface less when tilted)
  Scratch scratch;
  const PlaneScene& s = scene(0);
  const Views& v = views(0);
  // A face 8 px off the surface: low.
  for (double px : {8.0, -8.0}) {
    const Eigen::Vector3d c = s.O + Eigen::Vector3d(0.02, -0.03, px * s.footprint);
    const PatchResult r = score_patch(v, c, s.N, o, scratch);
    ASSERT_TRUE(r.valid());
    EXPECT_LT(r.omega(), 0.4f) << px;
  }
  // Tilting the patch normal away from the true one lowers the score monotonically
  // (the 11x11 patch leaves the surface by up to 5 px sin(tilt)).
  float prev = 2.f;
  for (double deg : {0.0, 15.0, 30.0, 45.0}) {
    const Eigen::Vector3d n = rotate(s.N, Eigen::Vector3d(1, 0.3, 0), deg);
    const PatchResult r = score_patch(v, s.O, n, o, scratch);
    ASSERT_TRUE(r.valid()) << deg;
    EXPECT_LT(r.score, prev) << deg;
    prev = r.score;
  }
  EXPECT_LT(prev, 0.85f);
  // Zero normal and degenerate triangles are invalid, never NaN.
  EXPECT_FALSE(score_patch(v, s.O, Eigen::Vector3d::Zero(), o, scratch).valid());
  EXPECT_FALSE(face_patch(v, s.O, s.O, s.O + Eigen::Vector3d(0.1, 0, 0), o, scratch).valid());
  EXPECT_EQ(face_score(v, s.O, s.O, s.O + Eigen::Vector3d(0.1, 0, 0), o, scratch), 0.0f);
}

TEST(FaceScore, OmegaTruncatesToUnitInterval) {
  PatchResult r;
  EXPECT_EQ(r.omega(), 0.0f);
  r.ref = 1;
  r.score = -0.3f;
  EXPECT_EQ(r.omega(), 0.0f);
  r.score = 0.45f;
  EXPECT_EQ(r.omega(), 0.45f);
  r.score = 1.0f;
  EXPECT_EQ(r.omega(), 1.0f);
}

TEST(PhotoLattice, PointsAndDivisions) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  std::vector<Eigen::Vector3d> p;
  triangle_lattice(a, b, c, 4, p);
  ASSERT_EQ(p.size(), 15u);
  EXPECT_EQ(p.front(), a);
  EXPECT_EQ(p[4], b);
  EXPECT_EQ(p.back(), c);
  for (const auto& q : p) EXPECT_LE(q.x() + q.y(), 1.0 + 1e-12);
  // Children of the midpoint split reuse the parent's points when n is even.
  std::vector<Eigen::Vector3d> child;
  triangle_lattice(a, (a + b) / 2, (a + c) / 2, 2, child);
  for (const auto& q : child)
    EXPECT_TRUE(std::any_of(p.begin(), p.end(), [&](const auto& r) { return (r - q).norm() < 1e-12; }));
  // Divisions: every edge at most one pixel per lattice step in every view.
  const PlaneScene& s = scene(0);
  const Eigen::Vector3d A(-0.1, -0.1, 0), B(0.15, -0.1, 0), C(0, 0.2, 0);
  const int n = lattice_divisions(views(0), A, B, C);
  double longest = 0;
  for (const auto& cam : s.cams)
    for (auto [P, Q] : {std::pair{A, B}, {B, C}, {C, A}})
      longest = std::max(longest, (cam.project(P) - cam.project(Q)).norm());
  EXPECT_EQ(n, static_cast<int>(std::ceil(longest)));
  EXPECT_EQ(lattice_divisions(views(0), A, B, C, 4.0), static_cast<int>(std::ceil(longest / 4)));
  EXPECT_NEAR(finest_footprint(views(0), s.O), s.footprint, 1e-12);
  EXPECT_TRUE(std::isinf(finest_footprint(views(0), Eigen::Vector3d(0, 0, 10))));
}

TEST(PointScore, PatchNormalParallelToFaceNormalUsesAStableLine) {
  // n_X || n_f: the line is stable_perpendicular(n_f), in the face plane; for a face
  // lying on the surface that line is on the surface.
  const PlaneScene& s = scene(0);
  Scratch scratch;
  for (const auto& X : surface_points(s)) {
    const PatchResult a = score_line(views(0), X, s.N, s.N, Options{}, scratch);
    const PatchResult b = score_line(views(0), X, s.N, -3.0 * s.N, Options{}, scratch);
    ASSERT_TRUE(a.valid());
    EXPECT_GT(a.score, 0.9f);
    EXPECT_EQ(a.score, score_line(views(0), X, s.N, s.N, Options{}, scratch).score);
    // -n_f gives the same face plane and the perpendicular of -n_f: still on the surface.
    ASSERT_TRUE(b.valid());
    EXPECT_GT(b.score, 0.9f);
    // Off the surface the score stays a number (never NaN).
    EXPECT_FALSE(std::isnan(score_line(views(0), X + 10 * s.footprint * s.N, s.N, s.N, Options{}, scratch).score));
  }
}

// ---------------------------------------------------------------------------------------
// The optimized kernel (transposed samples, SIMD lanes, fast bilinear path, branch-free
// top-k') must give bit-identical results to the straightforward formulation of
// docs/photo.md: per view sample_bilinear + normalize_patch, per pair ncc_normalized,
// per reference a sort of its row. The reference below is that formulation.
namespace {
PatchResult reference_patch(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& n,
                            const Eigen::Vector3d& a1, const Eigen::Vector3d* a2, const Options& o) {
  PatchResult out;
  std::vector<Candidate> cand = select_cameras(views, X, n, o);
  const int m = static_cast<int>(cand.size()), k = o.k;
  const int need = o.adaptive_k ? std::min(o.k_prime() + 1, 4) : o.k_prime() + 1;
  int kp = o.k_prime();
  const int top = std::min(m, k);
  double spacing = std::numeric_limits<double>::infinity();
  for (int i = 0; i < top; ++i) {
    const View& v = views[cand[i].view];
    spacing = std::min(spacing, v.project_h(X).z() * v.inv_focal);
  }
  if (top > 0) out.spacing = static_cast<float>(spacing);
  if (m < need) return out;
  const int mu = o.mu, ns = a2 ? mu * mu : mu, c = mu / 2;
  const Eigen::Vector3d d1 = a1 * spacing, d2 = a2 ? Eigen::Vector3d(*a2 * spacing) : Eigen::Vector3d::Zero();
  std::vector<std::vector<float>> rows;
  std::vector<int> used;
  for (int ci = 0; ci < m && static_cast<int>(used.size()) < k; ++ci) {
    if (static_cast<int>(used.size()) + (m - ci) < need) break;
    const View& v = views[cand[ci].view];
    const Eigen::Vector3d h0 = v.project_h(X), b1 = v.project_dir(d1), b2 = v.project_dir(d2);
    std::vector<float> row(ns);
    bool ok = true;
    if (a2) {
      // grid: the affine projection about the centre (detail::grid_axes)
      ok = h0.z() > 0;
      const detail::GridAxes g = ok ? detail::grid_axes(h0, b1, b2) : detail::GridAxes{};
      for (int j = 0; j < mu && ok; ++j)
        for (int i = 0; i < mu && ok; ++i) {
          const double ti = static_cast<double>(i - c), tj = static_cast<double>(j - c);
          ok = sample_bilinear(v.grey, (g.u0 + tj * g.du2) + ti * g.du1, (g.v0 + tj * g.dv2) + ti * g.dv1, row[j * mu + i]);
        }
    } else {
      // line: every sample projected exactly
      for (int i = 0; i < mu && ok; ++i) {
        const Eigen::Vector3d h = h0 + static_cast<double>(i - c) * b1;
        ok = h.z() > 0;
        if (ok) {
          const double iw = 1.0 / h.z();
          ok = sample_bilinear(v.grey, h.x() * iw, h.y() * iw, row[i]);
        }
      }
    }
    if (!ok) continue;
    if (o.detrend)
      normalize_patch_detrended(row.data(), mu, a2 ? mu : 1, static_cast<float>(o.min_std), row.data());
    else
      normalize_patch(row.data(), ns, static_cast<float>(o.min_std), row.data());
    rows.push_back(row);
    used.push_back(cand[ci].view);
  }
  const int u = static_cast<int>(used.size());
  if (u < need) return out;
  if (o.adaptive_k && u < k) kp = o.partners > 0 ? std::max(1, u - 1 - (k - 1 - o.partners)) : std::max(u / 2, 3);
  float best = -std::numeric_limits<float>::infinity();
  for (int r = 0; r < u; ++r) {
    std::vector<std::pair<float, int>> row;
    for (int j = 0; j < u; ++j)
      if (j != r) row.emplace_back(ncc_normalized(rows[r].data(), rows[j].data(), ns), j);
    std::sort(row.begin(), row.end(),
              [](const auto& a, const auto& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); });
    float sum = 0.f;
    for (int t = 0; t < kp; ++t) sum += row[t].first;
    const float mean = sum / static_cast<float>(kp);
    if (mean > best) {
      best = mean;
      out.ref = used[r];
      for (int t = 0; t < kp; ++t) out.partners[t] = used[row[t].second], out.partner_ncc[t] = row[t].first;
    }
  }
  out.score = best;
  out.num_partners = kp;
  out.num_views = u;
  for (int i = 0; i < u; ++i) out.views[i] = used[i];
  return out;
}

void expect_same(const PatchResult& a, const PatchResult& b) {
  EXPECT_EQ(a.score, b.score);  // bit-identical
  EXPECT_EQ(a.ref, b.ref);
  EXPECT_EQ(a.num_partners, b.num_partners);
  EXPECT_EQ(a.num_views, b.num_views);
  EXPECT_EQ(a.spacing, b.spacing);
  for (int t = 0; t < a.num_partners; ++t) EXPECT_EQ(a.partners[t], b.partners[t]);
  for (int t = 0; t < a.num_partners; ++t) EXPECT_EQ(a.partner_ncc[t], b.partner_ncc[t]);
  for (int t = 0; t < a.num_views; ++t) EXPECT_EQ(a.views[t], b.views[t]);
}
}  // namespace

TEST(PatchKernel, BitIdenticalToTheStraightforwardFormulation) {
  int defined = 0, total = 0;
  for (int which = 0; which < 3; ++which) {
    const PlaneScene& s = scene(which);
    const Views& v = views(which);
    const Eigen::Vector3d e1 = stable_perpendicular(s.N), e2 = s.N.cross(e1);
    for (int mu : {5, 11, 21})
      for (int k : {4, 5, 8, 12}) {
        Options o;
        o.mu = mu;
        o.k = k;
        o.adaptive_k = k > 5;
        o.detrend = (k == 5 || k == 12);
        o.partners = k == 8 ? 7 : 0;  // every pair (photo.point_partners), or the paper's k'
        o.check();
        if (k == 12) o.min_std = 0.05;  // some constant patches too
        Scratch scratch;
        for (int p = 0; p < 12; ++p) {
          // Points on, near and off the plane, some near the image borders.
          const double a = 0.37 * std::sin(1.7 * p + which), b = 0.29 * std::cos(2.3 * p + mu);
          const Eigen::Vector3d X = s.O + a * e1 + b * e2 + (p % 4 - 1.5) * 3 * s.footprint * s.N;
          for (int oi = 0; oi < kNumOrientations; ++oi) {
            const Eigen::Vector3d n = orientations()[oi];
            const Eigen::Vector3d line = stable_perpendicular(n);
            const Eigen::Vector3d a2 = n.cross(line);
            detail::prepare_centre(v, X, o, scratch);
            PatchResult got;
            detail::score_prepared(v, n, line, nullptr, o, scratch, got);
            expect_same(got, reference_patch(v, X, n, line, nullptr, o));
            if (mu <= 11 && p % 3 == 0) {
              detail::score_prepared(v, n, line, &a2, o, scratch, got);
              expect_same(got, reference_patch(v, X, n, line, &a2, o));
            }
            defined += got.valid();
            ++total;
          }
        }
      }
  }
  std::printf("kernel vs reference: %d of %d patches defined\n", defined, total);
  EXPECT_GT(defined, total / 5);
}

// Options::outline_fill: two views with the same camera and silhouette (the left half of
// the image), the same texture inside it and anti-correlated backgrounds. A patch across the
// outline correlates perfectly with the fill (its outside samples take its inside mean) and
// poorly without; one mostly outside is not scored; one wholly inside is scored as without.
TEST(PhotoPatch, OutlineFillTakesOnlyTheSamplesInsideTheSilhouette) {
  const int W = 64, H = 64;
  const Camera cam = tetmvs::testing::look_at(Eigen::Vector3d(0, 0, -5), Eigen::Vector3d(0, 0, 0), 100, W, H);
  cv::Mat sil(H, W, CV_8U, cv::Scalar(0));
  sil(cv::Rect(0, 0, 32, H)).setTo(255);
  cv::Mat a(H, W, CV_32F), b(H, W, CV_32F);
  cv::RNG rng(3);
  rng.fill(a, cv::RNG::UNIFORM, 0.1, 0.9);
  rng.fill(b, cv::RNG::UNIFORM, 0.1, 0.9);
  a(cv::Rect(0, 0, 32, H)).copyTo(b(cv::Rect(0, 0, 32, H)));  // the same object
  for (int y = 0; y < H; ++y)
    for (int x = 32; x < W; ++x) b.at<float>(y, x) = 1.f - a.at<float>(y, x);  // backgrounds anti-correlated
  const Views views({cam, cam}, {a, b}, {sil, sil}, true);
  const auto world = [&](double u, double v) { return cam.backproject(u, v, 5); };  // on the plane z = 0
  const int both[2] = {0, 1};
  const Eigen::Vector3d a1(1, 0, 0), a2(0, 1, 0);
  const auto score = [&](double u, bool fill) {
    Options o;
    o.outline_fill = fill;
    Scratch s;
    PatchResult r;
    detail::score_in_views(views, world(u, 32), a1, &a2, 0.05, both, 2, 1, o, s, r);  // 5 x 5 samples a pixel apart
    return r;
  };
  // columns 29..33, of which 29..31 lie inside: 15 of 25 samples
  const PatchResult across = score(31, true);
  ASSERT_TRUE(across.valid());
  EXPECT_NEAR(across.score, 1.f, 1e-5f);
  EXPECT_LT(score(31, false).score, 0.8f);
  EXPECT_TRUE(score(31, false).valid());
  EXPECT_FALSE(score(33, true).valid());  // columns 31..35: 5 of 25 inside
  EXPECT_TRUE(score(33, false).valid());
  EXPECT_EQ(views[0].inside_px.at<std::uint8_t>(32, 0), 32);  // the image border is not an outline
  EXPECT_EQ(views[0].inside_px.at<std::uint8_t>(32, 40), 0);
  {  // without the distances every patch's samples are tested: the same scores
    const Views plain({cam, cam}, {a, b}, {sil, sil});
    EXPECT_TRUE(plain[0].inside_px.empty());
    Options o;
    o.outline_fill = true;
    Scratch s;
    for (const double u : {12.0, 31.0}) {
      PatchResult r;
      detail::score_in_views(plain, world(u, 32), a1, &a2, 0.05, both, 2, 1, o, s, r);
      EXPECT_EQ(r.score, score(u, true).score) << u;
    }
  }
  EXPECT_EQ(score(12, true).score, score(12, false).score);  // wholly inside: untouched
  EXPECT_LT(score(12, true).score, 1.f + 1e-6f);
}
