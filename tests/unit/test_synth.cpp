#include <gtest/gtest.h>

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/fileio.h"
#include "common/image.h"
#include "common/par_io.h"
#include "common/ply.h"
#include "common/synth/objects.h"
#include "common/synth/scene.h"
#include "common/trimesh/bvh.h"
#include "common/trimesh/check.h"
#include "common/trimesh/evaluate.h"
#include "common/trimesh/raster.h"
#include <opencv2/imgproc.hpp>

using namespace tetmvs;
namespace fs = std::filesystem;

namespace {

const fs::path kDino = fs::path(TETMVS_SOURCE_DIR) / ".." / "shared" / "data" / "middlebury" / "dinoRing";

struct DinoSetup {
  std::vector<Camera> cams;
  Eigen::AlignedBox3d box;
};
bool load_dino(DinoSetup& d) {
  if (!fs::exists(kDino / "dinoR_par.txt")) return false;
  d.cams = read_par(kDino / "dinoR_par.txt");
  for (auto& c : d.cams) {
    c.width = 640;
    c.height = 480;
  }
  EXPECT_TRUE(synth::read_readme_box(kDino / "README.txt", d.box));
  return true;
}

// Grey value (mean of RGB, [0,1]) bilinear at (u, v).
double grey_at(const cv::Mat& rgb, double u, double v) {
  const int u0 = static_cast<int>(std::floor(u)), v0 = static_cast<int>(std::floor(v));
  const double a = u - u0, b = v - v0;
  auto g = [&](int x, int y) {
    const cv::Vec3b p = rgb.at<cv::Vec3b>(y, x);
    return (p[0] + p[1] + p[2]) / (3.0 * 255.0);
  };
  return (1 - b) * ((1 - a) * g(u0, v0) + a * g(u0 + 1, v0)) + b * ((1 - a) * g(u0, v0 + 1) + a * g(u0 + 1, v0 + 1));
}

// NCC of (2r+1)^2 patches centred at p1 in img1 and p2 in img2; -2 when a patch leaves an image.
double ncc(const cv::Mat& i1, const Eigen::Vector2d& p1, const cv::Mat& i2, const Eigen::Vector2d& p2, int r) {
  std::vector<double> a, b;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      const double u1 = p1.x() + dx, v1 = p1.y() + dy, u2 = p2.x() + dx, v2 = p2.y() + dy;
      if (u1 < 0 || v1 < 0 || u2 < 0 || v2 < 0 || u1 >= i1.cols - 1 || v1 >= i1.rows - 1 || u2 >= i2.cols - 1 ||
          v2 >= i2.rows - 1)
        return -2;
      a.push_back(grey_at(i1, u1, v1));
      b.push_back(grey_at(i2, u2, v2));
    }
  double ma = 0, mb = 0;
  for (std::size_t k = 0; k < a.size(); ++k) ma += a[k], mb += b[k];
  ma /= a.size();
  mb /= b.size();
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    sab += (a[k] - ma) * (b[k] - mb);
    saa += (a[k] - ma) * (a[k] - ma);
    sbb += (b[k] - mb) * (b[k] - mb);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : -2;
}

double median(std::vector<double> v) {
  if (v.empty()) return -3;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

synth::SolidTexture texture_for(const std::vector<Camera>& cams, const Eigen::AlignedBox3d& box, double strength = 1.0) {
  synth::TextureOptions t;
  const double px = pixel_footprint(cams, box.center());
  t.min_scale = 3 * px;
  t.max_scale = 40 * px;
  t.strength = strength;
  return synth::SolidTexture(t);
}

}  // namespace

TEST(Synth, DinoRingSceneFrame) {
  DinoSetup d;
  if (!load_dino(d)) GTEST_SKIP() << "no dinoRing data at " << kDino;
  ASSERT_EQ(d.cams.size(), 48u);
  EXPECT_NEAR(d.box.min().x(), -0.021897, 1e-9);
  EXPECT_NEAR(d.box.max().y(), 0.108227, 1e-9);
  EXPECT_EQ(synth::scene_up(d.cams, d.box.center()), Eigen::Vector3d(0, 1, 0));
  const double px = pixel_footprint(d.cams, d.box.center());
  EXPECT_NEAR(px, 0.65 / 3318, 0.01e-3);  // about 0.2 mm per pixel
}

