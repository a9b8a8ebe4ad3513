// Red-green refinement of the adaptive BCC mesh (Molino, Bridson, Teran, Fedkiw 2003;
// Sinha, Mordohai, Pollefeys 2007, Sec. 2.2).
//
// RED (1:8): the six edges of a BCC tet are bisected; the four corner tets are the
// parent scaled by 1/2 about each vertex, and the inner octahedron is split along its
// shortest diagonal into four tets. The eight children are BCC tets again, half the size
// (children 0..3 are the corners at v0..v3, 4..7 the octahedron tets).
//
// GREEN: a red-tree leaf some of whose edges are bisected (their midpoints exist as
// vertices because a neighbour was red-refined) is split without new vertices when the
// split edges form one of the patterns
//   1:2  one edge                       -> 2 cells
//   1:3  two edges sharing a vertex      -> 3 cells (their face: corner triangle + a quad
//        cut along its shorter diagonal, ties broken by vertex ids, so both cells of the
//        face agree)
//   1:4  two opposite edges              -> 4 cells
//   1:4  the three edges of one face     -> 4 cells (that face split into its 4 quarters)
// and red-refined otherwise.
//
// Why 1:3: with only the 1:2 and 1:4 patterns (Molino et al.; the first rule) the
// red closure does not stay local on the BCC lattice. Two active cells sharing one vertex
// already make a neighbour with two adjacent split edges red, and the red front then
// sweeps the whole mesh (measured: two such cells of an 8^3-cube grid red-refine all 5.3k
// cells in 35 passes; 17 random active cells of a 6^3 grid -> all cells). Allowing the
// adjacent pair as green (as Bey's red-green closure does) stops it: in the same tests the
// closure adds ~2 red cells per active cell and converges in <= 5 passes (see
// test_tetmesh.cpp, ClosureStaysLocal). It is also red-refined when any edge of its would-be green
// cells is itself bisected (an edge may be split once only: balance). This closure is
// iterated to a fixed point. Green cells are never refined: an active green cell makes its
// red node red-refine (its green cells are dropped and the closure rebuilt).
#pragma once
#include <cstdint>
#include <vector>

#include "common/tetmesh/edge_map.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::tet {

struct RefineStats {
  int rounds = 0;                 // closure passes until the fixed point
  std::int64_t red_active = 0;    // nodes red-refined because a cell of theirs was active
  std::int64_t red_closure = 0;   // nodes red-refined by the closure (pattern or balance)
  std::int64_t green_nodes = 0;   // red-tree leaves split green in the result
  std::int64_t green_cells = 0;
  // closure refinements by reason: an edge split twice, not a green pattern, an edge of a
  // would-be green cell split
  std::int64_t red_reason[3] = {0, 0, 0};
};

// One refinement step: `active` has one flag per cell of `old`; returns the mesh of level
// old.level + 1 with faces, face_parent/face_sub and cell_new_red filled.
TetMesh refine(const TetMesh& old, const std::vector<std::uint8_t>& active,
               RefineStats* stats = nullptr);

// Convenience: red-refines every cell `times` times (a uniform BCC mesh).
TetMesh refine_uniform(const TetMesh& m, int times);

// The edge -> midpoint map of a mesh, rebuilt from vparent.
EdgeMap edge_midpoints(const TetMesh& m);

// Green pattern of a red-tree leaf given the midpoints (-1 = not split) of its six local
// edges (kEdge order): writes its cells (positively oriented) into out and returns their
// count (1 for no split edge), or 0 when the pattern is not a green pattern.
int green_split(const Tet& v, const std::int32_t mid[6], const std::vector<std::int32_t>& vlat,
                Tet out[4]);

}  // namespace tetmvs::tet
