// COLMAP models: conventions (quaternion, translation, the half-pixel shift), text and
// binary formats, undistortion, the robust box, workspace layouts, and one-line errors.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "common/error.h"
#include "common/fileio.h"
#include "common/image.h"
#include "common/ingest/colmap.h"
#include "common/synth/colmap_export.h"
#include "common/synth/objects.h"
#include "common/synth/scene.h"

using namespace tetmvs;
namespace fs = std::filesystem;

namespace {

struct Tmp {
  fs::path dir;
  Tmp() {
    dir = fs::temp_directory_path() / ("tetmvs_colmap_" + std::to_string(::getpid()) + "_" +
                                       std::to_string(reinterpret_cast<std::uintptr_t>(this)));
    fs::create_directories(dir);
  }
  ~Tmp() { fs::remove_all(dir); }
};

void write(const fs::path& f, const std::string& text) {
  fs::create_directories(f.parent_path());
  std::ofstream(f) << text;
}

// A small scene: 8 ring cameras around a unit sphere.
std::vector<Camera> ring() {
  auto cams = synth::ring_cameras(8, 20, 4.0, Eigen::Vector3d::Zero(), 160, 120, 150.0);
  for (auto& c : cams) c.name = "view" + c.name + ".png";
  return cams;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Colmap, QuaternionIsHamiltonWorldToCamera) {
  // 90 degrees about z: (w, x, y, z) = (cos 45, 0, 0, sin 45) maps x to y
  const double h = std::sqrt(0.5);
  const Eigen::Matrix3d R = colmap::quaternion_to_rotation({h, 0, 0, h});
  EXPECT_NEAR((R * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 0, 1e-15);
  // 90 degrees about x maps y to z
  const Eigen::Matrix3d Rx = colmap::quaternion_to_rotation({h, h, 0, 0});
  EXPECT_NEAR((Rx * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitZ()).norm(), 0, 1e-15);
  // not normalised: normalised first
  EXPECT_NEAR((colmap::quaternion_to_rotation({2, 0, 0, 0}) - Eigen::Matrix3d::Identity()).norm(), 0, 1e-15);
  // round trip, w >= 0
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  for (int k = 0; k < 50; ++k) {
    const Eigen::Vector4d q = Eigen::Vector4d(g(rng), g(rng), g(rng), g(rng)).normalized();
    const Eigen::Vector4d q2 = colmap::rotation_to_quaternion(colmap::quaternion_to_rotation(q));
    EXPECT_GE(q2[0], 0);
    EXPECT_NEAR(std::min((q2 - q).norm(), (q2 + q).norm()), 0, 1e-12);
  }
}

TEST(Colmap, HandWrittenModelHalfPixelConvention) {
  // A model written by hand as COLMAP documents it: the camera at (0, 0, -5) looking
  // down +z (identity rotation, t = (0, 0, 5)); the world origin projects to the principal
  // point (320, 240) in COLMAP's pixels, which is pixel centre (319.5, 239.5) here.
  Tmp t;
  write(t.dir / "cameras.txt", "# comment\n1 PINHOLE 640 480 500 400 320 240\n");
  write(t.dir / "images.txt",
        "# Image list\n1 1 0 0 0 0 0 5 1 a.png\n320 240 7 345 240 8 1 1 -1\n"
        // rotated 90 degrees about z: camera x axis = world y
        "2 0.70710678118654757 0 0 0.70710678118654757 0 0 5 1 b.png\n320 240 7\n");
  write(t.dir / "points3D.txt", "7 0 0 0 10 20 30 0.5 1 0 2 0\n8 0.25 0 0 1 2 3 0.1 1 1\n");
  const colmap::Model m = colmap::read_model(t.dir);
  ASSERT_EQ(m.images.size(), 2u);
  ASSERT_EQ(m.points.size(), 2u);
  const Camera c = colmap::camera_of(m, m.images[0]);
  EXPECT_EQ(c.width, 640);
  EXPECT_EQ(c.height, 480);
  EXPECT_DOUBLE_EQ(c.K(0, 2), 319.5);
  EXPECT_DOUBLE_EQ(c.K(1, 2), 239.5);
  EXPECT_DOUBLE_EQ(c.K(1, 1), 400);
  EXPECT_NEAR((c.centre() - Eigen::Vector3d(0, 0, -5)).norm(), 0, 1e-15);
  const Eigen::Vector2d p = c.project(Eigen::Vector3d::Zero());
  EXPECT_NEAR(p.x(), 319.5, 1e-12);
  EXPECT_NEAR(p.y(), 239.5, 1e-12);
  // (0.25, 0, 0) at depth 5: 500 * 0.05 = 25 px right of the principal point
  const Eigen::Vector2d p8 = c.project(Eigen::Vector3d(0.25, 0, 0));
  EXPECT_NEAR(p8.x() + 0.5, 345, 1e-12);
  EXPECT_NEAR(colmap::project_colmap(m.cameras.at(1), m.images[0], {0.25, 0, 0}).x(), 345, 1e-12);
  // image 2: world x maps to camera y (down): (0.25, 0, 0) lands 20 px below the centre
  const Camera c2 = colmap::camera_of(m, m.images[1]);
  const Eigen::Vector2d q8 = c2.project(Eigen::Vector3d(0.25, 0, 0));
  EXPECT_NEAR(q8.x(), 319.5, 1e-9);
  EXPECT_NEAR(q8.y(), 239.5 + 20, 1e-9);
  EXPECT_EQ(m.images[0].points2d[2].point3d, colmap::kNoPoint);
  EXPECT_EQ(m.points[0].rgb[2], 30);
}

TEST(Colmap, ExportedModelProjectsOntoItsObservationsTextAndBinary) {
  const std::vector<Camera> cams = ring();
  const TriMesh sphere = synth::make_sphere(0.1);
  const colmap::Model m = synth::colmap_model(cams, sphere, nullptr, 500, 1);
  EXPECT_EQ(m.cameras.size(), 1u);  // one shared K
  EXPECT_GT(m.points.size(), 300u);
  Tmp t;
  colmap::write_text_model(t.dir / "txt", m);
  colmap::write_binary_model(t.dir / "bin", m);
  const colmap::Model a = colmap::read_model(t.dir / "txt"), b = colmap::read_model(t.dir / "bin");
  ASSERT_EQ(a.images.size(), cams.size());
  ASSERT_EQ(b.images.size(), cams.size());
  ASSERT_EQ(a.points.size(), m.points.size());
  ASSERT_EQ(b.points.size(), m.points.size());
  EXPECT_EQ(b.files[0].filename(), "cameras.bin");
  // the cameras come back as they were (the quaternion round trip loses ~1e-16)
  for (std::size_t i = 0; i < cams.size(); ++i) {
    for (const colmap::Model* mm : {&a, &b}) {
      const Camera c = colmap::camera_of(*mm, mm->images[i]);
      EXPECT_EQ(c.name, cams[i].name);
      const Eigen::Matrix<double, 3, 4> P = c.P(), P0 = cams[i].P();
      EXPECT_LT((P - P0).norm() / P0.norm(), 1e-12) << "camera " << i;
    }
  }
  // every observation is the projection of its point (COLMAP pixels), within 1e-6 px
  double worst = 0;
  std::size_t n = 0;
  for (const colmap::Model* mm : {&a, &b}) {
    std::map<std::uint32_t, const colmap::Image*> by_id;
    for (const auto& im : mm->images) by_id[im.id] = &im;
    for (const auto& p : mm->points) {
      EXPECT_GE(p.track.size(), 2u);
      for (const auto& te : p.track) {
        const colmap::Image& im = *by_id.at(te.image_id);
        const colmap::Observation& o = im.points2d.at(te.point2d_idx);
        EXPECT_EQ(o.point3d, p.id);
        const Eigen::Vector2d x = colmap::project_colmap(mm->cameras.at(im.camera_id), im, p.xyz);
        const Eigen::Vector2d y = colmap::camera_of(*mm, im).project(p.xyz) + Eigen::Vector2d(0.5, 0.5);
        worst = std::max({worst, (x - Eigen::Vector2d(o.x, o.y)).norm(), (y - Eigen::Vector2d(o.x, o.y)).norm()});
        ++n;
      }
    }
  }
  EXPECT_GT(n, 1000u);
  EXPECT_LT(worst, 1e-6);
  // observations are visible: a point on the far side of the sphere is never observed
  // (the cosine between the ray and the sphere's normal; its facets, h = 0.1, tilt by up to
  // about 0.05 rad, so points just beyond the smooth horizon can be seen)
  int beyond = 0;
  for (const auto& p : a.points)
    for (const auto& te : p.track) {
      const Camera& c = cams[te.image_id - 1];
      const double cosine = (c.centre() - p.xyz).normalized().dot(p.xyz.normalized());
      EXPECT_GT(cosine, -0.06) << "point " << p.id << " seen from behind";
      beyond += cosine < 0;
    }
  EXPECT_LT(beyond, int(n / 50));
}

TEST(Colmap, UndistortionMatchesColmapsDistortion) {
  // For each distorted model: an image whose pixels hold their own coordinates (a ramp)
  // is undistorted; pixel (u, v) of the result must hold the place where COLMAP's model
  // puts the ray of (u, v) in the distorted image.
  struct Case {
    const char* line;
    int model;
  };
  const Case cases[] = {{"SIMPLE_RADIAL", 2}, {"RADIAL", 3}, {"OPENCV", 4}, {"FULL_OPENCV", 6}};
  const int W = 200, H = 150;
  cv::Mat ramp(H, W, CV_32FC2);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) ramp.at<cv::Vec2f>(y, x) = cv::Vec2f(float(x), float(y));
  for (const auto& cs : cases) {
    colmap::Intrinsics in;
    in.model = cs.model;
    in.width = W;
    in.height = H;
    switch (cs.model) {
      case 2: in.params = {180, 101, 76, -0.15}; break;
      case 3: in.params = {180, 101, 76, -0.12, 0.04}; break;
      case 4: in.params = {180, 170, 101, 76, -0.1, 0.02, 0.003, -0.002}; break;
      case 6: in.params = {180, 170, 101, 76, -0.1, 0.02, 0.003, -0.002, 0.01, 0.02, 0.005, 0.001}; break;
    }
    const colmap::Pinhole ph = colmap::pinhole_of(in);
    ASSERT_TRUE(ph.distorted()) << cs.line;
    const cv::Mat out = colmap::undistort(ramp, ph);
    colmap::Image id;  // identity pose
    double worst = 0, largest = 0;
    int checked = 0;
    for (int v = 10; v < H - 10; v += 7)
      for (int u = 10; u < W - 10; u += 7) {
        // the ray of pinhole pixel (u, v) at depth 1
        const Eigen::Vector3d X((u - ph.K(0, 2)) / ph.K(0, 0), (v - ph.K(1, 2)) / ph.K(1, 1), 1);
        const Eigen::Vector2d d = colmap::project_colmap(in, id, X) - Eigen::Vector2d(0.5, 0.5);
        if (d.x() < 1 || d.y() < 1 || d.x() > W - 2 || d.y() > H - 2) continue;
        const cv::Vec2f got = out.at<cv::Vec2f>(v, u);
        worst = std::max(worst, std::hypot(got[0] - d.x(), got[1] - d.y()));
        largest = std::max(largest, std::hypot(u - d.x(), v - d.y()));
        ++checked;
      }
    EXPECT_GT(checked, 300) << cs.line;
    // remap interpolates with a table of 1/32 pixel: up to 1/64 px per axis
    EXPECT_LT(worst, 0.025) << cs.line;
    EXPECT_GT(largest, 2.0) << cs.line;  // the distortion moves pixels by more than that
  }
  // a pinhole camera is returned untouched
  colmap::Intrinsics pin;
  pin.model = 1;
  pin.params = {100, 100, 50, 50};
  EXPECT_FALSE(colmap::pinhole_of(pin).distorted());
}

TEST(Colmap, UnsupportedModelsPointToImageUndistorter) {
  colmap::Intrinsics fe;
  fe.model = 5;  // OPENCV_FISHEYE
  fe.params = {100, 100, 50, 50, 0.1, 0, 0, 0};
  fe.where = "cameras.txt:3";
  const std::string e = error_of([&] { colmap::pinhole_of(fe); });
  EXPECT_NE(e.find("cameras.txt:3"), std::string::npos) << e;
  EXPECT_NE(e.find("OPENCV_FISHEYE"), std::string::npos) << e;
  EXPECT_NE(e.find("colmap image_undistorter"), std::string::npos) << e;
}

TEST(Colmap, BadModelsGiveOneLineErrorsWithFileAndLine) {
  Tmp t;
  const std::string cams = "1 PINHOLE 160 120 100 100 80 60\n";
  const std::string ims = "1 1 0 0 0 0 0 5 1 a.png\n10 20 5\n2 1 0 0 0 0 0 6 1 b.png\n\n";
  const std::string pts = "5 0 0 0 1 2 3 0.5 1 0\n";
  struct Case {
    const char* what;
    std::string c, i, p;
    std::vector<std::string> words;
  };
  const std::vector<Case> cases = {
      {"valid", cams, ims, pts, {}},
      {"unknown model", "1 PINHOLEX 160 120 100 100 80 60\n", ims, pts, {"cameras.txt:1", "unknown camera model 'PINHOLEX'"}},
      {"param count", "# c\n1 PINHOLE 160 120 100 100 80\n", ims, pts, {"cameras.txt:2", "4 parameters"}},
      {"bad number", cams, "1 1 0 0 0 0 0 five 1 a.png\n\n", "", {"images.txt:1", "'five'"}},
      {"missing camera", cams, "1 1 0 0 0 0 0 5 3 a.png\n\n", "", {"images.txt:1", "camera 3"}},
      {"unknown image", cams, ims, "5 0 0 0 1 2 3 0.5 1 0 9 0\n", {"points3D.txt:1", "image 9"}},
      {"bad track index", cams, ims, "5 0 0 0 1 2 3 0.5 1 4\n", {"points3D.txt:1", "point2D 4"}},
      {"odd track", cams, ims, "5 0 0 0 1 2 3 0.5 1\n", {"points3D.txt:1", "pairs"}},
      {"point missing", cams, ims, "", {"images.txt:1", "point 5"}},
      {"points2D not triples", cams, "1 1 0 0 0 0 0 5 1 a.png\n10 20\n", "", {"images.txt:2", "multiple of 3"}},
      {"duplicate camera", cams + cams, ims, pts, {"cameras.txt:2", "twice"}},
      {"zero quaternion", cams, "1 0 0 0 0 0 0 5 1 a.png\n\n", "", {"images.txt:1", "quaternion"}},
      {"nan", cams, "1 1 0 0 0 0 0 nan 1 a.png\n\n", "", {"images.txt:1", "finite"}},
  };
  for (const auto& cs : cases) {
    const fs::path d = t.dir / cs.what;
    write(d / "cameras.txt", cs.c);
    write(d / "images.txt", cs.i);
    write(d / "points3D.txt", cs.p);
    const std::string e = error_of([&] { colmap::read_model(d); });
    if (cs.words.empty()) {
      EXPECT_EQ(e, "") << cs.what;
      continue;
    }
    EXPECT_EQ(e.find('\n'), std::string::npos) << cs.what << ": " << e;
    for (const auto& w : cs.words) EXPECT_NE(e.find(w), std::string::npos) << cs.what << ": '" << e << "' lacks " << w;
  }
  // binary: truncated and trailing bytes
  const colmap::Model m = synth::colmap_model(ring(), synth::make_sphere(0.2), nullptr, 100, 1);
  colmap::write_binary_model(t.dir / "bin", m);
  const std::string full = read_file(t.dir / "bin" / "images.bin");
  write_text_atomic(t.dir / "bin" / "images.bin", full.substr(0, full.size() / 2));
  std::string e = error_of([&] { colmap::read_model(t.dir / "bin"); });
  EXPECT_NE(e.find("images.bin"), std::string::npos) << e;
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
  write_text_atomic(t.dir / "bin" / "images.bin", full + "xx");
  e = error_of([&] { colmap::read_model(t.dir / "bin"); });
  EXPECT_NE(e.find("unexpected bytes"), std::string::npos) << e;
  write_text_atomic(t.dir / "bin" / "images.bin", full);
  std::string cb = read_file(t.dir / "bin" / "cameras.bin");
  cb[8 + 4] = 42;  // model id of the first camera
  write_text_atomic(t.dir / "bin" / "cameras.bin", cb);
  e = error_of([&] { colmap::read_model(t.dir / "bin"); });
  EXPECT_NE(e.find("cameras.bin: camera 1 (record 1): unknown camera model id 42"), std::string::npos) << e;
}

TEST(Colmap, RobustBoxIgnoresOutliersAndHonoursTheRoi) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Vector3d> pts;
  for (int k = 0; k < 5000; ++k) pts.emplace_back(u(rng), 0.5 * u(rng), 0.25 * u(rng));
  for (int k = 0; k < 20; ++k) pts.emplace_back(50 + u(rng), -40, 30);  // 0.4 % far outliers
  const Eigen::AlignedBox3d b = colmap::robust_box(pts, 1.0, 0.0, std::nullopt, 10, "test");
  EXPECT_NEAR(b.min().x(), -0.98, 0.02);
  EXPECT_NEAR(b.max().x(), 0.98, 0.02);
  EXPECT_NEAR(b.max().y(), 0.49, 0.01);
  EXPECT_NEAR(b.min().z(), -0.245, 0.005);
  // padding grows it by a fraction of the diagonal
  const Eigen::AlignedBox3d bp = colmap::robust_box(pts, 1.0, 0.1, std::nullopt, 10, "test");
  EXPECT_NEAR(bp.max().x() - b.max().x(), 0.1 * b.diagonal().norm(), 1e-12);
  // a region of interest keeps only its points and clips the box
  const Eigen::AlignedBox3d roi(Eigen::Vector3d(0, -1, -1), Eigen::Vector3d(2, 1, 1));
  const Eigen::AlignedBox3d br = colmap::robust_box(pts, 1.0, 0.1, roi, 10, "test");
  EXPECT_GE(br.min().x(), 0.0);
  EXPECT_NEAR(br.max().x(), 0.98 + 0.1 * 1.35, 0.05);
  const std::string e = error_of([&] { colmap::robust_box(pts, 1.0, 0.1, Eigen::AlignedBox3d(Eigen::Vector3d::Constant(5), Eigen::Vector3d::Constant(6)), 10, "pts.txt"); });
  EXPECT_NE(e.find("pts.txt: only 0 sparse points inside ingest.roi"), std::string::npos) << e;
}

