// The surface of a cut: the faces between inside and outside cells, oriented outward,
// made edge-manifold by splitting (not deleting) non-manifold edges and vertices.
//
// Around every edge of the surface the inside cells form sectors; each sector is bounded
// by exactly two cut faces, which become neighbours across that edge. Walking these
// pairings around a vertex gives its fans; each fan gets its own copy of the vertex. Two
// inside regions that touch along an edge or at a vertex thus become separate sheets
// that share positions but not vertices.
#pragma once
#include <cstdint>
#include <vector>

#include "common/tetmesh/tetmesh.h"
#include "common/trimesh/trimesh.h"

namespace tetmvs::cut {

struct SurfaceStats {
  std::int64_t faces = 0;
  std::int64_t split_vertices = 0;  // extra vertex copies made to split non-manifold spots
};

// inside: one flag per cell (cells beyond the mesh boundary count as outside).
// face_ids (optional) receives, per output triangle, the mesh face it came from.
TriMesh cut_surface(const tet::TetMesh& m, const std::vector<std::uint8_t>& inside,
                    SurfaceStats* stats = nullptr, std::vector<std::int32_t>* face_ids = nullptr);

}  // namespace tetmvs::cut
