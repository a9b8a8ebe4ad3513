// One level of the photoconsist stage (Algorithm 1, paper section 2.3): the crossing
// faces of the cells made by red refinement at this level, the active cells, the best
// oriented point of each crossing face (the level's part of Q) and the face cache for
// the next level.
//
// Faces tested: every face of a cell with cell_new_red (all faces at level 0). For each,
// a triangular lattice (face_lattice.h) with n = reusable_divisions(lattice_divisions)
// divisions, so that neighbouring points are at most Options::lattice_px apart in every
// view that sees the face. A face that is a cached face of the previous mesh, or one of
// its quarters (face_parent / face_sub), and whose cached sub-lattice is dense enough,
// takes its codes from the cache; other faces score their points: points outside the
// visual hull (hull.h) are skipped (not samples), the others get photo::score_point
// (best of 14 orientations, 1 x line_mu line on the face) and are photo-consistent when
// the score exceeds T. Crossing faces: Options::rule on (consistent, samples). A crossing
// face makes both its cells active.
#pragma once
#include <cstdint>
#include <vector>

#include "common/photoconsist/face_cache.h"
#include "common/photoconsist/hull.h"
#include "common/photoconsist/occlusion.h"
#include "common/photoconsist/options.h"
#include "common/photoconsist/sight_lines.h"
#include "common/qpoints.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::photoconsist {

struct LevelResult {
  // Per tested face (ascending face id).
  std::vector<std::int32_t> face;
  std::vector<std::int32_t> divisions;
  std::vector<std::int32_t> samples;     // lattice points inside the hull
  std::vector<std::int32_t> consistent;  // photo-consistent ones
  std::vector<std::uint8_t> crossing;
  std::vector<std::uint8_t> reused;      // codes taken from the cache
  std::vector<float> best_score;         // best lattice score (kNoScore when none)

  std::vector<std::uint8_t> active;  // one per cell
  QPoints points;                    // best point of each crossing face (face = its id)
  FaceCache cache;                   // for the next level

  // Totals.
  std::int64_t lattice_points = 0;  // all lattice points of the tested faces
  std::int64_t sample_points = 0;   // inside the hull
  std::int64_t distinct_points = 0; // distinct points of the fresh lattices (shared points once)
  std::int64_t scored_points = 0;   // scored in this run (not taken from the cache)
  std::int64_t consistent_points = 0;
  std::int64_t crossing_faces = 0;
  std::int64_t reused_faces = 0;
  std::int64_t active_cells = 0;
  std::int64_t hidden_points = 0;    // scored points hidden in at least one view (occlusion)
  std::int64_t rescored_points = 0;  // cached points scored again (their hidden views changed)
  std::int64_t hull_dropped_points = 0;  // recheck_hull: cached samples now outside the hull
  std::int64_t hull_added_points = 0;    // recheck_hull: cached outside points now inside, scored
  std::int64_t sight_faces = 0;          // faces with enough consistent points turned down: in seen air (sight_lines.h)
};

struct LevelInput {
  const tet::TetMesh* mesh = nullptr;
  const photo::Views* views = nullptr;  // scoring views (the level's image-pyramid level)
  // Full-resolution views (occlusion maps); nullptr: the same as views.
  const photo::Views* full = nullptr;
  const HullTest* hull = nullptr;
  const FaceCache* prev = nullptr;  // cache of the previous level (compatible), or nullptr
  // Occluders (Q of the previous levels, occlusion.h), or nullptr: no occlusion test.
  // With them, a lattice point is scored without the views it is hidden in.
  const OcclusionMaps* occl = nullptr;
  // The occluders the cached codes of `prev` were scored with (Q of the levels before the
  // previous one), or nullptr (none: level 1). A reused code is scored again only where
  // the point's hidden views differ between occl_prev and occl.
  const OcclusionMaps* occl_prev = nullptr;
  // The hull differs from the one the cached codes were made with (photo.q_hull: estimated
  // from Q, which grows per level): reused codes are checked against `hull` point by point,
  // samples now outside become outside, outside points now inside are scored.
  bool recheck_hull = false;
  // Lines of sight of Q of the previous levels (sight_lines.h), or nullptr: crossing faces
  // in the air they cross are not crossing.
  const SightLines* sight = nullptr;
  bool keep_all = false;            // cache every tested face (inspection), not only faces of active cells
  // Orientation prior (photo.orientation_prior): the previous level's points of Q, or
  // nullptr. A lattice point with such points within prior_radius scores only their
  // orientations and those orientations' neighbours (orientation_and_neighbours), instead of
  // all 14.
  const QPoints* prior = nullptr;
  double prior_radius = 0;
  bool progress = true;
};

// The faces tested at this level: faces of cells with cell_new_red, ascending.
std::vector<std::int32_t> faces_of_new_cells(const tet::TetMesh& m);

LevelResult run_level(const LevelInput& in, const Options& opts);

// The best point of a face (index into its lattice codes, -1 when no point is
// consistent): among the photo-consistent points, the one whose lattice neighbourhood
// (the hexagon of `radius` steps around it) has the highest mean score. The score
// saturates near 1 across a band several pixels thick around the surface, so the single
// highest score is a nearly random point of the band; the neighbourhood mean peaks where
// the band is centred, on the surface. Ties: the lowest index.
std::int64_t best_point(const std::vector<std::uint16_t>& codes, int n, int radius = 3);

// Lines of sight (sight_lines.h): of the tested faces `face`, the crossing ones whose three
// vertices are free (SightLines::free, full-resolution views) are made not crossing.
// Returns how many.
std::int64_t drop_faces_in_sight(const tet::TetMesh& m, const SightLines& sight, const photo::Views& full,
                                 const std::vector<std::int32_t>& face, std::vector<std::uint8_t>& crossing);

// Lattice coordinates of face f's vertices (face_vertices order).
FaceLat face_lat(const tet::TetMesh& m, std::int32_t f);

}  // namespace tetmvs::photoconsist
