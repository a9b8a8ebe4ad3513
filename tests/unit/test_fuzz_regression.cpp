// Replays the fuzz corpora (tests/fuzz_corpus/<target>/, seeds and every crashing input
// scripts/fuzz.sh ever found): each input must be accepted or rejected with
// tetmvs::Error, never crash.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "common/fileio.h"
#include "common/par_io.h"
#include "common/params.h"
#include "common/scene.h"
#include "common/tetmesh/mesh_io.h"
#include "fuzz/h5_builder.h"

namespace fs = std::filesystem;
using namespace tetmvs;

namespace {
std::vector<fs::path> corpus(const std::string& target) {
  std::vector<fs::path> out;
  const fs::path dir = fs::path(TETMVS_SOURCE_DIR) / "tests/fuzz_corpus" / target;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}
}  // namespace

TEST(FuzzRegression, ParReader) {
  const auto files = corpus("par");
  ASSERT_FALSE(files.empty());
  int parsed = 0;
  for (const auto& f : files) {
    try {
      read_par(f);
      ++parsed;
    } catch (const Error&) {
    }
  }
  EXPECT_GE(parsed, 1);  // the seed is a valid file
}

TEST(FuzzRegression, Params) {
  for (const auto& f : corpus("params")) {
    const std::string s = read_file(f);
    Params p = Params::defaults();
    try {
      p.set(s);
    } catch (const Error&) {
    }
    const auto j = nlohmann::json::parse(s, nullptr, false);
    try {
      if (!j.is_discarded()) p.merge(j, f.string());
    } catch (const Error&) {
    }
  }
}

TEST(FuzzRegression, Hdf5Readers) {
  const std::string path = (fs::temp_directory_path() / ("tetmvs_fuzzreg_" + std::to_string(::getpid()) + ".h5")).string();
  int files = 0;
  for (const auto& f : corpus("h5")) {
    const std::string bytes = read_file(f);
    fuzz::build_h5(path, reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    // each input is an edited valid file: the readers accept it or throw Error, nothing else
    try {
      read_scene(path, true);
    } catch (const Error&) {
    }
    try {
      tet::read_mesh(path);
    } catch (const Error&) {
    }
    ++files;
  }
  EXPECT_GE(files, 1);
  fs::remove(path);
}

// The builder's bases are valid files (else the fuzzer would only ever test the first
// check): no edits gives a readable scene / mesh.
TEST(FuzzRegression, Hdf5BuilderBasesAreValid) {
  const std::string path = (fs::temp_directory_path() / ("tetmvs_fuzzbase_" + std::to_string(::getpid()) + ".h5")).string();
  const std::uint8_t scene[] = {0, 0}, mesh[] = {1, 0};
  fuzz::build_h5(path, scene, sizeof scene);
  EXPECT_EQ(read_scene(path, true).size(), 2);
  fuzz::build_h5(path, mesh, sizeof mesh);
  EXPECT_GT(tet::read_mesh(path).num_cells(), 100);
  fs::remove(path);
}
