// The cut stage's computation (paper section 3.1): the minimum cut of the mesh's dual graph
// (graph_cut.h), the clean-up of its regions (cleanup.h), the cut surface (surface.h) and
// its check; everything cut<N>.h5 and cut<N>.ply hold.
#pragma once
#include <cstdint>
#include <vector>

#include "common/cut/cleanup.h"
#include "common/cut/graph_cut.h"
#include "common/cut/inputs.h"
#include "common/cut/surface.h"
#include "common/trimesh/check.h"
#include "common/trimesh/trimesh.h"

namespace tetmvs::cut {

struct Cut {
  CutResult flow;                      // the minimum cut; flow.inside after the clean-up
  CleanupStats cleanup;
  SurfaceStats surface_stats;
  std::vector<std::int32_t> face_ids;  // per surface triangle, the mesh face it lies in
  TriMesh surface;                     // outward, edge-manifold
  MeshCheck check;                     // of the surface
};

// omega: scores.h5's /faces/omega; labels: read_label_input (its evidence, when present, is
// the visibility term's, opt.beta > 0); min_region_fraction: cut.min_region_fraction.
// Throws Error (naming the labels file) when no interior cell survives.
Cut cut_mesh(const tet::TetMesh& mesh, const std::vector<float>& omega, const LabelInput& labels, CutOptions opt,
             double min_region_fraction);

}  // namespace tetmvs::cut
