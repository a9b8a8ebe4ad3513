#include "common/h5io.h"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <type_traits>

#include "common/budget.h"
#include "common/error.h"
#include "common/fileio.h"
#include "common/sha256.h"

namespace tetmvs::h5 {
namespace fs = std::filesystem;

namespace {

// HDF5 prints its own error stacks by default; we report errors ourselves. And the library
// must not clean up at exit: after a failed write (disk full) a file it could not close is
// still in its tables, and its exit handler then crashes trying to close it again. Every
// file is closed explicitly (File::close), so there is nothing left for it to do.
struct Silence {
  Silence() {
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
};
const Silence kSilence;

// RAII holder of an hid_t with its close function.
struct Id {
  hid_t id;
  herr_t (*close)(hid_t);
  Id(hid_t i, herr_t (*c)(hid_t)) : id(i), close(c) {}
  ~Id() {
    if (id >= 0) close(id);
  }
  // Closes now; false when the library reports an error (e.g. a write it had buffered failed).
  bool close_now() {
    const hid_t i = id;
    id = -1;
    return i < 0 || close(i) >= 0;
  }
  Id(const Id&) = delete;
  Id& operator=(const Id&) = delete;
  operator hid_t() const { return id; }
};

std::string norm(const std::string& name) {
  if (name.empty() || name[0] != '/') return "/" + name;
  return name;
}

template <typename T>
hid_t mem_type() {
  if constexpr (std::is_same_v<T, double>) return H5T_NATIVE_DOUBLE;
  else if constexpr (std::is_same_v<T, float>) return H5T_NATIVE_FLOAT;
  else if constexpr (std::is_same_v<T, std::int8_t>) return H5T_NATIVE_INT8;
  else if constexpr (std::is_same_v<T, std::uint8_t>) return H5T_NATIVE_UINT8;
  else if constexpr (std::is_same_v<T, std::int16_t>) return H5T_NATIVE_INT16;
  else if constexpr (std::is_same_v<T, std::uint16_t>) return H5T_NATIVE_UINT16;
  else if constexpr (std::is_same_v<T, std::int32_t>) return H5T_NATIVE_INT32;
  else if constexpr (std::is_same_v<T, std::uint32_t>) return H5T_NATIVE_UINT32;
  else if constexpr (std::is_same_v<T, std::int64_t>) return H5T_NATIVE_INT64;
  else if constexpr (std::is_same_v<T, std::uint64_t>) return H5T_NATIVE_UINT64;
  else static_assert(sizeof(T) == 0, "unsupported HDF5 element type");
}

template <typename T>
std::string type_name() {
  std::string s = std::is_floating_point_v<T> ? "float" : (std::is_signed_v<T> ? "int" : "uint");
  return s + std::to_string(8 * sizeof(T));
}

std::string describe_type(hid_t t) {
  const H5T_class_t c = H5Tget_class(t);
  const size_t sz = H5Tget_size(t);
  if (c == H5T_FLOAT) return "float" + std::to_string(8 * sz);
  if (c == H5T_INTEGER)
    return (H5Tget_sign(t) == H5T_SGN_NONE ? "uint" : "int") + std::to_string(8 * sz);
  if (c == H5T_STRING) return "string";
  return "compound/other";
}

std::string shape_str(const Shape& s) {
  std::ostringstream os;
  os << "(";
  for (size_t i = 0; i < s.size(); ++i) os << (i ? ", " : "") << s[i];
  if (s.size() == 1) os << ",";
  os << ")";
  return os.str();
}

hid_t open_object(hid_t file, const std::string& obj, const fs::path& path) {
  const hid_t o = H5Oopen(file, norm(obj).c_str(), H5P_DEFAULT);
  if (o < 0) fail(path.string(), ": object ", norm(obj), " not found");
  return o;
}

}  // namespace

File File::create(const fs::path& target) {
  File f;
  f.target_ = target;
  f.tmp_ = temp_path_for(target);
  make_parent_dirs(target);
  remove_stale_temps(target);
  f.id_ = H5Fcreate(f.tmp_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (f.id_ < 0) {
    std::error_code ec;
    fs::remove(f.tmp_, ec);
    fail(target.string(), ": cannot create HDF5 file (disk full or file size limit?)");
  }
  f.writable_ = true;
  return f;
}

File File::open(const fs::path& file, const std::string& schema, int min_version,
                int max_version) {
  if (!fs::exists(file)) fail(file.string(), ": file does not exist");
  if (fs::is_directory(file)) fail(file.string(), ": is a folder, expected an HDF5 file");
  check_regular_file(file);
  if (H5Fis_hdf5(file.c_str()) <= 0)
    fail(file.string(), ": not a readable HDF5 file (truncated, empty or another format)");
  File f;
  f.target_ = file;
  f.id_ = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f.id_ < 0) fail(file.string(), ": cannot open HDF5 file (truncated or corrupt?)");
  note_input(file);
  if (!schema.empty()) {
    if (!f.has_attr("/", "schema"))
      fail(file.string(), ": no 'schema' attribute; expected a ", schema, " file");
    const std::string got = f.attr_string("/", "schema");
    if (got != schema) fail(file.string(), ": is a ", got, " file, expected ", schema);
    const std::int64_t v = f.has_attr("/", "schema_version") ? f.attr_int("/", "schema_version") : -1;
    if (v < min_version || v > max_version)
      fail(file.string(), ": ", schema, " version ", v, " is not supported (need ", min_version,
           "..", max_version, "); rerun the stage that wrote it");
  }
  return f;
}

File::File(File&& o) noexcept { *this = std::move(o); }

File& File::operator=(File&& o) noexcept {
  if (this != &o) {
    close();
    id_ = o.id_;
    target_ = std::move(o.target_);
    tmp_ = std::move(o.tmp_);
    writable_ = o.writable_;
    committed_ = o.committed_;
    o.id_ = -1;
    o.writable_ = false;
  }
  return *this;
}

void File::close() {
  if (id_ >= 0) {
    H5Fclose(id_);
    id_ = -1;
  }
  if (writable_ && !committed_) {
    std::error_code ec;
    fs::remove(tmp_, ec);
  }
}

File::~File() { close(); }

void File::commit() {
  require(writable_ && !committed_, target_.string(), ": commit() on a file not open for writing");
  if (H5Fflush(id_, H5F_SCOPE_GLOBAL) < 0) fail(target_.string(), ": flush failed (disk full or file size limit?)");
  const herr_t closed = H5Fclose(id_);
  id_ = -1;
  if (closed < 0) fail(target_.string(), ": closing failed (disk full or file size limit?)");
  commit_file(tmp_, target_);
  committed_ = true;
}

void File::write_header(const std::string& schema, int version, const std::string& stage,
                        const nlohmann::json& params, const std::vector<fs::path>& inputs) {
  set_attr("/", "schema", schema);
  set_attr("/", "schema_version", static_cast<std::int64_t>(version));
  set_attr("/", "stage", stage);
  set_attr("/", "params", params.dump());
  nlohmann::json in = nlohmann::json::array();
  for (const auto& p : inputs) in.push_back({{"name", p.string()}, {"sha256", file_sha256(p)}});
  set_attr("/", "inputs", in.dump());
  set_attr("/", "created_by", std::string("tetmvs 0.1"));
}

bool File::has(const std::string& name) const {
  const std::string n = norm(name);
  if (n == "/") return true;
  // check each path component so that missing parents are not an HDF5 error
  size_t pos = 1;
  while (true) {
    const size_t next = n.find('/', pos);
    const std::string part = n.substr(0, next);
    if (H5Lexists(id_, part.c_str(), H5P_DEFAULT) <= 0) return false;
    if (next == std::string::npos) return true;
    pos = next + 1;
  }
}

void File::create_group(const std::string& name) {
  const std::string n = norm(name);
  size_t pos = 1;
  while (pos <= n.size()) {
    size_t next = n.find('/', pos);
    if (next == std::string::npos) next = n.size();
    const std::string part = n.substr(0, next);
    if (H5Lexists(id_, part.c_str(), H5P_DEFAULT) <= 0) {
      Id gcpl(H5Pcreate(H5P_GROUP_CREATE), H5Pclose);
      H5Pset_obj_track_times(gcpl, false);  // no creation times: same inputs, same bytes
      const hid_t g = H5Gcreate2(id_, part.c_str(), H5P_DEFAULT, gcpl, H5P_DEFAULT);
      if (g < 0) fail(target_.string(), ": cannot create group ", part);
      H5Gclose(g);
    }
    pos = next + 1;
  }
}

template <typename T>
void File::write(const std::string& name, const T* data, const Shape& shape) {
  const std::string n = norm(name);
  const size_t slash = n.rfind('/');
  if (slash > 0) create_group(n.substr(0, slash));
  std::vector<hsize_t> dims(shape.begin(), shape.end());
  std::uint64_t total = 1;
  for (auto d : shape) total *= d;
  if constexpr (std::is_floating_point_v<T>) {
    for (std::uint64_t i = 0; i < total; ++i)
      if (!std::isfinite(data[i]))
        fail(target_.string(), ": refusing to write non-finite value into ", n, " at index ", i);
  }
  Id space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  Id dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_obj_track_times(dcpl, false);  // no creation times: same inputs, same bytes
  if (total > 65536 && !dims.empty() && dims[0] > 0) {
    // chunk along the first axis, about 256 KiB a chunk
    std::vector<hsize_t> chunk = dims;
    std::uint64_t row = total / dims[0] * sizeof(T);
    chunk[0] = std::clamp<hsize_t>(static_cast<hsize_t>((256 * 1024) / std::max<std::uint64_t>(row, 1)), 1, dims[0]);
    H5Pset_chunk(dcpl, static_cast<int>(chunk.size()), chunk.data());
  }
  Id ds(H5Dcreate2(id_, n.c_str(), mem_type<T>(), space, H5P_DEFAULT, dcpl, H5P_DEFAULT), H5Dclose);
  if (ds < 0) fail(target_.string(), ": cannot create dataset ", n);
  if (total > 0 && H5Dwrite(ds, mem_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    fail(target_.string(), ": cannot write dataset ", n, " (disk full or file size limit?)");
  if (!ds.close_now()) fail(target_.string(), ": cannot write dataset ", n, " (disk full or file size limit?)");
}

void File::write_strings(const std::string& name, const std::vector<std::string>& v) {
  const std::string n = norm(name);
  const size_t slash = n.rfind('/');
  if (slash > 0) create_group(n.substr(0, slash));
  Id type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  hsize_t dim = v.size();
  Id space(H5Screate_simple(1, &dim, nullptr), H5Sclose);
  Id dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_obj_track_times(dcpl, false);
  Id ds(H5Dcreate2(id_, n.c_str(), type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT), H5Dclose);
  if (ds < 0) fail(target_.string(), ": cannot create dataset ", n);
  std::vector<const char*> ptrs;
  for (const auto& s : v) ptrs.push_back(s.c_str());
  if ((!v.empty() && H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data()) < 0) || !ds.close_now())
    fail(target_.string(), ": cannot write dataset ", n, " (disk full or file size limit?)");
}

Shape File::shape_of(const std::string& name) const {
  const std::string n = norm(name);
  if (!has(n)) fail(target_.string(), ": dataset ", n, " is missing");
  Id ds(H5Dopen2(id_, n.c_str(), H5P_DEFAULT), H5Dclose);
  if (ds < 0) fail(target_.string(), ": ", n, " is not a dataset");
  Id space(H5Dget_space(ds), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> dims(std::max(rank, 0));
  if (rank > 0) H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  return Shape(dims.begin(), dims.end());
}

template <typename T>
Array<T> File::read(const std::string& name, const std::vector<std::int64_t>& expect,
                    bool allow_nonfinite) const {
  const std::string n = norm(name);
  const std::string where = target_.string() + ": dataset " + n;
  if (!has(n)) fail(where, " is missing");
  Id ds(H5Dopen2(id_, n.c_str(), H5P_DEFAULT), H5Dclose);
  if (ds < 0) fail(where, " is not a dataset");
  Id ftype(H5Dget_type(ds), H5Tclose);
  const H5T_class_t cls = H5Tget_class(ftype);
  const bool want_float = std::is_floating_point_v<T>;
  const bool ok_class = want_float ? cls == H5T_FLOAT : cls == H5T_INTEGER;
  const bool ok_sign = want_float || cls != H5T_INTEGER ||
                       ((H5Tget_sign(ftype) != H5T_SGN_NONE) == std::is_signed_v<T>);
  if (!ok_class || !ok_sign || H5Tget_size(ftype) != sizeof(T))
    fail(where, " has dtype ", describe_type(ftype), ", expected ", type_name<T>());
  Array<T> a;
  a.shape = shape_of(n);
  if (!expect.empty()) {
    bool ok = expect.size() == a.shape.size();
    for (size_t i = 0; ok && i < expect.size(); ++i)
      ok = expect[i] == kAny || static_cast<std::uint64_t>(expect[i]) == a.shape[i];
    if (!ok) {
      std::ostringstream es;
      es << "(";
      for (size_t i = 0; i < expect.size(); ++i)
        es << (i ? ", " : "") << (expect[i] == kAny ? std::string("*") : std::to_string(expect[i]));
      es << (expect.size() == 1 ? ",)" : ")");
      fail(where, " has shape ", shape_str(a.shape), ", expected ", es.str());
    }
  }
  double declared = sizeof(T);
  for (auto d : a.shape) declared *= static_cast<double>(d);
  check_declared_bytes(declared, where + " of shape " + shape_str(a.shape));
  std::uint64_t total = 1;
  for (auto d : a.shape) total *= d;
  a.data.resize(total);
  if (total > 0 && H5Dread(ds, mem_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, a.data.data()) < 0)
    fail(where, " cannot be read (truncated or corrupt file?)");
  if constexpr (std::is_floating_point_v<T>) {
    if (!allow_nonfinite)
      for (std::uint64_t i = 0; i < total; ++i)
        if (!std::isfinite(a.data[i])) fail(where, " holds a non-finite value (NaN or inf) at index ", i);
  }
  return a;
}

std::vector<std::string> File::read_strings(const std::string& name) const {
  const std::string n = norm(name);
  const std::string where = target_.string() + ": dataset " + n;
  if (!has(n)) fail(where, " is missing");
  Id ds(H5Dopen2(id_, n.c_str(), H5P_DEFAULT), H5Dclose);
  Id ftype(H5Dget_type(ds), H5Tclose);
  if (H5Tget_class(ftype) != H5T_STRING) fail(where, " is not a string dataset");
  const Shape sh = shape_of(n);
  if (sh.size() != 1) fail(where, " must be one-dimensional");
  check_declared_bytes(64.0 * static_cast<double>(sh[0]), where + " of " + std::to_string(sh[0]) + " strings");
  std::vector<std::string> out(sh[0]);
  if (H5Tis_variable_str(ftype) > 0) {
    Id mt(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(mt, H5T_VARIABLE);
    H5Tset_cset(mt, H5Tget_cset(ftype));
    std::vector<char*> ptrs(sh[0], nullptr);
    if (sh[0] > 0 && H5Dread(ds, mt, H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data()) < 0)
      fail(where, " cannot be read");
    for (size_t i = 0; i < ptrs.size(); ++i) out[i] = ptrs[i] ? ptrs[i] : "";
    Id space(H5Dget_space(ds), H5Sclose);
    H5Dvlen_reclaim(mt, space, H5P_DEFAULT, ptrs.data());
  } else {
    const size_t sz = H5Tget_size(ftype);
    std::vector<char> buf(sz * sh[0] + 1, 0);
    if (sh[0] > 0 && H5Dread(ds, ftype, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()) < 0)
      fail(where, " cannot be read");
    for (size_t i = 0; i < sh[0]; ++i) out[i] = std::string(buf.data() + i * sz, strnlen(buf.data() + i * sz, sz));
  }
  return out;
}

namespace {
void write_attr_raw(hid_t file, const fs::path& path, const std::string& obj,
                    const std::string& name, hid_t type, hid_t space, const void* buf) {
  Id o(open_object(file, obj, path), H5Oclose);
  if (H5Aexists(o, name.c_str()) > 0) H5Adelete(o, name.c_str());
  Id a(H5Acreate2(o, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (a < 0 || H5Awrite(a, type, buf) < 0)
    fail(path.string(), ": cannot write attribute ", name, " on ", norm(obj));
}
}  // namespace

void File::set_attr(const std::string& obj, const std::string& name, const std::string& v) {
  Id type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  Id space(H5Screate(H5S_SCALAR), H5Sclose);
  const char* p = v.c_str();
  write_attr_raw(id_, target_, obj, name, type, space, &p);
}

void File::set_attr(const std::string& obj, const std::string& name, double v) {
  require(std::isfinite(v), target_.string(), ": refusing to write non-finite attribute ", name);
  Id space(H5Screate(H5S_SCALAR), H5Sclose);
  write_attr_raw(id_, target_, obj, name, H5T_NATIVE_DOUBLE, space, &v);
}

void File::set_attr(const std::string& obj, const std::string& name, std::int64_t v) {
  Id space(H5Screate(H5S_SCALAR), H5Sclose);
  write_attr_raw(id_, target_, obj, name, H5T_NATIVE_INT64, space, &v);
}

void File::set_attr(const std::string& obj, const std::string& name, const std::vector<double>& v) {
  for (double x : v)
    require(std::isfinite(x), target_.string(), ": refusing to write non-finite attribute ", name);
  hsize_t dim = v.size();
  Id space(H5Screate_simple(1, &dim, nullptr), H5Sclose);
  write_attr_raw(id_, target_, obj, name, H5T_NATIVE_DOUBLE, space, v.data());
}

bool File::has_attr(const std::string& obj, const std::string& name) const {
  if (!has(obj)) return false;
  Id o(open_object(id_, obj, target_), H5Oclose);
  return H5Aexists(o, name.c_str()) > 0;
}

std::string File::attr_string(const std::string& obj, const std::string& name) const {
  const std::string where = target_.string() + ": attribute " + name + " of " + norm(obj);
  if (!has_attr(obj, name)) fail(where, " is missing");
  Id o(open_object(id_, obj, target_), H5Oclose);
  Id a(H5Aopen(o, name.c_str(), H5P_DEFAULT), H5Aclose);
  Id ft(H5Aget_type(a), H5Tclose);
  if (H5Tget_class(ft) != H5T_STRING) fail(where, " is not a string");
  if (H5Tis_variable_str(ft) > 0) {
    Id mt(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(mt, H5T_VARIABLE);
    H5Tset_cset(mt, H5Tget_cset(ft));
    char* p = nullptr;
    if (H5Aread(a, mt, &p) < 0) fail(where, " cannot be read");
    std::string s = p ? p : "";
    H5free_memory(p);
    return s;
  }
  const size_t sz = H5Tget_size(ft);
  std::vector<char> buf(sz + 1, 0);
  if (H5Aread(a, ft, buf.data()) < 0) fail(where, " cannot be read");
  return std::string(buf.data(), strnlen(buf.data(), sz));
}

namespace {
template <typename T>
std::vector<T> read_attr_numeric(hid_t file, const fs::path& path, const std::string& obj,
                                 const std::string& name) {
  const std::string where = path.string() + ": attribute " + name + " of " + norm(obj);
  Id o(open_object(file, obj, path), H5Oclose);
  if (H5Aexists(o, name.c_str()) <= 0) fail(where, " is missing");
  Id a(H5Aopen(o, name.c_str(), H5P_DEFAULT), H5Aclose);
  Id ft(H5Aget_type(a), H5Tclose);
  const H5T_class_t c = H5Tget_class(ft);
  if (c != H5T_FLOAT && c != H5T_INTEGER) fail(where, " is not numeric");
  Id space(H5Aget_space(a), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  check_declared_bytes(8.0 * static_cast<double>(n), where);
  std::vector<T> v(std::max<hssize_t>(n, 0));
  if (n > 0 && H5Aread(a, mem_type<T>(), v.data()) < 0) fail(where, " cannot be read");
  return v;
}
}  // namespace

double File::attr_double(const std::string& obj, const std::string& name) const {
  auto v = read_attr_numeric<double>(id_, target_, obj, name);
  if (v.size() != 1) fail(target_.string(), ": attribute ", name, " is not a scalar");
  if (!std::isfinite(v[0])) fail(target_.string(), ": attribute ", name, " is not finite");
  return v[0];
}

std::int64_t File::attr_int(const std::string& obj, const std::string& name) const {
  auto v = read_attr_numeric<std::int64_t>(id_, target_, obj, name);
  if (v.size() != 1) fail(target_.string(), ": attribute ", name, " is not a scalar");
  return v[0];
}

std::vector<double> File::attr_doubles(const std::string& obj, const std::string& name) const {
  auto v = read_attr_numeric<double>(id_, target_, obj, name);
  for (double x : v)
    if (!std::isfinite(x)) fail(target_.string(), ": attribute ", name, " is not finite");
  return v;
}

nlohmann::json File::params() const {
  if (!has_attr("/", "params")) return nlohmann::json::object();
  try {
    return nlohmann::json::parse(attr_string("/", "params"));
  } catch (const nlohmann::json::exception&) {
    fail(target_.string(), ": 'params' attribute is not valid JSON");
  }
}

std::string file_sha256(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file.string(), ": cannot open to checksum");
  Sha256 s;
  std::vector<char> buf(1 << 20);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    s.update(buf.data(), static_cast<size_t>(in.gcount()));
  }
  return s.hex();
}

#define TETMVS_H5_INSTANTIATE(T)                                                              \
  template void File::write<T>(const std::string&, const T*, const Shape&);                   \
  template Array<T> File::read<T>(const std::string&, const std::vector<std::int64_t>&, bool) \
      const;
TETMVS_H5_INSTANTIATE(double)
TETMVS_H5_INSTANTIATE(float)
TETMVS_H5_INSTANTIATE(std::int8_t)
TETMVS_H5_INSTANTIATE(std::uint8_t)
TETMVS_H5_INSTANTIATE(std::int16_t)
TETMVS_H5_INSTANTIATE(std::uint16_t)
TETMVS_H5_INSTANTIATE(std::int32_t)
TETMVS_H5_INSTANTIATE(std::uint32_t)
TETMVS_H5_INSTANTIATE(std::int64_t)
TETMVS_H5_INSTANTIATE(std::uint64_t)

}  // namespace tetmvs::h5
