// Clean-up of a cut's cell labelling before its surface is extracted:
//  - voids: connected regions of outside cells that do not reach the mesh boundary are
//    enclosed by the object, seen by no camera: they become inside (their inward-facing
//    surfaces would otherwise be separate, inverted shells that deform rejects). This is
//    the one place where a label is overridden: an exterior label inside an enclosed void
//    (free-space evidence from rays that crossed the cut's walls) cannot be honoured by a
//    closed surface seen from outside; such cells are counted (void_exterior_cells).
//  - specks: connected regions of inside cells whose volume is below `min_fraction` of the
//    largest region and which hold no interior-labelled cell become outside. Interior labels
//    marked `weak` (silhouette-fix's constraints, the hull-core prior's cells) do not
//    protect a speck: a constraint that pulled nothing but its own cell is a speck, not a
//    protrusion.
// Regions are face-connected. Apart from enclosed voids, labels are never contradicted.
#pragma once
#include <cstdint>
#include <vector>

#include "common/tetmesh/tetmesh.h"

namespace tetmvs::cut {

struct CleanupStats {
  std::int64_t voids_filled = 0, void_cells = 0;
  std::int64_t void_exterior_cells = 0;  // exterior-labelled cells inside filled voids
  std::int64_t specks_removed = 0, speck_cells = 0;
  std::int64_t inside_regions = 0;  // after the clean-up
};

CleanupStats clean_up_regions(const tet::TetMesh& m, const std::vector<std::int8_t>& labels,
                              std::vector<std::uint8_t>& inside, double min_fraction,
                              const std::vector<std::uint8_t>* weak = nullptr);

}  // namespace tetmvs::cut