TEST(Colmap, BoxParameter) {
  Params p = Params::defaults();
  EXPECT_FALSE(colmap::box_param(p, "ingest.box"));
  p.set("ingest.box=-1,-2,-3,1,2,3.5");
  const auto b = colmap::box_param(p, "ingest.box");
  ASSERT_TRUE(b);
  EXPECT_EQ(b->max().z(), 3.5);
  EXPECT_EQ(b->min().y(), -2);
  p.set("ingest.box=1,2,3");
  EXPECT_NE(error_of([&] { colmap::box_param(p, "ingest.box"); }).find("ingest.box: expected six numbers"), std::string::npos);
  p.set("ingest.box=1,2,3,0,5,6");
  EXPECT_NE(error_of([&] { colmap::box_param(p, "ingest.box"); }).find("below the maximum"), std::string::npos);
}

TEST(Colmap, WorkspaceLayouts) {
  Tmp t;
  EXPECT_FALSE(colmap::find_layout(t.dir));  // a Middlebury folder (nothing here)
  write(t.dir / "ws" / "images" / "a.png", "");
  write(t.dir / "ws" / "sparse" / "0" / "cameras.txt", "");
  write(t.dir / "ws" / "sparse" / "1" / "cameras.txt", "");
  auto l = colmap::find_layout(t.dir / "ws");
  ASSERT_TRUE(l);
  EXPECT_EQ(l->model_dir, t.dir / "ws" / "sparse" / "0");
  EXPECT_EQ(l->image_dir, t.dir / "ws" / "images");
  EXPECT_EQ(l->root, t.dir / "ws");
  // the model folder itself: images two levels up
  l = colmap::find_layout(t.dir / "ws" / "sparse" / "1");
  ASSERT_TRUE(l);
  EXPECT_EQ(l->model_dir, t.dir / "ws" / "sparse" / "1");
  EXPECT_EQ(l->image_dir, t.dir / "ws" / "images");
  // sparse/ directly
  write(t.dir / "ws2" / "images" / "a.png", "");
  write(t.dir / "ws2" / "sparse" / "cameras.bin", "");
  l = colmap::find_layout(t.dir / "ws2/");
  ASSERT_TRUE(l);
  EXPECT_EQ(l->model_dir, t.dir / "ws2" / "sparse");
  // sparse/ without images/
  write(t.dir / "ws3" / "sparse" / "cameras.txt", "");
  EXPECT_NE(error_of([&] { colmap::find_layout(t.dir / "ws3"); }).find("images"), std::string::npos);
}

