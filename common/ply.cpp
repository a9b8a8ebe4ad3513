#include "common/ply.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "common/error.h"
#include "common/fileio.h"

namespace tetmvs {

namespace {

enum class PType { i8, u8, i16, u16, i32, u32, f32, f64, none };

PType parse_type(const std::string& s) {
  if (s == "char" || s == "int8") return PType::i8;
  if (s == "uchar" || s == "uint8") return PType::u8;
  if (s == "short" || s == "int16") return PType::i16;
  if (s == "ushort" || s == "uint16") return PType::u16;
  if (s == "int" || s == "int32") return PType::i32;
  if (s == "uint" || s == "uint32") return PType::u32;
  if (s == "float" || s == "float32") return PType::f32;
  if (s == "double" || s == "float64") return PType::f64;
  return PType::none;
}
int type_size(PType t) {
  switch (t) {
    case PType::i8: case PType::u8: return 1;
    case PType::i16: case PType::u16: return 2;
    case PType::i32: case PType::u32: case PType::f32: return 4;
    case PType::f64: return 8;
    default: return 0;
  }
}

struct Prop {
  std::string name;
  PType type = PType::none;
  bool is_list = false;
  PType count_type = PType::none;
};
struct Element {
  std::string name;
  std::size_t count = 0;
  std::vector<Prop> props;
};

enum class Format { ascii, le, be };

// Sequential reader over the body (binary or ascii tokens).
class Body {
 public:
  Body(const std::string& data, std::size_t pos, Format fmt, const std::string& file)
      : d_(data), pos_(pos), fmt_(fmt), file_(file) {}
  double read(PType t) {
    if (fmt_ == Format::ascii) return read_ascii();
    const int n = type_size(t);
    if (pos_ + n > d_.size()) fail(file_, ": file ends early (truncated binary data)");
    unsigned char b[8];
    std::memcpy(b, d_.data() + pos_, n);
    pos_ += n;
    const bool swap = (fmt_ == Format::be) == (std::endian::native == std::endian::little);
    if (swap)
      for (int i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    switch (t) {
      case PType::i8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
      case PType::u8: { std::uint8_t v; std::memcpy(&v, b, 1); return v; }
      case PType::i16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
      case PType::u16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
      case PType::i32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
      case PType::u32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
      case PType::f32: { float v; std::memcpy(&v, b, 4); return v; }
      case PType::f64: { double v; std::memcpy(&v, b, 8); return v; }
      default: fail(file_, ": bad property type");
    }
  }

 private:
  double read_ascii() {
    while (pos_ < d_.size() && std::isspace(static_cast<unsigned char>(d_[pos_]))) ++pos_;
    if (pos_ >= d_.size()) fail(file_, ": file ends early (missing ascii values)");
    const char* s = d_.c_str() + pos_;
    char* e = nullptr;
    const double v = std::strtod(s, &e);
    if (e == s) fail(file_, ": bad ascii number near byte ", pos_);
    pos_ += e - s;
    return v;
  }
  const std::string& d_;
  std::size_t pos_;
  Format fmt_;
  const std::string& file_;
};

struct Header {
  Format fmt;
  std::vector<Element> elems;
  std::size_t body;  // offset of the first byte after end_header
};

// The header (up to end_header) of a PLY file of file_size bytes whose first bytes are
// `data`; every problem is an Error naming the file.
Header parse_header(const std::string& data, const std::string& file, std::uint64_t file_size) {
  std::size_t pos = 0;
  auto next_line = [&](std::string& line) {
    if (pos >= data.size()) fail(file, ": header has no end_header line");
    std::size_t e = data.find('\n', pos);
    if (e == std::string::npos) fail(file, ": header has no end_header line");
    line = data.substr(pos, e - pos);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    pos = e + 1;
  };
  std::string line;
  next_line(line);
  require(line == "ply", file, ": not a PLY file (first line is not 'ply')");
  Format fmt = Format::ascii;
  bool have_format = false;
  std::vector<Element> elems;
  for (;;) {
    next_line(line);
    std::istringstream ls(line);
    std::string kw;
    ls >> kw;
    if (kw == "end_header") break;
    if (kw.empty() || kw == "comment" || kw == "obj_info") continue;
    if (kw == "format") {
      std::string f, ver;
      ls >> f >> ver;
      if (f == "ascii") fmt = Format::ascii;
      else if (f == "binary_little_endian") fmt = Format::le;
      else if (f == "binary_big_endian") fmt = Format::be;
      else fail(file, ": unknown PLY format '", f, "'");
      have_format = true;
    } else if (kw == "element") {
      Element e;
      long long n = -1;
      ls >> e.name >> n;
      require(!ls.fail() && n >= 0, file, ": bad element line '", line, "'");
      e.count = static_cast<std::size_t>(n);
      elems.push_back(e);
    } else if (kw == "property") {
      require(!elems.empty(), file, ": property before any element");
      Prop p;
      std::string t;
      ls >> t;
      if (t == "list") {
        std::string ct, it;
        ls >> ct >> it >> p.name;
        p.is_list = true;
        p.count_type = parse_type(ct);
        p.type = parse_type(it);
        require(p.count_type != PType::none && p.type != PType::none && !p.name.empty(), file,
                ": bad list property line '", line, "'");
      } else {
        p.type = parse_type(t);
        ls >> p.name;
        require(p.type != PType::none && !p.name.empty(), file, ": bad property line '", line, "'");
      }
      elems.back().props.push_back(p);
    } else {
      fail(file, ": unknown header keyword '", kw, "'");
    }
  }
  require(have_format, file, ": header has no format line");
  // Element counts the body cannot hold (a damaged or hostile header) are refused before
  // anything is allocated: each row takes at least its fixed-size properties (binary) or
  // two characters a value (ascii).
  {
    double need = 0;
    for (const Element& e : elems) {
      double row = 0;
      for (const Prop& p : e.props)
        row += fmt == Format::ascii ? 2 : type_size(p.is_list ? p.count_type : p.type);
      need += static_cast<double>(e.count) * std::max(row, 1.0);
    }
    const double have = static_cast<double>(file_size) - static_cast<double>(pos);
    if (need > have) {
      std::string counts;
      for (const Element& e : elems) counts += (counts.empty() ? "" : ", ") + std::to_string(e.count) + " " + e.name;
      fail(file, ": the header declares ", counts, " but the file holds only ", file_size - pos,
           " bytes of data (truncated or damaged)");
    }
  }

  return {fmt, std::move(elems), pos};
}

}  // namespace

void check_ply_header(const std::filesystem::path& path) {
  check_regular_file(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path.string(), ": cannot open (missing or unreadable)");
  std::string head(1 << 16, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  parse_header(head, path.string(), ec ? head.size() : size);
}

TriMesh read_ply(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::string data = read_file(path);
  const Header h = parse_header(data, file, data.size());
  const Format fmt = h.fmt;
  const std::vector<Element>& elems = h.elems;
  const std::size_t pos = h.body;

  TriMesh m;
  Body body(data, pos, fmt, file);
  bool have_vertex = false;
  for (const Element& e : elems) {
    if (e.name == "vertex") {
      have_vertex = true;
      int ix = -1, iy = -1, iz = -1, inx = -1, iny = -1, inz = -1, ir = -1, ig = -1, ib = -1;
      std::vector<int> extra;
      for (int k = 0; k < static_cast<int>(e.props.size()); ++k) {
        const Prop& p = e.props[k];
        require(!p.is_list, file, ": list property '", p.name, "' in element vertex is not supported");
        if (p.name == "x") ix = k;
        else if (p.name == "y") iy = k;
        else if (p.name == "z") iz = k;
        else if (p.name == "nx") inx = k;
        else if (p.name == "ny") iny = k;
        else if (p.name == "nz") inz = k;
        else if (p.name == "red" || p.name == "r") ir = k;
        else if (p.name == "green" || p.name == "g") ig = k;
        else if (p.name == "blue" || p.name == "b") ib = k;
        else if (p.name == "alpha" || p.name == "a") {}
        else extra.push_back(k);
      }
      require(ix >= 0 && iy >= 0 && iz >= 0, file, ": element vertex lacks x, y or z");
      const bool hasN = inx >= 0 && iny >= 0 && inz >= 0;
      const bool hasC = ir >= 0 && ig >= 0 && ib >= 0;
      const bool floatC = hasC && (e.props[ir].type == PType::f32 || e.props[ir].type == PType::f64);
      m.V.resize(e.count);
      if (hasN) m.N.resize(e.count);
      if (hasC) m.C.resize(e.count);
      std::vector<std::vector<float>> ex(extra.size(), std::vector<float>(e.count));
      std::vector<double> row(e.props.size());
      for (std::size_t i = 0; i < e.count; ++i) {
        for (std::size_t k = 0; k < e.props.size(); ++k) row[k] = body.read(e.props[k].type);
        m.V[i] = {row[ix], row[iy], row[iz]};
        require(m.V[i].allFinite(), file, ": vertex ", i, " has a non-finite coordinate");
        if (hasN) m.N[i] = Eigen::Vector3f(row[inx], row[iny], row[inz]);
        if (hasC) {
          for (int c = 0; c < 3; ++c) {
            double v = row[c == 0 ? ir : c == 1 ? ig : ib];
            if (floatC) v = std::lround(v * 255.0);
            require(v >= 0 && v <= 255, file, ": vertex ", i, " has colour value ", v, " outside 0..255");
            m.C[i][c] = static_cast<std::uint8_t>(v);
          }
        }
        for (std::size_t j = 0; j < extra.size(); ++j) ex[j][i] = static_cast<float>(row[extra[j]]);
      }
      for (std::size_t j = 0; j < extra.size(); ++j) m.vprops.emplace_back(e.props[extra[j]].name, std::move(ex[j]));
    } else if (e.name == "face") {
      int il = -1;
      std::vector<int> extra;
      for (int k = 0; k < static_cast<int>(e.props.size()); ++k) {
        const Prop& p = e.props[k];
        if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) il = k;
        else if (!p.is_list) extra.push_back(k);
      }
      require(il >= 0, file, ": element face has no vertex_indices list");
      std::vector<std::vector<float>> ex(extra.size());
      m.F.reserve(e.count);
      std::vector<int> poly;
      std::vector<double> scal(e.props.size());
      for (std::size_t i = 0; i < e.count; ++i) {
        poly.clear();
        for (std::size_t k = 0; k < e.props.size(); ++k) {
          const Prop& p = e.props[k];
          if (p.is_list) {
            const double n = body.read(p.count_type);
            require(n >= 0 && n < 1e6, file, ": face ", i, " has a bad list length ", n);
            for (int j = 0; j < static_cast<int>(n); ++j) {
              const double v = body.read(p.type);
              if (static_cast<int>(k) == il) poly.push_back(static_cast<int>(v));
            }
          } else {
            scal[k] = body.read(p.type);
          }
        }
        require(poly.size() >= 3, file, ": face ", i, " has ", poly.size(), " vertices (need at least 3)");
        for (std::size_t j = 1; j + 1 < poly.size(); ++j) {
          m.F.emplace_back(poly[0], poly[j], poly[j + 1]);
          for (std::size_t x = 0; x < extra.size(); ++x) ex[x].push_back(static_cast<float>(scal[extra[x]]));
        }
      }
      for (std::size_t j = 0; j < extra.size(); ++j) m.fprops.emplace_back(e.props[extra[j]].name, std::move(ex[j]));
    } else {
      for (std::size_t i = 0; i < e.count; ++i)
        for (const Prop& p : e.props) {
          if (p.is_list) {
            const double n = body.read(p.count_type);
            require(n >= 0 && n < 1e9, file, ": element ", e.name, " has a bad list length");
            for (int j = 0; j < static_cast<int>(n); ++j) body.read(p.type);
          } else {
            body.read(p.type);
          }
        }
    }
  }
  require(have_vertex, file, ": no vertex element");
  m.validate(file);
  return m;
}

void write_ply(const std::filesystem::path& file, const TriMesh& m, const PlyWriteOptions& opt) {
  m.validate(file.string());
  static_assert(std::endian::native == std::endian::little, "PLY writer assumes a little-endian host");
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\n";
  if (!opt.comment.empty()) h << "comment " << opt.comment << "\n";
  h << "element vertex " << m.V.size() << "\n";
  const char* ct = opt.double_coords ? "double" : "float";
  h << "property " << ct << " x\nproperty " << ct << " y\nproperty " << ct << " z\n";
  const bool hasN = !m.N.empty(), hasC = !m.C.empty();
  if (hasN) h << "property float nx\nproperty float ny\nproperty float nz\n";
  if (hasC) h << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  for (const auto& [n, v] : m.vprops) h << "property float " << n << "\n";
  if (!m.F.empty()) {
    h << "element face " << m.F.size() << "\nproperty list uchar int vertex_indices\n";
    for (const auto& [n, v] : m.fprops) h << "property float " << n << "\n";
  }
  h << "end_header\n";
  std::string out = h.str();
  const std::size_t vsize = (opt.double_coords ? 24 : 12) + (hasN ? 12 : 0) + (hasC ? 3 : 0) + 4 * m.vprops.size();
  const std::size_t fsize = 13 + 4 * m.fprops.size();
  std::string body(m.V.size() * vsize + (m.F.empty() ? 0 : m.F.size() * fsize), '\0');
  char* p = body.data();
  auto put = [&p](const auto& v) {
    std::memcpy(p, &v, sizeof(v));
    p += sizeof(v);
  };
  for (std::size_t i = 0; i < m.V.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      if (opt.double_coords) put(m.V[i][k]);
      else put(static_cast<float>(m.V[i][k]));
    }
    if (hasN) for (int k = 0; k < 3; ++k) put(m.N[i][k]);
    if (hasC) for (int k = 0; k < 3; ++k) put(m.C[i][k]);
    for (const auto& pr : m.vprops) put(pr.second[i]);
  }
  for (std::size_t f = 0; f < m.F.size(); ++f) {
    put(static_cast<std::uint8_t>(3));
    for (int k = 0; k < 3; ++k) put(static_cast<std::int32_t>(m.F[f][k]));
    for (const auto& pr : m.fprops) put(pr.second[f]);
  }
  out += body;
  write_text_atomic(file, out);
}

}  // namespace tetmvs
