// Hard labels for the cut (paper sections 2.1 and 2.4): which cells are surely outside
// (exterior, tied to the sink) and which surely inside (interior, tied to the source); the
// rest are free and the cut decides, helped by the soft evidence label writes for them.
//
// label_cells() follows the paper's steps, with a few named extensions:
//  1. Q filters: points of Q that cannot be on the surface are dropped before anything uses
//     Q (q_filters.h): inside the hull core (with the prior), outside the silhouettes
//     estimated from Q and in front of Q's median depth (scenes without silhouettes), and in
//     the free space other points of Q show.
//  2. Geometry (paper): cells touching the box boundary, and outside the visual hull, are
//     exterior (the silhouettes estimated from Q in scenes without any).
//  3. Votes (paper): every point of Q casts a ray to each camera it is consistent in
//     (votes.h); and for every free cell, what each view sees of it against Q's depth maps
//     (evidence.h): free space in front of Q, hidden behind Q, beyond Q's far side; behind
//     Q, the rays that cross a cell count as views seeing through it (lines of sight).
//  4. Rules (rules.h, with the one precedence table): the paper's voted_out (many votes) and
//     hidden (few votes, hidden behind Q), the latter only in a shell under Q's visible side;
//     the extensions hull_core, seen_free and seed_core.
// docs/architecture.md ("Labels") gives the reasons and the measurements.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "common/label/q_filters.h"
#include "common/label/rules.h"
#include "common/param_binding.h"
#include "common/q_silhouettes.h"
#include "common/qpoints.h"
#include "common/scene.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs {
class Params;
}

namespace tetmvs::label {

struct Options {
  double low_percentile = 10;   // paper: 10th; hidden cells need at most this percentile of votes
  double high_percentile = 75;  // paper: 75th; voted-out cells need more than this percentile
  // Evidence from views needs this many of them: hidden behind Q (interior), free space
  // (exterior by votes, and a point of Q in it is dropped), in front of Q's median (scenes
  // without silhouettes); and exterior by votes needs at least this many votes.
  int min_views = 3;
  // Margin of the free-space and occlusion tests against Q's depth; rays start half of it in
  // front of their point. Like every *_px depth here, in pixels at the object (pixel_size()).
  double depth_margin_px = 7;
  // Soft outside evidence (the cut's visibility term): a view that sees through the cell (or
  // beyond Q's far side) weighs this many views that hide it.
  double free_weight = 2;
  // hidden: the cell at most this deep (pixels at its depth) behind Q's visible side in
  // min_views of the views hiding it (<= 0: no limit): a shell under the seen surface thinner
  // than the walls of the cavities it must not claim.
  double interior_depth_px = 28;
  // hull_core (0 = off): cells whose whole projection lies this many pixels inside every
  // silhouette are interior; points of Q there are dropped and the hidden rule is off.
  double hull_core_px = 0;
  // seed_core (0 = off): when no other rule gives an interior cell, the hull core at this margin.
  double seed_core_px = 1.5;
  // seen_free (0 = off): free space in this many views, hidden in no view within
  // seen_free_wall_px behind Q's visible side, behind a wall in half of the views hiding it, ...
  int seen_free_views = 1;
  double seen_free_wall_px = 45;
  int seen_free_min_cells = 2;        // ... in a face-connected group of this many (not a parameter)
  // seen_free and voted_out: this deep inside every silhouette (pixels; 0 = no test): under a
  // surface that a silhouette bounds, Q's band lies inside the matter, which then looks free.
  double hull_depth_px = 28;
  double interior_min_share = 0.01;   // hidden: in a group of this share of the largest (0 = no test)
  QSilhouetteOptions q_sil;           // silhouettes estimated from Q (scenes without any)
  // Throws Error on a bad value: the documented ranges (q_sil's too), low_percentile <
  // high_percentile, seen_free_min_cells >= 0.
  void check() const;
  static Options from_params(const Params& p);  // reads label.* (and photo.q_hull*), then check()s

