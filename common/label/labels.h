// Hard labels for the cut (paper sections 2.1 and 2.4): which cells are surely outside
// (exterior, tied to the sink) and which surely inside (interior, tied to the source).
//
//  exterior  cells touching the mesh boundary (the box);
//            cells outside the visual hull: in some view with a silhouette the whole
//            projected cell (a disc around it) lies inside the image and outside the
//            silhouette (parts outside an image never carve);
//            inactive cells whose visibility votes exceed the upper percentile, that are
//            seen as free space (in front of Q by a margin) in at least `free_views` views.
//  interior  inactive cells inside the hull whose votes are at most the lower percentile
//            AND that lie between Q's near and far sides: in at least `min_occluding_views`
//            views the cell is behind the points Q visible in that view and in front of the
//            points of Q facing away from it (the far side, seen by other cameras); in no view
//            is it in front of the visible points (free space) or beyond the far side;
//            and in min_occluding_views of the hiding views it is at most interior_depth
//            finest cells behind the visible points (a shell under the seen surface).
//            The free-space condition keeps unreachable cavities (a cup's inside, which no
//            ray crosses) from becoming interior: some camera sees their air in front of the
//            cavity walls' points. The far-side condition keeps unseen space behind or below
//            the object (which ring cameras never see) from becoming interior.
// Free space outranks occlusion: a camera that sees past a cell proves it empty, while a
// cell hidden behind Q may be matter or an unseen cavity. A candidate seen as free space
// in at least `free_views` views, with votes above the upper percentile, is exterior even if
// other views hide it (the part of a cup's cavity that cameras see over the rim); the soft
// evidence also counts views where the cell is beyond Q's far side (below). "Beyond the far
// side" is not enough for a hard exterior label: where the far side's exit from the object is
// not in Q (a torus's second arm behind the hole), cells inside look beyond it (measured on
// the CI torus: 5 exterior cells inside the object, 0 with free space only, cut unchanged).
// Cavity regions no camera sees into are indistinguishable from matter in every image: the
// interior depth limit leaves them free, and the cut closes them with a floor at the edge of
// the seen free space.
// Free space outranks occlusion for Q too (Options::drop_free_points): before votes and
// depth maps, points of Q lying in front of what free_views other views see there are
// dropped as false matches floating in the air.
// Votes: every point of Q casts a ray to each camera it is photo-consistent in, starting
// `vote_offset` cell sizes in front of the point; every cell the ray crosses gets a vote.
// "Inactive" cells are the cells coarser than the finest level (away from the surface).
// Optional hull-core prior (Options::hull_core_px, off by default): see Options.
// In scenes without any silhouette (COLMAP workspaces, docs/colmap.md) every view gets one
// estimated from Q
// (Options::q_silhouettes, q_silhouettes() below): it carves like a silhouette, and points
// of Q outside it are dropped as false matches before votes and depth maps. In such scenes
// points of Q in front of Q's per-pixel median depth are dropped too
// (Options::median_free_views), and the hidden rule takes Q's visible side from that median.
// Conflicts (Options::conflict_cells, off by default): interior and exterior labels from Q that
// come within a few cells of each other mark a wall where neither rule is sure; they are left free.
// Seeds without Q (Options::seed_core_px): when Q gives no interior cell (a textureless
// object has almost no Q), the hull core of the silhouettes supplies the interior.
#pragma once
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "common/qpoints.h"
#include "common/scene.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::label {

enum Reason : std::uint8_t {
  kNone = 0,
  kBoundary = 1,      // exterior: touches the mesh boundary
  kOutsideHull = 2,   // exterior: outside a silhouette
  kVotedOut = 3,      // exterior: many votes, seen as free space
  kHidden = 4,        // interior: few votes, hidden behind Q in every view
  kHullCore = 7,      // interior: deep inside every silhouette (optional prior; 5, 6: silhouette-fix)
  kOutsideQHull = 8,  // exterior: outside a silhouette estimated from Q (view without one)
  kSeedCore = 9,      // interior: hull core used as the seed because Q gave no interior cell
  kSeenFree = 10,     // exterior: free space in seen_free_views views, in no view just under Q (optional)
};

