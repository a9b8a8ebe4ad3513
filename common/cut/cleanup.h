// Clean-up of a cut's cell labelling before its surface is extracted:
//  - voids: connected regions of outside cells that do not reach the mesh boundary and hold
//    no exterior-labelled cell are enclosed by the object, seen by no camera: they become
//    inside (their inward-facing surfaces would otherwise be separate, inverted shells);
//  - specks: connected regions of inside cells whose volume is below `min_fraction` of the
//    largest region and which hold no interior-labelled cell become outside. Interior labels
//    marked `weak` (silhouette-fix's constraints) do not protect a speck: a constraint
//    that pulled nothing but its own cell is a speck, not a protrusion.
// Regions are face-connected. Other labels are never contradicted.
#pragma once
#include <cstdint>
#include <vector>

#include "common/tetmesh/tetmesh.h"

namespace tetmvs::cut {

struct CleanupStats {
  std::int64_t voids_filled = 0, void_cells = 0;
  std::int64_t specks_removed = 0, speck_cells = 0;
  std::int64_t inside_regions = 0;  // after the clean-up
};

CleanupStats clean_up_regions(const tet::TetMesh& m, const std::vector<std::int8_t>& labels,
                              std::vector<std::uint8_t>& inside, double min_fraction,
                              const std::vector<std::uint8_t>* weak = nullptr);

}  // namespace tetmvs::cut
