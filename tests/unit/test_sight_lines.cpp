// Tests of photoconsist's lines of sight (common/photoconsist/sight_lines.h): points of Q
// on a plane seen by 8 cameras make the air in front of the plane free in the views that
// saw them, and nothing on or behind the plane.
#include <gtest/gtest.h>

#include "common/error.h"
#include "common/photo/views.h"
#include "common/photoconsist/level_pass.h"
#include "common/photoconsist/sight_lines.h"
#include "common/tetmesh/tetmesh.h"
#include "test_photo_scene.h"

using namespace tetmvs;
namespace pc = tetmvs::photoconsist;

namespace {

struct SightScene {
  tetmvs::testing::PlaneScene plane{Eigen::Vector3d(0, 0, 1), std::vector<double>(8, 25.0), 4.0, 300.0, 160, 120,
                                    0.03, 1};
  photo::Views views{plane.cams, plane.grey};
  static constexpr double kMarginPx = 5;  // 0.067 at depth 4

  // Points of the plane z = 0 on a 0.005 grid over [-0.4, 0.4]^2 (finer than a 2 px bin,
  // 0.027 at depth 4), seen in the given cameras.
  QPoints plane_points(const std::vector<std::int32_t>& cams) const {
    QPoints q;
    for (int i = -80; i <= 80; ++i)
      for (int j = -80; j <= 80; ++j) q.add(Eigen::Vector3d(0.005 * i, 0.005 * j, 0), plane.N, 0.95f, cams, -1);
    return q;
  }
};

const SightScene& scene() {
  static const SightScene s;
  return s;
}

}  // namespace

TEST(SightLines, AirInFrontOfSeenPointsIsFreeInTheViewsThatSawThem) {
  const auto& S = scene();
  const pc::SightLines all(S.views, S.plane_points({0, 1, 2, 3, 4, 5, 6, 7}), S.kMarginPx, 8);
  EXPECT_EQ(all.points(), 161 * 161);
  EXPECT_EQ(all.free_views(S.views, Eigen::Vector3d(0, 0, 0.2)), 8);
  EXPECT_TRUE(all.free(S.views, Eigen::Vector3d(0.05, -0.03, 0.2)));
  EXPECT_EQ(all.free_views(S.views, Eigen::Vector3d(0, 0, 0)), 0);      // on the surface
  EXPECT_EQ(all.free_views(S.views, Eigen::Vector3d(0, 0, 0.03)), 0);   // within the margin (0.067 along the ray)
  EXPECT_EQ(all.free_views(S.views, Eigen::Vector3d(0, 0, -0.2)), 0);   // behind the surface
  EXPECT_EQ(all.free_views(S.views, Eigen::Vector3d(3, 0, 0.2)), 0);    // outside every image

  // Points seen in camera 0 only free the air in view 0 only.
  const pc::SightLines one(S.views, S.plane_points({0}), S.kMarginPx, 2);
  EXPECT_EQ(one.free_views(S.views, Eigen::Vector3d(0, 0, 0.2)), 1);
  EXPECT_FALSE(one.free(S.views, Eigen::Vector3d(0, 0, 0.2)));

  // The margin is in pixels at the position's depth: a larger one keeps more air.
  const pc::SightLines wide(S.views, S.plane_points({0, 1, 2, 3, 4, 5, 6, 7}), 40, 1);
  EXPECT_EQ(wide.free_views(S.views, Eigen::Vector3d(0, 0, 0.2)), 0);  // 40 px = 0.53 at depth 4
  EXPECT_EQ(wide.free_views(S.views, Eigen::Vector3d(0, 0, 0.6)), 8);  // 0.66 along the rays
}

TEST(SightLines, BadArgumentsAreRefused) {
  const auto& S = scene();
  EXPECT_THROW(pc::SightLines(S.views, S.plane_points({0}), 5, 0), Error);
  EXPECT_THROW(pc::SightLines(S.views, S.plane_points({0}), -1, 1), Error);
}

TEST(SightLines, CrossingFacesWhollyInSeenAirAreDropped) {
  const auto& S = scene();
  const pc::SightLines sight(S.views, S.plane_points({0, 1, 2, 3, 4, 5, 6, 7}), S.kMarginPx, 8);
  const tet::TetMesh m = tet::build_bcc(tet::lattice_for_box(
      Eigen::AlignedBox3d(Eigen::Vector3d(-0.2, -0.2, -0.2), Eigen::Vector3d(0.2, 0.2, 0.4)), 8));
  std::vector<std::int32_t> face(m.num_faces());
  for (std::int32_t f = 0; f < m.num_faces(); ++f) face[f] = f;
  std::vector<std::uint8_t> crossing(face.size(), 1);
  crossing[0] = 0;
  const std::int64_t dropped = pc::drop_faces_in_sight(m, sight, S.views, face, crossing);
  std::int64_t zeroed = 0, above = 0;
  for (std::size_t t = 1; t < face.size(); ++t) {
    const auto fv = m.face_vertices(face[t]);
    double zmin = 1e9;
    for (const auto v : fv) zmin = std::min(zmin, m.vertex(v).z());
    above += zmin > 0.15;
    if (crossing[t]) continue;
    ++zeroed;
    EXPECT_GT(zmin, 0.03) << "face " << face[t] << " touches the surface's margin but was dropped";
  }
  EXPECT_EQ(crossing[0], 0);
  EXPECT_EQ(dropped, zeroed);
  EXPECT_GT(dropped, 0);
  EXPECT_GE(dropped, above);  // every face wholly well above the plane (and inside the views) is air
}