struct Options {
  double low_percentile = 10;   // paper: 10th
  double high_percentile = 75;  // paper: 75th
  int min_exterior_votes = 3;   // exterior by votes needs at least this many votes
  int min_occluding_views = 3;  // interior needs Q depth behind it in this many views
  double vote_offset = 1.0;     // rays start this many finest cell sizes in front of a point
  double depth_margin = 2.0;    // occlusion / free-space margin, in finest cell sizes
  int free_views = 3;           // free space seen in this many views is sure (see below)
  // Soft outside evidence (the cut's visibility term): a view that sees through the cell
  // (or beyond Q's far side) weighs this many views that hide it. Not saturating at
  // free_views: with 48 views, cells just under the surface are seen "free" in 1-4 views
  // where Q has a gap, and full outside evidence there cost the 48-view torus 0.4 mm at the
  // first cut (docs/architecture.md, "Free space outranks occlusion").
  double free_weight = 2;
  // Interior by "hidden behind Q" also needs Q's visible side close in front: in at least
  // min_occluding_views views the cell's centre lies at most this many finest cell sizes
  // behind the visible points (<= 0: no limit, the rule of before). It counts finest cells
  // but must stay below world-sized walls: 8 suits LEVELS=3 on the project's scenes (the
  // synthetic cup's wall is 9 cells there, 4.6 at LEVELS=2, where 4 is needed). The part of a cavity that no camera sees
  // into (a cup's inside below what the ring sees over the rim), and the space under an
  // object that cameras above never see, are hidden behind Q in every view exactly like
  // matter: nothing in the images tells them apart. What tells them apart from the inside of
  // a wall is depth: in every view they lie behind the whole wall (and more), while matter
  // lies just behind the surface in the views that face it. So interior labels are only
  // given in a shell under the seen surface, thinner than the walls of the cavities it
  // must not claim; deeper cells are left to the cut (with their soft inside evidence).
  double interior_depth = 8;
  // Seen free space (0 = off): a free cell, active or not, that is free space in at least this
  // many views (the nearest point of Q taken within seen_free_window finest cells, at Q's mean
  // depth, around its pixel), that no view hides within interior_depth behind Q's visible
  // side, and that has no point of Q within seen_free_clearance, is exterior. A cup's cavity
  // seen over the rim by a few ring cameras is free in those and hidden in the rest, but always
  // behind the whole near wall, while matter lies just under a seen surface in the views facing
  // it. Gaps in Q (a surface facing a view without points there) let cells under a surface look
  // free in a view: a wider window hides them (and the cavity near the rim in the image, where
  // the few seeing views look); the exit test and the clearance keep the ones just under the
  // surface, where the surface's own points are near (48-view torus, one view, no clearance:
  // 5754 cells inside the tube, some 8 cells deep). Costs and gains: docs/architecture.md,
  // "Seen free space".
  int seen_free_views = 0;
  double seen_free_window = 1;
  // ... and no point of Q within this many finest cell sizes of its centroid (0: no test)
  double seen_free_clearance = 0.5;
  // ... and in at least this share of the views hiding it, the ray has left the matter it met
  // before reaching the cell: a point of Q facing away from the view (the near wall's inner
  // side) lies between Q's visible side and the cell, and no point facing the view after it
  // (the far wall's inner side, when the cell is in the far wall). Matter inside a thick wall
  // is deeper than the shell in every view too, but no ray reaches it through air.
  double seen_free_exit_share = 0.5;
  // ... and, in scenes with silhouettes, lies at least seen_free_hull_depth finest cells inside
  // the visual hull (0 = no test): in every view with a silhouette, the pixel distance from its
  // centroid to the silhouette's edge, scaled to its depth, is at least that. Where a silhouette
  // bounds the surface, Q's band of photo-consistency is clipped in front of the surface and
  // reaches only inward, so Q's visible side can lie cells under the true surface and the
  // matter between looks free in several views and beyond Q's far side in the rest (cup with
  // dinoRing's cameras and the grid: 61853 cells inside the walls labelled exterior without
  // this test, 169 with it; docs/architecture.md, "Seen free space"). Like interior_depth it
  // counts finest cells and must stay below the depth of the cavity that cameras see.
  double seen_free_hull_depth = 8;
  // ... and lies in a face-connected group of at least this many such cells (0, 1 = no test):
  // single cells in a wall look free where Q has a gap or a stray point.
  int seen_free_min_cells = 0;
  // Exterior by votes (kVotedOut) also needs the cell's centroid this many finest cells inside
  // the visual hull (scenes with silhouettes; 0 = no test), measured as for
  // seen_free_hull_depth. Under a surface that a silhouette bounds, Q's band lies cells inside
  // the surface, and the rays of its points to their cameras cross the matter above it: cup
  // with dinoRing's cameras and the grid patch, 45 voted-out cells 4 to 6.5 cells deep in the
  // rim's top and the outer bottom corner without it (docs/architecture.md, "Seen free space").
  double voted_out_hull_depth = 0;
  // Drop points of Q that lie in free space (in front of what other points show) in at
  // least free_views views, before votes and depth maps: false matches floating in the air.
  bool drop_free_points = true;
  // Interior by "hidden behind Q" only in face-connected groups of such cells holding at least
  // this share of the largest group (0 = off); smaller islands are left free. Points of Q
  // floating in a cavity's unseen air hide small groups of air cells within the shell, while
  // the shell under a surface is one large group per object (cup with dinoRing's cameras and
  // the grid: 183 interior cells in the air, 30 at 0.01, all within 1.5 cells of a wall;
  // docs/architecture.md, "Islands"). small_groups() below.
  double interior_min_share = 0;
  // Conflicts between the labels from Q (finest cells; 0 = off): where a cell of the hidden rule
  // (interior) and one of the votes or of seen free space (exterior) lie within this distance of
  // each other (centroids), the interior cell is left free, and the exterior cell too unless the
  // views hiding it put it deeper than interior_depth + conflict_cells behind Q's visible side
  // (hidden_depth): beyond the reach of the shell. Contradicting evidence that close marks a wall,
  // where neither rule is sure: Q's gaps let cells inside a wall's inner side look free over a
  // cup's rim, and the shell under the outer side reaches past the inner side into the air (cup
  // with dinoRing's cameras and the grid: 10 interior and 27 exterior cells wholly on the wrong
  // side, none at 4.5; docs/architecture.md, "Conflicts"). resolve_conflicts() in labels.cpp.
  double conflict_cells = 0;
  // Hull-core prior (0 = off): a cell, active or not, whose whole projection lies at least
  // this many pixels inside the silhouette in every view with a silhouette that it
  // projects into (at least min_occluding_views of them) is interior, whatever Q says;
  // points of Q inside that core are dropped as false matches before votes and depth maps,
  // and the "hidden behind Q" interior rule is off (the core replaces it).
  // For weakly textured objects whose photo-consistency cannot tell the surface from the
  // inside (real dinoRing): the surface is then sought only in a band of this width under
  // the visual hull's surface. Wrong in concavities deeper than the margin, even ones the
  // cameras see into, so off by default.
  double hull_core_px = 0;
  // In a scene without any silhouette, every view gets one estimated from Q (q_silhouettes();
  // scenes with silhouettes in some views are left as they were): the points of Q
  // photo-consistent in the view, splatted over about one finest cell, closed by a disc of
  // q_sil_close_px, holes filled, grown by q_sil_margin_px. Cells outside it are exterior
  // (kOutsideQHull) and points of Q outside it are dropped (false matches in the air: near
  // occluding contours a patch in free space matches in nearby views). Measured on the
  // synthetic torus without silhouettes (docs/colmap.md): first surface completeness
  // 45 % -> 68 % (with the median test below: 87 %). The closing is wide (6 px) because
  // gaps of Q at a rim otherwise carve the object (1060 cells at 2 px on one run).
  // Views with fewer than q_sil_min_points consistent points get none.
  bool q_silhouettes = true;
  double q_sil_close_px = 6;
  double q_sil_margin_px = 2;
  int q_sil_min_points = 50;
  // In scenes without any silhouette: points of Q lying in front of the per-pixel
  // median depth of the points consistent in a view (by depth_margin), in at least this many
  // views, are dropped (0 = off). See in_front_of_quantile.
  int median_free_views = 3;
  int median_passes = 1;  // the median test repeated on the points it keeps
  // In scenes with silhouettes: points of Q lying in front of the per-pixel free_quantile
  // depth of the points consistent in a view (by depth_margin), in at least
  // quantile_free_views views and in at least quantile_free_share of the views where that
  // depth exists, are dropped (0 views = off). They are the band of photo-consistency in
  // front of a surface that no silhouette bounds (a cup's far inner wall, seen over the rim):
  // the window minimum of drop_free_points is one of them, so the cavity's air never looks
  // free. The share spares true points near occluding contours, where points hidden behind
  // the surface push the quantile back in a few views (see in_front_of_quantile in
  // labels.cpp; docs/architecture.md, "The band in front of unbounded surfaces"). Off by
  // default: it helps 16-view rings and costs 48-camera rings (the cup's rim erodes).
  int quantile_free_views = 0;
  double free_quantile = 0.25;
  double quantile_free_share = 0.25;
  // When Q gives no interior cell (and hides no cell that is only too deep: a cup's unseen
  // cavity, which the hull core would fill) and the scene has silhouettes, cells whose whole
  // projection lies this many pixels inside every silhouette, and that no view sees as free
  // space or beyond Q, become interior (kSeedCore), as the hull-core prior would make them
  // (0 = no fallback: label then fails).
  double seed_core_px = 1.5;
};

