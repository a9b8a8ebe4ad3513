// deform (paper section 3.3, brief step 7): the cut surface S2 (closed, outward,
// edge-manifold, faceted at the tetrahedral cells' resolution) refined into the final
// mesh H by moving its vertices under three forces (forces.h: non-shrinking smoothness and
// silhouettes; photometric.h: the Gauss-Newton step of a multi-view image similarity along
// the normal, coarse to fine over an image pyramid), remeshing as it goes (remesh.h: red-green
// splits of edges longer than max_edge_px in their finest view, collapses, flips), and
// never creating self-intersections (intersect.h: the vertices of a new intersection get
// their step halved, then reverted). Output: the mesh with vertex normals and colours
// sampled from each vertex's best visible view; statistics per iteration (schema
// tetmvs.deform, schemas/deform.md).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/deform/forces.h"
#include "common/deform/options.h"
#include "common/scene.h"
#include "common/trimesh/trimesh.h"

namespace tetmvs::deform {

// Parts of an iteration whose wall time is measured (IterationStats::part_seconds).
enum IterationPart {
  kPartFootprints,
  kPartTopology,
  kPartRaster,
  kPartSmoothSil,  // with the visibility tests of the rim candidates
  kPartPhoto,
  kPartMove,  // move + intersection checks and retries
  kPartRemesh,
  kPartRemeshCheck,
  kPartUntangle,
  kNumParts
};
inline constexpr const char* kPartNames[kNumParts] = {"footprints", "topology",   "raster", "smooth+sil",  "photo",
                                                      "move+isect", "remesh", "remesh-isect", "untangle"};

struct IterationStats {
  int iteration = 0;
  std::int64_t vertices = 0, faces = 0;  // after this iteration's remeshing
  double mean_move = 0;       // mean |applied displacement| over vertices (world units)
  double mean_move_px = 0;    // ... in pixels of each vertex's finest view
  double max_move_px = 0;
  int photo_level = -1;             // image-pyramid level of the photometric force (-1: none this iteration)
  double mean_ncc = -1;            // mean NCC of the photometric windows (-1: none)
  std::int64_t photo_pixels = 0;   // pixel pairs behind the photometric force
  double photo_moved = 0;          // fraction of vertices with a photometric step
  double mean_photo_step_px = 0;   // mean |photometric step| of those vertices (full-resolution pixels)
  std::int64_t rim_vertices = 0;   // vertices on a silhouette rim in at least one view
  std::int64_t spread_vertices = 0;  // vertices moved by the silhouette's reach around the rim (deform.sil_spread_px)
  double silhouette_iou = -1;      // mean IoU of the mesh's silhouettes before the move (-1: no silhouettes)
  std::int64_t splits = 0, collapses = 0, flips = 0;
  std::int64_t reduced_vertices = 0;  // vertices whose step was reduced to avoid intersections
  std::int64_t intersections = 0;     // intersecting triangle pairs after the iteration
  double seconds = 0;
  std::array<double, kNumParts> part_seconds{};      // wall seconds per IterationPart (logged, not in the stats file)
  std::array<double, kNumParts> part_cpu_seconds{};  // process CPU seconds (all threads) per IterationPart
};

struct Result {
  TriMesh mesh;  // V, F, N (unit), C (RGB)
  std::vector<IterationStats> iterations;
  std::int64_t start_intersections = 0, final_intersections = 0;
  double start_iou = -1, final_iou = -1;  // mean silhouette IoU (-1: no silhouettes)
  double footprint = 0;                   // median vertex pixel footprint of the final mesh (world units)
};

// scene: cameras, rgb and grey (load_grey() done), silhouettes optional per view.
// start: closed, edge-manifold, outward-oriented (Error otherwise).
Result deform_mesh(const TriMesh& start, const Scene& scene, const Options& opt);

// Per-vertex colours of m from each vertex's best view: the largest cos(normal, direction
// to the camera) among the views in which it is visible; grey where none sees it.
// m.N must be set. rasters: m's rasters of every view (rasterize_view) when at hand.
void sample_vertex_colours(TriMesh& m, const Scene& scene, double visibility_tol_px,
                           const std::vector<ViewRaster>* rasters = nullptr);

inline constexpr const char* kDeformSchema = "tetmvs.deform";
inline constexpr int kDeformVersion = 2;

}  // namespace tetmvs::deform