TEST(Synth, ObjectsFillTheDinoBox) {
  DinoSetup d;
  if (!load_dino(d)) GTEST_SKIP() << "no dinoRing data";
  const Eigen::Vector3d up = synth::scene_up(d.cams, d.box.center());
  for (const std::string& name : synth::object_names()) {
    SCOPED_TRACE(name);
    synth::Placement p;
    const TriMesh m = synth::make_placed_object(name, d.box, up, 0.85, 1e-3, &p);
    const auto [lo, hi] = bounds(m);
    EXPECT_TRUE(d.box.contains(lo) && d.box.contains(hi));
    // Tight along at least one axis: 85 % of the box.
    double best = 0;
    for (int k = 0; k < 3; ++k) best = std::max(best, (hi[k] - lo[k]) / d.box.sizes()[k]);
    EXPECT_NEAR(best, 0.85, 0.01);
    const MeshCheck c = check_mesh(m);
    EXPECT_TRUE(c.closed && c.oriented);
    for (const auto& k : c.components) EXPECT_GT(k.signed_volume, 0);
    double emax = 0;
    for (const auto& f : m.F)
      for (int k = 0; k < 3; ++k) emax = std::max(emax, (m.V[f[k]] - m.V[f[(k + 1) % 3]]).norm());
    EXPECT_LT(emax, 1.6e-3);
    EXPECT_GT(emax, 0.5e-3);
  }
  // The cup's axis is the scene's up (+y): its cavity opens toward the cameras.
  const TriMesh cup = synth::make_placed_object("cup", d.box, up, 0.85, 1e-3);
  const auto& reg = *cup.fprop("region");
  double ycav = 0, ybody = 0, ncav = 0, nbody = 0;
  for (std::size_t f = 0; f < cup.F.size(); ++f) {
    const double y = cup.V[cup.F[f][0]].y();
    (reg[f] == 1.0f ? ycav : ybody) += y;
    (reg[f] == 1.0f ? ncav : nbody) += 1;
  }
  EXPECT_GT(ycav / ncav, ybody / nbody);
  const auto [clo, chi] = bounds(cup);
  EXPECT_NEAR(chi.y() - clo.y(), chi.x() - clo.x(), 1e-4);  // height 2 = diameter 2
}

// Projected ground-truth points land on matching colours across views: patch NCC near 1
// at the true depth and low away from it.
TEST(Synth, GroundTruthIsPhotoConsistentOnDinoCameras) {
  DinoSetup d;
  if (!load_dino(d)) GTEST_SKIP() << "no dinoRing data";
  const Eigen::Vector3d up = synth::scene_up(d.cams, d.box.center());
  const double px = pixel_footprint(d.cams, d.box.center());
  const TriMesh m = synth::make_placed_object("cup", d.box, up, 0.85, 2 * px);
  const synth::SolidTexture tex = texture_for(d.cams, d.box);
  synth::ShadingOptions sh;
  sh.light = (up + 0.3 * Eigen::Vector3d::UnitX()).normalized();
  sh.noise = 0.01;
  const std::vector<Camera> cams = {d.cams[0], d.cams[2]};  // 15 degrees apart
  const synth::RenderedView a = synth::render_view(m, cams[0], tex, sh, 0);
  const synth::RenderedView b = synth::render_view(m, cams[1], tex, sh, 1);
  const SurfaceSamples s = sample_surface(m, 1e-3, 5);
  const std::vector<int> nvis = count_visible_views(m, s, cams, 1.0);
  std::vector<double> at, off_near, off_far;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (nvis[i] < 2) continue;
    const Eigen::Vector3d X = s.P[i];
    const Eigen::Vector3d ray = (X - cams[0].centre()).normalized();
    // Keep clearly front-facing points (grazing patches are foreshortened).
    if (s.N[i].dot(-ray) < 0.5 || s.N[i].dot((cams[1].centre() - X).normalized()) < 0.5) continue;
    const double c0 = ncc(a.rgb, cams[0].project(X), b.rgb, cams[1].project(X), 4);
    if (c0 < -1) continue;
    at.push_back(c0);
    for (double off : {-3e-3, 3e-3}) {  // ~ 2-3 pixels of parallax in view 2
      const Eigen::Vector3d Y = X + off * ray;
      const double c = ncc(a.rgb, cams[0].project(Y), b.rgb, cams[1].project(Y), 4);
      if (c >= -1) off_near.push_back(c);
    }
    const Eigen::Vector3d Z = X + 8e-3 * ray;
    const double c = ncc(a.rgb, cams[0].project(Z), b.rgb, cams[1].project(Z), 4);
    if (c >= -1) off_far.push_back(c);
  }
  ASSERT_GT(at.size(), 500u);
  EXPECT_GT(median(at), 0.9);
  EXPECT_LT(median(off_near), 0.5);
  EXPECT_LT(median(off_far), 0.3);
  // Texture strength 0: no pattern left to match.
  sh.noise = 0;
  const synth::SolidTexture flat = texture_for(d.cams, d.box, 0.0);
  const synth::RenderedView f = synth::render_view(m, cams[0], flat, sh, 0);
  const synth::RenderedView a0 = synth::render_view(m, cams[0], tex, sh, 0);
  cv::Mat g, g2;
  cv::cvtColor(f.rgb, g, cv::COLOR_RGB2GRAY);
  cv::cvtColor(a0.rgb, g2, cv::COLOR_RGB2GRAY);
  cv::Mat lap, lap2;
  cv::Laplacian(g, lap, CV_32F);
  cv::Laplacian(g2, lap2, CV_32F);
  // Median |Laplacian| over the object (robust to the few rim edges).
  std::vector<double> l1, l2;
  for (int y = 0; y < lap.rows; ++y)
    for (int x = 0; x < lap.cols; ++x)
      if (f.mask.at<std::uint8_t>(y, x)) {
        l1.push_back(std::abs(lap.at<float>(y, x)));
        l2.push_back(std::abs(lap2.at<float>(y, x)));
      }
  EXPECT_GE(median(l2), 3.0);
  EXPECT_LE(median(l1), 1.0);
}