struct Result {
  std::vector<std::int8_t> label;    // per cell: 1 interior, -1 exterior, 0 free
  std::vector<std::uint8_t> reason;  // Reason
  std::vector<std::int32_t> votes;
  // Soft evidence per free cell, in [0, 1], for the cut's visibility term: outside =
  // min(1, free_weight x views where the cell is free space or beyond Q's far side / views
  // where it projects);
  // inside = (1 - outside) x the share of the views (where the cell projects) in which it
  // lies between Q's visible and far sides.
  std::vector<float> inside_evidence, outside_evidence;
  // Per free cell, the number of views in which its centre is free space (in front of the
  // visible side of Q by the margin), beyond Q's far side, between the two (hidden), and
  // the views where it projects into the image at all.
  std::vector<std::uint8_t> free_views, beyond_views, hidden_views, seen_views;
  // Per free cell, the depth (finest cell sizes) of its centre behind Q's visible side, the
  // smallest reached in min_occluding_views of the views hiding it (-1: fewer views hide it).
  // Interior needs it at most Options::interior_depth.
  std::vector<float> hidden_depth;
  double low_votes = 0, high_votes = 0;  // the percentile values
  std::int64_t interior = 0, exterior = 0, hull_exterior = 0, boundary = 0, voted_out = 0, hull_core = 0;
  std::int64_t rays = 0;
  std::int64_t q_dropped = 0;  // points of Q inside the hull core (prior on), not used
  std::int64_t q_in_free_space = 0;  // points of Q dropped by drop_free_points
  std::int64_t interior_islands = 0;  // hidden cells left free by interior_min_share
  std::int64_t seen_free_islands = 0;  // seen-free cells left free by seen_free_min_cells
  std::int64_t conflict_interior = 0;  // interior cells left free by conflict_cells
  std::int64_t conflict_exterior = 0;  // exterior cells (votes, seen free space) left free by conflict_cells
  std::int64_t voted_out_near_hull = 0;  // cells the vote rule would make exterior, left free by voted_out_hull_depth
  std::int64_t seen_free = 0;  // cells labelled exterior by the seen-free-space rule (kSeenFree)
  std::int64_t too_deep = 0;   // cells that passed the hidden rule but lie deeper than interior_depth
  std::int64_t q_sil_views = 0;      // views given a silhouette estimated from Q
  std::int64_t q_outside_hull = 0;   // points of Q outside the estimated silhouettes, dropped
  std::int64_t q_hull_exterior = 0;  // cells exterior by the estimated silhouettes
  std::int64_t seed_core = 0;        // interior cells from the seed fallback (Q gave none)
  std::int64_t q_in_front_of_median = 0;  // points of Q dropped by median_free_views
  std::int64_t q_in_front_of_quantile = 0;  // points of Q dropped by quantile_free_views
};

