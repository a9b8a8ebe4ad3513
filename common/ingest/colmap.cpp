#include "common/ingest/colmap.h"

#include <omp.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <set>
#include <sstream>
#include <unordered_map>

#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/fileio.h"
#include "common/image.h"
#include "common/ingest/dataset.h"
#include "common/log.h"

namespace tetmvs::colmap {
namespace fs = std::filesystem;

// ---- camera models ------------------------------------------------------------------------
namespace {
constexpr ModelInfo kModels[] = {
    {0, "SIMPLE_PINHOLE", 3}, {1, "PINHOLE", 4},        {2, "SIMPLE_RADIAL", 4},
    {3, "RADIAL", 5},         {4, "OPENCV", 8},         {5, "OPENCV_FISHEYE", 8},
    {6, "FULL_OPENCV", 12},   {7, "FOV", 5},            {8, "SIMPLE_RADIAL_FISHEYE", 4},
    {9, "RADIAL_FISHEYE", 5}, {10, "THIN_PRISM_FISHEYE", 12},
};
}  // namespace

const ModelInfo* model_by_name(const std::string& name) {
  for (const auto& m : kModels)
    if (name == m.name) return &m;
  return nullptr;
}
const ModelInfo* model_by_id(int id) {
  for (const auto& m : kModels)
    if (id == m.id) return &m;
  return nullptr;
}
std::string known_models() {
  std::string s;
  for (const auto& m : kModels) s += (s.empty() ? "" : ", ") + std::string(m.name);
  return s;
}

// ---- small parsing helpers -------------------------------------------------------------------
namespace {

std::vector<std::string_view> tokens(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    std::size_t j = i;
    while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

// A text file as numbered lines; `where(i)` is "file:line".
struct Lines {
  fs::path file;
  std::vector<std::string> lines;
  explicit Lines(const fs::path& f) : file(f) {
    require(fs::exists(f), f.string(), ": file does not exist");
    std::string text = read_file(f);
    std::size_t b = 0;
    while (b <= text.size()) {
      std::size_t e = text.find('\n', b);
      if (e == std::string::npos) e = text.size();
      std::string l = text.substr(b, e - b);
      if (!l.empty() && l.back() == '\r') l.pop_back();
      lines.push_back(std::move(l));
      if (e == text.size()) break;
      b = e + 1;
    }
  }
  std::string where(std::size_t i) const { return file.string() + ":" + std::to_string(i + 1); }
  static bool skip(const std::string& l) {
    const auto t = trim(l);
    return t.empty() || t.front() == '#';
  }
};

double to_double(std::string_view s, const std::string& where, const char* what) {
  double v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v))
    fail(where, ": ", what, " '", std::string(s), "' is not a finite number");
  return v;
}

std::int64_t to_int(std::string_view s, const std::string& where, const char* what) {
  std::int64_t v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size())
    fail(where, ": ", what, " '", std::string(s), "' is not an integer");
  return v;
}

std::uint32_t to_id32(std::string_view s, const std::string& where, const char* what) {
  const std::int64_t v = to_int(s, where, what);
  if (v < 0 || v > std::int64_t(0xFFFFFFFFu)) fail(where, ": ", what, " ", v, " is out of range");
  return static_cast<std::uint32_t>(v);
}

void check_camera(const Intrinsics& c) {
  require(c.width > 0 && c.height > 0 && c.width < 1000000 && c.height < 1000000, c.where,
          ": camera ", c.id, " has image size ", c.width, "x", c.height);
  for (double v : c.params) require(std::isfinite(v), c.where, ": camera ", c.id, " has a non-finite parameter");
}

void check_quaternion(const Image& im) {
  const double n = im.q.norm();
  require(im.q.allFinite() && im.t.allFinite(), im.where, ": image ", im.id, " pose is not finite");
  require(n > 1e-9, im.where, ": image ", im.id, " quaternion is zero");
}

