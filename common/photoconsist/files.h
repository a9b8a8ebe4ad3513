// Files of the photoconsist stage: pc_<i>.h5 (schema "tetmvs.photoconsist",
// schemas/photoconsist.md) and scores.h5 (schema "tetmvs.scores", schemas/scores.md): what
// each holds (LevelOutput, ScoresOutput, made by modes.h) and the one table of its datasets
// and attributes, which also makes the stage's summary line (common/h5fields.h).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/h5fields.h"
#include "common/photoconsist/face_cache.h"
#include "common/photoconsist/face_scores.h"
#include "common/photoconsist/ground_truth.h"
#include "common/photoconsist/level_pass.h"
#include "common/qpoints.h"

namespace tetmvs {

namespace photoconsist {

inline constexpr const char* kLevelSchema = "tetmvs.photoconsist";
inline constexpr int kLevelVersion = 2;
inline constexpr const char* kScoresSchema = "tetmvs.scores";
inline constexpr int kScoresVersion = 1;

// Q with the level each point was found at.
struct LeveledPoints {
  QPoints q;
  std::vector<std::int32_t> level;  // one per point
  void append(const QPoints& more, int lvl, bool keep_face);
  QPoints of_level(int lvl) const;  // the points of one level (faces -1)
  int last_level() const;           // the highest level of a point (-1 when there is none)
};

// qpoints_fields() plus level (paths relative to the group).
const h5::Fields<LeveledPoints>& leveled_points_fields();
// Writes them to `group`.
void write_leveled_points(h5::File& f, const LeveledPoints& p, const std::string& group);
LeveledPoints read_leveled_points(const h5::File& f, int num_cameras, const std::string& group);

// The ground-truth measurements of a level (--gt).
struct LevelEvalOutput {
  LevelEval eval;
  double cell_size = 0;  // red edge length of the level
};

// Everything pc_<i>.h5 holds (the level mode).
struct LevelOutput {
  int level = 0;
  int pyramid = 0;        // the image-pyramid level the lattice points were scored on
  double cell_px = 0;     // level_cell_px
  LevelResult pass;       // run_level's result (its cache's pyramid set)
  LeveledPoints all;      // Q over levels 0..level
  std::int64_t num_cells = 0;  // of the mesh
  bool occlusion = false;      // occluders were used (photo.occlusion, and Q of earlier levels)
  std::int64_t occluders = 0, occluders_dropped = 0;
  std::int64_t q_hull_views = 0;              // views with a silhouette estimated from Q
  std::optional<double> q_hull_gt_inside;     // --gt and q_hull_views > 0
  std::optional<LevelEvalOutput> eval;        // --gt
};

// Everything scores.h5 holds (the scores mode).
struct ScoresOutput {
  int level = 0;                       // of the mesh scored
  std::int64_t num_faces = 0;
  ScoresResult scores;                 // omega and its counts
  std::vector<std::uint8_t> scored;    // per face, 1 when scored (faces_to_score)
  LeveledPoints q;                     // Q of the last level
  bool occlusion = false;
  std::int64_t occluders = 0, occluders_dropped = 0;
  std::optional<double> q_within_cell;  // --gt: share of Q within a finest cell of the GT surface
  std::int64_t q_hull_views = 0;
  std::optional<double> q_hull_gt_inside;
};

// pc_<i>.h5's rows; the summary: "level=... pyramid=... faces_tested=... ... Q=..." and the
// optional parts (occluders, the estimated hull, the ground-truth measurements).
const h5::Fields<LevelOutput>& level_fields();
// scores.h5's rows; the summary: "faces=... scored=... outside_hull=... defined_orientations=... points=...".
const h5::Fields<ScoresOutput>& scores_fields();

}  // namespace photoconsist
}  // namespace tetmvs
