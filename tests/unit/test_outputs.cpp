// Unit tests of the defences against hostile inputs and failing outputs: the commit group
// (all outputs or none), the output-path checks, image headers read without decoding,
// declared sizes against the budget, PLY headers against the file size, scene geometry.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>

#include "common/budget.h"
#include "common/error.h"
#include "common/fileio.h"
#include "common/h5io.h"
#include "common/image.h"
#include "common/outputs.h"
#include "common/params.h"
#include "common/ply.h"
#include "common/scene.h"
#include "common/synth/scene.h"
#include "common/validate.h"

namespace fs = std::filesystem;
using namespace tetmvs;

namespace outputs_test {

fs::path fresh_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("tetmvs_outputs_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void put(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }

std::string get(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string error_text(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// A scene of two cameras on the z axis looking at a unit box around the origin.
Scene two_view_scene() {
  Scene s;
  for (int i = 0; i < 2; ++i) {
    Camera c;
    c.name = "v" + std::to_string(i) + ".png";
    c.K << 100, 0, 50, 0, 100, 40, 0, 0, 1;
    c.R = Eigen::AngleAxisd(0.2 * i, Eigen::Vector3d::UnitY()).toRotationMatrix();
    c.t = Eigen::Vector3d(0, 0, 5);
    c.width = 100;
    c.height = 80;
    s.cams.push_back(c);
  }
  s.box = Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1));
  return s;
}

}  // namespace outputs_test

using namespace outputs_test;

TEST(CommitGroup, RenamesEverythingAtTheEndOrNothing) {
  const auto d = fresh_dir("group");
  {
    CommitGroup g;
    write_text_atomic(d / "a.txt", "A");
    write_text_atomic(d / "sub" / "b.txt", "B");
    EXPECT_FALSE(fs::exists(d / "a.txt")) << "renamed before the end of the stage";
    EXPECT_EQ(g.targets().size(), 2u);
    g.commit_all();
  }
  EXPECT_EQ(get(d / "a.txt"), "A");
  EXPECT_EQ(get(d / "sub" / "b.txt"), "B");
  fs::remove_all(d / "sub");
  fs::remove(d / "a.txt");
  {
    CommitGroup g;  // the stage fails after writing both
    write_text_atomic(d / "a.txt", "A");
    write_text_atomic(d / "new" / "deeper" / "b.txt", "B");
  }
  EXPECT_TRUE(fs::is_empty(d)) << "a failed stage left files or the folders it made";
  fs::remove_all(d);
}

TEST(CommitGroup, RefusesToReplaceAFileTheStageRead) {
  const auto d = fresh_dir("input");
  put(d / "in.txt", "precious");
  {
    CommitGroup g;
    EXPECT_EQ(read_file(d / "in.txt"), "precious");
    write_text_atomic(d / "other.txt", "x");
    write_text_atomic(d / "." / "in.txt", "overwritten");
    const std::string e = error_text([&] { g.commit_all(); });
    EXPECT_NE(e.find("in.txt"), std::string::npos) << e;
    EXPECT_NE(e.find("is also an input"), std::string::npos) << e;
  }
  EXPECT_EQ(get(d / "in.txt"), "precious");
  EXPECT_FALSE(fs::exists(d / "other.txt"));
  fs::remove_all(d);
}

TEST(CommitGroup, AFailedRenameRemovesTheOutputsAlreadyInPlace) {
  const auto d = fresh_dir("rename");
  {
    CommitGroup g;
    write_text_atomic(d / "first.txt", "1");
    write_text_atomic(d / "second.txt", "2");
    fs::create_directories(d / "third.txt");  // a folder takes the last one's place: its rename fails
    put(d / "third.txt" / "x", "x");
    write_text_atomic(d / "late.txt", "3");
    AtomicFile f(d / "third.txt");
    put(f.tmp(), "3");
    f.commit();
    const std::string e = error_text([&] { g.commit_all(); });
    EXPECT_NE(e.find("third.txt"), std::string::npos) << e;
  }
  EXPECT_FALSE(fs::exists(d / "first.txt"));
  EXPECT_FALSE(fs::exists(d / "second.txt"));
  EXPECT_FALSE(fs::exists(d / "late.txt"));
  for (const auto& e : fs::directory_iterator(d))
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
  fs::remove_all(d);
}

TEST(CommitGroup, HdfFilesJoinTheGroup) {
  const auto d = fresh_dir("h5");
  {
    CommitGroup g;
    auto f = h5::File::create(d / "x.h5");
    f.write("/v", std::vector<double>{1, 2});
    f.commit();
    EXPECT_FALSE(fs::exists(d / "x.h5"));
  }
  EXPECT_TRUE(fs::is_empty(d));
  fs::remove_all(d);
}

TEST(OutputPaths, RefusedBeforeAnyWork) {
  const auto d = fresh_dir("paths");
  put(d / "in.h5", "input");
  put(d / "a_file", "x");
  fs::create_symlink(d / "in.h5", d / "link.h5");
  const std::vector<PathArg> inputs = {{"--scene", d / "in.h5", false}};
  const auto check = [&](const PathArg& o) { return error_text([&] { check_output_paths({o}, inputs); }); };
  EXPECT_EQ(check({"--out", d / "new" / "out.h5", false}), "");
  EXPECT_NE(check({"--out", d / "in.h5", false}).find("is also the input --scene"), std::string::npos);
  EXPECT_NE(check({"--out", d / "link.h5", false}).find("is also the input"), std::string::npos);
  EXPECT_NE(check({"--out", d / "sub" / ".." / "in.h5", false}).find("is also the input"), std::string::npos);
  EXPECT_NE(check({"--out", d / "a_file" / "x.h5", false}).find("is not a folder"), std::string::npos);
  EXPECT_NE(check({"--out", d, false}).find("is a folder"), std::string::npos);
  EXPECT_NE(check({"--png-dir", d / "a_file", true}).find("not a folder"), std::string::npos);
  EXPECT_NE(check({"--out", "/dev/null", false}).find("not a regular file"), std::string::npos);
  EXPECT_NE(check({"--out", "", false}).find("empty"), std::string::npos);
  const std::string two = error_text([&] {
    check_output_paths({{"--out", d / "x.h5", false}, {"--ply", d / "x.h5", false}}, inputs);
  });
  EXPECT_NE(two.find("is also the output --out"), std::string::npos) << two;
  if (::geteuid() != 0) {  // (root writes anywhere)
    fs::create_directories(d / "ro");
    fs::permissions(d / "ro", fs::perms::owner_read | fs::perms::owner_exec);
    EXPECT_NE(check({"--out", d / "ro" / "x.h5", false}).find("cannot write"), std::string::npos);
    fs::permissions(d / "ro", fs::perms::owner_all);
  }
  fs::remove_all(d);
}

TEST(ImageHeader, SizesReadWithoutDecoding) {
  const auto d = fresh_dir("headers");
  // PNG: signature, IHDR length and type, width, height
  std::string png("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0\xea\x60\0\0\x75\x30\x08\x02\0\0\0", 29);
  put(d / "a.png", png);
  auto s = read_image_size(d / "a.png");
  ASSERT_TRUE(s);
  EXPECT_EQ(s->width, 60000);
  EXPECT_EQ(s->height, 30000);
  // JPEG: SOI, an APP0 segment to skip, SOF0 (height, width)
  std::string jpg("\xff\xd8\xff\xe0\0\x04\0\0\xff\xc0\0\x0b\x08\x01\x2c\x02\x58\x01\x01\x11\0", 21);
  put(d / "a.jpg", jpg);
  s = read_image_size(d / "a.jpg");
  ASSERT_TRUE(s);
  EXPECT_EQ(s->width, 600);
  EXPECT_EQ(s->height, 300);
  put(d / "a.ppm", "P6\n# comment\n640 480\n255\n");
  s = read_image_size(d / "a.ppm");
  ASSERT_TRUE(s);
  EXPECT_EQ(s->width, 640);
  EXPECT_EQ(s->height, 480);
  put(d / "a.txt", "not an image");
  EXPECT_FALSE(read_image_size(d / "a.txt"));
  // a header over the budget is refused before decoding, naming the file
  set_stage_memory_budget({1024.0 * 1024 * 1024, "resource.memory_gb"});
  const std::string e = error_text([&] { load_rgb(d / "a.png"); });
  set_stage_memory_budget({});
  EXPECT_NE(e.find("a.png"), std::string::npos) << e;
  EXPECT_NE(e.find("60000 x 30000"), std::string::npos) << e;
  EXPECT_NE(e.find("memory budget"), std::string::npos) << e;
  // past OpenCV's own limit: an Error, not an exception from inside OpenCV
  const std::string e2 = error_text([&] { load_rgb(d / "a.png"); });
  EXPECT_NE(e2.find("a.png"), std::string::npos) << e2;
  fs::remove_all(d);
}

TEST(DeclaredSizes, HdfDatasetsOverTheBudgetAreRefusedBeforeReading) {
  const auto d = fresh_dir("declared");
  {
    auto f = h5::File::create(d / "x.h5");
    f.write("/v", std::vector<double>(1000, 1.0));
    f.commit();
  }
  auto f = h5::File::open(d / "x.h5");
  set_stage_memory_budget({4000.0, "resource.memory_gb"});
  const std::string e = error_text([&] { f.read<double>("/v"); });
  set_stage_memory_budget({});
  EXPECT_NE(e.find("x.h5"), std::string::npos) << e;
  EXPECT_NE(e.find("/v"), std::string::npos) << e;
  EXPECT_EQ(f.read<double>("/v").data.size(), 1000u);
  fs::remove_all(d);
}

TEST(DeclaredSizes, PlyCountsTheFileCannotHoldAreRefused) {
  const auto d = fresh_dir("ply");
  put(d / "big.ply",
      "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n0123456789");
  for (const auto& f : std::vector<std::function<void()>>{[&] { read_ply(d / "big.ply"); },
                                                          [&] { check_ply_header(d / "big.ply"); }}) {
    const std::string e = error_text(f);
    EXPECT_NE(e.find("1000000000000 vertex"), std::string::npos) << e;
  }
  EXPECT_NE(file_problem(d / "big.ply").find("big.ply"), std::string::npos);
  put(d / "x.json", "{\"a\": ");
  EXPECT_NE(file_problem(d / "x.json").find("not valid JSON"), std::string::npos);
  put(d / "x.h5", "");
  EXPECT_NE(file_problem(d / "x.h5"), "");
  EXPECT_NE(error_text([] { read_file("/dev/zero"); }).find("not a regular file"), std::string::npos);
  fs::remove_all(d);
}

TEST(SceneGeometry, NonsenseRefusedSuspiciousWarned) {
  Scene s = two_view_scene();
  EXPECT_TRUE(check_scene_geometry(s, "scene.h5").empty());
  {
    Scene t = s;
    t.box = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-1e30), Eigen::Vector3d::Constant(1e30));
    EXPECT_NE(error_text([&] { check_scene_geometry(t, "scene.h5"); }).find("inside the box"), std::string::npos);
    t.box = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-1e308), Eigen::Vector3d::Constant(1e308));
    EXPECT_NE(error_text([&] { check_scene_geometry(t, "scene.h5"); }).find("not a finite box"), std::string::npos);
  }
  {
    Scene t = s;
    t.cams.resize(1);
    EXPECT_NE(error_text([&] { check_scene_geometry(t, "scene.h5"); }).find("1 view"), std::string::npos);
  }
  {
    Scene t = s;
    t.cams.push_back(s.cams[0]);
    t.cams.back().name = "twin.png";
    const auto w = check_scene_geometry(t, "scene.h5");
    ASSERT_EQ(w.size(), 1u);
    EXPECT_NE(w[0].find("same pose"), std::string::npos) << w[0];
    // a camera turned half a turn about its y axis sees none of the box
    Camera& c = t.cams.back();
    const Eigen::Matrix3d D = Eigen::Vector3d(-1, 1, -1).asDiagonal();
    c.R = D * c.R;
    c.t = D * c.t;
    const auto w2 = check_scene_geometry(t, "scene.h5");
    ASSERT_EQ(w2.size(), 1u);
    EXPECT_NE(w2[0].find("twin.png"), std::string::npos) << w2[0];
    EXPECT_NE(w2[0].find("sees none of the box"), std::string::npos) << w2[0];
    t.cams[1] = c;  // only one view left that sees the box
    EXPECT_NE(error_text([&] { check_scene_geometry(t, "scene.h5"); }).find("only 1 of 3 views"), std::string::npos);
  }
  {
    Scene t = s;
    t.rgb = {cv::Mat(80, 100, CV_8UC3, cv::Scalar(0, 0, 0)), cv::Mat(80, 100, CV_8UC3, cv::Scalar(0, 0, 0))};
    EXPECT_NE(error_text([&] { check_scene_images(t, "data"); }).find("every image is uniform"), std::string::npos);
    cv::randu(t.rgb[1], 0, 255);
    const auto w = check_scene_images(t, "data");
    ASSERT_EQ(w.size(), 1u);
    EXPECT_NE(w[0].find("v0.png"), std::string::npos) << w[0];
  }
}

