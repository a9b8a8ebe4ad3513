#include "common/fileio.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <fstream>
#include <sstream>

#include "common/budget.h"
#include "common/error.h"

namespace tetmvs {
namespace fs = std::filesystem;

namespace {
CommitGroup* g_active = nullptr;
}  // namespace

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

fs::path resolved(const fs::path& p) {
  std::error_code ec;
  fs::path r = fs::weakly_canonical(fs::absolute(p, ec), ec);
  if (ec) r = fs::absolute(p, ec).lexically_normal();
  return r;
}

void commit_file(const fs::path& tmp, const fs::path& target) {
  if (CommitGroup* g = CommitGroup::active()) {
    g->defer(tmp, target);
    return;
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) fail(target.string(), ": cannot rename temporary file into place: ", ec.message());
}

void make_parent_dirs(const fs::path& target) {
  if (!target.has_parent_path()) return;
  // the missing folders, outermost first
  std::vector<fs::path> missing;
  std::error_code ec;
  for (fs::path d = target.parent_path(); !d.empty() && !fs::exists(d, ec); d = d.parent_path()) {
    missing.push_back(d);
    if (d == d.parent_path()) break;
  }
  std::reverse(missing.begin(), missing.end());
  for (const auto& d : missing) {
    const bool made = fs::create_directory(d, ec);  // false without error: made meanwhile by another thread
    if (ec) fail(d.string(), ": cannot create folder for ", target.string(), ": ", ec.message());
    if (CommitGroup* g = CommitGroup::active(); g && made) g->made_dir(d);
  }
}

void write_text_atomic(const fs::path& target, const std::string& content) {
  AtomicFile f(target);
  {
    std::ofstream out(f.tmp(), std::ios::binary);
    if (!out) fail(target.string(), ": cannot open for writing");
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.close();  // the buffered tail is written here: check it too
    if (!out) fail(target.string(), ": write failed (disk full or file size limit?)");
  }
  f.commit();
}

void check_regular_file(const fs::path& file) {
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (!fs::exists(st) || fs::is_regular_file(st)) return;
  fail(file.string(), ": is ", fs::is_directory(st) ? "a folder" : "not a regular file (a device or a pipe)",
       ", expected a file");
}

std::string read_file(const fs::path& file) {
  check_regular_file(file);
  std::error_code ec;
  if (const auto size = fs::file_size(file, ec); !ec)
    check_declared_bytes(static_cast<double>(size), file.string() + " (read whole)");
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file.string(), ": cannot open (missing or unreadable)");
  note_input(file);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

void note_input(const fs::path& file) {
  if (CommitGroup* g = CommitGroup::active()) g->read(file);
}

AtomicFile::AtomicFile(fs::path target) : target_(std::move(target)), tmp_(temp_path_for(target_)) {
  make_parent_dirs(target_);
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

CommitGroup::CommitGroup() : previous_(g_active) { g_active = this; }

CommitGroup::~CommitGroup() {
  discard();  // what commit_all() did not rename
  g_active = previous_;
}

CommitGroup* CommitGroup::active() { return g_active; }

void CommitGroup::defer(const fs::path& tmp, const fs::path& target) {
  std::lock_guard<std::mutex> lock(mu_);
  // a target written twice: its temporary (same name) holds the last version
  std::erase_if(files_, [&](const auto& f) { return f.second == target; });
  files_.emplace_back(tmp, target);
}

void CommitGroup::made_dir(const fs::path& dir) {
  std::lock_guard<std::mutex> lock(mu_);
  dirs_.push_back(dir);
}

void CommitGroup::read(const fs::path& file) {
  const fs::path r = resolved(file);
  std::lock_guard<std::mutex> lock(mu_);
  if (std::find(inputs_.begin(), inputs_.end(), r) == inputs_.end()) inputs_.push_back(r);
}

std::vector<fs::path> CommitGroup::targets() const {
  std::lock_guard<std::mutex> lock(mu_);
  std::vector<fs::path> t;
  for (const auto& f : files_) t.push_back(f.second);
  return t;
}

void CommitGroup::discard() {
  std::error_code ec;
  for (const auto& f : files_) fs::remove(f.first, ec);
  // deepest first (threads may have recorded a folder and its parent in either order);
  // fs::remove leaves a folder that is not empty
  std::sort(dirs_.begin(), dirs_.end(), [](const fs::path& a, const fs::path& b) {
    return a.native().size() > b.native().size();
  });
  for (const auto& d : dirs_) fs::remove(d, ec);
  files_.clear();
  dirs_.clear();
}

void CommitGroup::commit_all() {
  std::lock_guard<std::mutex> lock(mu_);
  for (const auto& f : files_) {
    const fs::path r = resolved(f.second);
    if (std::find(inputs_.begin(), inputs_.end(), r) != inputs_.end())
      fail(f.second.string(), ": is also an input of this stage (writing it would destroy it); choose another output "
           "path (nothing was written)");
  }
  for (std::size_t i = 0; i < files_.size(); ++i) {
    std::error_code ec;
    fs::rename(files_[i].first, files_[i].second, ec);
    if (ec) {
      std::error_code rm;
      for (std::size_t k = 0; k < i; ++k) fs::remove(files_[k].second, rm);
      for (std::size_t k = i; k < files_.size(); ++k) fs::remove(files_[k].first, rm);
      const fs::path target = files_[i].second;
      files_.clear();
      fail(target.string(), ": cannot rename temporary file into place: ", ec.message(),
           " (the stage's other outputs were removed too)");
    }
  }
  files_.clear();
  dirs_.clear();
}

}  // namespace tetmvs