// Silhouettes equal the projection of the ground truth: every pixel's mask agrees with a
// ray cast through its centre.
TEST(Synth, SilhouettesAreTheProjectionOfTheGroundTruth) {
  DinoSetup d;
  if (!load_dino(d)) GTEST_SKIP() << "no dinoRing data";
  const Eigen::Vector3d up = synth::scene_up(d.cams, d.box.center());
  for (const std::string name : {"torus", "two"}) {
    SCOPED_TRACE(name);
    const TriMesh m = synth::make_placed_object(name, d.box, up, 0.85, 1e-3);
    const MeshBVH bvh(m);
    const synth::SolidTexture tex = texture_for(d.cams, d.box);
    synth::ShadingOptions sh;
    sh.supersample = 2;  // even: mask from a separate centre pass
    const Camera& cam = d.cams[30];
    const synth::RenderedView rv = synth::render_view(m, cam, tex, sh, 30);
    std::int64_t mismatch = 0, inside = 0;
    for (int v = 0; v < cam.height; ++v)
      for (int u = 0; u < cam.width; ++u) {
        const bool hit = bvh.raycast(cam.centre(), cam.ray_direction(u, v)).face >= 0;
        inside += hit;
        mismatch += hit != (rv.mask.at<std::uint8_t>(v, u) == 255);
      }
    EXPECT_GT(inside, 20000);
    EXPECT_LE(mismatch, 2);  // only exact edge ties may differ
    // Background is dark, the object lit and anti-aliased (intermediate values on the rim).
    cv::Mat grey;
    cv::cvtColor(rv.rgb, grey, cv::COLOR_RGB2GRAY);
    EXPECT_LT(cv::mean(grey, rv.mask == 0)[0], 25);
    EXPECT_GT(cv::mean(grey, rv.mask)[0], 60);
  }
}

