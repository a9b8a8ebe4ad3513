// How big the mesh cells look in the images: the stopping rule of the refinement
// (paper: stop when the finest cells project to about 1-5 pixels).
#pragma once
#include <Eigen/Geometry>
#include <vector>

#include "common/camera.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::tet {

// Largest projected size, in pixels, of the finest cells of the mesh: for every cell of
// the deepest level and every camera that sees its centroid, (longest red edge of that
// level) * focal / depth. 0 when no camera sees any of them.
double max_projected_cell_size(const TetMesh& m, const std::vector<Camera>& cams);

// Number of refinement levels L such that a level-L cell (edge h / 2^L) at the depth of
// the box centre projects to at most `target_px` pixels in every camera that has the box
// centre in front of it: the smallest L >= 0 with max_cam(h 2^-L f / depth) <= target_px.
// (The box centre stands for the surface; cells nearer a camera look larger, farther ones
// smaller.) Throws when no camera has the box centre in front of it.
int levels_for_pixels(const Lattice& lat, const Eigen::AlignedBox3d& box, const std::vector<Camera>& cams,
                      double target_px);

}  // namespace tetmvs::tet
