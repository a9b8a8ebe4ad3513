#include "common/log.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>

namespace tetmvs {

namespace {
std::atomic<bool> g_quiet{false};
std::mutex g_io;
std::vector<std::string> g_warnings;
}  // namespace

void set_quiet(bool q) { g_quiet = q; }
bool is_quiet() { return g_quiet; }

void log_line(const std::string& level, const std::string& msg) {
  std::lock_guard<std::mutex> lock(g_io);
  std::fprintf(stderr, "%s%s\n", level.c_str(), msg.c_str());
  if (level == "warning: ") g_warnings.push_back(msg);
}

std::vector<std::string> warnings_given() {
  std::lock_guard<std::mutex> lock(g_io);
  return g_warnings;
}

std::int64_t peak_memory_bytes() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<std::int64_t>(ru.ru_maxrss) * 1024;
}

Progress::Progress(std::string label, std::int64_t total)
    : label_(std::move(label)), total_(total), enabled_(!is_quiet() && ::isatty(2) && total > 0),
      start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() { done(); }

void Progress::tick(std::int64_t n) {
  const std::int64_t v = count_.fetch_add(n) + n;
  if (!enabled_) return;
  // redraw at most ~200 times over the loop
  const std::int64_t step = std::max<std::int64_t>(1, total_ / 200);
  const std::int64_t bucket = v / step;
  std::int64_t last = last_drawn_.load();
  if (bucket > last && last_drawn_.compare_exchange_strong(last, bucket)) draw(v);
}

void Progress::draw(std::int64_t v) {
  std::lock_guard<std::mutex> lock(mu_);
  if (finished_) return;
  const double frac = std::min(1.0, static_cast<double>(v) / static_cast<double>(total_));
  const int width = 30, fill = static_cast<int>(frac * width);
  const double secs =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string bar(fill, '#');
  bar.resize(width, '.');
  std::fprintf(stderr, "\r%s [%s] %3.0f%% %lld/%lld %.1fs", label_.c_str(), bar.c_str(), frac * 100,
               static_cast<long long>(v), static_cast<long long>(total_), secs);
  std::fflush(stderr);
}

void Progress::done() {
  if (!enabled_) return;
  draw(total_);
  std::lock_guard<std::mutex> lock(mu_);
  if (!finished_) std::fprintf(stderr, "\n");
  finished_ = true;
}

}  // namespace tetmvs
