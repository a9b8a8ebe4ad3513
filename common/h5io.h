// HDF5 input/output over the official C API.
//
// Every file a stage writes carries, on its root group, the attributes
//   schema          e.g. "tetmvs.mesh"           (see schemas/<schema>.md)
//   schema_version  integer
//   stage           the program that wrote it
//   params          JSON of every parameter value the stage used
//   inputs          JSON list of {"name", "sha256"} of the files it read
//   created_by      "tetmvs <version>"
// Writers go to a temporary file that commit() renames into place, so an
// interrupted stage never leaves a file that looks finished.
// Readers validate: schema name and version, dataset presence, dtype, shape,
// and (for floating point data) finiteness; every failure is an Error naming
// the file and the dataset.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tetmvs::h5 {

using Shape = std::vector<std::uint64_t>;
constexpr std::int64_t kAny = -1;  // wildcard in expected shapes

// Flat array with its shape, as read from a file (row-major).
template <typename T>
struct Array {
  std::vector<T> data;
  Shape shape;
  std::uint64_t rows() const { return shape.empty() ? 0 : shape[0]; }
  std::uint64_t cols() const { return shape.size() < 2 ? 1 : shape[1]; }
};

class File {
 public:
  // New file at `target`; data goes to a temporary sibling until commit().
  static File create(const std::filesystem::path& target);
  // Existing file, read-only. When schema is non-empty, the root attributes must name
  // it with a version in [min_version, max_version] (default: exactly 1); otherwise an Error explains.
  static File open(const std::filesystem::path& file, const std::string& schema = "",
                   int min_version = 1, int max_version = 1);
  File(File&& o) noexcept;
  File& operator=(File&& o) noexcept;
  File(const File&) = delete;
  File& operator=(const File&) = delete;
  ~File();  // closes; an uncommitted created file is deleted

  // Closes and renames the temporary file into place.
  void commit();
  const std::filesystem::path& path() const { return target_; }

  // The standard root attributes (see top of file).
  void write_header(const std::string& schema, int version, const std::string& stage,
                    const nlohmann::json& params,
                    const std::vector<std::filesystem::path>& inputs);

  bool has(const std::string& name) const;  // dataset or group, "/a/b" or "a/b"
  void create_group(const std::string& name);  // parents created as needed

  // Datasets. Shape defaults to {n}. Arrays of more than 64 Ki elements are chunked
  // (about 256 KiB a chunk) and stored uncompressed: most files are read by several stages,
  // and inflating them cost more CPU than reading the larger file (docs/architecture.md).
  template <typename T>
  void write(const std::string& name, const T* data, const Shape& shape);
  template <typename T>
  void write(const std::string& name, const std::vector<T>& v, Shape shape = {}) {
    if (shape.empty()) shape = {v.size()};
    write(name, v.data(), shape);
  }
  void write_strings(const std::string& name, const std::vector<std::string>& v);

  // Reads a dataset; `expect` gives the expected shape (kAny for any extent, empty for
  // no check). dtype must match T in class and size; floats must be finite unless
  // allow_nonfinite.
  template <typename T>
  Array<T> read(const std::string& name, const std::vector<std::int64_t>& expect = {},
                bool allow_nonfinite = false) const;
  template <typename T>
  std::vector<T> read_vec(const std::string& name, std::int64_t n = kAny) const {
    return read<T>(name, {n}).data;
  }
  std::vector<std::string> read_strings(const std::string& name) const;
  Shape shape_of(const std::string& name) const;

  // Attributes on an object ("/" for the root).
  void set_attr(const std::string& obj, const std::string& name, const std::string& v);
  void set_attr(const std::string& obj, const std::string& name, double v);
  void set_attr(const std::string& obj, const std::string& name, std::int64_t v);
  void set_attr(const std::string& obj, const std::string& name, const std::vector<double>& v);
  bool has_attr(const std::string& obj, const std::string& name) const;
  std::string attr_string(const std::string& obj, const std::string& name) const;
  double attr_double(const std::string& obj, const std::string& name) const;
  std::int64_t attr_int(const std::string& obj, const std::string& name) const;
  std::vector<double> attr_doubles(const std::string& obj, const std::string& name) const;
  // The "params" root attribute parsed as JSON (empty object when absent).
  nlohmann::json params() const;

 private:
  File() = default;
  void close();
  std::int64_t id_ = -1;
  std::filesystem::path target_, tmp_;
  bool writable_ = false, committed_ = false;
};

// SHA-256 of a file's bytes, as lowercase hex.
std::string file_sha256(const std::filesystem::path& file);

}  // namespace tetmvs::h5
