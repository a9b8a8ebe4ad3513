#include "common/validate.h"

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/fileio.h"
#include "common/h5io.h"
#include "common/ply.h"

namespace tetmvs {
namespace fs = std::filesystem;

std::string file_problem(const fs::path& file) {
  try {
    if (!fs::exists(file)) return file.string() + ": does not exist";
    const std::string ext = file.extension().string();
    if (ext == ".h5") {
      const auto f = h5::File::open(file);
      require(f.has_attr("/", "schema") && f.has_attr("/", "schema_version"), file.string(),
              ": no schema attributes (not written by a tetmvs stage)");
      f.attr_string("/", "schema");
      f.attr_int("/", "schema_version");
    } else if (ext == ".ply") {
      check_ply_header(file);
      if (fs::file_size(file) <= (8u << 20)) read_ply(file);
    } else if (ext == ".json") {
      const std::string text = read_file(file);
      if (!nlohmann::json::accept(text)) fail(file.string(), ": not valid JSON (truncated or damaged?)");
    }
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    return file.string() + ": " + e.what();
  }
  return "";
}

}  // namespace tetmvs
