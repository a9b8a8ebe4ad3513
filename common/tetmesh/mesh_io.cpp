// Mesh HDF5 files and the .vtu export.
#include "common/tetmesh/mesh_io.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "common/error.h"
#include "common/fileio.h"
#include "common/h5io.h"

namespace tetmvs::tet {

namespace {
template <typename T, std::size_t K>
std::vector<T> flat(const std::vector<std::array<T, K>>& v) {
  std::vector<T> out(v.size() * K);
  if (!v.empty()) std::memcpy(out.data(), v.data(), out.size() * sizeof(T));
  return out;
}
template <typename T, std::size_t K>
std::vector<std::array<T, K>> unflat(const std::vector<T>& v) {
  std::vector<std::array<T, K>> out(v.size() / K);
  if (!out.empty()) std::memcpy(out.data(), v.data(), out.size() * K * sizeof(T));
  return out;
}
}  // namespace

namespace {

std::vector<double> vertex_positions(const TetMesh& m) {
  const std::uint64_t NV = m.num_vertices();
  std::vector<double> xyz(3 * NV);
  for (std::uint64_t v = 0; v < NV; ++v) {
    const Eigen::Vector3d p = m.vertex(static_cast<std::int32_t>(v));
    xyz[3 * v] = p.x(), xyz[3 * v + 1] = p.y(), xyz[3 * v + 2] = p.z();
  }
  return xyz;
}

std::vector<std::int8_t> cell_levels(const TetMesh& m) {
  const std::uint64_t NC = m.num_cells();
  std::vector<std::int8_t> lev(NC);
  for (std::uint64_t c = 0; c < NC; ++c) lev[c] = m.node_level[m.cell_node[c]];
  return lev;
}

std::vector<std::array<std::int32_t, 3>> face_vertex_rows(const TetMesh& m) {
  std::vector<std::array<std::int32_t, 3>> fv(m.num_faces());
  for (std::size_t i = 0; i < fv.size(); ++i) fv[i] = m.face_vertices(static_cast<std::int32_t>(i));
  return fv;
}

std::vector<std::array<std::int32_t, 2>> face_cell_rows(const TetMesh& m) {
  std::vector<std::array<std::int32_t, 2>> fc(m.num_faces());
  for (std::size_t i = 0; i < fc.size(); ++i)
    fc[i] = {m.face_cell(static_cast<std::int32_t>(i), 0), m.face_cell(static_cast<std::int32_t>(i), 1)};
  return fc;
}

h5::Fields<TetMesh> make_mesh_fields() {
  h5::Fields<TetMesh> t;
  t.attr("/", "level", &TetMesh::level)
      .attr("/", "lattice_origin",
            [](const TetMesh& m) { return std::array<double, 3>{m.lat.origin.x(), m.lat.origin.y(), m.lat.origin.z()}; })
      .attr("/", "lattice_h", [](const TetMesh& m) { return m.lat.h; })
      .attr("/", "lattice_dims",
            [](const TetMesh& m) {
              return std::array<double, 3>{double(m.lat.dims[0]), double(m.lat.dims[1]), double(m.lat.dims[2])};
            })
      .attr("/", "lattice_bits", [](const TetMesh&) { return kLatticeBits; })
      .attr("/", "lattice_unit", [](const TetMesh& m) { return m.lat.unit(); })
      .attr("/", "num_level0", &TetMesh::num_level0)
      .dataset("/vertices", vertex_positions, 3)
      .dataset("/vertices_lattice", &TetMesh::vlat, 3)
      .dataset("/vertex_parent", &TetMesh::vparent, 2)
      .dataset("/cells", &TetMesh::cell_v)
      .dataset("/cell_level", cell_levels)
      .dataset("/cell_colour", &TetMesh::cell_colour)
      .dataset("/cell_node", &TetMesh::cell_node)
      .dataset("/cell_new_red", &TetMesh::cell_new_red)
      .dataset("/cell_faces", &TetMesh::cell_face)
      .dataset("/faces", face_vertex_rows)
      .dataset("/face_cells", face_cell_rows)
      .dataset("/face_parent", &TetMesh::face_parent)
      .dataset("/face_sub", &TetMesh::face_sub)
      .dataset("/tree/vertices", &TetMesh::node_v)
      .dataset("/tree/level", &TetMesh::node_level)
      .dataset("/tree/parent", &TetMesh::node_parent)
      .dataset("/tree/first_child", &TetMesh::node_child)
      .dataset("/tree/first_cell", &TetMesh::node_cell)
      .dataset("/tree/num_cells", &TetMesh::node_ncell);
  return t;
}

}  // namespace

const h5::Fields<TetMesh>& mesh_fields() {
  static const h5::Fields<TetMesh> t = make_mesh_fields();
  return t;
}

void write_mesh(const std::filesystem::path& file, const TetMesh& m, const std::string& stage,
                const nlohmann::json& params, const std::vector<std::filesystem::path>& inputs) {
  auto f = h5::File::create(file);
  f.write_header(kMeshSchema, kMeshVersion, stage, params, inputs);
  mesh_fields().write(f, m);
  f.commit();
}

TetMesh read_mesh(const std::filesystem::path& file) {
  const auto f = h5::File::open(file, kMeshSchema, 1, kMeshVersion);
  const std::string name = file.string();
  TetMesh m;
  const std::int64_t level = f.attr_int("/", "level");
  require(level >= 0 && level <= kMaxLevel, name, ": level ", level, " is outside 0..", kMaxLevel);
  m.level = static_cast<int>(level);
  const auto o = f.attr_doubles("/", "lattice_origin");
  const auto d = f.attr_doubles("/", "lattice_dims");
  require(o.size() == 3 && d.size() == 3, name, ": lattice_origin / lattice_dims need 3 values");
  require(f.attr_int("/", "lattice_bits") == kLatticeBits, name, ": lattice_bits is ",
          f.attr_int("/", "lattice_bits"), ", this build uses ", kLatticeBits);
  m.lat.origin = Eigen::Vector3d(o[0], o[1], o[2]);
  m.lat.h = f.attr_double("/", "lattice_h");
  require(m.lat.h > 0, name, ": lattice_h must be > 0");
  for (int a = 0; a < 3; ++a) {
    // bounded before the conversion (a huge value would overflow the cast)
    require(d[a] >= 1 && d[a] <= kMaxDims && d[a] == std::floor(d[a]), name, ": lattice_dims must be whole numbers in 1..",
            kMaxDims);
    m.lat.dims[a] = static_cast<int>(d[a]);
  }
  const std::int64_t n0 = f.attr_int("/", "num_level0");
  require(n0 >= 0 && n0 < (std::int64_t{1} << 31), name, ": num_level0 ", n0, " is out of range");
  m.num_level0 = static_cast<std::int32_t>(n0);
  m.vlat = f.read<std::int32_t>("/vertices_lattice", {h5::kAny, 3}).data;
  const auto NV = static_cast<std::int64_t>(m.vlat.size() / 3);
  {
    // /vertices is derived from the lattice; it must agree (and be finite: read<> checks)
    const auto xyz = f.read<double>("/vertices", {NV, 3}).data;
    for (std::int64_t v = 0; v < NV; ++v)
      for (int k = 0; k < 3; ++k) {
        const double want = m.lat.origin[k] + m.lat.unit() * m.vlat[3 * v + k];
        require(std::abs(xyz[3 * v + k] - want) <= 1e-9 * m.lat.h + 1e-12 * std::abs(want), name, ": /vertices row ", v,
                " disagrees with /vertices_lattice (file edited or corrupt)");
      }
  }
  m.vparent = f.read<std::int32_t>("/vertex_parent", {NV, 2}).data;
  m.cell_v = unflat<std::int32_t, 4>(f.read<std::int32_t>("/cells", {h5::kAny, 4}).data);
  const auto NC = static_cast<std::int64_t>(m.cell_v.size());
  m.cell_colour = f.read_vec<std::uint8_t>("/cell_colour", NC);
  m.cell_node = f.read_vec<std::int32_t>("/cell_node", NC);
  m.cell_new_red = f.read_vec<std::uint8_t>("/cell_new_red", NC);
  m.node_v = unflat<std::int32_t, 4>(f.read<std::int32_t>("/tree/vertices", {h5::kAny, 4}).data);
  const auto NN = static_cast<std::int64_t>(m.node_v.size());
  m.node_level = f.read_vec<std::int8_t>("/tree/level", NN);
  m.node_parent = f.read_vec<std::int32_t>("/tree/parent", NN);
  m.node_child = f.read_vec<std::int32_t>("/tree/first_child", NN);
  m.node_cell = f.read_vec<std::int32_t>("/tree/first_cell", NN);
  m.node_ncell = f.read_vec<std::uint8_t>("/tree/num_cells", NN);
  // indices into the vertex array are checked before anything follows them
  const auto vertex_ok = [&](std::int32_t v) { return v >= 0 && v < NV; };
  for (std::size_t i = 0; i < m.vparent.size(); ++i)
    require(m.vparent[i] == -1 || vertex_ok(m.vparent[i]), name, ": /vertex_parent row ", i / 2, " names vertex ",
            m.vparent[i], ", the mesh has ", NV);
  for (std::int64_t c = 0; c < NC; ++c)
    for (const std::int32_t v : m.cell_v[c])
      require(vertex_ok(v), name, ": /cells row ", c, " names vertex ", v, ", the mesh has ", NV);
  for (std::int64_t n = 0; n < NN; ++n)
    for (const std::int32_t v : m.node_v[n])
      require(vertex_ok(v), name, ": /tree/vertices row ", n, " names vertex ", v, ", the mesh has ", NV);
  require(NC < (std::int64_t{1} << 29) && NV < (std::int64_t{1} << 31) && NN < (std::int64_t{1} << 31), name,
          ": too many cells, vertices or nodes for 32-bit indices");
  m.cell_face = unflat<std::int32_t, 4>(f.read<std::int32_t>("/cell_faces", {NC, 4}).data);
  try {
    link_faces(m);
  } catch (const Error& e) {
    fail(name, ": /cell_faces: ", e.what());
  }
  const auto NF = static_cast<std::int64_t>(m.num_faces());
  const auto fc = f.read<std::int32_t>("/face_cells", {NF, 2}).data;
  for (std::int64_t i = 0; i < NF; ++i)
    require(fc[2 * i] == m.face_cell(static_cast<std::int32_t>(i), 0) &&
                fc[2 * i + 1] == m.face_cell(static_cast<std::int32_t>(i), 1),
            name, ": /face_cells does not match the faces of /cells at face ", i);
  m.face_parent = f.read_vec<std::int32_t>("/face_parent", NF);
  m.face_sub = f.read_vec<std::int8_t>("/face_sub", NF);
  try {
    check_mesh(m);
  } catch (const Error& e) {
    fail(name, ": ", e.what());
  }
  return m;
}

std::vector<std::uint8_t> read_cell_flags(const std::filesystem::path& file, const std::string& dataset,
                                          std::int64_t num_cells) {
  const auto f = h5::File::open(file);
  require(f.has(dataset), file.string(), ": no dataset ", dataset);
  const auto shape = f.shape_of(dataset);
  require(shape.size() == 1 && static_cast<std::int64_t>(shape[0]) == num_cells, file.string(), ": ",
          dataset, " has ", shape.empty() ? 0 : shape[0], " entries, the mesh has ", num_cells, " cells");
  return f.read_vec<std::uint8_t>(dataset, num_cells);
}

void write_vtu(const std::filesystem::path& file, const TetMesh& m, const std::vector<CellField>& fields) {
  const std::uint64_t NV = m.num_vertices(), NC = m.num_cells();
  for (const auto& fl : fields)
    require(fl.values.size() == NC, "write_vtu: field ", fl.name, " has ", fl.values.size(),
            " values for ", NC, " cells");
  std::ostringstream xml, data;
  std::uint64_t offset = 0;
  auto block = [&](const void* p, std::uint64_t bytes) {
    const std::uint64_t o = offset;
    data.write(reinterpret_cast<const char*>(&bytes), sizeof(bytes));
    data.write(reinterpret_cast<const char*>(p), static_cast<std::streamsize>(bytes));
    offset += sizeof(bytes) + bytes;
    return o;
  };
  std::vector<double> xyz(3 * NV);
  for (std::uint64_t v = 0; v < NV; ++v) {
    const Eigen::Vector3d p = m.vertex(static_cast<std::int32_t>(v));
    xyz[3 * v] = p.x(), xyz[3 * v + 1] = p.y(), xyz[3 * v + 2] = p.z();
  }
  const auto conn = flat(m.cell_v);
  std::vector<std::int32_t> offs(NC);
  std::vector<std::uint8_t> types(NC, 10);  // VTK_TETRA
  for (std::uint64_t c = 0; c < NC; ++c) offs[c] = static_cast<std::int32_t>(4 * (c + 1));
  std::vector<std::int32_t> level(NC);
  for (std::uint64_t c = 0; c < NC; ++c) level[c] = m.node_level[m.cell_node[c]];
  xml << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
         "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\""
      << NV << "\" NumberOfCells=\"" << NC << "\">\n";
  xml << "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"appended\" offset=\""
      << block(xyz.data(), xyz.size() * 8) << "\"/></Points>\n<Cells>\n";
  xml << "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"appended\" offset=\""
      << block(conn.data(), conn.size() * 4) << "\"/>\n";
  xml << "<DataArray type=\"Int32\" Name=\"offsets\" format=\"appended\" offset=\""
      << block(offs.data(), offs.size() * 4) << "\"/>\n";
  xml << "<DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"" << block(types.data(), NC)
      << "\"/>\n</Cells>\n<CellData Scalars=\"level\">\n";
  xml << "<DataArray type=\"Int32\" Name=\"level\" format=\"appended\" offset=\""
      << block(level.data(), NC * 4) << "\"/>\n";
  xml << "<DataArray type=\"UInt8\" Name=\"colour\" format=\"appended\" offset=\""
      << block(m.cell_colour.data(), NC) << "\"/>\n";
  xml << "<DataArray type=\"UInt8\" Name=\"new_red\" format=\"appended\" offset=\""
      << block(m.cell_new_red.data(), NC) << "\"/>\n";
  xml << "<DataArray type=\"Int32\" Name=\"node\" format=\"appended\" offset=\""
      << block(m.cell_node.data(), NC * 4) << "\"/>\n";
  for (const auto& fl : fields)
    xml << "<DataArray type=\"Float64\" Name=\"" << fl.name << "\" format=\"appended\" offset=\""
        << block(fl.values.data(), NC * 8) << "\"/>\n";
  xml << "</CellData>\n</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_";
  std::string out = xml.str() + data.str() + "\n</AppendedData>\n</VTKFile>\n";
  write_text_atomic(file, out);
}

}  // namespace tetmvs::tet
