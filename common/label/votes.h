// Visibility votes (paper 2.4): every point of Q casts a ray to each camera it is
// photo-consistent in, starting `offset` (world units) in front of the point and ending where
// it leaves the grid box; every cell the ray crosses gets a vote.
#pragma once
#include <cstdint>
#include <vector>

#include "common/label/geometry.h"
#include "common/qpoints.h"
#include "common/scene.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::label {

// Votes per cell: the number of rays crossing it, as the exact walk of common/tetmesh/locate.h
// finds them. counted (optional, one flag per cell): only these cells' votes are computed
// (the others get 0). Each view's rays pass through its camera centre, so each projects to
// one point: every cell is tested against the rays whose point its projection holds (and
// that start no nearer to the camera than its nearest vertex), exactly up to a tolerance
// of 1e-6 of the level-0 edge (16 units of the walk's fixed-point grid); the few rays
// within it, and every ray of a view with its camera inside the grid or behind a counted
// cell, are walked.
std::vector<std::int32_t> visibility_votes(const tet::TetMesh& m, const Scene& s, const QPoints& q, double offset,
                                           std::int64_t* rays = nullptr,
                                           const std::vector<std::uint8_t>* counted = nullptr,
                                           const MeshPoints* pts = nullptr);

// The value at `pct` percent of v (nearest rank; 0 for an empty v).
double percentile(std::vector<std::int32_t> v, double pct);

}  // namespace tetmvs::label
