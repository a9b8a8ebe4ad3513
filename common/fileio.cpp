#include "common/fileio.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>

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

void remove_stale_temps(const fs::path& target) {
  std::error_code ec;
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::string prefix = target.filename().string() + ".tmp.";
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string digits = name.substr(prefix.size());
    if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(digits));
    if (pid == ::getpid() || !(::kill(pid, 0) == -1 && errno == ESRCH)) continue;  // alive: not ours to touch
    std::error_code rm;
    fs::remove(it->path(), rm);
  }
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
  remove_stale_temps(target_);
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
