// Remeshing of deform (paper section 3.3): 2-D red-green subdivision of long edges,
// collapse of short edges and of the shortest edge of needle triangles, and
// Delaunay edge flips. Every operation keeps a closed edge-manifold mesh closed and
// edge-manifold, keeps the orientation and never changes the topology (collapses check
// the link condition). Edge lengths are measured in pixels: length / footprint, with
// fp[v] the pixel footprint (world units per pixel) at vertex v in its finest view.
// Deterministic (sequential, in edge order).
#pragma once
#include <Eigen/Dense>
#include <cstdint>
#include <utility>
#include <vector>

namespace tetmvs::deform {

struct RemeshMesh {
  std::vector<Eigen::Vector3d> V;
  std::vector<Eigen::Vector3i> F;
  std::vector<double> fp;  // per-vertex pixel footprint (world units per pixel), > 0
  // Per face, when tracked (not empty): the face it was when the tracking began, or -1 when
  // an operation made it or moved a corner. Every operation below keeps it.
  std::vector<int> origin;
  // Per vertex, when not empty: the photometric step it took in the last iteration (world
  // units along its normal; deform's momentum). A split's new vertex and a collapse's merged
  // one take the mean of the two ends.
  std::vector<double> last_step;
};

// Length of edge (a, b) in pixels.
double edge_px(const RemeshMesh& m, int a, int b);

// Red-green split: edges longer than max_px are split at their midpoints; a face with one
// split edge becomes 2 triangles (midpoint to the opposite corner), with two 3 (the corner
// between them cut off, the rest split by the shorter diagonal), with three 4. Only long
// edges are split (no red closure: it spread 1:4 splits over edges of 1-2 px and doubled
// the mesh on dinoRing). New vertices: footprint = mean of the ends. Returns the number of
// edges split.
std::int64_t split_long_edges(RemeshMesh& m, double max_px);

// Collapses edges shorter than min_px, and the shortest edge of triangles whose
// shortest / longest edge ratio is below needle_ratio, into their midpoint, shortest
// first, when the link condition holds (the ends share exactly the two opposite
// vertices, both of degree > 3), no surrounding triangle turns by more than 60 degrees
// or becomes degenerate, and no new edge exceeds max_px. Unused vertices are removed.
// Returns the number of collapses.
std::int64_t collapse_short_edges(RemeshMesh& m, double min_px, double needle_ratio, double max_px);

// Drops faces with a repeated vertex and vertices no face uses (order kept).
void compact(RemeshMesh& m);

// What collapse_folds did to the faces (empty maps when it collapsed nothing): the new
// index of each old face (-1: removed), and per new face whether a corner was merged.
struct FoldCollapses {
  std::int64_t count = 0;
  std::vector<int> face_to_new;
  std::vector<char> changed;
};

// Removes fold-overs: for each listed pair of intersecting faces (indices into m.F), the
// shortest edge at a corner of the two faces whose collapse keeps the mesh closed and
// manifold (link condition, degrees > 3, no degenerate triangle) is collapsed, the merged
// vertex placed at either end or the midpoint, where the surrounding triangles turn least
// from the fan's mean normal; one collapse per pair and none in the 1-ring of another. No
// turn limit (the fold is the turn). deform uses it on the sub-pixel fold-overs within one
// vertex's fan that smoothing does not unfold. Returns what it did.
FoldCollapses collapse_folds(RemeshMesh& m, const std::vector<std::pair<int, int>>& pairs);

// Flips edges whose two opposite angles sum to more than pi (Delaunay criterion), when
// the two triangles are within max_dihedral_deg of coplanar, the new edge does not exist
// yet and the ends keep degree >= 4. Returns the number of flips.
std::int64_t flip_edges(RemeshMesh& m, double max_dihedral_deg);

}  // namespace tetmvs::deform
