#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "common/synth/objects.h"
#include "common/trimesh/raster.h"

using namespace tetmvs;

namespace {
// Camera at the origin looking along +z, f = 100, principal point at pixel centre (cx, cy).
Camera simple_cam(int w, int h, double f = 100) {
  Camera c;
  c.K << f, 0, (w - 1) / 2.0, 0, f, (h - 1) / 2.0, 0, 0, 1;
  c.width = w;
  c.height = h;
  return c;
}
// Quad in the plane z = d whose projection covers pixel coordinates [u0,u1] x [v0,v1].
TriMesh quad(const Camera& c, double u0, double v0, double u1, double v1, double d) {
  TriMesh m;
  for (auto [u, v] : {std::pair{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}}) m.V.push_back(c.backproject(u, v, d));
  m.F = {{0, 1, 2}, {0, 2, 3}};
  return m;
}
}  // namespace

TEST(Raster, SharedEdgesCoverEachPixelOnce) {
  const Camera c = simple_cam(40, 30);
  // A fan of 12 triangles around a centre, passing exactly through pixel centres.
  TriMesh m;
  m.V.push_back(c.backproject(20, 15, 2));
  for (int k = 0; k < 12; ++k) {
    const double a = k * 2 * 3.14159265358979 / 12;
    m.V.push_back(c.backproject(20 + 12 * std::cos(a), 15 + 12 * std::sin(a), 2));
  }
  for (int k = 0; k < 12; ++k) m.F.push_back({0, 1 + k, 1 + (k + 1) % 12});
  // Count covers per pixel by rasterising each triangle alone.
  cv::Mat count(30, 40, CV_32S, cv::Scalar(0));
  for (int k = 0; k < 12; ++k) {
    TriMesh one = m;
    one.F = {m.F[k]};
    const Raster r = rasterize(one, c);
    for (int v = 0; v < 30; ++v)
      for (int u = 0; u < 40; ++u) count.at<int>(v, u) += r.tri.at<int>(v, u) >= 0;
  }
  int covered = 0;
  for (int v = 0; v < 30; ++v)
    for (int u = 0; u < 40; ++u) {
      EXPECT_LE(count.at<int>(v, u), 1) << u << "," << v;
      covered += count.at<int>(v, u);
    }
  EXPECT_EQ(count.at<int>(15, 20), 1);  // the shared centre vertex, on every triangle
  const Raster all = rasterize(m, c);
  int all_cov = 0;
  for (int v = 0; v < 30; ++v)
    for (int u = 0; u < 40; ++u) all_cov += all.tri.at<int>(v, u) >= 0;
  EXPECT_EQ(all_cov, covered);
  // Dodecagon of circumradius 12: area 3 * 144 = 432 pixels, give or take the boundary.
  EXPECT_NEAR(covered, 432, 40);
}

TEST(Raster, TopLeftRuleOnAnAxisAlignedSquare) {
  const Camera c = simple_cam(20, 20);
  // Square with corners on pixel centres: [2,6] x [3,8] -> left/top edges in, right/bottom out.
  const Raster r = rasterize(quad(c, 2, 3, 6, 8, 1.0), c);
  for (int v = 0; v < 20; ++v)
    for (int u = 0; u < 20; ++u) {
      const bool want = u >= 2 && u < 6 && v >= 3 && v < 8;
      EXPECT_EQ(r.tri.at<int>(v, u) >= 0, want) << u << "," << v;
    }
  // Same square, both windings and both triangulation diagonals: same pixels.
  TriMesh q = quad(c, 2, 3, 6, 8, 1.0);
  q.F = {{0, 2, 1}, {0, 3, 2}};
  const Raster r2 = rasterize(q, c);
  q.F = {{0, 1, 3}, {1, 2, 3}};
  const Raster r3 = rasterize(q, c);
  EXPECT_EQ(cv::countNonZero(r.tri != r2.tri), 0);
  EXPECT_EQ(cv::countNonZero((r.tri >= 0) != (r3.tri >= 0)), 0);
  // Half-integer corners: exactly 4 x 5 pixels.
  const Raster h = rasterize(quad(c, 1.5, 2.5, 5.5, 7.5, 1.0), c);
  EXPECT_EQ(cv::countNonZero(h.tri >= 0), 20);
}

