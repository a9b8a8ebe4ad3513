#include "common/trimesh/trimesh.h"

#include <cmath>

#include "common/error.h"

namespace tetmvs {

namespace {
const std::vector<float>* find_prop(const std::vector<std::pair<std::string, std::vector<float>>>& p,
                                    const std::string& name) {
  for (const auto& [n, v] : p)
    if (n == name) return &v;
  return nullptr;
}
void put_prop(std::vector<std::pair<std::string, std::vector<float>>>& p, const std::string& name,
              std::vector<float> values) {
  for (auto& [n, v] : p)
    if (n == name) {
      v = std::move(values);
      return;
    }
  p.emplace_back(name, std::move(values));
}
}  // namespace

const std::vector<float>* TriMesh::vprop(const std::string& name) const { return find_prop(vprops, name); }
const std::vector<float>* TriMesh::fprop(const std::string& name) const { return find_prop(fprops, name); }
void TriMesh::set_vprop(const std::string& name, std::vector<float> values) {
  require(values.size() == V.size(), "vertex property '", name, "' has ", values.size(), " values for ",
          V.size(), " vertices");
  put_prop(vprops, name, std::move(values));
}
void TriMesh::set_fprop(const std::string& name, std::vector<float> values) {
  require(values.size() == F.size(), "face property '", name, "' has ", values.size(), " values for ",
          F.size(), " faces");
  put_prop(fprops, name, std::move(values));
}

void TriMesh::validate(const std::string& what) const {
  require(N.empty() || N.size() == V.size(), what, ": ", N.size(), " normals for ", V.size(), " vertices");
  require(C.empty() || C.size() == V.size(), what, ": ", C.size(), " colours for ", V.size(), " vertices");
  for (const auto& [n, v] : vprops)
    require(v.size() == V.size(), what, ": vertex property '", n, "' has ", v.size(), " values");
  for (const auto& [n, v] : fprops)
    require(v.size() == F.size(), what, ": face property '", n, "' has ", v.size(), " values");
  for (std::size_t i = 0; i < V.size(); ++i)
    require(V[i].allFinite(), what, ": vertex ", i, " has a non-finite coordinate");
  const int n = static_cast<int>(V.size());
  for (std::size_t f = 0; f < F.size(); ++f)
    for (int k = 0; k < 3; ++k)
      require(F[f][k] >= 0 && F[f][k] < n, what, ": face ", f, " refers to vertex ", F[f][k], " of ", n);
}

double total_area(const TriMesh& m) {
  double a = 0;
  for (std::size_t f = 0; f < m.F.size(); ++f) a += face_area(m, f);
  return a;
}

double signed_volume(const TriMesh& m) {
  double v = 0;
  for (const auto& t : m.F) v += m.V[t[0]].dot(m.V[t[1]].cross(m.V[t[2]]));
  return v / 6.0;
}

void compute_vertex_normals(TriMesh& m) {
  std::vector<Eigen::Vector3d> acc(m.V.size(), Eigen::Vector3d::Zero());
  for (std::size_t f = 0; f < m.F.size(); ++f) {
    const Eigen::Vector3d c = face_cross(m, f);
    for (int k = 0; k < 3; ++k) acc[m.F[f][k]] += c;
  }
  m.N.resize(m.V.size());
  for (std::size_t i = 0; i < acc.size(); ++i) {
    const double l = acc[i].norm();
    m.N[i] = l > 0 ? Eigen::Vector3f((acc[i] / l).cast<float>()) : Eigen::Vector3f::Zero();
  }
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> bounds(const TriMesh& m) {
  require(!m.V.empty(), "bounds of an empty mesh");
  Eigen::Vector3d lo = m.V[0], hi = m.V[0];
  for (const auto& p : m.V) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return {lo, hi};
}

void transform(TriMesh& m, const Eigen::Matrix3d& rot, double s, const Eigen::Vector3d& t) {
  for (auto& p : m.V) p = s * (rot * p) + t;
  const Eigen::Matrix3f rf = rot.cast<float>();
  for (auto& n : m.N) n = rf * n;
  if (s < 0) flip_orientation(m);
}

void flip_orientation(TriMesh& m) {
  for (auto& f : m.F) std::swap(f[1], f[2]);
  for (auto& n : m.N) n = -n;
}

void append(TriMesh& a, const TriMesh& b) {
  const int off = static_cast<int>(a.V.size());
  const bool keepN = a.N.size() == a.V.size() && b.N.size() == b.V.size();
  const bool keepC = a.C.size() == a.V.size() && b.C.size() == b.V.size();
  auto merge = [](auto& pa, const auto& pb, std::size_t na, std::size_t nb) {
    std::vector<std::pair<std::string, std::vector<float>>> out;
    for (auto& [n, v] : pa)
      for (const auto& [n2, v2] : pb)
        if (n == n2 && v.size() == na && v2.size() == nb) {
          std::vector<float> w = v;
          w.insert(w.end(), v2.begin(), v2.end());
          out.emplace_back(n, std::move(w));
        }
    pa = std::move(out);
  };
  merge(a.vprops, b.vprops, a.V.size(), b.V.size());
  merge(a.fprops, b.fprops, a.F.size(), b.F.size());
  if (keepN) a.N.insert(a.N.end(), b.N.begin(), b.N.end()); else a.N.clear();
  if (keepC) a.C.insert(a.C.end(), b.C.begin(), b.C.end()); else a.C.clear();
  a.V.insert(a.V.end(), b.V.begin(), b.V.end());
  for (const auto& f : b.F) a.F.push_back(f + Eigen::Vector3i::Constant(off));
}

TriMesh submesh(const TriMesh& m, const std::vector<char>& keep) {
  require(keep.size() == m.F.size(), "submesh: keep has ", keep.size(), " entries for ", m.F.size(), " faces");
  std::vector<int> map(m.V.size(), -1);
  TriMesh out;
  std::vector<std::size_t> faces;
  for (std::size_t f = 0; f < m.F.size(); ++f) {
    if (!keep[f]) continue;
    faces.push_back(f);
    Eigen::Vector3i t;
    for (int k = 0; k < 3; ++k) {
      int& id = map[m.F[f][k]];
      if (id < 0) {
        id = static_cast<int>(out.V.size());
        out.V.push_back(m.V[m.F[f][k]]);
      }
      t[k] = id;
    }
    out.F.push_back(t);
  }
  std::vector<std::size_t> inv(out.V.size());
  for (std::size_t i = 0; i < map.size(); ++i)
    if (map[i] >= 0) inv[map[i]] = i;
  if (m.N.size() == m.V.size())
    for (std::size_t i : inv) out.N.push_back(m.N[i]);
  if (m.C.size() == m.V.size())
    for (std::size_t i : inv) out.C.push_back(m.C[i]);
  for (const auto& [n, v] : m.vprops) {
    std::vector<float> w;
    for (std::size_t i : inv) w.push_back(v[i]);
    out.vprops.emplace_back(n, std::move(w));
  }
  for (const auto& [n, v] : m.fprops) {
    std::vector<float> w;
    for (std::size_t f : faces) w.push_back(v[f]);
    out.fprops.emplace_back(n, std::move(w));
  }
  return out;
}

}  // namespace tetmvs
