// One exception type for every user-facing failure. Each stage's main catches it,
// prints the one-line message and exits non-zero.
#pragma once
#include <sstream>
#include <stdexcept>
#include <string>

namespace tetmvs {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

// fail("file.h5", ": dataset /cells has ", n, " columns, expected 4") -> throws Error
template <typename... Args>
[[noreturn]] void fail(const Args&... parts) {
  std::ostringstream os;
  (os << ... << parts);
  throw Error(os.str());
}

// require(cond, parts...) throws Error(parts...) when cond is false.
template <typename... Args>
void require(bool cond, const Args&... parts) {
  if (!cond) fail(parts...);
}

}  // namespace tetmvs
