// The photoconsist stage's two modes around run_level (level_pass.h) and score_faces
// (face_scores.h): the previous levels' file, the level's image scale (level_scale.h), the
// hull (the silhouettes, or estimated from Q: q_hull.h), the occluders (occlusion.h) and the
// ground-truth measurements. Each returns everything its file holds (files.h writes it).
#pragma once
#include <filesystem>

#include "common/photo/views.h"
#include "common/photoconsist/face_cache.h"
#include "common/photoconsist/files.h"
#include "common/photoconsist/ground_truth.h"
#include "common/photoconsist/options.h"
#include "common/scene.h"
#include "common/tetmesh/tetmesh.h"
#include "common/trimesh/trimesh.h"

namespace tetmvs::photoconsist {

// pc_{i-1}.h5 as the next level and the scores mode read it.
struct Previous {
  std::filesystem::path file;  // empty: none
  LeveledPoints all;           // Q of the levels so far (/points_all)
  FaceCache cache;             // /cache
  bool reusable = false;       // the cache was made with the same options (Options::cache_signature)
};

// Reads `file` (a tetmvs.photoconsist file); throws Error when it was made on another level-0
// lattice than `mesh` (mesh_file names it in the message). warn_unused: warn when its face
// cache cannot be reused (other options).
Previous read_previous(const std::filesystem::path& file, const std::filesystem::path& mesh_file, int num_cameras,
                       const tet::TetMesh& mesh, const Options& opts, bool warn_unused);

// What both modes work on.
struct ModeInput {
  const Scene* scene = nullptr;
  const photo::Views* views = nullptr;  // full-resolution views of the scene
  const tet::TetMesh* mesh = nullptr;
  std::filesystem::path mesh_file;      // (for messages)
  const TriMesh* gt_mesh = nullptr;     // ground truth (--gt), or nullptr
  const GroundTruth* gt = nullptr;      // made of gt_mesh
  bool progress = true;
};

// Level mode: the crossing faces of the mesh's level (in.mesh->level == level), with the face
// cache of the previous level when it is reusable (Error when it is of another level than
// level - 1), and all of Q so far (prev's and this level's).
LevelOutput run_level_mode(const ModeInput& in, Previous prev, int level, bool keep_all, const Options& opts);

// Scores mode: omega of every face of the final mesh, and Q of the last level.
ScoresOutput run_scores_mode(const ModeInput& in, const Previous& prev, const Options& opts);

}  // namespace tetmvs::photoconsist
