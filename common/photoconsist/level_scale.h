// The image scale of a refinement level (docs/photoconsist.md, "Level mode", step 2): level
// i's lattice points are scored on the image-pyramid level (photo::Views::reduced) at which
// the level's cells project to about photo.level_cell_px pixels, so every level sees its
// cells at the same size in pixels: coarse levels look at blurred, less noisy images with
// few lattice points per face; a level whose cells are about that size already is scored
// on the full photos.
#pragma once
#include "common/photo/views.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::photoconsist {

// Largest projection, in full-resolution pixels, of a red edge of `level` placed at the
// centre of the mesh's grid box, over the views the centre is in front of (0 when none).
double level_cell_px(const photo::Views& full, const tet::Lattice& lat, int level);

// The pyramid level p >= 0 that brings cell_px_full (level_cell_px) closest to target_px
// on a log scale: round(log2(cell_px_full / target_px)), at least 0, and at most the
// deepest level the images allow (their smaller side at least 16 pixels). 0 when
// target_px is 0 (full resolution always).
int pyramid_level(double cell_px_full, double target_px, int width, int height);

// The views a level is scored on: `full` reduced to the pyramid level of mesh m's level for
// photo.level_cell_px = target_px (its index in *pyramid when given).
photo::Views level_views(const photo::Views& full, const tet::TetMesh& m, double target_px, int* pyramid = nullptr);

}  // namespace tetmvs::photoconsist
