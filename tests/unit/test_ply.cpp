#include <gtest/gtest.h>

#include <filesystem>
#include <cstring>
#include <fstream>
#include <unistd.h>

#include "common/error.h"
#include "common/fileio.h"
#include "common/ply.h"

using namespace tetmvs;
namespace fs = std::filesystem;

namespace {
// One folder per test process, removed when the process ends.
struct TempFolder {
  fs::path d = fs::temp_directory_path() / ("tetmvs_test_ply_" + std::to_string(::getpid()));
  TempFolder() { fs::create_directories(d); }
  ~TempFolder() {
    std::error_code ec;
    fs::remove_all(d, ec);
  }
};
fs::path tmpdir() {
  static const TempFolder folder;
  return folder.d;
}
TriMesh small_mesh() {
  TriMesh m;
  m.V = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.F = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  m.N = {{0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0.6f, 0.8f}};
  m.C = {{{255, 0, 0}}, {{0, 255, 0}}, {{0, 0, 255}}, {{10, 20, 30}}};
  m.set_vprop("quality", {0.5f, -1.f, 2.f, 3.25f});
  m.set_fprop("region", {0, 1, 2, 1});
  return m;
}
}  // namespace

TEST(Ply, BinaryRoundTripKeepsEverything) {
  const fs::path f = tmpdir() / "rt.ply";
  TriMesh m = small_mesh();
  m.V[1] = {0.0123456789, -0.5, 1e-3};
  PlyWriteOptions o;
  o.double_coords = true;
  o.comment = "test";
  write_ply(f, m, o);
  const TriMesh r = read_ply(f);
  ASSERT_EQ(r.V.size(), 4u);
  ASSERT_EQ(r.F.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(r.V[i], m.V[i]);  // double coordinates round-trip exactly
    EXPECT_EQ(r.N[i], m.N[i]);
    EXPECT_EQ(r.C[i], m.C[i]);
    EXPECT_EQ(r.F[i], m.F[i]);
  }
  ASSERT_NE(r.vprop("quality"), nullptr);
  EXPECT_EQ(*r.vprop("quality"), *m.vprop("quality"));
  ASSERT_NE(r.fprop("region"), nullptr);
  EXPECT_EQ(*r.fprop("region"), *m.fprop("region"));
  // Float coordinates: exact to float precision, and the file is the documented size.
  write_ply(f, m);
  const TriMesh r2 = read_ply(f);
  EXPECT_EQ(r2.V[1].x(), static_cast<double>(static_cast<float>(0.0123456789)));
  std::ifstream in(f, std::ios::binary | std::ios::ate);
  const std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex 4\n"
                             "property float x\nproperty float y\nproperty float z\n"
                             "property float nx\nproperty float ny\nproperty float nz\n"
                             "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                             "property float quality\nelement face 4\n"
                             "property list uchar int vertex_indices\nproperty float region\nend_header\n";
  EXPECT_EQ(static_cast<std::size_t>(in.tellg()), header.size() + 4 * (12 + 12 + 3 + 4) + 4 * (13 + 4));
}

TEST(Ply, PointCloudHasNoFaceElement) {
  const fs::path f = tmpdir() / "pc.ply";
  TriMesh m;
  m.V = {{1, 2, 3}, {4, 5, 6}};
  write_ply(f, m);
  const TriMesh r = read_ply(f);
  EXPECT_TRUE(r.is_point_cloud());
  EXPECT_EQ(r.V[1], Eigen::Vector3d(4, 5, 6));
  EXPECT_TRUE(r.N.empty());
  EXPECT_TRUE(r.C.empty());
}

TEST(Ply, ReadsAsciiWithQuadsAndOtherElements) {
  const fs::path f = tmpdir() / "ascii.ply";
  std::ofstream(f) << "ply\r\nformat ascii 1.0\r\ncomment hi\r\nelement vertex 5\r\n"
                      "property double x\r\nproperty double y\r\nproperty double z\r\nproperty uchar red\r\n"
                      "property uchar green\r\nproperty uchar blue\r\nproperty uchar alpha\r\nproperty float confidence\r\n"
                      "element face 2\r\nproperty list uchar uint vertex_index\r\nproperty int label\r\n"
                      "element edge 1\r\nproperty int vertex1\r\nproperty int vertex2\r\nend_header\r\n"
                      "0 0 0 1 2 3 255 0.5\r\n1 0 0 1 2 3 255 0.5\r\n1 1 0 1 2 3 255 0.5\r\n0 1 0 1 2 3 255 0.5\r\n"
                      "0 0 1 1 2 3 255 0.25\r\n"
                      "4 0 1 2 3 7\r\n3 0 1 4 9\r\n0 1\r\n";
  const TriMesh r = read_ply(f);
  ASSERT_EQ(r.V.size(), 5u);
  ASSERT_EQ(r.F.size(), 3u);  // quad -> 2 triangles
  EXPECT_EQ(r.F[0], Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(r.F[1], Eigen::Vector3i(0, 2, 3));
  EXPECT_EQ(r.F[2], Eigen::Vector3i(0, 1, 4));
  EXPECT_EQ((*r.fprop("label")), (std::vector<float>{7, 7, 9}));
  EXPECT_FLOAT_EQ((*r.vprop("confidence"))[4], 0.25f);
  EXPECT_EQ(r.C[2][2], 3);
}

TEST(Ply, BigEndianBinary) {
  const fs::path f = tmpdir() / "be.ply";
  std::string s = "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                  "property float z\nend_header\n";
  const float v[3] = {1.5f, -2.0f, 3.0f};
  for (float x : v) {
    unsigned char b[4];
    std::memcpy(b, &x, 4);
    for (int i = 3; i >= 0; --i) s.push_back(static_cast<char>(b[i]));
  }
  std::ofstream(f, std::ios::binary) << s;
  const TriMesh r = read_ply(f);
  EXPECT_EQ(r.V[0], Eigen::Vector3d(1.5, -2.0, 3.0));
}

TEST(Ply, ErrorsNameTheFile) {
  const fs::path d = tmpdir();
  auto expect_error = [](const fs::path& f, const std::string& what) {
    try {
      read_ply(f);
      ADD_FAILURE() << "no error for " << f;
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(f.filename().string()), std::string::npos) << msg;
      EXPECT_NE(msg.find(what), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
  };
  expect_error(d / "missing.ply", "missing.ply");
  write_ply(d / "trunc.ply", small_mesh());
  {
    std::string s = read_file(d / "trunc.ply");
    s.resize(s.size() - 5);
    std::ofstream(d / "trunc.ply", std::ios::binary) << s;
  }
  expect_error(d / "trunc.ply", "truncated");
  std::ofstream(d / "badidx.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                     "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                     "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n";
  expect_error(d / "badidx.ply", "refers to vertex 3");
  std::ofstream(d / "notply.ply") << "OFF\n";
  expect_error(d / "notply.ply", "not a PLY");
  std::ofstream(d / "nan.ply") << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                  "property float z\nend_header\nnan 0 0\n";
  expect_error(d / "nan.ply", "non-finite");
}
