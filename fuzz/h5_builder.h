// Structure-aware HDF5 input builder shared by the fuzz target and its regression test.
//
// The fuzzer's bytes are decoded into edits of a VALID file, so the readers' checks past
// the schema test are reached (raw byte mutation would mostly exercise libhdf5's own
// parser, which is not ours). The first byte picks the base:
//   0: a small valid scene.h5 (2 cameras, 4x3 images, one silhouette, a box)
//   1: a small valid mesh (BCC level 0 + one adaptive refinement step: red, green cells)
//   2: an empty file with random root attributes (the original from-scratch builder)
// then up to 24 edits follow, each picking a dataset or attribute the readers look at:
//   poke one element (of any dataset, in its own dtype: -1, 0, 1, INT_MIN/MAX, +-1, NaN,
//   inf, random), delete a dataset, replace a dataset with a random dtype/shape/values,
//   rewrite a root attribute (random type, scalar or short vector), rewrite a string
//   dataset (count and contents).
#pragma once
#include <hdf5.h>
#include <unistd.h>

#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "common/fileio.h"
#include "common/h5io.h"
#include "common/scene.h"
#include "common/tetmesh/mesh_io.h"
#include "common/tetmesh/refine.h"

namespace tetmvs::fuzz {

struct Reader {
  const std::uint8_t* p;
  std::size_t n;
  std::uint8_t byte() { return n ? (--n, *p++) : 0; }
  std::uint32_t u32() {
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v |= std::uint32_t(byte()) << (8 * k);
    return v;
  }
  double real() {
    switch (byte() % 10) {
      case 0: return NAN;
      case 1: return INFINITY;
      case 2: return -1.0;
      case 3: return 0.0;
      case 4: return 1e300;
      case 5: return -INFINITY;
      default: return static_cast<double>(static_cast<std::int32_t>(u32())) / 1000.0;
    }
  }
  std::int64_t integer(std::int64_t old) {
    switch (byte() % 10) {
      case 0: return -1;
      case 1: return 0;
      case 2: return 1;
      case 3: return INT32_MAX;
      case 4: return INT32_MIN;
      case 5: return old + 1;
      case 6: return old - 1;
      case 7: return INT64_MAX;
      default: return static_cast<std::int32_t>(u32());
    }
  }
};

inline const char* const kNames[] = {
    "/cameras/K", "/cameras/R", "/cameras/t", "/cameras/size", "/cameras/names", "/images/rgb",
    "/silhouettes/mask", "/silhouettes/valid", "/box/min", "/box/max", "/vertices", "/vertices_lattice",
    "/vertex_parent", "/cells", "/cell_level", "/cell_colour", "/cell_node", "/cell_new_red", "/cell_faces",
    "/faces", "/face_cells", "/face_parent", "/face_sub", "/tree/vertices", "/tree/level", "/tree/parent",
    "/tree/first_child", "/tree/first_cell", "/tree/num_cells"};
inline constexpr int kNumNames = sizeof(kNames) / sizeof(kNames[0]);
inline const char* const kAttrs[] = {"schema", "schema_version", "level", "num_level0", "lattice_bits",
                                     "lattice_h", "lattice_unit", "lattice_origin", "lattice_dims", "dataset"};
inline constexpr int kNumAttrs = sizeof(kAttrs) / sizeof(kAttrs[0]);
inline const hid_t* const kTypes[] = {&H5T_NATIVE_DOUBLE, &H5T_NATIVE_FLOAT, &H5T_NATIVE_INT32,
                                      &H5T_NATIVE_UINT8,  &H5T_NATIVE_INT8,  &H5T_NATIVE_INT64};

// The valid base files, made once per process.
inline std::string make_scene_bytes(const std::string& dir) {
  Scene s;
  for (int i = 0; i < 2; ++i) {
    Camera c;
    c.name = "v" + std::to_string(i) + ".png";
    c.K << 4, 0, 2, 0, 4, 1.5, 0, 0, 1;
    c.R = Eigen::AngleAxisd(0.3 * i, Eigen::Vector3d::UnitY()).toRotationMatrix();
    c.t = Eigen::Vector3d(0, 0, 5);
    c.width = 4;
    c.height = 3;
    s.cams.push_back(c);
    s.rgb.push_back(cv::Mat(3, 4, CV_8UC3, cv::Scalar(10 * i, 20, 30)));
    s.sil.push_back(i == 0 ? cv::Mat(3, 4, CV_8U, cv::Scalar(255)) : cv::Mat());
  }
  s.box = Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1));
  s.box_source = "given";
  s.dataset = "fuzz";
  const std::string path = dir + "/base_scene.h5";
  {
    auto f = h5::File::create(path);
    f.write_header(kSceneSchema, kSceneVersion, "fuzz", nlohmann::json::object(), {});
    write_scene(f, s);
    f.commit();
  }
  return read_file(path);
}

