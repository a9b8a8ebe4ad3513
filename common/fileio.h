// Atomic file output: write to "<name>.tmp.<pid>" next to the target, rename at the end.
// A stage that fails or is killed leaves no file under the final name.
#pragma once
#include <filesystem>
#include <string>

namespace tetmvs {

// Temporary sibling path for an atomic write of `target`.
std::filesystem::path temp_path_for(const std::filesystem::path& target);

// Removes temporary siblings "<target>.tmp.<pid>" left by stages that were killed (their
// process no longer exists); called before every atomic write of `target`, so a rerun
// after an interruption leaves no debris. Errors are ignored (best effort).
void remove_stale_temps(const std::filesystem::path& target);

// Renames tmp over target (atomic on POSIX within one filesystem).
void commit_file(const std::filesystem::path& tmp, const std::filesystem::path& target);

// Writes a whole text or binary file atomically.
void write_text_atomic(const std::filesystem::path& target, const std::string& content);

// Reads a whole file; throws Error naming the file when it cannot.
std::string read_file(const std::filesystem::path& file);

// RAII guard: removes the temporary file unless commit() was called.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path target);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  const std::filesystem::path& tmp() const { return tmp_; }
  const std::filesystem::path& target() const { return target_; }
  void commit();

 private:
  std::filesystem::path target_, tmp_;
  bool done_ = false;
};

}  // namespace tetmvs
