// Structure-aware HDF5 file builder shared by the fuzz target and its regression test:
// decodes fuzzer bytes into an HDF5 file with the dataset names the readers look for,
// random dtypes, shapes (including empty) and values (including NaN and inf).
#pragma once
#include <hdf5.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace tetmvs::fuzz {
struct Reader {
  const std::uint8_t* p;
  std::size_t n;
  std::uint8_t byte() { return n ? (--n, *p++) : 0; }
  std::uint32_t u32() { return byte() | (byte() << 8) | (byte() << 16) | (std::uint32_t(byte()) << 24); }
  double real() {
    switch (byte() % 8) {
      case 0: return NAN;
      case 1: return INFINITY;
      case 2: return -1.0;
      case 3: return 0.0;
      default: return static_cast<double>(static_cast<std::int32_t>(u32())) / 1000.0;
    }
  }
};

const char* kNames[] = {"/cameras/K", "/cameras/R", "/cameras/t", "/cameras/size", "/cameras/names",
                        "/images/rgb", "/silhouettes/mask", "/silhouettes/valid", "/box/min", "/box/max",
                        "/vertices", "/vertices_lattice", "/vertex_parent", "/cells", "/cell_level",
                        "/cell_colour", "/cell_node", "/cell_new_red", "/cell_faces", "/faces",
                        "/face_cells", "/face_parent", "/face_sub", "/tree/vertices", "/tree/level",
                        "/tree/parent", "/tree/first_child"};
const hid_t* kTypes[] = {&H5T_NATIVE_DOUBLE, &H5T_NATIVE_FLOAT, &H5T_NATIVE_INT32, &H5T_NATIVE_UINT8,
                         &H5T_NATIVE_INT8, &H5T_NATIVE_INT64};

inline void build(const std::string& path, Reader& r) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  // root attributes
  const char* schemas[] = {"tetmvs.scene", "tetmvs.mesh", "tetmvs.other"};
  const hid_t st = H5Tcopy(H5T_C_S1);
  H5Tset_size(st, H5T_VARIABLE);
  const hid_t scalar = H5Screate(H5S_SCALAR);
  const char* sv = schemas[r.byte() % 3];
  hid_t a = H5Acreate2(f, "schema", st, scalar, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, st, &sv);
  H5Aclose(a);
  std::int64_t ver = r.byte() % 3;
  a = H5Acreate2(f, "schema_version", H5T_NATIVE_INT64, scalar, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, H5T_NATIVE_INT64, &ver);
  H5Aclose(a);
  for (const char* an : {"level", "num_level0", "lattice_bits"}) {
    std::int64_t v = static_cast<std::int32_t>(r.u32()) % 40;
    a = H5Acreate2(f, an, H5T_NATIVE_INT64, scalar, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_INT64, &v);
    H5Aclose(a);
  }
  for (const char* an : {"lattice_h", "lattice_unit"}) {
    double v = r.real();
    a = H5Acreate2(f, an, H5T_NATIVE_DOUBLE, scalar, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_DOUBLE, &v);
    H5Aclose(a);
  }
  const int nsets = r.byte() % 24;
  for (int i = 0; i < nsets && r.n; ++i) {
    const char* name = kNames[r.byte() % (sizeof(kNames) / sizeof(kNames[0]))];
    if (H5Lexists(f, name, H5P_DEFAULT) > 0) continue;
    const hid_t type = *kTypes[r.byte() % 6];
    const int rank = 1 + r.byte() % 3;
    hsize_t dims[3];
    std::size_t total = 1;
    for (int k = 0; k < rank; ++k) {
      dims[k] = r.byte() % 7;
      total *= dims[k];
    }
    const hid_t sp = H5Screate_simple(rank, dims, nullptr);
    const hid_t ds = H5Dcreate2(f, name, type, sp, lcpl, H5P_DEFAULT, H5P_DEFAULT);
    std::vector<double> v(total);
    for (auto& x : v) x = r.real();
    if (ds >= 0 && total) H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    if (ds >= 0) H5Dclose(ds);
    H5Sclose(sp);
  }
  H5Sclose(scalar);
  H5Tclose(st);
  H5Pclose(lcpl);
  H5Fclose(f);
}

inline void build_h5(const std::string& path, const std::uint8_t* data, std::size_t size) {
  Reader r{data, size};
  build(path, r);
}

}  // namespace tetmvs::fuzz
