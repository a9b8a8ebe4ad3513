// Command-line pieces shared by the bcc-init and refine stages (inspection outputs).
#pragma once
#include <string>

#include "common/stage.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::tet {

struct InspectOptions {
  std::string vtu, slice_png, slice_axis = "z";
  double slice_at = 0.5;  // fraction of the grid box along the slice axis
  int slice_width = 1024;
  void add_to(StageCli& cli);
  // Writes the requested .vtu and slice picture (cells coloured by level).
  void write(const TetMesh& m) const;
};

}  // namespace tetmvs::tet