TEST(Colmap, SceneOfAWorkspaceMatchesTheCameras) {
  // A tiny workspace: rendered-free images (grey), the exported model; with no box, no
  // bbox.txt and no silhouettes the box comes from the sparse points.
  Tmp t;
  const std::vector<Camera> cams = ring();
  const TriMesh sphere = synth::make_sphere(0.1);
  colmap::Model m = synth::colmap_model(cams, sphere, nullptr, 800, 2);
  colmap::write_text_model(t.dir / "sparse", m);
  for (const auto& c : cams) {
    cv::Mat img(c.height, c.width, CV_8UC3, cv::Scalar(90, 90, 90));
    write_png_rgb(t.dir / "images" / c.name, img);
  }
  const Params p = Params::defaults();
  const auto l = colmap::find_layout(t.dir);
  ASSERT_TRUE(l);
  const Scene s = colmap::read_scene(*l, p);
  ASSERT_EQ(s.size(), int(cams.size()));
  EXPECT_EQ(s.num_silhouettes(), 0);
  EXPECT_EQ(s.box_source, "sparse points");
  for (int i = 0; i < s.size(); ++i) EXPECT_LT((s.cams[i].P() - cams[i].P()).norm() / cams[i].P().norm(), 1e-12);
  // the unit sphere's box, within the percentile trim and padding (the ring cameras,
  // 20 degrees up, do not see the bottom: z starts higher)
  for (int k = 0; k < 3; ++k) {
    if (k < 2) {
      EXPECT_LT(s.box.min()[k], -0.9);
    }
    EXPECT_GT(s.box.min()[k], -1.3);
    EXPECT_GT(s.box.max()[k], 0.9);
    EXPECT_LT(s.box.max()[k], 1.3);
  }
  EXPECT_LT(s.box.min().z(), -0.2);
  // a missing image: one line naming the image and images.txt's line
  fs::remove(t.dir / "images" / cams[3].name);
  const std::string e = error_of([&] { colmap::read_scene(*l, p); });
  EXPECT_NE(e.find(cams[3].name + ": image file missing (named by "), std::string::npos) << e;
  EXPECT_NE(e.find("images.txt:" + std::to_string(5 + 2 * 3)), std::string::npos) << e;
}
