#include "common/par_io.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>

#include "common/error.h"
#include "common/fileio.h"

namespace tetmvs {
namespace fs = std::filesystem;

namespace {

std::vector<std::string> split_ws(const std::string& line) {
  std::istringstream is(line);
  std::vector<std::string> out;
  std::string w;
  while (is >> w) out.push_back(w);
  return out;
}

bool parse_double(const std::string& s, double& v) {
  errno = 0;
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end != s.c_str() && *end == '\0' && errno == 0 && std::isfinite(v);
}

}  // namespace

std::vector<Camera> read_par(const fs::path& file, double rot_tol) {
  check_regular_file(file);
  note_input(file);
  std::ifstream in(file);
  if (!in) fail(file.string(), ": cannot open camera file");
  std::string line;
  int lineno = 0;
  long declared = -1;
  std::vector<Camera> cams;
  std::set<std::string> names;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto f = split_ws(line);
    if (f.empty()) continue;
    const std::string where = file.string() + ":" + std::to_string(lineno) + ": ";
    if (declared < 0) {
      double v;
      // (bounded before the conversion: a huge count would overflow the cast)
      if (f.size() != 1 || !parse_double(f[0], v) || v < 1 || v > 1e6 || v != std::floor(v))
        fail(where, "first line must be the number of views (1 to 1000000), got '", line, "'");
      declared = static_cast<long>(v);
      continue;
    }
    if (f.size() != 22)
      fail(where, "expected 22 fields (name, 9 of K, 9 of R, 3 of t), found ", f.size());
    double v[21];
    for (int i = 0; i < 21; ++i)
      if (!parse_double(f[i + 1], v[i]))
        fail(where, "field ", i + 2, " '", f[i + 1], "' is not a finite number");
    Camera c;
    c.name = f[0];
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) {
        c.K(r, k) = v[r * 3 + k];
        c.R(r, k) = v[9 + r * 3 + k];
      }
    c.t = Eigen::Vector3d(v[18], v[19], v[20]);
    if (!(c.K(0, 0) > 0 && c.K(1, 1) > 0 && c.K(1, 0) == 0 && c.K(2, 0) == 0 && c.K(2, 1) == 0 &&
          c.K(2, 2) == 1))
      fail(where, "K must be upper triangular with positive focal lengths and k33 = 1");
    if (!is_rotation(c.R, rot_tol))
      fail(where, "R is not a rotation (R R^T != I or det != 1 within ", rot_tol, ")");
    if (!names.insert(c.name).second) fail(where, "duplicate image name '", c.name, "'");
    cams.push_back(std::move(c));
  }
  if (declared < 0) fail(file.string(), ": empty camera file");
  if (static_cast<long>(cams.size()) != declared)
    fail(file.string(), ":1: declares ", declared, " views but lists ", cams.size());
  return cams;
}

void write_par(const fs::path& file, const std::vector<Camera>& cams) {
  std::ostringstream os;
  os << cams.size() << "\n" << std::setprecision(17);
  for (const auto& c : cams) {
    os << c.name;
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) os << ' ' << c.K(r, k);
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) os << ' ' << c.R(r, k);
    os << ' ' << c.t.x() << ' ' << c.t.y() << ' ' << c.t.z() << "\n";
  }
  write_text_atomic(file, os.str());
}

fs::path find_par_file(const fs::path& dir) {
  if (!fs::is_directory(dir)) fail(dir.string(), ": dataset folder does not exist");
  std::vector<fs::path> found;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n.size() > 8 && n.substr(n.size() - 8) == "_par.txt") found.push_back(e.path());
  }
  if (found.empty()) fail(dir.string(), ": no *_par.txt camera file in the dataset folder");
  if (found.size() > 1)
    fail(dir.string(), ": ", found.size(), " *_par.txt files; a dataset folder must hold exactly one");
  return found[0];
}

}  // namespace tetmvs
