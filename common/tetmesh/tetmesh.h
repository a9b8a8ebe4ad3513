// The adaptive body-centred-cubic (BCC) tetrahedral mesh: data layout and shared services.
//
// LATTICE. Level 0 is a grid of dims[0] x dims[1] x dims[2] cubes of edge h starting at
// `origin`. Vertex positions are stored as integers on a grid of spacing
// unit = h / 2^kLatticeBits ("lattice coordinates"), so every edge midpoint down to level
// kMaxLevel is exact, conformity is decided exactly, and all predicates are exact
// (predicates.h). World position = origin + unit * lattice.
//
// M0 (build_bcc): lattice A = cube corners, lattice B = cube centres. For every pair of
// face-adjacent cubes, the B edge joining their centres and each of the four A edges of
// their shared square give one tetrahedron: all tets are congruent (two opposite edges of
// length h, four of length h*sqrt(3)/2). The union of these tets is the cube grid minus
// a square pyramid (apex = cube centre) over every boundary square; those pyramids are
// called "ghost pyramids" here and are handled by the ray walk. The grid is chosen h/2
// larger than the scene box on every side, so the box is covered.
//
// HIERARCHY ("red tree", append-only across levels). Every BCC tet ever created is a
// node: the level-0 tets are nodes 0..N0-1; red refinement (1:8) of a node appends its
// eight children as a block (node_child = first child). Node vertices are positively
// oriented. A red-tree leaf is either an unsplit cell (red) or is split into 2, 3 or 4
// green cells by the green closure; green cells are not nodes and are rebuilt at every
// refinement: the green closure is recomputed from scratch at each level from the set
// of existing edge midpoints. Green cells are never refined: a green cell that must be
// refined makes its red node red-refine instead.
//
// CELLS are the leaves of the current mesh (unsplit red-tree leaves and green cells),
// numbered in node order (the green cells of one node are consecutive). Vertex order
// (v0, v1, v2, v3) is positively oriented: det[v1-v0, v2-v0, v3-v0] > 0.
//
// FACES: face j of a cell is the triangle opposite v_j, with vertex order kFace[j]
// giving the outward normal (right-hand rule). A half-face is cell*4 + j. Every face has
// face_half[f][0] (its first cell, lowest half-face) and face_half[f][1] (the other
// cell, or -1 on the boundary of the domain). The face's vertex order is that of its
// first half-face, so its normal points from the first cell to the second.
#pragma once
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "common/tetmesh/predicates.h"