TEST(Synth, WritesAMiddleburyFolderDeterministically) {
  const fs::path dir = fs::temp_directory_path() / ("tetmvs_test_synth_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const Eigen::AlignedBox3d box(Eigen::Vector3d::Constant(-0.035), Eigen::Vector3d::Constant(0.035));
  const int W = 160, H = 120;
  const double focal = 0.4 * std::min(W, H) * 0.65 / (0.5 * box.sizes().norm());
  std::vector<Camera> cams = synth::ring_cameras(6, 20, 0.65, box.center(), W, H, focal);
  for (const Camera& c : cams) EXPECT_TRUE(c.sees(box.center()));
  const Eigen::Vector3d up = synth::scene_up(cams, box.center());
  EXPECT_EQ(up, Eigen::Vector3d::UnitZ());
  const TriMesh m = synth::make_placed_object("horn", box, up, 0.85, 3 * pixel_footprint(cams, box.center()));
  const synth::SolidTexture tex = texture_for(cams, box);
  synth::ShadingOptions sh;
  synth::DatasetInfo info;
  info.prefix = "horn";
  info.box = box;
  info.meta = {{"object", "horn"}};
  omp_set_num_threads(1);
  synth::write_dataset(dir / "a", m, cams, tex, sh, info);
  omp_set_num_threads(2);
  synth::write_dataset(dir / "b", m, cams, tex, sh, info);
  for (const std::string f : {"horn_par.txt", "horn0001.png", "horn0006.png", "silhouettes/horn0003.png", "bbox.txt",
                              "gt.ply", "synth.json"}) {
    ASSERT_TRUE(fs::exists(dir / "a" / f)) << f;
    EXPECT_EQ(read_file(dir / "a" / f), read_file(dir / "b" / f)) << f;
  }
  const std::vector<Camera> back = read_par(dir / "a" / "horn_par.txt");
  ASSERT_EQ(back.size(), 6u);
  EXPECT_EQ(back[2].name, "horn0003.png");
  EXPECT_LT((back[2].K - cams[2].K).norm(), 1e-9);
  EXPECT_EQ(find_par_file(dir / "a"), dir / "a" / "horn_par.txt");
  const cv::Mat img = load_rgb(dir / "a" / "horn0003.png");
  EXPECT_EQ(img.cols, W);
  const cv::Mat sil = load_mask(dir / "a" / "silhouettes" / "horn0003.png");
  EXPECT_GT(cv::countNonZero(sil), 500);
  const TriMesh gt = read_ply(dir / "a" / "gt.ply");
  EXPECT_EQ(gt.F.size(), m.F.size());
  ASSERT_NE(gt.fprop("region"), nullptr);
  EXPECT_EQ(std::count(gt.fprop("region")->begin(), gt.fprop("region")->end(), 2.0f) > 0, true);
  std::ifstream bb(dir / "a" / "bbox.txt");
  double v[6];
  for (double& x : v) bb >> x;
  EXPECT_DOUBLE_EQ(v[0], -0.035);
  EXPECT_DOUBLE_EQ(v[5], 0.035);
  // Another seed changes the images.
  synth::ShadingOptions sh2 = sh;
  sh2.seed = 2;
  synth::write_dataset(dir / "c", m, cams, tex, sh2, info);
  EXPECT_NE(read_file(dir / "a" / "horn0001.png"), read_file(dir / "c" / "horn0001.png"));
  fs::remove_all(dir);
}

TEST(Synth, CameraHelpers) {
  const Eigen::Vector3d target(0.1, 0.2, 0.3);
  const auto ring = synth::ring_cameras(8, 30, 2.0, target, 64, 48, 50);
  for (const Camera& c : ring) {
    EXPECT_NEAR((c.centre() - target).norm(), 2.0, 1e-12);
    EXPECT_NEAR(c.centre().z() - target.z(), 1.0, 1e-12);  // sin(30) * 2
    const Eigen::Vector2d p = c.project(target);
    EXPECT_NEAR(p.x(), 31.5, 1e-9);
    EXPECT_NEAR(p.y(), 23.5, 1e-9);
    EXPECT_TRUE(is_rotation(c.R));
    // World up projects upward in the image.
    EXPECT_LT(c.project(target + 0.1 * Eigen::Vector3d::UnitZ()).y(), p.y());
  }
  const auto hemi = synth::hemisphere_cameras(20, 1.0, target, 64, 48, 50);
  for (const Camera& c : hemi) EXPECT_GT(c.centre().z(), target.z() + std::sin(9.9 * 3.14159265 / 180));
  std::vector<Camera> sub = synth::subset_views(ring, 4);
  ASSERT_EQ(sub.size(), 4u);
  EXPECT_EQ(sub[1].name, ring[2].name);
  // Resizing keeps the projection of a point (scaled about pixel centres).
  std::vector<Camera> half = sub;
  synth::resize_cameras(half, 32, 24);
  const Eigen::Vector3d X = target + Eigen::Vector3d(0.3, -0.2, 0.1);
  const Eigen::Vector2d p = sub[0].project(X), q = half[0].project(X);
  EXPECT_NEAR(q.x(), (p.x() + 0.5) / 2 - 0.5, 1e-9);
  EXPECT_NEAR(q.y(), (p.y() + 0.5) / 2 - 0.5, 1e-9);
}

// The cup's cavity shows in no dinoRing silhouette: the cup and the cup closed by a lid
// have the same silhouettes (to within rim discretisation).
TEST(Synth, CupCavityIsHiddenFromEverySilhouette) {
  DinoSetup d;
  if (!load_dino(d)) GTEST_SKIP() << "no dinoRing data";
  const Eigen::Vector3d up = synth::scene_up(d.cams, d.box.center());
  const TriMesh cup = synth::make_placed_object("cup", d.box, up, 0.85, 1e-3);
  const TriMesh lid = synth::make_placed_object("cup_filled", d.box, up, 0.85, 1e-3);
  std::int64_t differ = 0, area = 0;
  for (std::size_t v = 0; v < d.cams.size(); v += 3) {
    const cv::Mat a = rasterize(cup, d.cams[v]).tri >= 0, b = rasterize(lid, d.cams[v]).tri >= 0;
    differ += cv::countNonZero(a != b);
    area += cv::countNonZero(a);
  }
  EXPECT_GT(area, 16 * 20000);
  EXPECT_LT(static_cast<double>(differ) / area, 2e-3);
}
