// Triangle mesh (or point cloud, when it has no faces) in flat arrays, with optional
// per-vertex normals and colours and named float properties per vertex and per face.
// This is what common/ply.h reads and writes, and what every common/trimesh/ tool takes.
#pragma once
#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace tetmvs {

struct TriMesh {
  std::vector<Eigen::Vector3d> V;               // vertex positions
  std::vector<Eigen::Vector3i> F;               // triangles (vertex indices); empty = point cloud
  std::vector<Eigen::Vector3f> N;               // per-vertex normals, empty or V.size()
  std::vector<std::array<std::uint8_t, 3>> C;   // per-vertex RGB, empty or V.size()
  // Extra scalar properties in file order: (name, values) with V.size() / F.size() values.
  std::vector<std::pair<std::string, std::vector<float>>> vprops, fprops;

  std::size_t nv() const { return V.size(); }
  std::size_t nf() const { return F.size(); }
  bool is_point_cloud() const { return F.empty(); }

  // Named property or nullptr.
  const std::vector<float>* vprop(const std::string& name) const;
  const std::vector<float>* fprop(const std::string& name) const;
  // Adds or replaces a property (size must match).
  void set_vprop(const std::string& name, std::vector<float> values);
  void set_fprop(const std::string& name, std::vector<float> values);

  // Throws Error (prefixed by `what`) when sizes disagree, an index is out of range or a
  // coordinate is not finite.
  void validate(const std::string& what) const;
};

// Unnormalised face normal (b - a) x (c - a): its length is twice the area.
inline Eigen::Vector3d face_cross(const TriMesh& m, std::size_t f) {
  const auto& t = m.F[f];
  return (m.V[t[1]] - m.V[t[0]]).cross(m.V[t[2]] - m.V[t[0]]);
}
inline double face_area(const TriMesh& m, std::size_t f) { return 0.5 * face_cross(m, f).norm(); }
double total_area(const TriMesh& m);
// Signed volume enclosed (positive for a closed mesh with outward normals).
double signed_volume(const TriMesh& m);
// Area-weighted vertex normals (unit; zero for isolated vertices), stored into m.N.
void compute_vertex_normals(TriMesh& m);
// Axis-aligned bounds of the vertices: {min, max}. Throws on an empty mesh.
std::pair<Eigen::Vector3d, Eigen::Vector3d> bounds(const TriMesh& m);
// Applies X -> s * Rot * X + t to positions (and Rot to normals).
void transform(TriMesh& m, const Eigen::Matrix3d& rot, double s, const Eigen::Vector3d& t);
// Reverses every triangle (and normal).
void flip_orientation(TriMesh& m);
// Appends b to a (properties present in both are kept, others dropped; normals/colours
// kept only when both have them).
void append(TriMesh& a, const TriMesh& b);
// Mesh with only the faces where keep[f] is true; unreferenced vertices removed.
TriMesh submesh(const TriMesh& m, const std::vector<char>& keep);

}  // namespace tetmvs