// A capture from one side (photo.one_sided_deg): cameras on a cap above the object (synth's
// cap, like DTU's), turn on occlusion-aware scoring and, with silhouettes, the hull core at
// label.seed_core_px; a ring around the object changes nothing; an explicit hull core is
// kept; 0 degrees turns the rule off.
TEST(SceneGeometry, OneSidedCaptureAdaptsTheDefaults) {
  const Eigen::Vector3d centre(0, 0, 0);
  const auto cap = [&](bool silhouettes) {
    Scene s;
    s.box = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1));
    s.cams = synth::cap_cameras(12, 10, centre, 64, 48, 80);  // `synth --cameras cap`
    s.sil.assign(12, silhouettes ? cv::Mat(48, 64, CV_8U, cv::Scalar(255)) : cv::Mat());
    return s;
  };
  Scene ring;
  ring.box = cap(true).box;
  ring.cams = synth::ring_cameras(16, 20, 10, centre, 64, 48, 80);
  ring.sil.assign(16, cv::Mat(48, 64, CV_8U, cv::Scalar(255)));

  EXPECT_LT(camera_spread_deg(cap(true)), 45);
  EXPECT_NEAR(camera_spread_deg(ring), 70, 0.5);  // 90 - the ring's elevation
  {
    Params p = Params::defaults();
    EXPECT_TRUE(adapt_to_one_sided_capture(ring, p).empty());
    EXPECT_FALSE(p.b("photo.occlusion"));
    EXPECT_EQ(p.d("label.hull_core_px"), 0);
  }
  {
    Params p = Params::defaults();
    const std::string why = adapt_to_one_sided_capture(cap(true), p);
    EXPECT_NE(why.find("one side"), std::string::npos) << why;
    EXPECT_TRUE(p.b("photo.occlusion"));
    EXPECT_EQ(p.d("label.hull_core_px"), p.d("label.seed_core_px"));
    EXPECT_GT(p.d("label.hull_core_px"), 0);
  }
  {
    Params p = Params::defaults();  // no silhouettes: no hull core
    EXPECT_FALSE(adapt_to_one_sided_capture(cap(false), p).empty());
    EXPECT_TRUE(p.b("photo.occlusion"));
    EXPECT_EQ(p.d("label.hull_core_px"), 0);
  }
  {
    Params p = Params::defaults();
    p.set("label.hull_core_px=3");
    EXPECT_FALSE(adapt_to_one_sided_capture(cap(true), p).empty());
    EXPECT_EQ(p.d("label.hull_core_px"), 3);
  }
  {
    Params p = Params::defaults();
    p.set("photo.one_sided_deg=0");
    EXPECT_TRUE(adapt_to_one_sided_capture(cap(true), p).empty());
    EXPECT_FALSE(p.b("photo.occlusion"));
  }
}