// Cross-checks shared by both formats: image -> camera, point -> image/point2D, point2D -> point.
void cross_check(const Model& m, const std::vector<std::string>& point_where) {
  std::unordered_map<std::uint32_t, std::size_t> image_index;
  for (std::size_t i = 0; i < m.images.size(); ++i) {
    const Image& im = m.images[i];
    if (!image_index.emplace(im.id, i).second) fail(im.where, ": image id ", im.id, " appears twice");
    if (!m.cameras.count(im.camera_id))
      fail(im.where, ": image ", im.id, " (", im.name, ") uses camera ", im.camera_id,
           ", which the cameras file does not hold");
  }
  std::unordered_map<std::uint64_t, std::size_t> point_index;
  for (std::size_t k = 0; k < m.points.size(); ++k) {
    const Point3D& p = m.points[k];
    if (!point_index.emplace(p.id, k).second) fail(point_where[k], ": point id ", p.id, " appears twice");
    for (const auto& te : p.track) {
      const auto it = image_index.find(te.image_id);
      if (it == image_index.end())
        fail(point_where[k], ": point ", p.id, " is observed by image ", te.image_id,
             ", which the images file does not hold");
      const Image& im = m.images[it->second];
      if (te.point2d_idx >= im.points2d.size())
        fail(point_where[k], ": point ", p.id, " names point2D ", te.point2d_idx, " of image ", te.image_id,
             ", which has only ", im.points2d.size(), " (", im.where, ")");
      if (im.points2d[te.point2d_idx].point3d != p.id)
        fail(point_where[k], ": point ", p.id, " names point2D ", te.point2d_idx, " of image ", te.image_id,
             ", which ", im.where, " ties to point ",
             im.points2d[te.point2d_idx].point3d == kNoPoint ? std::string("-1")
                                                             : std::to_string(im.points2d[te.point2d_idx].point3d));
    }
  }
  for (const Image& im : m.images)
    for (const auto& o : im.points2d)
      if (o.point3d != kNoPoint && !point_index.count(o.point3d))
        fail(im.where, ": image ", im.id, " observes point ", o.point3d, ", which the points3D file does not hold");
}

}  // namespace

bool is_model_dir(const fs::path& dir) {
  return fs::is_regular_file(dir / "cameras.txt") || fs::is_regular_file(dir / "cameras.bin");
}

// ---- text format ------------------------------------------------------------------------------
Model read_text_model(const fs::path& dir) {
  Model m;
  {
    const Lines L(dir / "cameras.txt");
    m.files.push_back(L.file);
    for (std::size_t i = 0; i < L.lines.size(); ++i) {
      if (Lines::skip(L.lines[i])) continue;
      const auto w = L.where(i);
      const auto tk = tokens(L.lines[i]);
      if (tk.size() < 4) fail(w, ": expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[], got ", tk.size(), " fields");
      Intrinsics c;
      c.where = w;
      c.id = to_id32(tk[0], w, "CAMERA_ID");
      const ModelInfo* mi = model_by_name(std::string(tk[1]));
      if (!mi) fail(w, ": unknown camera model '", std::string(tk[1]), "' (COLMAP's models: ", known_models(), ")");
      c.model = mi->id;
      const std::int64_t W = to_int(tk[2], w, "WIDTH"), H = to_int(tk[3], w, "HEIGHT");
      require(W > 0 && H > 0, w, ": camera ", c.id, " has image size ", W, "x", H);
      c.width = W;
      c.height = H;
      if (int(tk.size()) - 4 != mi->num_params)
        fail(w, ": camera model ", mi->name, " has ", mi->num_params, " parameters, the line gives ", tk.size() - 4);
      for (std::size_t k = 4; k < tk.size(); ++k) c.params.push_back(to_double(tk[k], w, "parameter"));
      check_camera(c);
      if (!m.cameras.emplace(c.id, c).second) fail(w, ": camera id ", c.id, " appears twice");
    }
  }
  {
    const Lines L(dir / "images.txt");
    m.files.push_back(L.file);
    for (std::size_t i = 0; i < L.lines.size(); ++i) {
      if (Lines::skip(L.lines[i])) continue;
      const auto w = L.where(i);
      const auto tk = tokens(L.lines[i]);
      if (tk.size() < 10)
        fail(w, ": expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME, got ", tk.size(), " fields");
      Image im;
      im.where = w;
      im.id = to_id32(tk[0], w, "IMAGE_ID");
      for (int k = 0; k < 4; ++k) im.q[k] = to_double(tk[1 + k], w, "quaternion component");
      for (int k = 0; k < 3; ++k) im.t[k] = to_double(tk[5 + k], w, "translation component");
      im.camera_id = to_id32(tk[8], w, "CAMERA_ID");
      // the name is the rest of the line (it may hold spaces)
      const std::string_view line = L.lines[i];
      im.name = std::string(trim(line.substr(static_cast<std::size_t>(tk[9].data() - line.data()))));
      check_quaternion(im);
      // the next line holds the observations (possibly empty)
      ++i;
      if (i < L.lines.size()) {
        const auto w2 = L.where(i);
        const auto ob = tokens(L.lines[i]);
        if (!ob.empty() && ob[0].front() == '#') fail(w2, ": expected the POINTS2D line of image ", im.id, ", found a comment");
        if (ob.size() % 3 != 0) fail(w2, ": POINTS2D of image ", im.id, " has ", ob.size(), " numbers, not a multiple of 3 (X Y POINT3D_ID)");
        im.points2d.resize(ob.size() / 3);
        for (std::size_t k = 0; k < im.points2d.size(); ++k) {
          auto& o = im.points2d[k];
          o.x = to_double(ob[3 * k], w2, "X");
          o.y = to_double(ob[3 * k + 1], w2, "Y");
          const std::int64_t pid = to_int(ob[3 * k + 2], w2, "POINT3D_ID");
          if (pid < -1) fail(w2, ": POINT3D_ID ", pid, " is negative (only -1 means none)");
          o.point3d = pid == -1 ? kNoPoint : static_cast<std::uint64_t>(pid);
        }
      }
      m.images.push_back(std::move(im));
    }
  }
  std::vector<std::string> point_where;
  {
    const Lines L(dir / "points3D.txt");
    m.files.push_back(L.file);
    for (std::size_t i = 0; i < L.lines.size(); ++i) {
      if (Lines::skip(L.lines[i])) continue;
      const auto w = L.where(i);
      const auto tk = tokens(L.lines[i]);
      if (tk.size() < 8 || (tk.size() - 8) % 2 != 0)
        fail(w, ": expected POINT3D_ID X Y Z R G B ERROR and (IMAGE_ID POINT2D_IDX) pairs, got ", tk.size(), " fields");
      Point3D p;
      const std::int64_t id = to_int(tk[0], w, "POINT3D_ID");
      require(id >= 0, w, ": POINT3D_ID ", id, " is negative");
      p.id = static_cast<std::uint64_t>(id);
      for (int k = 0; k < 3; ++k) p.xyz[k] = to_double(tk[1 + k], w, "coordinate");
      for (int k = 0; k < 3; ++k) {
        const std::int64_t c = to_int(tk[4 + k], w, "colour");
        require(c >= 0 && c <= 255, w, ": colour ", c, " is outside 0..255");
        p.rgb[k] = static_cast<std::uint8_t>(c);
      }
      p.error = to_double(tk[7], w, "ERROR");
      for (std::size_t k = 8; k < tk.size(); k += 2)
        p.track.push_back({to_id32(tk[k], w, "IMAGE_ID"), to_id32(tk[k + 1], w, "POINT2D_IDX")});
      m.points.push_back(std::move(p));
      point_where.push_back(w);
    }
  }
  std::sort(m.images.begin(), m.images.end(), [](const Image& a, const Image& b) { return a.id < b.id; });
  cross_check(m, point_where);
  return m;
}

