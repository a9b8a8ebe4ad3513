// The face scores of the cut (paper section 3.1, Eq. 1): omega of every face of the
// final mesh for each of its two orientations (photo/face_score.h, the mu x mu patch at
// the centroid seen by the best k cameras within the cone of that normal).
//
// Which faces are scored: the faces of the cells "near the surface band", i.e. the cells
// made by red refinement in the last step (the finest cells, cell_new_red) and their
// face neighbours; every other face gets omega = 0 (far from the active region the cut
// only needs the area term; omega = 0 costs about (1 + lambda) a_f there). A scored face
// whose centroid is outside the visual hull also gets omega = 0: no surface lies there.
#pragma once
#include <cstdint>
#include <vector>

#include "common/photoconsist/hull.h"
#include "common/photoconsist/occlusion.h"
#include "common/photo/options.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::photoconsist {

// One flag per face: 1 when the face is scored (see top).
std::vector<std::uint8_t> faces_to_score(const tet::TetMesh& m);

struct ScoresResult {
  std::vector<float> omega;  // F x 2: [2f] normal from face_cell(f,0) to face_cell(f,1), [2f+1] reversed
  std::int64_t scored_faces = 0;   // selected faces
  std::int64_t outside_hull = 0;   // of those, skipped because the centroid is outside the hull
  std::int64_t defined = 0;        // oriented faces with a defined score (enough views)
  std::int64_t hidden = 0;         // scored faces whose centroid is hidden in some view (occlusion)
};

// omega for the selected faces (OpenMP over faces; independent of the thread count).
// With occl, a face is scored without the views its centroid is hidden in (occlusion.h).
ScoresResult score_faces(const tet::TetMesh& m, const photo::Views& views, const HullTest& hull,
                         const photo::Options& opts, const std::vector<std::uint8_t>& selected,
                         bool progress = true, const OcclusionMaps* occl = nullptr);

}  // namespace tetmvs::photoconsist
