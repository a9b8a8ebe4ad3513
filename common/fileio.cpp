#include "common/fileio.h"

#include <unistd.h>

#include <fstream>
#include <sstream>

#include "common/error.h"

namespace tetmvs {
namespace fs = std::filesystem;

fs::path temp_path_for(const fs::path& target) {
  fs::path p = target;
  p += ".tmp." + std::to_string(::getpid());
  return p;
}

void commit_file(const fs::path& tmp, const fs::path& target) {
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) fail(target.string(), ": cannot rename temporary file into place: ", ec.message());
}

void write_text_atomic(const fs::path& target, const std::string& content) {
  AtomicFile f(target);
  {
    std::ofstream out(f.tmp(), std::ios::binary);
    if (!out) fail(target.string(), ": cannot open for writing");
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    if (!out) fail(target.string(), ": write failed (disk full?)");
  }
  f.commit();
}

std::string read_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file.string(), ": cannot open (missing or unreadable)");
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

AtomicFile::AtomicFile(fs::path target) : target_(std::move(target)), tmp_(temp_path_for(target_)) {
  if (target_.has_parent_path()) {
    std::error_code ec;
    fs::create_directories(target_.parent_path(), ec);
  }
}

AtomicFile::~AtomicFile() {
  if (!done_) {
    std::error_code ec;
    fs::remove(tmp_, ec);
  }
}

void AtomicFile::commit() {
  commit_file(tmp_, target_);
  done_ = true;
}

}  // namespace tetmvs
