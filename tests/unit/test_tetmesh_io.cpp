// Mesh file round trip, .vtu and slice outputs, projected cell sizes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/camera.h"
#include "common/error.h"
#include "common/h5io.h"
#include "common/params.h"
#include "common/tetmesh/mesh_io.h"
#include "common/tetmesh/projection.h"
#include "common/tetmesh/refine.h"
#include "common/tetmesh/slice.h"

using namespace tetmvs::tet;
namespace fs = std::filesystem;

namespace {
TetMesh small_adaptive() {
  Lattice lat;
  lat.origin = Eigen::Vector3d(1, 2, 3);
  lat.h = 0.25;
  lat.dims = {3, 3, 2};
  TetMesh m = build_bcc(lat);
  for (int l = 0; l < 2; ++l) {
    std::vector<std::uint8_t> act(m.num_cells(), 0);
    for (std::int32_t c = 0; c < m.num_cells(); ++c)
      act[c] = (m.cell_centroid(c) - Eigen::Vector3d(1.3, 2.4, 3.2)).norm() < 0.2;
    m = refine(m, act);
  }
  return m;
}
}  // namespace

TEST(TetMeshIo, RoundTrip) {
  const TetMesh m = small_adaptive();
  const fs::path dir = fs::temp_directory_path() / "tetmvs_test_tetmesh_io";
  fs::create_directories(dir);
  const fs::path file = dir / "mesh_2.h5";
  write_mesh(file, m, "test", nlohmann::json::object(), {});
  const TetMesh r = read_mesh(file);
  EXPECT_EQ(r.level, 2);
  EXPECT_EQ(r.lat.dims, m.lat.dims);
  EXPECT_EQ(r.lat.h, m.lat.h);
  EXPECT_EQ(r.vlat, m.vlat);
  EXPECT_EQ(r.vparent, m.vparent);
  EXPECT_EQ(r.cell_v, m.cell_v);
  EXPECT_EQ(r.cell_colour, m.cell_colour);
  EXPECT_EQ(r.cell_new_red, m.cell_new_red);
  EXPECT_EQ(r.node_child, m.node_child);
  EXPECT_EQ(r.face_half, m.face_half);
  EXPECT_EQ(r.face_parent, m.face_parent);
  EXPECT_EQ(r.face_sub, m.face_sub);
  // a refinement of the read mesh equals a refinement of the original
  std::vector<std::uint8_t> act(m.num_cells(), 0);
  for (std::int32_t c = 0; c < m.num_cells(); c += 7) act[c] = 1;
  EXPECT_EQ(refine(r, act).cell_v, refine(m, act).cell_v);
  // flags file: wrong length is an error naming the file
  {
    auto f = tetmvs::h5::File::create(dir / "pc.h5");
    f.write("/cells/active", std::vector<std::uint8_t>(5, 1));
    f.commit();
  }
  EXPECT_THROW(read_cell_flags(dir / "pc.h5", "/cells/active", m.num_cells()), tetmvs::Error);
  EXPECT_EQ(read_cell_flags(dir / "pc.h5", "/cells/active", 5).size(), 5u);
  // world vertices match the lattice
  tetmvs::h5::File f = tetmvs::h5::File::open(file, kMeshSchema);
  const auto X = f.read<double>("/vertices", {m.num_vertices(), 3}).data;
  for (std::int32_t v = 0; v < m.num_vertices(); ++v)
    EXPECT_NEAR((Eigen::Vector3d(X[3 * v], X[3 * v + 1], X[3 * v + 2]) - m.vertex(v)).norm(), 0.0, 1e-15);
  fs::remove_all(dir);
}

TEST(TetMeshIo, LinkFacesNamesTheFacesBuildFacesMakesAndRejectsBadOnes) {
  const TetMesh m = small_adaptive();
  TetMesh r = m;
  r.face_half.clear();
  link_faces(r);
  EXPECT_EQ(r.face_half, m.face_half);
  // a face named out of order, by a third cell, or with other corners
  std::int32_t c0 = -1, c1 = -1;  // two cells sharing a face
  int j0 = 0;
  for (std::int32_t f = 0; f < m.num_faces() && c0 < 0; ++f)
    if (m.face_half[f][1] >= 0 && m.face_half[f][1] >> 2 != m.face_half[f][0] >> 2)
      c0 = m.face_half[f][0] >> 2, j0 = m.face_half[f][0] & 3, c1 = m.face_half[f][1] >> 2;
  ASSERT_GE(c0, 0);
  {
    TetMesh b = m;
    b.cell_face[0][0] = m.num_faces() - 1;  // the last face named first
    EXPECT_THROW(link_faces(b), tetmvs::Error);
  }
  {
    TetMesh b = m;
    const std::int32_t f = m.cell_face[c0][j0];
    b.cell_face[c1 + 1 < m.num_cells() ? m.num_cells() - 1 : 0][0] = f;  // a third half-face
    EXPECT_THROW(link_faces(b), tetmvs::Error);
  }
  {
    TetMesh b = m;
    std::swap(b.cell_v[c1][0], b.cell_v[c1][1]);  // c1's corners reordered: the faces it names
    std::swap(b.cell_v[c1][2], b.cell_v[c1][3]);  // no longer have its corners
    EXPECT_THROW(link_faces(b), tetmvs::Error);
  }
}

