// Unit tests of the foundation: par reader, camera projection, HDF5 I/O, atomic
// writing, parameters, SHA-256.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <random>

#include "common/camera.h"
#include "common/error.h"
#include "common/fileio.h"
#include "common/h5io.h"
#include "common/par_io.h"
#include "common/params.h"
#include "common/sha256.h"

namespace fs = std::filesystem;
using namespace tetmvs;

namespace {

fs::path temp_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("tetmvs_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void write_file(const fs::path& p, const std::string& s) { std::ofstream(p) << s; }

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

const char* kGoodLine =
    "img1.png 3310.4 0 316.73 0 3325.5 200.55 0 0 1 -0.08661715685291285200 0.97203145042392447000 "
    "0.21829465483805316000 -0.97597093004059532000 -0.03881511324024737600 -0.21441803766270939000 "
    "-0.19994795321325870000 -0.23162091782017200000 0.95203517502501223000 -0.0526034704197 "
    "0.023290917003 0.659119498846\n";

Camera random_camera(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Camera c;
  c.K << 800, 0.5, 320, 0, 810, 240, 0, 0, 1;
  c.R = Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
  c.t = Eigen::Vector3d(u(rng), u(rng), 3 + u(rng));
  c.width = 640;
  c.height = 480;
  return c;
}

}  // namespace

// The real dinoRing par file, when the shared Middlebury data sits beside the checkout
// (a clean clone elsewhere has none: those tests skip).
static fs::path dino_par() {
  return fs::path(TETMVS_SOURCE_DIR) / "../shared/data/middlebury/dinoRing/dinoR_par.txt";
}

TEST(ParReader, ReadsTheRealDinoRingFile) {
  if (!fs::exists(dino_par())) GTEST_SKIP() << "no dinoRing data at " << dino_par();
  const auto cams = read_par(dino_par());
  ASSERT_EQ(cams.size(), 48u);
  EXPECT_EQ(cams[0].name, "dinoR0001.png");
  EXPECT_NEAR(cams[0].K(0, 0), 3310.4, 1e-9);
  EXPECT_NEAR(cams[0].K(1, 2), 200.55, 1e-9);
  EXPECT_NEAR(cams[0].t.z(), 0.659119498846, 1e-12);
  // The box centre of dinoRing projects inside every image, in front of the camera.
  const Eigen::Vector3d centre(0.0145, 0.0647, 0.0188);
  for (auto c : cams) {
    c.width = 640;
    c.height = 480;
    EXPECT_TRUE(c.sees(centre)) << c.name;
  }
}

TEST(ParReader, RejectsBrokenFilesWithFileAndLine) {
  const auto d = temp_dir("par");
  struct Case { std::string text, expect; };
  std::string bad_r = kGoodLine;
  bad_r.replace(bad_r.find("-0.08661715685291285200"), 23, "0.5");
  std::string nonnum = kGoodLine;
  nonnum.replace(nonnum.find("316.73"), 6, "abc");
  std::string nan_line = kGoodLine;
  nan_line.replace(nan_line.find("316.73"), 6, "nan");
  const std::vector<Case> cases = {
      {"", "empty camera file"},
      {"2\n" + std::string(kGoodLine), "declares 2 views but lists 1"},
      {"1\nimg1.png 1 2 3\n", ":2: expected 22 fields"},
      {"1\n" + nonnum, ":2: field 4 'abc' is not a finite number"},
      {"1\n" + nan_line, "is not a finite number"},
      {"1\n" + bad_r, ":2: R is not a rotation"},
      {"2\n" + std::string(kGoodLine) + kGoodLine, ":3: duplicate image name 'img1.png'"},
      {"x\n" + std::string(kGoodLine), ":1: first line must be the number of views"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const auto p = d / ("case" + std::to_string(i) + "_par.txt");
    write_file(p, cases[i].text);
    const std::string msg = message_of([&] { read_par(p); });
    EXPECT_NE(msg.find(cases[i].expect), std::string::npos) << "case " << i << ": " << msg;
    EXPECT_NE(msg.find(p.string()), std::string::npos) << "message must name the file: " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
  }
  EXPECT_NE(message_of([&] { read_par(d / "missing_par.txt"); }).find("cannot open"), std::string::npos);
  fs::remove_all(d);
}

TEST(ParReader, WriteReadRoundTripIsExact) {
  const auto d = temp_dir("parrt");
  std::mt19937 rng(7);
  std::vector<Camera> cams;
  for (int i = 0; i < 5; ++i) {
    cams.push_back(random_camera(rng));
    cams.back().name = "v" + std::to_string(i) + ".png";
  }
  write_par(d / "x_par.txt", cams);
  const auto back = read_par(d / "x_par.txt");
  ASSERT_EQ(back.size(), cams.size());
  for (size_t i = 0; i < cams.size(); ++i) {
    EXPECT_EQ(back[i].name, cams[i].name);
    EXPECT_EQ(back[i].K, cams[i].K);
    EXPECT_EQ(back[i].R, cams[i].R);
    EXPECT_EQ(back[i].t, cams[i].t);
  }
  EXPECT_EQ(find_par_file(d), d / "x_par.txt");
  fs::remove_all(d);
}

TEST(Camera, ProjectBackprojectRoundTrip) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> pix(0, 639), depth(0.5, 5);
  for (int i = 0; i < 1000; ++i) {
    const Camera c = random_camera(rng);
    const double u = pix(rng), v = pix(rng) * 0.75, d = depth(rng);
    const Eigen::Vector3d X = c.backproject(u, v, d);
    EXPECT_NEAR(c.depth(X), d, 1e-9);
    const Eigen::Vector2d p = c.project(X);
    EXPECT_NEAR(p.x(), u, 1e-7);
    EXPECT_NEAR(p.y(), v, 1e-7);
    // the viewing ray passes through X
    const Eigen::Vector3d r = c.ray_direction(u, v);
    EXPECT_NEAR(r.norm(), 1.0, 1e-12);
    EXPECT_NEAR(((X - c.centre()).normalized() - r).norm(), 0.0, 1e-9);
  }
}

TEST(Camera, PixelConventionCentreOfPixelIsInteger) {
  Camera c;
  c.K << 100, 0, 10, 0, 100, 20, 0, 0, 1;
  // the principal point is the pixel centre (10, 20): the optical axis hits it
  const Eigen::Vector2d p = c.project(Eigen::Vector3d(0, 0, 2));
  EXPECT_DOUBLE_EQ(p.x(), 10.0);
  EXPECT_DOUBLE_EQ(p.y(), 20.0);
  EXPECT_DOUBLE_EQ(c.project(Eigen::Vector3d(0.02, 0, 2)).x(), 11.0);
}

TEST(Hdf5, RoundTripsTypedArraysStringsAndAttributes) {
  const auto d = temp_dir("h5");
  const auto p = d / "a.h5";
  std::vector<double> big(300000);
  for (size_t i = 0; i < big.size(); ++i) big[i] = std::sin(double(i));
  {
    auto f = h5::File::create(p);
    f.write_header("tetmvs.test", 3, "unit", {{"a", 1}}, {});
    f.write("/g/x", std::vector<std::int32_t>{1, -2, 3, 4, 5, 6}, {2, 3});
    f.write("/big", big, {100000, 3});
    f.write("/u8", std::vector<std::uint8_t>{0, 255});
    f.write_strings("/names", {"a", "bé", ""});
    f.set_attr("/g", "pi", 3.25);
    f.set_attr("/g", "v", std::vector<double>{1, 2});
    f.commit();
  }
  auto f = h5::File::open(p, "tetmvs.test", 3, 3);
  const auto x = f.read<std::int32_t>("g/x", {2, 3});
  EXPECT_EQ(x.data, (std::vector<std::int32_t>{1, -2, 3, 4, 5, 6}));
  EXPECT_EQ(f.read<double>("/big", {h5::kAny, 3}).data, big);
  EXPECT_EQ(f.read_strings("/names"), (std::vector<std::string>{"a", "bé", ""}));
  EXPECT_EQ(f.attr_double("/g", "pi"), 3.25);
  EXPECT_EQ(f.attr_doubles("/g", "v"), (std::vector<double>{1, 2}));
  EXPECT_EQ(f.attr_string("/", "stage"), "unit");
  EXPECT_EQ(f.params()["a"], 1);
  // validation errors name file and dataset
  EXPECT_NE(message_of([&] { f.read<float>("g/x"); }).find("has dtype int32, expected float32"), std::string::npos);
  EXPECT_NE(message_of([&] { f.read<std::int32_t>("g/x", {3, 2}); }).find("has shape (2, 3), expected (3, 2)"), std::string::npos);
  EXPECT_NE(message_of([&] { f.read<double>("/nope"); }).find("/nope is missing"), std::string::npos);
  EXPECT_NE(message_of([&] { h5::File::open(p, "tetmvs.mesh"); }).find("is a tetmvs.test file, expected tetmvs.mesh"), std::string::npos);
  EXPECT_NE(message_of([&] { h5::File::open(p, "tetmvs.test", 4, 4); }).find("version 3 is not supported"), std::string::npos);
  fs::remove_all(d);
}

TEST(Hdf5, RejectsTruncatedAndNonHdf5Files) {
  const auto d = temp_dir("h5bad");
  {
    auto f = h5::File::create(d / "good.h5");
    f.write("/x", std::vector<double>(100000, 1.0));
    f.commit();
  }
  const std::string bytes = read_file(d / "good.h5");
  write_text_atomic(d / "trunc.h5", bytes.substr(0, bytes.size() / 2));
  write_file(d / "text.h5", "hello");
  write_file(d / "empty.h5", "");
  for (const char* name : {"trunc.h5", "text.h5", "empty.h5", "absent.h5"}) {
    const std::string msg = message_of([&] {
      auto f = h5::File::open(d / name);
      f.read<double>("/x");
    });
    EXPECT_FALSE(msg.empty()) << name;
    EXPECT_NE(msg.find(name), std::string::npos) << msg;
  }
  fs::remove_all(d);
}

TEST(Hdf5, RefusesNonFiniteValuesBothWays) {
  const auto d = temp_dir("h5nan");
  auto f = h5::File::create(d / "n.h5");
  EXPECT_NE(message_of([&] { f.write("/x", std::vector<double>{1.0, NAN}); }).find("non-finite"), std::string::npos);
  fs::remove_all(d);
}

TEST(AtomicWrite, FailureLeavesNoOutputFile) {
  const auto d = temp_dir("atomic");
  const auto p = d / "out.h5";
  try {
    auto f = h5::File::create(p);
    f.write("/x", std::vector<double>{1, 2, 3});
    throw Error("stage failed half way");
  } catch (const Error&) {
  }
  EXPECT_FALSE(fs::exists(p));
  EXPECT_TRUE(fs::is_empty(d)) << "temporary file left behind";
  {
    AtomicFile a(d / "t.txt");
    std::ofstream(a.tmp()) << "x";
  }  // not committed
  EXPECT_FALSE(fs::exists(d / "t.txt"));
  EXPECT_TRUE(fs::is_empty(d));
  fs::remove_all(d);
}

TEST(Params, DefaultsAreDocumentedAndOverridesAreChecked) {
  Params p = Params::defaults();
  for (auto& [k, decl] : p.table().items()) {
    EXPECT_FALSE(decl["meaning"].get<std::string>().empty()) << k;
    EXPECT_TRUE(decl.contains("unit")) << k;
    EXPECT_TRUE(decl.contains("paper")) << k;
    EXPECT_FALSE(decl["stages"].empty()) << k;
  }
  EXPECT_DOUBLE_EQ(p.d("ingest.sil_threshold"), 0.19);
  p.set("ingest.sil_threshold=0.25");
  EXPECT_DOUBLE_EQ(p.d("ingest.sil_threshold"), 0.25);
  p.merge({{"ingest.sil_dilate", 4}}, "x.json");
  EXPECT_EQ(p.i("ingest.sil_dilate"), 4);
  EXPECT_NE(message_of([&] { p.set("ingest.nope=1"); }).find("unknown parameter 'ingest.nope'"), std::string::npos);
  EXPECT_NE(message_of([&] { p.set("ingest.sil_dilate=1.5"); }).find("must be an integer"), std::string::npos);
  EXPECT_NE(message_of([&] { p.set("ingest.sil_threshold=abc"); }).find("not a valid double"), std::string::npos);
  EXPECT_NE(message_of([&] { p.set("ingest.sil_threshold=2"); }).find("above its maximum"), std::string::npos);
  EXPECT_NE(message_of([&] { p.merge({{"ingest.sil_dilate", "x"}}, "d.json"); }).find("d.json: parameter ingest.sil_dilate must be an integer"), std::string::npos);
  EXPECT_EQ(p.values_for("ingest").size(), p.keys_for("ingest").size());
}

// Every parameter has a tier; --help lists the paper's and the extensions' parameters, and
// the expert ones only with --help-all.
TEST(Params, TiersDecideWhatHelpShows) {
  const Params p = Params::defaults();
  int paper = 0, expert = 0;
  for (auto& [k, decl] : p.table().items()) {
    const std::string t = decl["tier"].get<std::string>();
    EXPECT_TRUE(t == "paper" || t == "extension" || t == "expert") << k;
    paper += t == "paper";
    expert += t == "expert";
  }
  EXPECT_GE(paper, 10);
  EXPECT_GT(expert, 0);
  const std::string brief = p.help_for("photoconsist"), all = p.help_for("photoconsist", true);
  EXPECT_NE(brief.find("photo.T = "), std::string::npos);          // paper
  EXPECT_NE(brief.find("photo.detrend = "), std::string::npos);    // extension
  EXPECT_EQ(brief.find("photo.occl_bin_px = "), std::string::npos);  // expert
  EXPECT_NE(all.find("photo.occl_bin_px = "), std::string::npos);
  EXPECT_NE(brief.find("--help-all"), std::string::npos);
}

// Every settings file shipped in examples/params/ (loaded automatically for DATA=<its name>)
// names only known parameters with valid values and says why in its _comment.
TEST(Params, ShippedSettingsFilesLoad) {
  int files = 0;
  for (const auto& e : fs::directory_iterator(fs::path(TETMVS_SOURCE_DIR) / "examples/params")) {
    if (e.path().extension() != ".json") continue;
    ++files;
    Params p = Params::defaults();
    EXPECT_NO_THROW(p.merge_file(e.path())) << e.path();
    std::ifstream in(e.path());
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_TRUE(j.contains("_comment")) << e.path();
  }
  EXPECT_GE(files, 2);  // dinoRing, templeRing
  Params dino = Params::defaults();
  dino.merge_file(fs::path(TETMVS_SOURCE_DIR) / "examples/params/dinoRing.json");
  EXPECT_EQ(dino.s("photo.point_patch"), "grid");
  EXPECT_EQ(dino.d("label.hull_core_px"), 1.5);
}

TEST(Sha256, KnownVectors) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  if (fs::exists(dino_par())) {
    EXPECT_EQ(h5::file_sha256(dino_par()),
              "a1ff4466587abe2bad6e7999e99e052994c7515ddcbe8ab0326732c3b04474a0");
  }
}