namespace tetmvs::tet {

inline constexpr int kLatticeBits = 16;               // unit = h / 2^16
inline constexpr int kMaxLevel = kLatticeBits - 1;    // deepest red-tree level
inline constexpr int kFixedBits = 8;                  // extra bits for query points
inline constexpr int kMaxDims = 1 << (30 - kLatticeBits);  // cubes per axis

// Face j (opposite v_j) with outward orientation; local edges and their vertex pairs.
inline constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
inline constexpr int kEdge[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
inline constexpr int kEdgeIndex[4][4] = {{-1, 0, 1, 2}, {0, -1, 3, 4}, {1, 3, -1, 5}, {2, 4, 5, -1}};

enum Colour : std::uint8_t { kRed = 0, kGreen = 1 };

using Tet = std::array<std::int32_t, 4>;

struct Lattice {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double h = 1.0;                 // level-0 cube edge (world units)
  std::array<int, 3> dims{1, 1, 1};  // cubes per axis
  double unit() const { return std::ldexp(h, -kLatticeBits); }
  // Cube-grid box in world coordinates (the tets cover it minus the ghost pyramids).
  Eigen::AlignedBox3d grid_box() const;
  // Continuous lattice coordinates of a world point.
  Eigen::Vector3d to_lattice(const Eigen::Vector3d& x) const { return (x - origin) / unit(); }
  // Fixed-point query coordinates (lattice << kFixedBits), rounded.
  I3 to_fixed(const Eigen::Vector3d& x) const;
  std::int64_t cube_fixed() const { return std::int64_t{1} << (kLatticeBits + kFixedBits); }
};

// Edge length (longest edge) of a red tet of `level`, in world units.
inline double red_edge_length(const Lattice& lat, int level) { return std::ldexp(lat.h, -level); }

struct TetMesh {
  Lattice lat;
  int level = 0;  // refinement steps done (mesh_<level>.h5)

  // Vertices: lattice coordinates (3 per vertex) and, for vertices made by bisecting an
  // edge, the edge's two end vertices (-1, -1 for level-0 vertices).
  std::vector<std::int32_t> vlat;
  std::vector<std::int32_t> vparent;

  // Red tree.
  std::vector<Tet> node_v;
  std::vector<std::int8_t> node_level;
  std::vector<std::int32_t> node_parent;  // -1 for level 0
  std::vector<std::int32_t> node_child;   // first of 8 children, -1 for a red-tree leaf
  std::vector<std::int32_t> node_cell;    // first cell of a leaf, -1 for inner nodes
  std::vector<std::uint8_t> node_ncell;   // 0 inner node, 1 unsplit, 2..4 green cells
  std::int32_t num_level0 = 0;            // nodes 0..num_level0-1 are level 0

  // Cells (leaves).
  std::vector<Tet> cell_v;
  std::vector<std::int32_t> cell_node;     // red-tree node this cell is, or is a green part of
  std::vector<std::uint8_t> cell_colour;   // kRed / kGreen
  std::vector<std::uint8_t> cell_new_red;  // 1: its node was made by red refinement in the
                                           // step that produced this mesh (all cells of M0)

  // Faces.
  std::vector<std::array<std::int32_t, 4>> cell_face;  // face id of each local face
  std::vector<std::array<std::int32_t, 2>> face_half;  // half-faces (cell*4+j), [1] = -1 on boundary
  // Filled by refine (and by build_bcc: -1 / -1): the face of the previous mesh this face
  // lies in (-1: none, i.e. inside an old cell or across old faces), and which part of it:
  // kSubWhole (the same triangle), 0..2 (the corner quarter at the old face's vertex k),
  // 3 (the middle quarter), -1 (another part, from a green split).
  std::vector<std::int32_t> face_parent;
  std::vector<std::int8_t> face_sub;

  // ---- sizes and accessors ----
  std::int32_t num_vertices() const { return static_cast<std::int32_t>(vlat.size() / 3); }
  std::int32_t num_nodes() const { return static_cast<std::int32_t>(node_v.size()); }
  std::int32_t num_cells() const { return static_cast<std::int32_t>(cell_v.size()); }
  std::int32_t num_faces() const { return static_cast<std::int32_t>(face_half.size()); }
  int max_cell_level() const;

  I3 vfixed(std::int32_t v) const {
    return {std::int64_t{vlat[3 * v]} << kFixedBits, std::int64_t{vlat[3 * v + 1]} << kFixedBits,
            std::int64_t{vlat[3 * v + 2]} << kFixedBits};
  }
  I3 vint(std::int32_t v) const { return {vlat[3 * v], vlat[3 * v + 1], vlat[3 * v + 2]}; }
  Eigen::Vector3d vertex(std::int32_t v) const {
    return lat.origin + lat.unit() * Eigen::Vector3d(vlat[3 * v], vlat[3 * v + 1], vlat[3 * v + 2]);
  }
  // The two cells of a face (second -1 on the boundary).
  std::int32_t face_cell(std::int32_t f, int k) const {
    const std::int32_t h = face_half[f][k];
    return h < 0 ? -1 : h >> 2;
  }
  bool face_on_boundary(std::int32_t f) const { return face_half[f][1] < 0; }
  // The face's vertices, ordered with the normal from its first cell to its second.
  std::array<std::int32_t, 3> face_vertices(std::int32_t f) const;
  // Vertices of half-face h (cell h / 4, local face h % 4) in the order kFace gives.
  std::array<std::int32_t, 3> half_face_vertices(std::int32_t h) const {
    const Tet& t = cell_v[h >> 2];
    const int j = h & 3;
    return {t[kFace[j][0]], t[kFace[j][1]], t[kFace[j][2]]};
  }
  // The cell across local face j of cell c (-1 on the boundary).
  std::int32_t neighbour(std::int32_t c, int j) const;

  // ---- geometry (world units) ----
  double cell_volume(std::int32_t c) const;
  Eigen::Vector3d cell_centroid(std::int32_t c) const;
  double face_area(std::int32_t f) const;
  Eigen::Vector3d face_normal(std::int32_t f) const;  // unit, first cell -> second
  Eigen::Vector3d face_centroid(std::int32_t f) const;
  // Exact 6 * volume in lattice units^3.
  i128 cell_volume6_lattice(std::int32_t c) const;

  // Approximate heap memory in bytes (capacity of every array).
  std::size_t memory_bytes() const;
};

inline constexpr std::int8_t kSubWhole = 4;

// ---- construction (tetmesh.cpp) ----

// Chooses the level-0 lattice for a box: h = longest side / cells_longest, and the cube
// grid extends at least h/2 beyond the box on every side (so the tets cover the box).
Lattice lattice_for_box(const Eigen::AlignedBox3d& box, int cells_longest);
// The level-0 BCC mesh M0 on a lattice (faces built, every cell new_red).
TetMesh build_bcc(const Lattice& lat);

// Rebuilds cell_face / face_half from cell_v. Throws Error when a face is shared by more
// than two cells or twice with the same orientation (a non-conforming mesh).
void build_faces(TetMesh& m);

// Rebuilds face_half from a cell_face read from a file (linear, no sort), checking that it
// names the faces build_faces would: numbered in the order of their first half-face, each
// shared by at most two cells with the same corners in opposite orientations, and no
// unshared face repeating another face's corners. Throws Error naming the first problem.
void link_faces(TetMesh& m);

// Full consistency check (used by tests and after reading a file): orientation, faces,
// tree links. Throws Error naming the first problem.
void check_mesh(const TetMesh& m);

// Expensive geometric conformity check (tests, `refine --check`): no mesh vertex lies in
// a closed cell other than as one of its corners (so none in the interior of another
// cell's edge or face), every boundary face lies on the boundary of the level-0 domain,
// and the exact cell volumes add up to the level-0 domain volume. Throws Error.
void check_conforming(const TetMesh& m);

}  // namespace tetmvs::tet