TEST(TetMeshIo, VtuAndSlice) {
  const TetMesh m = small_adaptive();
  const fs::path dir = fs::temp_directory_path() / "tetmvs_test_tetmesh_vtu";
  fs::create_directories(dir);
  std::vector<double> field(m.num_cells());
  for (std::int32_t c = 0; c < m.num_cells(); ++c) field[c] = m.cell_volume(c);
  write_vtu(dir / "m.vtu", m, {{"volume", field}});
  std::ifstream in(dir / "m.vtu", std::ios::binary);
  const std::string s((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(s.find("NumberOfCells=\"" + std::to_string(m.num_cells()) + "\""), std::string::npos);
  EXPECT_NE(s.find("Name=\"volume\""), std::string::npos);
  EXPECT_THROW(write_vtu(dir / "bad.vtu", m, {{"x", {1.0}}}), tetmvs::Error);
  // slice through the refined region: more distinct colours than levels 0..2 and green
  SliceSpec sp;
  sp.axis = 2;
  sp.position = 3.2;
  sp.width = 300;
  const cv::Mat img = render_slice(m, sp, colours_by_level(m));
  ASSERT_EQ(img.type(), CV_8UC3);
  EXPECT_EQ(img.cols, 300);
  std::set<std::array<int, 3>> cols;
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) {
      const auto p = img.at<cv::Vec3b>(y, x);
      cols.insert({p[0], p[1], p[2]});
    }
  const auto pal = colours_by_level(m);
  int found = 0;
  for (int lev = 0; lev <= 2; ++lev)
    for (std::int32_t c = 0; c < m.num_cells(); ++c)
      if (m.node_level[m.cell_node[c]] == lev && m.cell_colour[c] == kRed) {
        found += cols.count({pal[c][0], pal[c][1], pal[c][2]}) > 0;
        break;
      }
  EXPECT_EQ(found, 3);  // all three levels appear in the slice
  fs::remove_all(dir);
}

TEST(TetMeshProjection, LevelsForPixels) {
  Lattice lat;
  lat.h = 0.1;
  lat.dims = {10, 10, 10};
  const Eigen::AlignedBox3d box(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1));
  tetmvs::Camera cam;
  cam.K << 800, 0, 320, 0, 800, 240, 0, 0, 1;
  cam.t = Eigen::Vector3d(-0.5, -0.5, 4.5);  // box centre at depth 5
  cam.width = 640, cam.height = 480;
  // level-0 cell: 0.1 * 800 / 5 = 16 px; 2 px needs 3 halvings
  EXPECT_EQ(levels_for_pixels(lat, box, {cam}, 2.0), 3);
  EXPECT_EQ(levels_for_pixels(lat, box, {cam}, 16.0), 0);
  EXPECT_EQ(levels_for_pixels(lat, box, {cam}, 1.9), 4);
  // the default target (pipeline.mk's LEVELS=auto): 640 x 480 photos with level-0 cells of
  // 28 px (dinoRing's cameras: 24-32 px) keep 3 levels, 1600 x 1200 photos with cells of 255 px
  // (a DTU scan at mesh.cells 16) get 6, both ending at 2-4 px
  const double target = tetmvs::Params::defaults().d("refine.target_pixels");
  tetmvs::Camera dino = cam, dtu = cam;
  dino.K(0, 0) = dino.K(1, 1) = 28 * 5 / lat.h;
  dtu.K(0, 0) = dtu.K(1, 1) = 255 * 5 / lat.h;
  dtu.width = 1600, dtu.height = 1200;
  EXPECT_EQ(levels_for_pixels(lat, box, {dino}, target), 3);
  EXPECT_EQ(levels_for_pixels(lat, box, {dtu}, target), 6);
  tetmvs::Camera behind = cam;
  behind.t = Eigen::Vector3d(-0.5, -0.5, -10);
  EXPECT_THROW(levels_for_pixels(lat, box, {behind}, 2.0), tetmvs::Error);
  // a real mesh: the finest cells near depth 5 project to about h/2^L * 800 / 5
  const TetMesh m = refine_uniform(build_bcc(lattice_for_box(box, 4)), 1);
  const double px = max_projected_cell_size(m, {cam});
  const double h1 = m.lat.h / 2;
  const double near = m.lat.grid_box().min().z() + 4.5, far = m.lat.grid_box().max().z() + 4.5;
  EXPECT_LT(px, h1 * 800 / near);          // no cell centroid is nearer than the grid
  EXPECT_GT(px, h1 * 800 / (near + 0.1));  // and some are close to it
  EXPECT_GT(far, near + 1.0);
}
