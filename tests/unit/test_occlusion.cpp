// Tests of photoconsist's occlusion-aware camera selection (common/photoconsist/occlusion.h):
// a textured plane seen by 8 cameras, with a small patch of points of Q floating in front
// of it on the line of sight of one camera.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <limits>

#include "common/error.h"
#include "common/photo/oriented_point.h"
#include "common/photo/patch.h"
#include "common/photo/views.h"
#include "common/photoconsist/occlusion.h"
#include "test_photo_scene.h"

using namespace tetmvs;
namespace pc = tetmvs::photoconsist;

namespace {

struct OccluderScene {
  tetmvs::testing::PlaneScene plane{Eigen::Vector3d(0, 0, 1), std::vector<double>(8, 25.0), 4.0, 300.0, 160, 120,
                                    0.03, 1};
  photo::Views views{plane.cams, plane.grey};
  Eigen::Vector3d O{0, 0, 0};
  Eigen::Vector3d d0 = (plane.cams[0].centre() - O).normalized();  // towards camera 0
  Eigen::Vector3d d1 = (plane.cams[1].centre() - O).normalized();
  static constexpr double kCell = 0.04;                            // level-0 cell of the occluders

  // A 17 x 17 patch of points, 0.01 apart, across camera 0's line of sight at distance 1 from O.
  QPoints patch() const {
    QPoints q;
    const Eigen::Vector3d a = d0.cross(Eigen::Vector3d::UnitZ()).normalized(), b = d0.cross(a);
    for (int i = -8; i <= 8; ++i)
      for (int j = -8; j <= 8; ++j) q.add(O + d0 + 0.01 * i * a + 0.01 * j * b, d0, 0.95f, {0}, -1);
    return q;
  }
  pc::OcclusionMaps maps(const QPoints& q, int support = 2) const {
    pc::OcclusionOptions o;
    o.support = support;  // splat 0.5 cell = 0.02, margin 1 cell = 0.04 (defaults)
    return pc::OcclusionMaps(views, q, std::vector<std::int32_t>(q.size(), 0), {kCell}, o);
  }
};

const OccluderScene& scene() {
  static const OccluderScene s;
  return s;
}

std::vector<int> hidden(const pc::OcclusionMaps& m, const photo::Views& v, const Eigen::Vector3d& X) {
  std::vector<std::uint8_t> mask(v.size(), 7);
  const int n = m.hidden_views(v, X, mask.data());
  std::vector<int> out;
  for (int i = 0; i < v.size(); ++i) {
    EXPECT_LE(mask[i], 1);
    if (mask[i]) out.push_back(i);
  }
  EXPECT_EQ(n, static_cast<int>(out.size()));
  return out;
}

}  // namespace

TEST(Occlusion, PointBehindQIsHiddenOnlyInTheBlockedView) {
  const auto& S = scene();
  const pc::OcclusionMaps m = S.maps(S.patch());
  EXPECT_EQ(m.points(), 17 * 17);
  EXPECT_GT(m.occluding_bins(), 0);
  // O is 1.0 behind the patch in view 0; the other views' lines of sight pass >= 0.3 away.
  EXPECT_EQ(hidden(m, S.views, S.O), std::vector<int>{0});
  // Depth margin: 1 cell (0.04) behind the splats' depth. (Just behind the patch, the
  // other views look through it too.)
  const auto has0 = [&](double behind) {
    const auto h = hidden(m, S.views, S.O + (1 - behind) * S.d0);
    return !h.empty() && h[0] == 0;
  };
  EXPECT_TRUE(hidden(m, S.views, S.O + S.d0).empty());  // on the patch: no view
  EXPECT_FALSE(has0(0.03));                             // 0.03 behind it: within the margin
  EXPECT_TRUE(has0(0.06));                              // 0.06 behind it: hidden
  // Beside the patch (0.2 off the line of sight, splats reach 0.08 + 0.02): visible.
  const Eigen::Vector3d side = S.d0.cross(Eigen::Vector3d::UnitZ()).normalized();
  EXPECT_TRUE(hidden(m, S.views, S.O + 0.2 * side).empty());
  // No occluders in view 3 at all: an infinite limit.
  EXPECT_EQ(m.limit(3, 80, 60), std::numeric_limits<float>::infinity());
}

TEST(Occlusion, HiddenViewIsNotScored) {
  const auto& S = scene();
  const pc::OcclusionMaps m = S.maps(S.patch());
  photo::Options o;
  o.k = 8;  // every view of the ring
  o.mu = 11;
  photo::Scratch scratch;
  const Eigen::Vector3d nf(1, 0, 0);  // a face through O across the plane
  const Eigen::Vector3d N(0, 0, 1);
  std::vector<std::uint8_t> mask(S.views.size());
  ASSERT_EQ(m.hidden_views(S.views, S.O, mask.data()), 1);
  // The patch on the plane (normal N, all 8 cameras within the cone): 8 views, then 7.
  const photo::PatchResult all = photo::score_patch(S.views, S.O, N, o, scratch);
  scratch.hidden = mask.data();
  const photo::PatchResult seen = photo::score_patch(S.views, S.O, N, o, scratch);
  const photo::PointResult point = photo::score_point(S.views, S.O, nf, o, scratch);  // best of 14 orientations
  scratch.hidden = nullptr;
  ASSERT_TRUE(all.valid());
  ASSERT_TRUE(seen.valid());
  ASSERT_TRUE(point.valid());
  EXPECT_EQ(all.num_views, 8);
  EXPECT_EQ(seen.num_views, 7);
  for (const photo::PatchResult* r : {static_cast<const photo::PatchResult*>(&seen),
                                      static_cast<const photo::PatchResult*>(&point)}) {
    for (int i = 0; i < r->num_views; ++i) EXPECT_NE(r->views[i], 0);
    EXPECT_NE(r->ref, 0);
    for (int i = 0; i < r->num_partners; ++i) EXPECT_NE(r->partners[i], 0);
  }
  EXPECT_GT(seen.score, 0.9f);  // the plane is still seen consistently by the other 7
  EXPECT_GT(point.score, 0.9f);
  // The scratch forgets the mask: the next call uses all views again.
  EXPECT_EQ(photo::score_patch(S.views, S.O, N, o, scratch).num_views, 8);
}

