// The image border is not the object's outline (common/silhouette/border.h), checked on a
// synthetic mask cut by the border and through its consumers: the visual-hull test, the
// scene's silhouette test, deform's signed distance and the silhouette agreement.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "common/camera.h"
#include "common/deform/forces.h"
#include "common/photo/views.h"
#include "common/photoconsist/hull.h"
#include "common/render/shaded.h"
#include "common/scene.h"
#include "common/silhouette/border.h"

using namespace tetmvs;

namespace silhouette_border_test {

// 80 x 60 mask: a disc of radius 20 centred on the left border (x = 0, y = 30), so the
// border cuts it along rows 10..50 of column 0.
cv::Mat cut_disc() {
  cv::Mat m = cv::Mat::zeros(60, 80, CV_8U);
  cv::circle(m, {0, 30}, 20, cv::Scalar(255), cv::FILLED);
  return m;
}

}  // namespace silhouette_border_test

TEST(SilhouetteBorder, OutlineAndDistancesLeaveTheBorderOut) {
  const cv::Mat m = silhouette_border_test::cut_disc();
  EXPECT_TRUE(silhouette::touches_border(m));
  cv::Mat inner = cv::Mat::zeros(60, 80, CV_8U);
  cv::circle(inner, {40, 30}, 10, cv::Scalar(255), cv::FILLED);
  EXPECT_FALSE(silhouette::touches_border(inner));

  const cv::Mat o = silhouette::outline(m);
  // on the border column only the disc's two ends (real background above and below) are outline
  int on_border = 0;
  for (int y = 0; y < m.rows; ++y) on_border += o.at<std::uint8_t>(y, 0) != 0;
  EXPECT_LE(on_border, 2);
  EXPECT_EQ(o.at<std::uint8_t>(30, 0), 0);   // the cut, not an outline
  EXPECT_EQ(o.at<std::uint8_t>(30, 20), 255);  // the disc's rim is
  EXPECT_EQ(o.at<std::uint8_t>(30, 10), 0);    // inside

  // distances: the pixel on the border at the disc's centre is a radius deep
  const cv::Mat din = silhouette::distance_inside(m), dout = silhouette::distance_outside(m);
  EXPECT_NEAR(din.at<float>(30, 0), 21.0f, 1.0f);
  EXPECT_NEAR(dout.at<float>(30, 40), 20.0f, 1.0f);
  EXPECT_EQ(dout.at<float>(30, 0), 0.0f);
  // deform's signed distance follows: deep inside at the border, not on a contour
  const cv::Mat sd = deform::signed_distance(m);
  EXPECT_LT(sd.at<float>(30, 0), -19.0f);

  // pixels: outside the image the view says nothing
  int x = -1, y = -1;
  EXPECT_FALSE(silhouette::nearest_pixel_in_image({-0.6, 30}, 80, 60, x, y));
  EXPECT_FALSE(silhouette::nearest_pixel_in_image({79.5, 30}, 80, 60, x, y));
  ASSERT_TRUE(silhouette::nearest_pixel_in_image({-0.4, 29.6}, 80, 60, x, y));
  EXPECT_EQ(x, 0);
  EXPECT_EQ(y, 30);
}

TEST(SilhouetteBorder, PointsBeyondTheBorderAreNeverCarved) {
  // a camera looking along +z from the origin; the mask is the cut disc
  Camera cam;
  cam.name = "v";
  cam.K << 100, 0, 39.5, 0, 100, 29.5, 0, 0, 1;
  cam.width = 80, cam.height = 60;
  const cv::Mat m = silhouette_border_test::cut_disc();
  const cv::Mat grey(60, 80, CV_32F, cv::Scalar(0.5f));
  const photo::Views views({cam}, {grey}, {m});
  const photoconsist::HullTest hull(views, {m}, 0.0);
  const auto at_pixel = [&](double u, double v) {  // the point at depth 1 seen at (u, v)
    return Eigen::Vector3d((u - 39.5) / 100, (v - 29.5) / 100, 1.0);
  };
  EXPECT_TRUE(hull.inside(at_pixel(2, 30)));     // in the disc, next to the border
  EXPECT_FALSE(hull.inside(at_pixel(40, 30)));   // real background: carved
  EXPECT_TRUE(hull.inside(at_pixel(-5, 30)));    // beyond the border: never carved
  EXPECT_TRUE(hull.inside(at_pixel(-5, 2)));     // beyond the border, beside background: never carved
  Scene s;
  s.cams = {cam};
  s.sil = {m};
  EXPECT_TRUE(s.in_silhouette(0, -3, 2, true));
  EXPECT_FALSE(s.in_silhouette(0, 3, 2, true));
  EXPECT_TRUE(s.in_silhouette(0, 0, 30, false));
}

TEST(SilhouetteBorder, AgreementCountsViewsCutByTheBorder) {
  // a quad in front of the camera covering exactly the left half of the image: its
  // silhouette runs past the border, as the mask does
  Camera cam;
  cam.name = "v";
  cam.K << 100, 0, 39.5, 0, 100, 29.5, 0, 0, 1;
  cam.width = 80, cam.height = 60;
  TriMesh quad;
  const double z = 1;
  quad.V = {{-1, -1, z}, {(19.5 - 39.5) / 100, -1, z}, {(19.5 - 39.5) / 100, 1, z}, {-1, 1, z}};
  quad.F = {{0, 2, 1}, {0, 3, 2}};  // facing the camera
  Scene s;
  s.cams = {cam};
  cv::Mat truth = cv::Mat::zeros(60, 80, CV_8U);
  truth(cv::Rect(0, 0, 20, 60)).setTo(255);
  s.sil = {truth};
  s.rgb = {cv::Mat(60, 80, CV_8UC3, cv::Scalar(0, 0, 0))};
  const SilhouetteAgreement a = silhouette_agreement(quad, s);
  ASSERT_EQ(a.iou.size(), 1u);
  ASSERT_EQ(a.cut_by_border.size(), 1u);
  EXPECT_TRUE(a.cut_by_border[0]);
  EXPECT_GT(a.iou[0], 0.9);
  EXPECT_EQ(a.mean_iou_inside, -1);  // no view lies wholly inside the image
}
