// Messages on stderr: info (silenced by --quiet), warnings, the progress bar and
// the per-stage summary line.
#pragma once
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

namespace tetmvs {

void set_quiet(bool q);
bool is_quiet();
void log_line(const std::string& level, const std::string& msg);
// Every warning given so far by this process (the stage's run log records them).
std::vector<std::string> warnings_given();

template <typename... Args>
void info(const Args&... parts) {
  if (is_quiet()) return;
  std::ostringstream os;
  (os << ... << parts);
  log_line("", os.str());
}
template <typename... Args>
void warn(const Args&... parts) {
  std::ostringstream os;
  (os << ... << parts);
  log_line("warning: ", os.str());
}

// Peak resident memory of this process in bytes.
std::int64_t peak_memory_bytes();

// A progress bar on stderr for long loops; drawn only when stderr is a terminal and
// not quiet. tick() is thread-safe and cheap.
class Progress {
 public:
  Progress(std::string label, std::int64_t total);
  ~Progress();
  void tick(std::int64_t n = 1);
  void done();

 private:
  void draw(std::int64_t v);
  std::string label_;
  std::int64_t total_;
  std::atomic<std::int64_t> count_{0};
  std::atomic<std::int64_t> last_drawn_{-1};
  bool enabled_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
  std::mutex mu_;
};

}  // namespace tetmvs
