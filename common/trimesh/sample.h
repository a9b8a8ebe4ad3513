// Area-weighted random sampling of a triangle mesh surface: every sample stands for the
// same area, so statistics over samples are area-weighted. Deterministic for a seed,
// whatever the thread count.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "common/trimesh/trimesh.h"

namespace tetmvs {

struct SurfaceSamples {
  std::vector<Eigen::Vector3d> P;  // positions
  std::vector<Eigen::Vector3d> N;  // unit face normals
  std::vector<int> face;           // source triangle
  std::size_t size() const { return P.size(); }
};

// About area / spacing^2 samples: face f gets floor(area_f / spacing^2 + r_f) samples with
// r_f uniform in [0,1) (so the expected count is exact per face), placed uniformly.
// Degenerate faces get none.
SurfaceSamples sample_surface(const TriMesh& m, double spacing, std::uint64_t seed = 1);

}  // namespace tetmvs
