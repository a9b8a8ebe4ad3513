// libFuzzer target: validation of HDF5 inputs. The fuzzer's bytes are decoded into edits
// of a valid scene or mesh file (fuzz/h5_builder.h: poked elements, deleted or replaced
// datasets, rewritten attributes), then the scene and mesh readers must accept the file
// or throw tetmvs::Error: no crash, no other exception, no sanitizer report.
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/scene.h"
#include "common/tetmesh/mesh_io.h"
#include "fuzz/h5_builder.h"


extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/tetmvs_fuzz_h5_" + std::to_string(::getpid()) + ".h5";
  tetmvs::fuzz::build_h5(path, data, size);
  try {
    (void)tetmvs::read_scene(path, true);
  } catch (const tetmvs::Error&) {
  }
  try {
    (void)tetmvs::tet::read_mesh(path);
  } catch (const tetmvs::Error&) {
  }
  return 0;
}