inline std::string make_mesh_bytes(const std::string& dir) {
  const auto lat = tet::lattice_for_box(
      Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1)), 1);
  const tet::TetMesh m0 = tet::build_bcc(lat);
  std::vector<std::uint8_t> active(m0.num_cells(), 0);
  active[0] = 1;  // one red refinement: its neighbours close green
  const tet::TetMesh m1 = tet::refine(m0, active);
  const std::string path = dir + "/base_mesh.h5";
  tet::write_mesh(path, m1, "fuzz", nlohmann::json::object(), {});
  return read_file(path);
}

inline const std::string& base_bytes(int kind) {
  static const std::pair<std::string, std::string> bases = [] {
    char tmpl[] = "/tmp/tetmvs_fuzz_base_XXXXXX";
    const char* d = ::mkdtemp(tmpl);
    if (!d) std::abort();
    std::pair<std::string, std::string> b{make_scene_bytes(d), make_mesh_bytes(d)};
    std::filesystem::remove_all(d);
    return b;
  }();
  return kind == 0 ? bases.first : bases.second;
}

inline void poke(hid_t f, const char* name, Reader& r) {
  const hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
  if (ds < 0) return;
  const hid_t ft = H5Dget_type(ds), sp = H5Dget_space(ds);
  const H5T_class_t cls = H5Tget_class(ft);
  const hssize_t n = H5Sget_simple_extent_npoints(sp);
  if (n > 0 && (cls == H5T_INTEGER || cls == H5T_FLOAT)) {
    const std::size_t i = r.u32() % static_cast<std::size_t>(n);
    if (cls == H5T_INTEGER) {
      std::vector<std::int64_t> v(n);
      H5Dread(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
      v[i] = r.integer(v[i]);
      H5Dwrite(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    } else {
      std::vector<double> v(n);
      H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
      v[i] = r.byte() % 2 ? r.real() : v[i] * (1 + 1e-3 * (r.byte() - 128));
      H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    }
  }
  H5Sclose(sp);
  H5Tclose(ft);
  H5Dclose(ds);
}

inline void replace_random(hid_t f, const char* name, Reader& r) {
  if (H5Lexists(f, name, H5P_DEFAULT) > 0) H5Ldelete(f, name, H5P_DEFAULT);
  const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  const hid_t type = *kTypes[r.byte() % 6];
  const int rank = 1 + r.byte() % 4;
  hsize_t dims[4];
  std::size_t total = 1;
  for (int k = 0; k < rank; ++k) {
    dims[k] = r.byte() % 9;
    total *= dims[k];
  }
  const hid_t sp = H5Screate_simple(rank, dims, nullptr);
  const hid_t ds = H5Dcreate2(f, name, type, sp, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  std::vector<double> v(total);
  for (auto& x : v) x = r.real();
  if (ds >= 0 && total) H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  if (ds >= 0) H5Dclose(ds);
  H5Sclose(sp);
  H5Pclose(lcpl);
}

inline void replace_strings(hid_t f, const char* name, Reader& r) {
  if (H5Lexists(f, name, H5P_DEFAULT) > 0) H5Ldelete(f, name, H5P_DEFAULT);
  const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  const hid_t st = H5Tcopy(H5T_C_S1);
  const bool fixed = r.byte() % 2;
  H5Tset_size(st, fixed ? 1 + r.byte() % 8 : H5T_VARIABLE);
  hsize_t dims[2] = {hsize_t(r.byte() % 5), hsize_t(1 + r.byte() % 2)};
  const int rank = r.byte() % 4 == 0 ? 2 : 1;
  const hid_t sp = H5Screate_simple(rank, dims, nullptr);
  const hid_t ds = H5Dcreate2(f, name, st, sp, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  const std::size_t total = rank == 2 ? dims[0] * dims[1] : dims[0];
  std::vector<std::string> words(total);
  for (auto& w : words) w = std::string(r.byte() % 4, char('a' + r.byte() % 3));
  if (ds >= 0 && total) {
    if (fixed) {
      const std::size_t sz = H5Tget_size(st);
      std::vector<char> buf(total * sz, 0);
      for (std::size_t i = 0; i < total; ++i) std::memcpy(&buf[i * sz], words[i].data(), std::min(sz, words[i].size()));
      H5Dwrite(ds, st, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data());
    } else {
      std::vector<const char*> ptrs;
      for (const auto& w : words) ptrs.push_back(w.c_str());
      H5Dwrite(ds, st, H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data());
    }
  }
  if (ds >= 0) H5Dclose(ds);
  H5Sclose(sp);
  H5Tclose(st);
  H5Pclose(lcpl);
}

inline void set_attr(hid_t f, const char* name, Reader& r) {
  if (H5Aexists(f, name) > 0) H5Adelete(f, name);
  const int kind = r.byte() % 5;
  if (kind == 0) {  // a string
    static const char* const words[] = {"tetmvs.scene", "tetmvs.mesh", "tetmvs.other", "", "{"};
    const char* sv = words[r.byte() % 5];
    const hid_t st = H5Tcopy(H5T_C_S1);
    H5Tset_size(st, H5T_VARIABLE);
    const hid_t sp = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(f, name, st, sp, H5P_DEFAULT, H5P_DEFAULT);
    if (a >= 0) H5Awrite(a, st, &sv), H5Aclose(a);
    H5Sclose(sp);
    H5Tclose(st);
    return;
  }
  const hsize_t n = kind == 1 ? 1 + r.byte() % 4 : 1;
  const hid_t sp = kind == 1 ? H5Screate_simple(1, &n, nullptr) : H5Screate(H5S_SCALAR);
  std::vector<double> v(n);
  for (auto& x : v) x = kind == 3 ? double(r.integer(0)) : r.real();
  const hid_t type = kind == 2 || kind == 3 ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE;
  const hid_t a = H5Acreate2(f, name, type, sp, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) H5Awrite(a, H5T_NATIVE_DOUBLE, v.data()), H5Aclose(a);
  H5Sclose(sp);
}

inline void build(const std::string& path, Reader& r) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const int base = r.byte() % 3;
  hid_t f;
  if (base < 2) {
    const std::string& bytes = base_bytes(base);
    {
      std::ofstream out(path, std::ios::binary | std::ios::trunc);
      out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    }
    f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  } else {
    f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    for (int k = 0; k < kNumAttrs; ++k) set_attr(f, kAttrs[k], r);
  }
  if (f < 0) return;
  const int nedits = r.byte() % 24;
  for (int i = 0; i < nedits && r.n; ++i) {
    const int op = r.byte() % 8;
    const char* name = kNames[r.byte() % kNumNames];
    if (op <= 3) {
      poke(f, name, r);
    } else if (op == 4) {
      if (H5Lexists(f, name, H5P_DEFAULT) > 0) H5Ldelete(f, name, H5P_DEFAULT);
    } else if (op == 5) {
      replace_random(f, name, r);
    } else if (op == 6) {
      set_attr(f, kAttrs[r.byte() % kNumAttrs], r);
    } else {
      replace_strings(f, r.byte() % 2 ? "/cameras/names" : name, r);
    }
  }
  H5Fclose(f);
}

inline void build_h5(const std::string& path, const std::uint8_t* data, std::size_t size) {
  Reader r{data, size};
  build(path, r);
}

}  // namespace tetmvs::fuzz