// Per view without a silhouette (and with at least min_points points of Q consistent in
// it), a silhouette estimated from Q (CV_8U, 255 = object); an empty Mat for the other
// views. cell: splat radius in world units (projected at each point's depth, >= 1 px).
std::vector<cv::Mat> q_silhouettes(const Scene& s, const QPoints& q, double cell, double close_px, double margin_px,
                                   int min_points);

// Cells whose whole projection lies at least core_px pixels inside the silhouette in every
// view with a silhouette it projects into (and at least min_views such views), among the
// cells with label 0. dist: per view the distance (pixels) to the silhouette boundary
// inside the silhouette (empty: no silhouette).
std::vector<std::uint8_t> hull_core_cells(const tet::TetMesh& m, const Scene& s, const std::vector<cv::Mat>& dist,
                                          const std::vector<std::int8_t>& label, double core_px, int min_views);

// Per point of q: 1 when it lies in front of the per-pixel `quantile` depth of the splats
// (radius about `cell`) of the points consistent in a view, by `margin`, in at least
// views_needed views and in at least `share` of the views where that depth exists
// (Options::quantile_free_views with free_quantile and quantile_free_share; the median test
// of Options::median_free_views is quantile 0.5, share 0).
std::vector<std::uint8_t> in_front_of_quantile(const Scene& s, const QPoints& q, double cell, double margin,
                                               double quantile, int views_needed, double share);