TEST(Occlusion, AStrayPointDoesNotBlindAView) {
  const auto& S = scene();
  QPoints one;
  one.add(S.O + S.d1, S.d1, 0.95f, {1}, -1);  // a single point on camera 1's line of sight
  EXPECT_TRUE(hidden(S.maps(one, 2), S.views, S.O).empty());
  EXPECT_EQ(hidden(S.maps(one, 1), S.views, S.O), std::vector<int>{1});  // support 1: it does
  QPoints two = one;
  two.add(S.O + 1.01 * S.d1, S.d1, 0.95f, {1}, -1);
  EXPECT_EQ(hidden(S.maps(two, 2), S.views, S.O), std::vector<int>{1});
}

TEST(Occlusion, FalsePointsHiddenInTheirOwnCamerasDoNotOcclude) {
  const auto& S = scene();
  // A cluster of 5 points between the patch and O, said to be consistent in camera 0,
  // where the patch hides them; in camera 1 they lie in front of the plane point Y.
  const Eigen::Vector3d P = S.O + 0.5 * S.d0, C1 = S.plane.cams[1].centre();
  const Eigen::Vector3d Y = C1 + (-C1.z() / (P - C1).z()) * (P - C1);
  ASSERT_NEAR(Y.z(), 0, 1e-12);
  QPoints q = S.patch();
  const std::int64_t np = q.size();
  for (int k = 0; k < 5; ++k) q.add(P + 0.002 * Eigen::Vector3d(k % 2, k / 2 % 2, k / 4), S.d0, 0.95f, {0}, -1);
  pc::OcclusionOptions o;
  o.filter = false;
  const pc::OcclusionMaps raw(S.views, q, std::vector<std::int32_t>(q.size(), 0), {OccluderScene::kCell}, o);
  EXPECT_EQ(raw.dropped(), 0);
  EXPECT_EQ(hidden(raw, S.views, Y), std::vector<int>{1});  // unfiltered, they hide Y in camera 1
  o.filter = true;
  const pc::OcclusionMaps filtered(S.views, q, std::vector<std::int32_t>(q.size(), 0), {OccluderScene::kCell}, o);
  EXPECT_EQ(filtered.dropped(), 5);
  EXPECT_EQ(filtered.points(), np);
  for (std::int64_t p = 0; p < q.size(); ++p) EXPECT_EQ(filtered.used()[p], p < np ? 1 : 0) << p;
  EXPECT_TRUE(hidden(filtered, S.views, Y).empty());
  EXPECT_EQ(hidden(filtered, S.views, S.O), std::vector<int>{0});  // the patch still hides O
}

TEST(Occlusion, SameMapsForAnyThreadCount) {
  const auto& S = scene();
  QPoints q = S.patch();
  q.add(S.O + S.d1, S.d1, 0.9f, {1}, -1);
  q.add(S.O + 0.5 * S.d1, S.d1, 0.9f, {1}, -1);
  // Extremes: just in front of camera 0 (a huge disc), far off every image, behind camera 0.
  q.add(S.plane.cams[0].centre() - 1e-9 * S.d0, S.d0, 0.9f, {0}, -1);
  q.add(S.O + 1e6 * S.d0.cross(Eigen::Vector3d::UnitZ()), S.d0, 0.9f, {0}, -1);
  q.add(S.plane.cams[0].centre() + S.d0, S.d0, 0.9f, {0}, -1);
  const pc::OcclusionMaps many = S.maps(q, 2);
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const pc::OcclusionMaps one = S.maps(q, 2);
  omp_set_num_threads(saved);
  std::int64_t finite = 0;
  for (int v = 0; v < S.views.size(); ++v)
    for (int w = 0; w < S.views[v].height; ++w)
      for (int u = 0; u < S.views[v].width; ++u) {
        ASSERT_EQ(one.limit(v, u, w), many.limit(v, u, w));
        finite += std::isfinite(one.limit(v, u, w));
      }
  EXPECT_GT(finite, 100);
}

TEST(Occlusion, OptionsAreChecked) {
  pc::OcclusionOptions o;
  EXPECT_NO_THROW(o.check());
  o.support = 0;
  EXPECT_THROW(o.check(), Error);
  o = {};
  o.bin_px = 0;
  EXPECT_THROW(o.check(), Error);
  o = {};
  o.margin_cells = -1;
  EXPECT_THROW(o.check(), Error);
  const auto& S = scene();
  QPoints q = S.patch();
  EXPECT_THROW(pc::OcclusionMaps(S.views, q, std::vector<std::int32_t>(q.size(), 1), {0.04}, {}), Error);  // no cell size
}
