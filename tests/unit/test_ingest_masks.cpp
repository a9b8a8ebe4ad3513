// Ingest of a dataset folder's masks: the naming conventions find_mask accepts and the
// warning that names the views a silhouettes/ folder has no mask for. Synthetic folders of
// four small views, written by the test.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/camera.h"
#include "common/ingest/dataset.h"
#include "common/log.h"
#include "common/par_io.h"
#include "common/params.h"

namespace fs = std::filesystem;
using namespace tetmvs;

namespace ingest_masks_test {

fs::path fresh_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("tetmvs_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d / "silhouettes");
  return d;
}

// Four 64 x 48 views looking along +z at a box around the origin; the images are written
// under `names`, the masks (a disc) under `masks` ("" = none).
void write_folder(const fs::path& d, const std::vector<std::string>& names, const std::vector<std::string>& masks) {
  std::vector<Camera> cams;
  for (std::size_t i = 0; i < names.size(); ++i) {
    Camera c;
    c.name = names[i];
    c.K << 60, 0, 31.5, 0, 60, 23.5, 0, 0, 1;
    const double a = 0.15 * (double(i) - 1.5);  // a small arc of views, all facing the box
    c.R = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix();
    c.t = Eigen::Vector3d(0, 0, 5);
    cams.push_back(c);
    cv::Mat img(48, 64, CV_8UC3, cv::Scalar(30, 30, 30));
    cv::circle(img, {32, 24}, 10, cv::Scalar(200, 180, 160), cv::FILLED);
    cv::imwrite((d / names[i]).string(), img);
    if (!masks[i].empty()) {
      cv::Mat m = cv::Mat::zeros(48, 64, CV_8U);
      cv::circle(m, {32, 24}, 10, cv::Scalar(255), cv::FILLED);
      cv::imwrite((d / "silhouettes" / masks[i]).string(), m);
    }
  }
  write_par(d / "t_par.txt", cams);
  std::ofstream(d / "bbox.txt") << "-0.5 -0.5 -0.5\n0.5 0.5 0.5\n";
}

}  // namespace ingest_masks_test

TEST(IngestMasks, FindsTheCommonNamingConventions) {
  using namespace ingest_masks_test;
  const fs::path d = fresh_dir("masks");
  // the image's own name, its stem + .png (DTU), COLMAP's name + .png, and none
  write_folder(d, {"a.png", "b.jpg", "c.jpg", "d.jpg"}, {"a.png", "b.png", "c.jpg.png", ""});
  EXPECT_EQ(find_mask(d / "silhouettes", "a.png"), d / "silhouettes" / "a.png");
  EXPECT_EQ(find_mask(d / "silhouettes", "b.jpg"), d / "silhouettes" / "b.png");
  EXPECT_EQ(find_mask(d / "silhouettes", "c.jpg"), d / "silhouettes" / "c.jpg.png");
  EXPECT_FALSE(find_mask(d / "silhouettes", "d.jpg").has_value());

  const std::size_t before = warnings_given().size();
  const Scene s = read_dataset(d, Params::defaults());
  ASSERT_EQ(s.size(), 4);
  EXPECT_TRUE(s.has_silhouette(0));
  EXPECT_TRUE(s.has_silhouette(1));
  EXPECT_TRUE(s.has_silhouette(2));
  EXPECT_FALSE(s.has_silhouette(3));
  EXPECT_EQ(cv::countNonZero(s.sil[1]), cv::countNonZero(s.sil[0]));
  // the view without a mask is named in a warning (which the stage's run log records)
  const auto w = warnings_given();
  ASSERT_GT(w.size(), before);
  const bool named = std::any_of(w.begin() + long(before), w.end(), [](const std::string& m) {
    return m.find("d.jpg") != std::string::npos && m.find("no mask") != std::string::npos;
  });
  EXPECT_TRUE(named);
  fs::remove_all(d);
}

TEST(IngestMasks, OwnNameWinsOverTheOtherConventions) {
  using namespace ingest_masks_test;
  const fs::path d = fresh_dir("masks_order");
  write_folder(d, {"a.jpg"}, {"a.jpg"});
  cv::imwrite((d / "silhouettes" / "a.png").string(), cv::Mat::zeros(48, 64, CV_8U));
  EXPECT_EQ(find_mask(d / "silhouettes", "a.jpg"), d / "silhouettes" / "a.jpg");
  fs::remove_all(d);
}