namespace {
std::string fmt17(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
}  // namespace

void write_text_model(const fs::path& dir, const Model& m) {
  std::ostringstream c;
  c << "# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
    << "# Number of cameras: " << m.cameras.size() << "\n";
  for (const auto& [id, cam] : m.cameras) {
    const ModelInfo* mi = model_by_id(cam.model);
    require(mi, "write_text_model: unknown model id ", cam.model);
    c << id << " " << mi->name << " " << cam.width << " " << cam.height;
    for (double v : cam.params) c << " " << fmt17(v);
    c << "\n";
  }
  write_text_atomic(dir / "cameras.txt", c.str());
  std::ostringstream im;
  im << "# Image list with two lines of data per image:\n"
     << "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
     << "# Number of images: " << m.images.size() << "\n";
  for (const Image& i : m.images) {
    im << i.id;
    for (int k = 0; k < 4; ++k) im << " " << fmt17(i.q[k]);
    for (int k = 0; k < 3; ++k) im << " " << fmt17(i.t[k]);
    im << " " << i.camera_id << " " << i.name << "\n";
    bool first = true;
    for (const auto& o : i.points2d) {
      im << (first ? "" : " ") << fmt17(o.x) << " " << fmt17(o.y) << " ";
      if (o.point3d == kNoPoint)
        im << -1;
      else
        im << o.point3d;
      first = false;
    }
    im << "\n";
  }
  write_text_atomic(dir / "images.txt", im.str());
  std::ostringstream p;
  p << "# 3D point list with one line of data per point:\n"
    << "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
    << "# Number of points: " << m.points.size() << "\n";
  for (const Point3D& q : m.points) {
    p << q.id;
    for (int k = 0; k < 3; ++k) p << " " << fmt17(q.xyz[k]);
    for (int k = 0; k < 3; ++k) p << " " << int(q.rgb[k]);
    p << " " << fmt17(q.error);
    for (const auto& te : q.track) p << " " << te.image_id << " " << te.point2d_idx;
    p << "\n";
  }
  write_text_atomic(dir / "points3D.txt", p.str());
}

// ---- binary format ------------------------------------------------------------------------------
namespace {

struct Reader {
  fs::path file;
  std::string data;
  std::size_t pos = 0;
  explicit Reader(const fs::path& f) : file(f) {
    require(fs::exists(f), f.string(), ": file does not exist");
    data = read_file(f);
  }
  template <typename T>
  T get(const std::string& what) {
    if (pos + sizeof(T) > data.size())
      fail(file.string(), ": truncated at byte ", pos, " (of ", data.size(), ") while reading ", what);
    T v;
    std::memcpy(&v, data.data() + pos, sizeof(T));
    pos += sizeof(T);
    return v;
  }
  std::string cstring(const std::string& what) {
    const std::size_t e = data.find('\0', pos);
    if (e == std::string::npos) fail(file.string(), ": truncated at byte ", pos, " while reading ", what);
    std::string s = data.substr(pos, e - pos);
    pos = e + 1;
    return s;
  }
  // A count of records of at least `min_bytes` each must fit in what is left.
  std::uint64_t count(const std::string& what, std::size_t min_bytes) {
    const std::uint64_t n = get<std::uint64_t>(what);
    if (n > (data.size() - pos) / std::max<std::size_t>(1, min_bytes))
      fail(file.string(), ": ", what, " ", n, " at byte ", pos - 8, " does not fit in the file (corrupt or truncated)");
    return n;
  }
  void done() {
    if (pos != data.size())
      fail(file.string(), ": ", data.size() - pos, " unexpected bytes after the last record (byte ", pos, ")");
  }
  std::string where(const std::string& rec) const { return file.string() + ": " + rec; }
};

template <typename T>
void put(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

}  // namespace

Model read_binary_model(const fs::path& dir) {
  static_assert(sizeof(double) == 8);
  Model m;
  {
    Reader r(dir / "cameras.bin");
    m.files.push_back(r.file);
    const std::uint64_t n = r.count("number of cameras", 24);
    for (std::uint64_t k = 0; k < n; ++k) {
      Intrinsics c;
      c.id = r.get<std::uint32_t>("a camera id");
      c.where = r.where("camera " + std::to_string(c.id) + " (record " + std::to_string(k + 1) + ")");
      c.model = r.get<std::int32_t>("a camera model id");
      const ModelInfo* mi = model_by_id(c.model);
      if (!mi) fail(c.where, ": unknown camera model id ", c.model, " (COLMAP's models: ", known_models(), ")");
      c.width = r.get<std::uint64_t>("a width");
      c.height = r.get<std::uint64_t>("a height");
      for (int j = 0; j < mi->num_params; ++j) c.params.push_back(r.get<double>("camera parameters"));
      check_camera(c);
      if (!m.cameras.emplace(c.id, c).second) fail(c.where, ": camera id ", c.id, " appears twice");
    }
    r.done();
  }
  {
    Reader r(dir / "images.bin");
    m.files.push_back(r.file);
    const std::uint64_t n = r.count("number of images", 4 + 64 + 4 + 1 + 8);
    for (std::uint64_t k = 0; k < n; ++k) {
      Image im;
      im.id = r.get<std::uint32_t>("an image id");
      im.where = r.where("image " + std::to_string(im.id) + " (record " + std::to_string(k + 1) + ")");
      for (int j = 0; j < 4; ++j) im.q[j] = r.get<double>("a quaternion");
      for (int j = 0; j < 3; ++j) im.t[j] = r.get<double>("a translation");
      im.camera_id = r.get<std::uint32_t>("a camera id");
      im.name = r.cstring("an image name");
      require(!im.name.empty(), im.where, ": empty image name");
      check_quaternion(im);
      const std::uint64_t np = r.count("number of points2D", 24);
      im.points2d.resize(np);
      for (auto& o : im.points2d) {
        o.x = r.get<double>("a point2D");
        o.y = r.get<double>("a point2D");
        o.point3d = r.get<std::uint64_t>("a point3D id");
        require(std::isfinite(o.x) && std::isfinite(o.y), im.where, ": a point2D is not finite");
      }
      m.images.push_back(std::move(im));
    }
    r.done();
  }
  std::vector<std::string> point_where;
  {
    Reader r(dir / "points3D.bin");
    m.files.push_back(r.file);
    const std::uint64_t n = r.count("number of points", 8 + 24 + 3 + 8 + 8);
    m.points.reserve(n);
    for (std::uint64_t k = 0; k < n; ++k) {
      Point3D p;
      p.id = r.get<std::uint64_t>("a point3D id");
      const std::string w = r.where("point " + std::to_string(p.id) + " (record " + std::to_string(k + 1) + ")");
      for (int j = 0; j < 3; ++j) p.xyz[j] = r.get<double>("a point position");
      for (int j = 0; j < 3; ++j) p.rgb[j] = r.get<std::uint8_t>("a point colour");
      p.error = r.get<double>("a point error");
      require(p.xyz.allFinite() && std::isfinite(p.error), w, ": position or error is not finite");
      const std::uint64_t nt = r.count("track length", 8);
      p.track.resize(nt);
      for (auto& te : p.track) {
        te.image_id = r.get<std::uint32_t>("a track image id");
        te.point2d_idx = r.get<std::uint32_t>("a track point2D index");
      }
      m.points.push_back(std::move(p));
      point_where.push_back(w);
    }
    r.done();
  }
  std::sort(m.images.begin(), m.images.end(), [](const Image& a, const Image& b) { return a.id < b.id; });
  cross_check(m, point_where);
  return m;
}

void write_binary_model(const fs::path& dir, const Model& m) {
  std::string c;
  put<std::uint64_t>(c, m.cameras.size());
  for (const auto& [id, cam] : m.cameras) {
    put<std::uint32_t>(c, id);
    put<std::int32_t>(c, cam.model);
    put<std::uint64_t>(c, cam.width);
    put<std::uint64_t>(c, cam.height);
    for (double v : cam.params) put<double>(c, v);
  }
  write_text_atomic(dir / "cameras.bin", c);
  std::string im;
  put<std::uint64_t>(im, m.images.size());
  for (const Image& i : m.images) {
    put<std::uint32_t>(im, i.id);
    for (int k = 0; k < 4; ++k) put<double>(im, i.q[k]);
    for (int k = 0; k < 3; ++k) put<double>(im, i.t[k]);
    put<std::uint32_t>(im, i.camera_id);
    im.append(i.name);
    im.push_back('\0');
    put<std::uint64_t>(im, i.points2d.size());
    for (const auto& o : i.points2d) {
      put<double>(im, o.x);
      put<double>(im, o.y);
      put<std::uint64_t>(im, o.point3d);
    }
  }
  write_text_atomic(dir / "images.bin", im);
  std::string p;
  put<std::uint64_t>(p, m.points.size());
  for (const Point3D& q : m.points) {
    put<std::uint64_t>(p, q.id);
    for (int k = 0; k < 3; ++k) put<double>(p, q.xyz[k]);
    for (int k = 0; k < 3; ++k) put<std::uint8_t>(p, q.rgb[k]);
    put<double>(p, q.error);
    put<std::uint64_t>(p, q.track.size());
    for (const auto& te : q.track) {
      put<std::uint32_t>(p, te.image_id);
      put<std::uint32_t>(p, te.point2d_idx);
    }
  }
  write_text_atomic(dir / "points3D.bin", p);
}

Model read_model(const fs::path& dir) {
  const bool bin = fs::exists(dir / "cameras.bin") && fs::exists(dir / "images.bin") && fs::exists(dir / "points3D.bin");
  if (bin) return read_binary_model(dir);
  if (fs::exists(dir / "cameras.txt") || fs::exists(dir / "images.txt")) return read_text_model(dir);
  if (fs::exists(dir / "cameras.bin"))  // a partial binary model: name what is missing
    for (const char* f : {"images.bin", "points3D.bin"})
      require(fs::exists(dir / f), (dir / f).string(), ": file does not exist (cameras.bin is there)");
  fail(dir.string(), ": no COLMAP model (cameras.txt/images.txt/points3D.txt or the .bin files)");
}

// ---- geometry ---------------------------------------------------------------------------------
Eigen::Matrix3d quaternion_to_rotation(const Eigen::Vector4d& q) {
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
}

Eigen::Vector4d rotation_to_quaternion(const Eigen::Matrix3d& R) {
  const Eigen::Quaterniond q(R);
  Eigen::Vector4d v(q.w(), q.x(), q.y(), q.z());
  v.normalize();
  if (v[0] < 0) v = -v;
  return v;
}

bool Pinhole::distorted() const {
  for (double d : dist)
    if (d != 0) return true;
  return false;
}

Pinhole pinhole_of(const Intrinsics& c) {
  const ModelInfo* mi = model_by_id(c.model);
  require(mi, c.where, ": unknown camera model id ", c.model);
  const auto& q = c.params;
  require(int(q.size()) == mi->num_params, c.where, ": ", mi->name, " needs ", mi->num_params, " parameters");
  Pinhole p;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  switch (c.model) {
    case 0: fx = fy = q[0], cx = q[1], cy = q[2]; break;                                  // SIMPLE_PINHOLE
    case 1: fx = q[0], fy = q[1], cx = q[2], cy = q[3]; break;                             // PINHOLE
    case 2: fx = fy = q[0], cx = q[1], cy = q[2], p.dist = {q[3], 0, 0, 0}; break;         // SIMPLE_RADIAL
    case 3: fx = fy = q[0], cx = q[1], cy = q[2], p.dist = {q[3], q[4], 0, 0}; break;      // RADIAL
    case 4: fx = q[0], fy = q[1], cx = q[2], cy = q[3], p.dist.assign(q.begin() + 4, q.end()); break;  // OPENCV
    case 6: fx = q[0], fy = q[1], cx = q[2], cy = q[3], p.dist.assign(q.begin() + 4, q.end()); break;  // FULL_OPENCV
    default:
      fail(c.where, ": camera model ", mi->name,
           " cannot be undistorted here; run `colmap image_undistorter --image_path IMAGES --input_path MODEL "
           "--output_path OUT` and ingest OUT (a PINHOLE model with undistorted images)");
  }
  require(fx > 0 && fy > 0, c.where, ": camera ", c.id, " has a non-positive focal length");
  p.K << fx, 0, cx - 0.5, 0, fy, cy - 0.5, 0, 0, 1;
  return p;
}

Camera camera_of(const Model& m, const Image& im) {
  const Intrinsics& c = m.cameras.at(im.camera_id);
  Camera cam;
  cam.name = im.name;
  cam.K = pinhole_of(c).K;
  cam.R = quaternion_to_rotation(im.q);
  cam.t = im.t;
  cam.width = static_cast<int>(c.width);
  cam.height = static_cast<int>(c.height);
  return cam;
}

namespace {
// OpenCV's distortion (= COLMAP's for the supported models) of normalised coordinates.
Eigen::Vector2d distort(const std::vector<double>& d, double u, double v) {
  if (d.empty()) return {u, v};
  const double k1 = d[0], k2 = d[1], p1 = d[2], p2 = d[3];
  const double k3 = d.size() > 4 ? d[4] : 0, k4 = d.size() > 5 ? d[5] : 0, k5 = d.size() > 6 ? d[6] : 0,
               k6 = d.size() > 7 ? d[7] : 0;
  const double r2 = u * u + v * v, r4 = r2 * r2, r6 = r4 * r2;
  const double radial = (1 + k1 * r2 + k2 * r4 + k3 * r6) / (1 + k4 * r2 + k5 * r4 + k6 * r6);
  return {u * radial + 2 * p1 * u * v + p2 * (r2 + 2 * u * u), v * radial + 2 * p2 * u * v + p1 * (r2 + 2 * v * v)};
}
}  // namespace

Eigen::Vector2d project_colmap(const Intrinsics& c, const Image& im, const Eigen::Vector3d& X) {
  const Pinhole p = pinhole_of(c);
  const Eigen::Vector3d x = quaternion_to_rotation(im.q) * X + im.t;
  const Eigen::Vector2d d = distort(p.dist, x.x() / x.z(), x.y() / x.z());
  return {p.K(0, 0) * d.x() + p.K(0, 2) + 0.5, p.K(1, 1) * d.y() + p.K(1, 2) + 0.5};
}

cv::Mat undistort(const cv::Mat& img, const Pinhole& p, bool nearest) {
  if (!p.distorted()) return img;
  // The map of cv::initUndistortRectifyMap (no rectification, the same K), computed here in
  // double precision with the model's own distortion; OpenCV's remap samples it.
  const double fx = p.K(0, 0), fy = p.K(1, 1), cx = p.K(0, 2), cy = p.K(1, 2);
  cv::Mat mx(img.size(), CV_32F), my(img.size(), CV_32F);
#pragma omp parallel for schedule(static)
  for (int v = 0; v < img.rows; ++v) {
    auto* px = mx.ptr<float>(v);
    auto* py = my.ptr<float>(v);
    for (int u = 0; u < img.cols; ++u) {
      const Eigen::Vector2d d = distort(p.dist, (u - cx) / fx, (v - cy) / fy);
      px[u] = static_cast<float>(fx * d.x() + cx);
      py[u] = static_cast<float>(fy * d.y() + cy);
    }
  }
  cv::Mat out;
  cv::remap(img, out, mx, my, nearest ? cv::INTER_NEAREST : cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar::all(0));
  return out;
}

// ---- workspace ----------------------------------------------------------------------------------
std::optional<Layout> find_layout(const fs::path& dir_in) {
  const fs::path dir = fs::absolute(dir_in).lexically_normal();
  const fs::path d = dir.has_filename() ? dir : dir.parent_path();
  Layout l;
  if (is_model_dir(d)) {
    l.model_dir = d;
    for (const fs::path& c : {d / "images", d.parent_path() / "images", d.parent_path().parent_path() / "images"})
      if (fs::is_directory(c)) {
        l.image_dir = c;
        break;
      }
    if (l.image_dir.empty())
      fail(d.string(), ": a COLMAP model without an images/ folder beside it or one or two levels above it");
    l.root = l.image_dir.parent_path();
    return l;
  }
  const fs::path sp = d / "sparse";
  if (!fs::is_directory(sp)) return std::nullopt;
  if (is_model_dir(sp)) {
    l.model_dir = sp;
  } else {
    // sparse/0, sparse/1, ... (several models when the mapper split the scene): the lowest number
    long best = -1;
    int count = 0;
    for (const auto& e : fs::directory_iterator(sp)) {
      const std::string n = e.path().filename().string();
      if (!e.is_directory() || n.empty() || !std::all_of(n.begin(), n.end(), [](unsigned char ch) { return std::isdigit(ch) != 0; }) || !is_model_dir(e.path())) continue;
      ++count;
      const long k = std::stol(n);
      if (best < 0 || k < best) best = k;
    }
    if (best < 0) fail(sp.string(), ": no COLMAP model in it (cameras.txt / cameras.bin, directly or in sparse/0/)");
    l.model_dir = sp / std::to_string(best);
    if (count > 1) warn(sp.string(), ": ", count, " models; using ", l.model_dir.string());
  }
  l.image_dir = d / "images";
  require(fs::is_directory(l.image_dir), l.image_dir.string(), ": COLMAP workspace without its images/ folder");
  l.root = d;
  return l;
}

std::optional<Eigen::AlignedBox3d> box_param(const Params& p, const std::string& key) {
  std::string s = p.s(key);
  std::replace(s.begin(), s.end(), ',', ' ');
  if (trim(s).empty()) return std::nullopt;
  std::istringstream is(s);
  double v[6];
  for (double& x : v)
    if (!(is >> x) || !std::isfinite(x)) fail("parameter ", key, ": expected six numbers minx,miny,minz,maxx,maxy,maxz, got '", p.s(key), "'");
  std::string extra;
  if (is >> extra) fail("parameter ", key, ": expected six numbers minx,miny,minz,maxx,maxy,maxz, got '", p.s(key), "'");
  const Eigen::Vector3d lo(v[0], v[1], v[2]), hi(v[3], v[4], v[5]);
  require((lo.array() < hi.array()).all(), "parameter ", key, ": the minimum must be below the maximum on every axis");
  return Eigen::AlignedBox3d(lo, hi);
}

Eigen::AlignedBox3d robust_box(const std::vector<Eigen::Vector3d>& pts, double pct, double padding,
                               const std::optional<Eigen::AlignedBox3d>& roi, int min_points, const std::string& what) {
  require(pct >= 0 && pct < 50, "robust_box: percentile ", pct, " outside [0, 50)");
  std::vector<double> ax[3];
  for (const auto& x : pts)
    if (!roi || roi->contains(x))
      for (int k = 0; k < 3; ++k) ax[k].push_back(x[k]);
  const int n = static_cast<int>(ax[0].size());
  if (n < min_points)
    fail(what, ": only ", n, " sparse points", roi ? " inside ingest.roi" : "", " to bound the object (need ", min_points,
         "); give the box (ingest.box or a bbox.txt) or a larger ingest.roi");
  Eigen::Vector3d lo, hi;
  for (int k = 0; k < 3; ++k) {
    auto& a = ax[k];
    const auto il = static_cast<std::size_t>(std::llround(pct / 100.0 * (n - 1)));
    const auto ih = static_cast<std::size_t>(std::llround((1 - pct / 100.0) * (n - 1)));
    std::nth_element(a.begin(), a.begin() + il, a.end());
    lo[k] = a[il];
    std::nth_element(a.begin(), a.begin() + ih, a.end());
    hi[k] = a[ih];
  }
  const double pad = padding * (hi - lo).norm();
  Eigen::AlignedBox3d box(lo.array() - pad, hi.array() + pad);
  if (roi) box = box.intersection(*roi);
  require(!box.isEmpty() && (box.sizes().array() > 0).all(), what,
          ": the sparse points span no volume (all on a plane?); give the box (ingest.box or a bbox.txt)");
  return box;
}

namespace {
void drop_degenerate(Scene& s) {
  for (int v = 0; v < s.size(); ++v) {
    if (s.sil[v].empty()) continue;
    const int nz = cv::countNonZero(s.sil[v]);
    if (nz == 0 || nz == int(s.sil[v].total())) {
      warn(s.cams[v].name, ": silhouette is ", nz == 0 ? "empty" : "the whole image", "; the view will carry no silhouette");
      s.sil[v] = cv::Mat();
    }
  }
}
}  // namespace

Scene read_scene(const Layout& l, const Params& p) {
  const Model m = read_model(l.model_dir);
  const fs::path imfile = m.files.size() > 1 ? m.files[1] : l.model_dir;
  require(!m.images.empty(), imfile.string(), ": the model holds no image");
  // views in image-name order (IMAGE_IDs follow the feature extractor's threads, names the
  // photographer's sequence)
  std::vector<const Image*> ims;
  for (const Image& im : m.images) ims.push_back(&im);
  std::sort(ims.begin(), ims.end(), [](const Image* a, const Image* b) { return a->name < b->name; });
  for (std::size_t k = 1; k < ims.size(); ++k)
    if (ims[k]->name == ims[k - 1]->name)
      fail(ims[k]->where, ": image name ", ims[k]->name, " is also used by ", ims[k - 1]->where);
  Scene s;
  s.dataset = l.root.filename().string();
  const int n = static_cast<int>(m.images.size());
  s.cams.resize(n);
  s.rgb.resize(n);
  s.sil.resize(n);
  const fs::path sildir = l.root / "silhouettes";
  const bool sils = fs::is_directory(sildir);
  {
    std::vector<fs::path> files;
    for (const Image* im : ims) files.push_back(l.image_dir / im->name);
    check_images_budget(p, files);
  }
  std::vector<char> no_mask(n, 0);
  std::vector<std::string> errors(n);
#pragma omp parallel for schedule(dynamic)
  for (int v = 0; v < n; ++v) {
    try {
      const Image& im = *ims[v];
      const Intrinsics& c = m.cameras.at(im.camera_id);
      const Pinhole ph = pinhole_of(c);
      const fs::path f = l.image_dir / im.name;
      if (!fs::exists(f)) fail(f.string(), ": image file missing (named by ", im.where, ")");
      cv::Mat rgb = load_rgb(f);
      if (rgb.cols != int(c.width) || rgb.rows != int(c.height))
        fail(f.string(), ": image is ", rgb.cols, "x", rgb.rows, " but its camera (", c.where, ") is ", c.width, "x",
             c.height);
      s.rgb[v] = undistort(rgb, ph);
      s.cams[v] = camera_of(m, im);
      if (sils) {
        if (const auto found = find_mask(sildir, im.name)) {
          const fs::path& mf = *found;
          cv::Mat mask = load_mask(mf);
          if (mask.size() != rgb.size())
            fail(mf.string(), ": mask is ", mask.cols, "x", mask.rows, " but its image is ", rgb.cols, "x", rgb.rows);
          s.sil[v] = undistort(mask, ph, /*nearest=*/true);
        } else {
          no_mask[v] = 1;
        }
      }
    } catch (const Error& e) {
      errors[v] = e.what();
    } catch (const std::exception& e) {
      errors[v] = ims[v]->where + ": " + e.what();
    }
  }
  for (const auto& e : errors)
    if (!e.empty()) throw Error(e);
  {
    std::vector<std::string> missing;
    for (int v = 0; v < n; ++v)
      if (no_mask[v]) missing.push_back(ims[v]->name);
    warn_missing_masks(sildir, missing, n);
  }
  for (int v = 1; v < n; ++v)
    if (s.rgb[v].size() != s.rgb[0].size())
      fail((l.image_dir / s.cams[v].name).string(), ": image is ", s.rgb[v].cols, "x", s.rgb[v].rows, " but ",
           s.cams[0].name, " is ", s.rgb[0].cols, "x", s.rgb[0].rows, "; all images of a dataset must share one size");
  drop_degenerate(s);

  // bounding box
  const auto roi = box_param(p, "ingest.roi");
  std::string src;
  if (auto b = box_param(p, "ingest.box")) {
    s.box = *b;
    s.box_source = "given";
  } else if (auto sb = read_stated_box(l.root, &src)) {
    s.box = *sb;
    s.box_source = src;
  } else {
    // the sparse points' robust box, and with silhouettes the visual hull's: each bounds the
    // object (the hull is loose where the object fills the images, the points where the
    // background has some), so their intersection is kept when both exist
    const int min_track = p.i("ingest.points_min_track");
    std::vector<Eigen::Vector3d> pts;
    for (const auto& q : m.points)
      if (int(q.track.size()) >= min_track) pts.push_back(q.xyz);
    const fs::path pf = m.files.size() > 2 ? m.files[2] : l.model_dir;
    const std::string what = pf.string() + " (points seen by at least " + std::to_string(min_track) + " images)";
    constexpr int kMinPoints = 10;
    std::optional<Eigen::AlignedBox3d> pbox;
    if (s.num_silhouettes() == 0 || int(pts.size()) >= kMinPoints) {
      pbox = robust_box(pts, p.d("ingest.points_percentile"), p.d("ingest.box_padding"), roi, kMinPoints, what);
      info("ingest: sparse-point box from ", pts.size(), " of ", m.points.size(), " points", roi ? " (inside ingest.roi)" : "");
    }
    if (s.num_silhouettes() > 0) {
      const Eigen::AlignedBox3d region = roi ? *roi : pbox ? *pbox : camera_search_region(s.cams);
      s.box = padded_hull_box(s, region, p, l.root.string(), "give ingest.box or a bbox.txt");
      s.box_source = "visual hull";
      if (pbox && !s.box.intersection(*pbox).isEmpty()) {
        s.box = s.box.intersection(*pbox);
        s.box_source = "visual hull and sparse points";
      }
      if (roi) s.box = s.box.intersection(*roi);
      require(!s.box.isEmpty(), l.root.string(), ": the visual hull lies outside ingest.roi");
    } else {
      s.box = *pbox;
      s.box_source = "sparse points";
    }
  }
  vet_scene(s, imfile);
  return s;
}

}  // namespace tetmvs::colmap
