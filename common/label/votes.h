// Visibility votes (paper 2.4): every point of Q casts a ray to each camera it is
// photo-consistent in, starting `offset` (world units) in front of the point; every cell the
// ray crosses gets a vote.
#pragma once
#include <cstdint>
#include <vector>

#include "common/label/geometry.h"
#include "common/qpoints.h"
#include "common/scene.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::label {

// Votes per cell. counted (optional, one flag per cell): only these
// cells' votes are needed; a ray then stops where no such cell lies further along it (a
// voxel map of their bounding boxes decides, conservatively), so the cells beyond get fewer
// votes than the full walk gives, and the counted cells exactly as many.
std::vector<std::int32_t> visibility_votes(const tet::TetMesh& m, const Scene& s, const QPoints& q, double offset,
                                           std::int64_t* rays = nullptr,
                                           const std::vector<std::uint8_t>* counted = nullptr,
                                           const MeshPoints* pts = nullptr);

// The value at `pct` percent of v (nearest rank; 0 for an empty v).
double percentile(std::vector<std::int32_t> v, double pct);

}  // namespace tetmvs::label