TEST(Raster, PerspectiveCorrectDepthAndNearestWins) {
  const Camera c = simple_cam(32, 24);
  // A slanted plane: z = 2 + 0.5 x.
  TriMesh m;
  for (auto [x, y] : {std::pair{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}}) m.V.emplace_back(x, y, 2 + 0.5 * x);
  m.F = {{0, 1, 2}, {0, 2, 3}};
  const Raster r = rasterize(m, c);
  int n = 0;
  for (int v = 0; v < 24; ++v)
    for (int u = 0; u < 32; ++u) {
      if (r.tri.at<int>(v, u) < 0) continue;
      ++n;
      // Ray (x/z, y/z) = ((u-cx)/f, (v-cy)/f): z = 2 + 0.5 z a -> z = 2 / (1 - 0.5 a)
      const double a = (u - 15.5) / 100.0;
      EXPECT_NEAR(r.depth.at<float>(v, u), 2 / (1 - 0.5 * a), 2e-6);
      Eigen::Vector3d X;
      ASSERT_TRUE(pixel_point_on_triangle(m, r.tri.at<int>(v, u), c, u, v, X));
      EXPECT_NEAR(X.z(), r.depth.at<float>(v, u), 2e-6);
    }
  EXPECT_GT(n, 100);
  // A nearer square in front hides part of it.
  TriMesh both = m;
  TriMesh q = quad(c, 10, 8, 20, 16, 1.0);
  append(both, q);
  const Raster b = rasterize(both, c);
  EXPECT_EQ(b.tri.at<int>(10, 12), 2 + b.tri.at<int>(10, 12) - 2);
  EXPECT_GE(b.tri.at<int>(10, 12), 2);
  EXPECT_FLOAT_EQ(b.depth.at<float>(10, 12), 1.0f);
  EXPECT_LT(b.tri.at<int>(5, 5), 2);
}

TEST(Raster, SupersamplingCoverageAndCentreMask) {
  const Camera c = simple_cam(20, 20);
  // Square covering [3.5, 8.5] horizontally but [3.0, 8.0] vertically... use 1/3 offsets.
  RasterOptions o;
  o.supersample = 3;
  const Raster r = rasterize(quad(c, 3.5, 3.5, 8.5 - 1.0 / 3.0, 8.5, 1.0), c, o);
  const cv::Mat cov = r.coverage();
  EXPECT_FLOAT_EQ(cov.at<float>(5, 5), 1.0f);
  EXPECT_FLOAT_EQ(cov.at<float>(5, 8), 2.0f / 3.0f);  // two of three sample columns in pixel 8
  EXPECT_FLOAT_EQ(cov.at<float>(5, 9), 0.0f);
  const cv::Mat mask = r.centre_mask();
  const Raster r1 = rasterize(quad(c, 3.5, 3.5, 8.5 - 1.0 / 3.0, 8.5, 1.0), c);
  EXPECT_EQ(cv::countNonZero(mask != (r1.tri >= 0)), 0);
}

TEST(Raster, SphereSilhouetteMatchesTheAnalyticCone) {
  Camera c = simple_cam(120, 90, 150);
  c.t = Eigen::Vector3d(0.05, -0.1, 4);  // sphere centre at camera coordinates (0.05, -0.1, 4)
  const TriMesh m = synth::make_sphere(0.02);
  const Raster r = rasterize(m, c);
  const Eigen::Vector3d ctr = c.t;
  const double half = std::asin(1.0 / ctr.norm());
  int bad = 0, inside = 0;
  for (int v = 0; v < 90; ++v)
    for (int u = 0; u < 120; ++u) {
      const Eigen::Vector3d d = c.K.inverse() * Eigen::Vector3d(u, v, 1);
      const double ang = std::acos(d.normalized().dot(ctr.normalized()));
      const bool want = ang < half;
      inside += want;
      // Pixels farther than ~0.5 px from the rim must agree (the mesh is inscribed).
      if (std::abs(ang - half) * 150 > 0.5 && want != (r.tri.at<int>(v, u) >= 0)) ++bad;
      if (r.tri.at<int>(v, u) >= 0) {  // depth: the nearer root of the ray-sphere intersection, polygon slightly inside
        const Eigen::Vector3d dir = d.normalized();
        const double b = dir.dot(ctr), disc = b * b - ctr.squaredNorm() + 1;
        if (disc > 0.05) { EXPECT_NEAR(r.depth.at<float>(v, u), (b - std::sqrt(disc)) * dir.z(), 2e-3); }
      }
    }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(inside, 1000);
  // Back-face culling keeps the same silhouette for a closed outward mesh.
  RasterOptions cull;
  cull.cull_back = true;
  const Raster rc = rasterize(m, c, cull);
  EXPECT_EQ(cv::countNonZero((rc.tri >= 0) != (r.tri >= 0)), 0);
  EXPECT_LE(cv::countNonZero(rc.tri != r.tri), 2);  // ties on rim edges only
}

