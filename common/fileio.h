// Atomic file output: write to "<name>.tmp.<pid>" next to the target, rename at the end.
// A stage that fails or is killed leaves no file under the final name.
//
// Inside a stage run (common/stage.h) the renames are deferred to the end of the run: a
// CommitGroup is active, commit_file() only records the finished temporary, and the group
// renames them all once the stage's work succeeded (in the order they were committed), or
// removes them all when it failed. So a stage leaves all of its outputs or none of them.
#pragma once
#include <filesystem>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace tetmvs {

// Temporary sibling path for an atomic write of `target`.
std::filesystem::path temp_path_for(const std::filesystem::path& target);

// Removes temporary siblings "<target>.tmp.<pid>" left by stages that were killed (their
// process no longer exists); called before every atomic write of `target`, so a rerun
// after an interruption leaves no debris. Errors are ignored (best effort).
void remove_stale_temps(const std::filesystem::path& target);

// Renames tmp over target (atomic on POSIX within one filesystem); deferred to the end of
// the stage while a CommitGroup is active.
void commit_file(const std::filesystem::path& tmp, const std::filesystem::path& target);

// Creates the folder that will hold `target` (and its missing parents); folders made here
// during a stage run are removed again when the stage fails (if still empty).
void make_parent_dirs(const std::filesystem::path& target);

// Writes a whole text or binary file atomically.
void write_text_atomic(const std::filesystem::path& target, const std::string& content);

// Reads a whole file; throws Error naming the file when it cannot, when it is not a
// regular file, or when it is larger than the stage's memory budget.
std::string read_file(const std::filesystem::path& file);

// Throws Error naming the file when it exists but is not a regular file (after following
// symbolic links): a folder, a device such as /dev/zero, a pipe that would block forever.
void check_regular_file(const std::filesystem::path& file);

// Records that the running stage reads `file` (the readers call it): no output of the
// stage may replace it (checked by the CommitGroup before any rename).
void note_input(const std::filesystem::path& file);

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

// The outputs of one stage run, renamed into place together (see the top of the file).
// One group is active at a time (the stage's); without one, commit_file renames at once.
class CommitGroup {
 public:
  CommitGroup();   // becomes the active group
  ~CommitGroup();  // removes every temporary not yet renamed and the (empty) folders it made
  CommitGroup(const CommitGroup&) = delete;
  CommitGroup& operator=(const CommitGroup&) = delete;
  static CommitGroup* active();

  void defer(const std::filesystem::path& tmp, const std::filesystem::path& target);
  void made_dir(const std::filesystem::path& dir);
  void read(const std::filesystem::path& file);
  // Renames every temporary recorded so far into place (the group stays active for the
  // files written after). Refuses (Error, nothing renamed) when a
  // target is a file the stage read; when a rename fails, removes the outputs already
  // renamed and the remaining temporaries, then throws an Error naming the file.
  void commit_all();
  // The targets recorded so far (in commit order).
  std::vector<std::filesystem::path> targets() const;

 private:
  void discard();
  mutable std::mutex mu_;
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> files_;  // tmp, target
  std::vector<std::filesystem::path> dirs_;    // folders created
  std::vector<std::filesystem::path> inputs_;  // canonical paths of files read
  CommitGroup* previous_ = nullptr;
};

// The canonical form of a path for comparisons: symbolic links and "..", "." resolved as
// far as the path exists (std::filesystem::weakly_canonical), absolute.
std::filesystem::path resolved(const std::filesystem::path& p);

}  // namespace tetmvs