  static constexpr auto params() {  // the fields that hold parameters (common/param_binding.h)
    return std::to_array<ParamField<Options>>({
        {"label.low_percentile", &Options::low_percentile},
        {"label.high_percentile", &Options::high_percentile},
        {"label.min_views", &Options::min_views},
        {"label.depth_margin_px", &Options::depth_margin_px},
        {"label.free_weight", &Options::free_weight},
        {"label.interior_depth_px", &Options::interior_depth_px},
        {"label.hull_core_px", &Options::hull_core_px},
        {"label.seed_core_px", &Options::seed_core_px},
        {"label.seen_free_views", &Options::seen_free_views},
        {"label.seen_free_wall_px", &Options::seen_free_wall_px},
        {"label.hull_depth_px", &Options::hull_depth_px},
        {"label.interior_min_share", &Options::interior_min_share},
    });
  }
};

struct Result {
  std::vector<std::int8_t> label;    // per cell: 1 interior, -1 exterior, 0 free
  std::vector<std::uint8_t> reason;  // Reason (common/reason.h)
  std::vector<std::int32_t> votes;   // visibility votes (counted where they can decide a label)
  // Soft evidence per free cell, in [0, 1], for the cut's visibility term: outside =
  // min(1, free_weight x views where the cell is free space or beyond Q's far side (behind Q:
  // or the rays of Q crossing it, if more) / views where it projects); inside = (1 - outside)
  // x the share of those views in which it lies between Q's visible and far sides.
  std::vector<float> inside_evidence, outside_evidence;
  // Per free cell, the number of views in which its centre is free space (in front of the
  // visible side of Q by the margin), beyond Q's far side, between the two (hidden), and the
  // views where it projects into the image at all.
  std::vector<std::uint8_t> free_views, beyond_views, hidden_views, seen_views;
  // Per free cell, the depth (pixels at its depth) of its centre behind Q's visible side, the
  // smallest reached in min_views of the views hiding it (-1: fewer views hide it).
  std::vector<float> hidden_depth;
  // Lines of sight (evidence.h, add_sight_lines): per cell, the rays of Q crossing it where
  // it lies behind Q (0 elsewhere); the cells they reach, the rays cast, and the views
  // dropped from points of Q hidden in them.
  std::vector<std::int32_t> sight_rays;
  std::int64_t sight_cells = 0, sight_cast = 0, unseen_views = 0;
  double low_votes = 0, high_votes = 0;           // the percentile values
  std::array<std::int64_t, kNumRules> cells{};    // cells each rule labels (rules.h)
  std::array<std::int64_t, kNumFilters> dropped{};  // points of Q each filter drops (q_filters.h)
  std::int64_t interior = 0, exterior = 0, rays = 0;
  std::int64_t q_sil_views = 0;  // views given a silhouette estimated from Q
  // cells a rule's own test turned down (left to the rules below it, or free)
  std::int64_t too_deep = 0;             // hidden, but deeper than interior_depth_px
  std::int64_t interior_islands = 0;     // hidden, in a group smaller than interior_min_share
  std::int64_t voted_out_near_hull = 0;  // voted out, less than hull_depth_px inside the hull
  std::int64_t seen_free_islands = 0;    // seen free, in a group smaller than seen_free_min_cells
  std::int64_t count(Rule r) const { return cells[static_cast<int>(r)]; }
  std::int64_t count(Filter f) const { return dropped[static_cast<int>(f)]; }
};

Result label_cells(const tet::TetMesh& m, const Scene& s, const QPoints& q, const Options& o);

// Per cell: the number of cells of its face-connected group of `in` cells (0 for the others).
std::vector<std::int32_t> group_sizes(const tet::TetMesh& m, const std::vector<std::uint8_t>& in);

// Per cell: 1 when the cell is one of the `in` cells and its face-connected group of `in`
// cells holds fewer than `share` x the cells of the largest such group.
std::vector<std::uint8_t> small_groups(const tet::TetMesh& m, const std::vector<std::uint8_t>& in, double share);

}  // namespace tetmvs::label
