// The memory budget (common/budget.h) and the removal of killed stages' temporary files
// (common/fileio.h remove_stale_temps).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "common/budget.h"
#include "common/error.h"
#include "common/fileio.h"
#include "common/tetmesh/mesh_io.h"

namespace fs = std::filesystem;
using namespace tetmvs;

TEST(Budget, RefusesOverBudgetWithEstimateBudgetAndParameter) {
  ::unsetenv("TETMVS_MEMORY_GB");
  Params p = Params::defaults();
  p.set("resource.memory_gb=2");
  EXPECT_DOUBLE_EQ(memory_budget(p).bytes, 2.0 * (1 << 30));
  EXPECT_NO_THROW(check_memory_budget(p, 1.9 * (1 << 30), "x", "y"));
  try {
    check_memory_budget(p, 3.0 * (1 << 30), "refine: mesh_3.h5", "refine fewer levels");
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("refine: mesh_3.h5"), std::string::npos) << m;
    EXPECT_NE(m.find("3 GiB"), std::string::npos) << m;
    EXPECT_NE(m.find("2 GiB"), std::string::npos) << m;
    EXPECT_NE(m.find("resource.memory_gb"), std::string::npos) << m;
    EXPECT_NE(m.find("refine fewer levels"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  // NaN estimates are refused too (never silently pass)
  EXPECT_THROW(check_memory_budget(p, NAN, "x", "y"), Error);
}

TEST(Budget, EnvironmentReplacesParameter) {
  Params p = Params::defaults();
  ::setenv("TETMVS_MEMORY_GB", "0.5", 1);
  EXPECT_DOUBLE_EQ(memory_budget(p).bytes, 0.5 * (1 << 30));
  EXPECT_EQ(memory_budget(p).source, "TETMVS_MEMORY_GB");
  ::setenv("TETMVS_MEMORY_GB", "lots", 1);
  EXPECT_THROW(memory_budget(p), Error);
  ::setenv("TETMVS_MEMORY_GB", "-1", 1);
  EXPECT_THROW(memory_budget(p), Error);
  ::unsetenv("TETMVS_MEMORY_GB");
  EXPECT_EQ(memory_budget(p).source, "resource.memory_gb");
}

TEST(Budget, MeshEstimateCoversTheRealMesh) {
  const auto lat = tet::lattice_for_box(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1)), 6);
  const tet::TetMesh m = tet::build_bcc(lat);
  const fs::path f = fs::temp_directory_path() / ("tetmvs_budget_" + std::to_string(::getpid()) + ".h5");
  tet::write_mesh(f, m, "test", nlohmann::json::object(), {});
  const MeshCounts c = mesh_counts(f);
  fs::remove(f);
  EXPECT_EQ(c.cells, m.num_cells());
  EXPECT_EQ(c.faces, m.num_faces());
  EXPECT_EQ(c.vertices, m.num_vertices());
  EXPECT_EQ(c.nodes, m.num_nodes());
  const double exact = mesh_bytes(c.cells, c.faces, c.vertices, c.nodes);
  EXPECT_GE(exact, 0.6 * static_cast<double>(m.memory_bytes()));
  EXPECT_LE(exact, 1.5 * static_cast<double>(m.memory_bytes()));
  EXPECT_GT(c.read_bytes(), exact);
  // the proportional estimate is within a factor 1.5 for a BCC mesh
  EXPECT_NEAR(mesh_bytes(static_cast<double>(c.cells)) / exact, 1.0, 0.5);
}

TEST(StaleTemps, KilledWritersDebrisIsRemovedLiveOnesKept) {
  const fs::path dir = fs::temp_directory_path() / ("tetmvs_stale_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path target = dir / "mesh_2.h5";
  // a pid that surely does not exist any more: a child that has exited and been reaped
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ::waitpid(dead, nullptr, 0);
  const fs::path stale = dir / ("mesh_2.h5.tmp." + std::to_string(dead));
  const fs::path live = dir / ("mesh_2.h5.tmp." + std::to_string(::getppid()));  // our parent is alive
  const fs::path other = dir / ("mesh_20.h5.tmp." + std::to_string(dead));        // another target's
  for (const auto& p : {stale, live, other}) std::ofstream(p) << "x";
  write_text_atomic(target, "done");
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));
  EXPECT_TRUE(fs::exists(other));
  EXPECT_EQ(read_file(target), "done");
  fs::remove_all(dir);
}