// Per cell: the number of cells of its face-connected group of `in` cells (0 for the others).
std::vector<std::int32_t> group_sizes(const tet::TetMesh& m, const std::vector<std::uint8_t>& in);

// Per cell: 1 when the cell is one of the `in` cells and its face-connected group of `in`
// cells holds fewer than `share` x the cells of the largest such group (Options::interior_min_share).
std::vector<std::uint8_t> small_groups(const tet::TetMesh& m, const std::vector<std::uint8_t>& in, double share);

// Per cell: 1 when the cell is surely outside the visual hull (see top).
std::vector<std::uint8_t> outside_visual_hull(const tet::TetMesh& m, const Scene& s);

// Visibility votes of Q (see top). offset in world units.
std::vector<std::int32_t> visibility_votes(const tet::TetMesh& m, const Scene& s, const QPoints& q,
                                           double offset, std::int64_t* rays = nullptr);

// Options::conflict_cells applied to r (its label, reason and hidden_depth; counts in
// r.conflict_interior / conflict_exterior): see Options. cell: the finest cell size.
void resolve_conflicts(const tet::TetMesh& m, const Options& o, double cell, Result& r);

Result label_cells(const tet::TetMesh& m, const Scene& s, const QPoints& q, const Options& o);

}  // namespace tetmvs::label
