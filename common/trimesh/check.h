// Topology checks of a triangle mesh: counts, connected components, edge-manifoldness,
// closedness, orientation and genus per component.
#pragma once
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/trimesh/trimesh.h"

namespace tetmvs {

struct ComponentCheck {
  std::int64_t vertices = 0, faces = 0, edges = 0;
  std::int64_t boundary_edges = 0;   // edges with one face
  std::int64_t boundary_loops = 0;   // connected groups of boundary edges
  int euler = 0;                     // V - E + F
  bool closed = false;               // every edge has exactly two faces
  bool edge_manifold = false;        // no edge has more than two faces
  bool oriented = false;             // every two-face edge is used in opposite directions
  int genus = -1;                    // (2 - euler - boundary_loops) / 2; -1 unless edge-manifold and oriented
  double area = 0;
  double signed_volume = 0;          // meaningful when closed: > 0 means outward normals
};

struct MeshCheck {
  std::int64_t vertices = 0, faces = 0, edges = 0;
  std::int64_t unreferenced_vertices = 0;
  std::int64_t degenerate_faces = 0;     // repeated vertex index or zero area
  std::int64_t boundary_edges = 0;
  std::int64_t nonmanifold_edges = 0;    // more than two faces
  std::int64_t misoriented_edges = 0;    // two faces using the edge in the same direction
  bool edge_manifold = false, closed = false, oriented = false;
  std::vector<ComponentCheck> components;  // sorted by face count, largest first
  std::vector<int> face_component;         // component of each face (index into components)
};

MeshCheck check_mesh(const TriMesh& m);
nlohmann::json to_json(const MeshCheck& c);

}  // namespace tetmvs
