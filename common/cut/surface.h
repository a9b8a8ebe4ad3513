// The surface of a cut: the faces between inside and outside cells, oriented outward,
// made closed and manifold by splitting (not deleting) non-manifold edges and vertices.
//
// Around every mesh edge of the surface the cut faces alternate between "leaving an inside
// run of cells" and "leaving an outside run"; each cut face is glued across that edge to the
// next cut face through an inside run (the default). Walking these gluings around a mesh
// vertex gives its fans: closed cycles of triangles; each fan gets its own copy of the
// vertex. Two inside regions that touch along an edge or at a vertex thus become separate
// sheets that share positions but not vertices.
//
// A fan can still pass twice by the same edge: when the inside touches itself along an edge
// uv and is connected around both u and v, the two gluings at uv get the same copies of u and
// v and the output edge would have four triangles. Such edges are first re-glued through the
// outside runs instead (this splits the fans of u and v in two; kept only when it lowers the
// number of such edges at u and v); an edge still shared after that gets, per extra gluing, a
// midpoint vertex of its own that splits the pair's two triangles. The result: every output
// edge has exactly two triangles used in opposite directions, every vertex has a single
// fan whose edges lead to distinct vertices (a disk), whatever the labels.
#pragma once
#include <cstdint>
#include <vector>

#include "common/tetmesh/tetmesh.h"
#include "common/trimesh/trimesh.h"

namespace tetmvs::cut {

struct SurfaceStats {
  std::int64_t faces = 0;              // cut faces (output triangles before midpoint splits)
  std::int64_t split_vertices = 0;     // extra vertex copies made to split non-manifold spots
  std::int64_t nonmanifold_edges = 0;  // gluings that shared both copies with another, first found
  std::int64_t repaired_edges = 0;     // mesh edges re-glued through their outside runs
  std::int64_t split_edges = 0;        // midpoint vertices added (each splits two triangles)
};

struct SurfaceOptions {
  bool repair = true;  // re-glue shared edges through the outside runs before splitting them
};

// inside: one flag per cell (cells beyond the mesh boundary count as outside).
// face_ids (optional) receives, per output triangle, the mesh face it lies in (a face split
// at a midpoint gives two or more triangles).
TriMesh cut_surface(const tet::TetMesh& m, const std::vector<std::uint8_t>& inside,
                    SurfaceStats* stats = nullptr, std::vector<std::int32_t>* face_ids = nullptr,
                    const SurfaceOptions& opt = {});

}  // namespace tetmvs::cut