TEST(Raster, SkipsTrianglesBehindTheCamera) {
  const Camera c = simple_cam(20, 20);
  TriMesh m;
  m.V = {{0, 0, -1}, {1, 0, 1}, {0, 1, 1}};
  m.F = {{0, 1, 2}};
  const Raster r = rasterize(m, c);
  EXPECT_EQ(r.skipped_near, 1);
  EXPECT_EQ(cv::countNonZero(r.tri >= 0), 0);
}

TEST(Raster, SubsampledIsTheRasterOfThePyramidLevel) {
  // a torus filling much of a 101 x 77 image (odd sizes: the levels round up)
  Camera c = simple_cam(101, 77, 120);
  c.t = Eigen::Vector3d(0.05, -0.03, 3.0);
  const TriMesh m = synth::make_torus(0.05);
  const Raster full = rasterize(m, c);
  for (int level : {1, 2, 3}) {
    Camera cl = c;
    cl.K.row(0) /= 1 << level;
    cl.K.row(1) /= 1 << level;
    for (int l = 0; l < level; ++l) {
      cl.width = (cl.width + 1) / 2;
      cl.height = (cl.height + 1) / 2;
    }
    const Raster direct = rasterize(m, cl), sub = subsample(full, level);
    ASSERT_EQ(sub.width, cl.width);
    ASSERT_EQ(sub.height, cl.height);
    ASSERT_EQ(sub.tri.size(), direct.tri.size());
    int covered = 0, same = 0;
    for (int y = 0; y < sub.height; ++y)
      for (int x = 0; x < sub.width; ++x) {
        const int t = direct.tri.at<int>(y, x);
        covered += t >= 0;
        if (t == sub.tri.at<int>(y, x)) {
          ++same;
          if (t >= 0) {
            EXPECT_NEAR(sub.depth.at<float>(y, x), direct.depth.at<float>(y, x), 1e-4);
          }
        }
      }
    EXPECT_GT(covered, 50) << level;
    // only samples on a triangle's edge may differ (the vertices snap to the sample grid):
    // under one in a hundred with triangles this small
    EXPECT_GE(same, 0.99 * sub.width * sub.height) << level;
    // the subsampled raster's covered box is its own samples' box
    cv::Mat pts;
    cv::findNonZero(sub.tri >= 0, pts);
    EXPECT_EQ(sub.covered_box, cv::boundingRect(pts)) << level;
  }
}

TEST(Raster, CoveredBoxBoundsTheCoveredSamplesOfRandomTriangles) {
  // random triangles (slivers, ones crossing the border, both orientations): covered_box is
  // the covered samples' box, and a triangle inside the image covers its area give or take
  // its outline
  const Camera c = simple_cam(64, 48);
  std::uint32_t seed = 12345;
  const auto rnd = [&](double lo, double hi) {
    seed = seed * 1664525u + 1013904223u;
    return lo + (hi - lo) * (seed >> 8) / double(1u << 24);
  };
  for (int trial = 0; trial < 200; ++trial) {
    TriMesh m;
    for (int k = 0; k < 3; ++k) m.V.push_back(c.backproject(rnd(-10, 74), rnd(-10, 58), rnd(1, 3)));
    m.F = {{0, 1, 2}};
    const Raster r = rasterize(m, c);
    int x0 = 64, x1 = -1, y0 = 48, y1 = -1, n = 0;
    for (int v = 0; v < 48; ++v)
      for (int u = 0; u < 64; ++u)
        if (r.tri.at<int>(v, u) >= 0) x0 = std::min(x0, u), x1 = std::max(x1, u), y0 = std::min(y0, v), y1 = std::max(y1, v), ++n;
    if (n == 0) {
      EXPECT_TRUE(r.covered_box.empty());
      continue;
    }
    EXPECT_EQ(r.covered_box, cv::Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1)) << trial;
    // the area of a non-degenerate triangle, give or take its outline
    const Eigen::Vector2d a = c.project(m.V[0]), b = c.project(m.V[1]), d = c.project(m.V[2]);
    const double area = 0.5 * std::abs((b - a).x() * (d - a).y() - (b - a).y() * (d - a).x());
    const double perimeter = (b - a).norm() + (d - b).norm() + (a - d).norm();
    if (x0 > 0 && y0 > 0 && x1 < 63 && y1 < 47) {
      EXPECT_NEAR(n, area, perimeter + 2) << trial;
    }
  }
}
