// The BCC mesh of the cube [-1, 1]^3 that the cut tests (test_cut, test_cut_surface) use.
#pragma once
#include <Eigen/Geometry>

#include "common/tetmesh/refine.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::test {

// `cells` lattice cells along the cube's side, then `refinements` uniform red refinements.
inline tet::TetMesh cube_mesh(int cells, int refinements) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1));
  tet::TetMesh m = tet::build_bcc(tet::lattice_for_box(box, cells));
  if (refinements) m = tet::refine_uniform(m, refinements);
  return m;
}

}  // namespace tetmvs::test
