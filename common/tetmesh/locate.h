// Point location and ray/segment walks in the adaptive BCC mesh.
//
// Both are exact: points and segment ends are rounded to the fixed-point grid
// (lattice unit / 2^kFixedBits, about 1e-7 of the coarse spacing / 2^16) and every
// decision is an exact predicate with symbolic perturbation (predicates.h), so
//  - a point on a face, edge or vertex belongs to exactly one cell, the same cell that
//    a brute-force loop over all cells with cell_contains() finds;
//  - a segment through vertices or along edges or faces gets a consistent sequence of
//    face-adjacent cells (those of the infinitesimally perturbed segment).
// Points are located through the hierarchy: the level-0 tet by lattice arithmetic, then
// down the red tree (at most 8 children per level), then among a node's green cells.
//
// The mesh covers the cube grid minus a "ghost" pyramid over each boundary square
// (tetmesh.h). A walk that leaves the mesh through a boundary face crosses the ghost
// pyramid and re-enters the mesh where the segment does (or ends when it leaves the grid
// box); the cells before and after such a gap are reported in order, the gap itself is
// not (t_out of the cell before it < t_in of the cell after it).
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/tetmesh/tetmesh.h"

namespace tetmvs::tet {

// Exact: cell c contains the perturbed point P + e*v (strictly, after perturbation).
bool cell_contains(const TetMesh& m, std::int32_t c, const I3& P, const I3& v = kSoS1);

// Cell holding world point x; -1 when x is outside the mesh (outside the grid box or in a
// ghost pyramid).
std::int32_t locate(const TetMesh& m, const Eigen::Vector3d& x);
// Same on a fixed-point point with perturbation v; *ghost (optional) receives the ghost
// pyramid id when the point lies in one, else -1.
std::int32_t locate_fixed(const TetMesh& m, const I3& P, const I3& v = kSoS1, std::int32_t* ghost = nullptr);

struct WalkHit {
  std::int32_t cell;
  std::int32_t face_in;   // face the segment enters through (-1: it starts inside the cell)
  std::int32_t face_out;  // face it leaves through (-1: it ends inside the cell)
  double t_in, t_out;     // parameters along a -> b (0 at a, 1 at b), t_in <= t_out
};

// The cells the segment a -> b crosses, in order from a. Reuses `out` (cleared first).
void walk_segment(const TetMesh& m, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                  std::vector<WalkHit>& out);
// The ray from `origin` along `dir` up to where it leaves the grid box; t is in units of
// |dir| (the point origin + t * dir). With t_stop, the walk ends at the first cell entered
// beyond it: the cells reported are the first ones of the full walk's, up to that parameter.
// start (optional, in and out): a cell to try first for the origin (rays that start near one
// another pass the previous ray's); on return the cell the walk started in (-1: outside).
void walk_ray(const TetMesh& m, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
              std::vector<WalkHit>& out, double t_stop = std::numeric_limits<double>::infinity(),
              std::int32_t* start = nullptr);

}  // namespace tetmvs::tet
