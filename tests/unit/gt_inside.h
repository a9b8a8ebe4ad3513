// Ground truth for the tests: whether a point is inside a closed triangle mesh, by the
// parity of a ray's crossings, majority of three fixed directions (robust to a ray that
// grazes an edge). tests/e2e/gt_inside.py is the one-ray Python counterpart.
#pragma once
#include <Eigen/Core>

#include "common/trimesh/bvh.h"

namespace tetmvs::test {

inline bool inside_mesh(const MeshBVH& bvh, const Eigen::Vector3d& p) {
  static const Eigen::Vector3d dirs[3] = {Eigen::Vector3d(0.5773, 0.3111, 0.7549).normalized(),
                                          Eigen::Vector3d(-0.2718, 0.8813, -0.3871).normalized(),
                                          Eigen::Vector3d(0.6931, -0.5209, -0.4983).normalized()};
  int votes = 0;
  for (const auto& d : dirs) {
    int n = 0;
    double t = 0;
    for (;;) {
      const RayHit h = bvh.raycast(p, d, t);
      if (h.face < 0) break;
      ++n;
      t = h.t + 1e-9;
    }
    votes += n % 2;
  }
  return votes >= 2;
}

}  // namespace tetmvs::test
