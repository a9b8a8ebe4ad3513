#include "common/outputs.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "common/error.h"
#include "common/fileio.h"

namespace tetmvs {
namespace fs = std::filesystem;

namespace {

std::string arg(const PathArg& a) { return a.option + " " + a.path.string(); }

// Creates and removes a probe file in `dir`; returns the error text, empty when writable.
std::string probe_folder(const fs::path& dir) {
  const fs::path probe = dir / (".tetmvs-probe." + std::to_string(::getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0) return std::strerror(errno);
  ::close(fd);
  ::unlink(probe.c_str());
  return "";
}

void check_one(const PathArg& o) {
  if (o.path.empty()) fail(o.option, ": the path is empty");
  std::error_code ec;
  const fs::file_status st = fs::status(o.path, ec);
  if (fs::exists(st)) {
    if (o.folder && !fs::is_directory(st)) fail(arg(o), ": exists and is not a folder");
    if (!o.folder && fs::is_directory(st)) fail(arg(o), ": is a folder, expected a file path");
    // (renaming onto a device such as /dev/null would replace it)
    if (!o.folder && !fs::is_regular_file(st)) fail(arg(o), ": exists and is not a regular file (a device or a pipe)");
  }
  // the folder that will hold the output (the output folder itself when it exists), or
  // its nearest existing parent when it is still to be made
  fs::path dir = o.folder && fs::exists(st) ? o.path : o.path.parent_path();
  if (dir.empty()) dir = ".";
  while (!fs::exists(dir, ec)) {
    if (!dir.has_parent_path() || dir.parent_path() == dir) break;
    dir = dir.parent_path();
  }
  if (!fs::exists(dir, ec)) dir = ".";
  if (!fs::is_directory(dir, ec)) fail(arg(o), ": ", dir.string(), " is not a folder");
  const std::string why = probe_folder(dir);
  if (!why.empty()) fail(arg(o), ": cannot write in ", dir.string(), " (", why, ")");
}

}  // namespace

void check_not_output(const PathArg& input, const std::vector<PathArg>& outputs) {
  if (input.path.empty()) return;
  const fs::path r = resolved(input.path);
  for (const auto& o : outputs)
    if (!o.path.empty() && resolved(o.path) == r)
      fail(arg(o), ": is also the input ", input.option == o.option ? "" : input.option + " ",
           input.path.string(), " (writing it would destroy it); choose another output path");
}

void check_output_paths(const std::vector<PathArg>& outputs, const std::vector<PathArg>& inputs) {
  for (const auto& o : outputs) check_one(o);
  for (const auto& i : inputs) check_not_output(i, outputs);
  for (std::size_t a = 0; a < outputs.size(); ++a)
    for (std::size_t b = a + 1; b < outputs.size(); ++b)
      if (resolved(outputs[a].path) == resolved(outputs[b].path))
        fail(arg(outputs[b]), ": is also the output ", outputs[a].option, "; give each output its own path");
}

}  // namespace tetmvs
