#include "common/label/labels.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.h"
#include "common/label/depth_maps.h"
#include "common/label/evidence.h"
#include "common/label/geometry.h"
#include "common/label/hull.h"
#include "common/label/votes.h"

namespace tetmvs::label {

void Options::check() const {
  check_param_ranges(*this);
  require(low_percentile < high_percentile, "label.low_percentile (", low_percentile,
          ") must be below label.high_percentile (", high_percentile, ")");
  require(seen_free_min_cells >= 0, "label options: seen_free_min_cells must be >= 0, got ", seen_free_min_cells);
  q_sil.check();
}

Options Options::from_params(const Params& p) {
  Options o;
  read_params(p, o);
  read_params(p, o.q_sil);
  o.check();
  return o;
}

namespace {

// What the rules share: the mesh, the scene with the silhouettes that bound it (given or
// estimated from Q), Q after the filters, and what the views see of each cell.
struct Inputs {
  const tet::TetMesh& m;
  const Scene& s;         // the scene as given
  const Scene& hull;      // its silhouettes, or in a scene without any those estimated from Q
  const QPoints& q;       // after the filters
  const Options& o;
  const MeshPoints& pts;
  double pixel;           // the world size of a pixel at the object (pixel_size)
  std::vector<cv::Mat> hull_dist;  // silhouette_distances(hull), when a rule needs them
};

std::vector<std::uint8_t> boundary_cells(const tet::TetMesh& m) {
  std::vector<std::uint8_t> out(m.num_cells(), 0);
  for (std::int32_t f = 0; f < m.num_faces(); ++f)
    if (m.face_on_boundary(f)) out[m.face_cell(f, 0)] = 1;
  return out;
}

// Of `cells`, those lying less than depth_px inside some silhouette.
std::vector<std::uint8_t> near_hull_surface(const Inputs& in, const std::vector<std::uint8_t>& cells, double depth_px) {
  std::vector<std::uint8_t> out(cells.size(), 0);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int32_t c = 0; c < in.m.num_cells(); ++c)
    out[c] = cells[c] && !deep_in_hull(in.hull, in.hull_dist, in.pts.centroid[c], depth_px);
  return out;
}

// voted_out (paper): a candidate with more votes than the upper percentile, at least
// min_views of them, seen as free space in min_views views; optionally deep inside the hull
// (under a surface that a silhouette bounds, Q's band lies inside the matter and the rays of
// its points cross the matter above it).
std::vector<std::uint8_t> voted_out_cells(const Inputs& in, const std::vector<std::uint8_t>& candidate,
                                          const std::vector<std::int32_t>& votes, double high,
                                          const ViewEvidence& ev, Result& r) {
  std::vector<std::uint8_t> out(candidate.size(), 0);
  for (std::size_t c = 0; c < out.size(); ++c)
    out[c] = candidate[c] && votes[c] > high && votes[c] >= in.o.min_views && (ev.facts[c] & kFreeInViews);
  if (in.o.hull_depth_px > 0 && in.hull.num_silhouettes() > 0) {
    const auto shallow = near_hull_surface(in, out, in.o.hull_depth_px);
    for (std::size_t c = 0; c < out.size(); ++c)
      if (shallow[c]) out[c] = 0, ++r.voted_out_near_hull;
  }
  return out;
}

// hidden (paper, with a depth limit): a candidate wholly inside every silhouette, with at
// most the lower percentile of votes, hidden behind Q in min_views views and seen as free
// space or beyond Q's far side in none, at most interior_depth_px behind Q's visible side;
// optionally not in a small island of such cells. Off with the hull-core prior (the core
// replaces it: it rests on the very points the prior distrusts).
std::vector<std::uint8_t> hidden_cells(const Inputs& in, const std::vector<std::uint8_t>& candidate,
                                       const std::vector<std::int32_t>& votes, double low, const ViewEvidence& ev,
                                       Result& r) {
  const std::int32_t C = in.m.num_cells();
  std::vector<std::uint8_t> out(C, 0);
  if (in.o.hull_core_px > 0) return out;
  const auto vertex_in = vertices_in_silhouettes(in.pts, in.hull);
  for (std::int32_t c = 0; c < C; ++c) {
    if (!candidate[c] || votes[c] > low || !(ev.facts[c] & (kHiddenInShell | kHiddenTooDeep))) continue;
    const tet::Tet& t = in.m.cell_v[c];
    if (!(vertex_in[t[0]] && vertex_in[t[1]] && vertex_in[t[2]] && vertex_in[t[3]])) continue;
    if (ev.facts[c] & kHiddenInShell)
      out[c] = 1;
    else
      ++r.too_deep;
  }
  if (in.o.interior_min_share > 0) {
    const auto islands = small_groups(in.m, out, in.o.interior_min_share);
    for (std::int32_t c = 0; c < C; ++c)
      if (islands[c]) out[c] = 0, ++r.interior_islands;
  }
  return out;
}

// seen_free: air that a few views see over a cavity's rim and the others hide only behind a
// whole wall (the evidence's kSeenFreeAir), clear of Q, deep inside the visual hull, in a
// group of seen_free_min_cells such cells.
std::vector<std::uint8_t> seen_free_cells(const Inputs& in, const ViewEvidence& ev, Result& r) {
  const std::int32_t C = in.m.num_cells();
  std::vector<std::uint8_t> out(C, 0);
  if (in.o.seen_free_views <= 0) return out;
  for (std::int32_t c = 0; c < C; ++c) out[c] = (ev.facts[c] & kSeenFreeAir) != 0;
  if (in.o.hull_depth_px > 0 && in.hull.num_silhouettes() > 0) {
    const auto shallow = near_hull_surface(in, out, in.o.hull_depth_px);
    for (std::int32_t c = 0; c < C; ++c) out[c] = out[c] && !shallow[c];
  }
  if (in.o.seen_free_min_cells > 1) {
    const auto sizes = group_sizes(in.m, out);
    for (std::int32_t c = 0; c < C; ++c)
      if (out[c] && sizes[c] < in.o.seen_free_min_cells) out[c] = 0, ++r.seen_free_islands;
  }
  return out;
}

// seed_core: the hull core, where no view sees free space or beyond Q. Only when Q hides no
// cell that is merely too deep (a cup's unseen cavity, which the core would fill).
std::vector<std::uint8_t> seed_core_cells(const Inputs& in, const Decision& d, const ViewEvidence& ev) {
  std::vector<std::uint8_t> skip(in.m.num_cells());
  for (std::int32_t c = 0; c < in.m.num_cells(); ++c) skip[c] = d.label[c] != 0 || !(ev.facts[c] & kNeverFree);
  return hull_core_cells(in.m, in.pts, in.s, silhouette_distances(in.s), skip, in.o.seed_core_px, in.o.min_views);
}

// hull_core: cells deep inside every silhouette (of those no geometry rule labels).
std::vector<std::uint8_t> hull_core_rule(const Inputs& in, const std::vector<std::uint8_t>& free_cell) {
  std::vector<std::uint8_t> labelled(free_cell.size());
  for (std::size_t c = 0; c < labelled.size(); ++c) labelled[c] = !free_cell[c];
  return hull_core_cells(in.m, in.pts, in.s, silhouette_distances(in.s), labelled, in.o.hull_core_px, in.o.min_views);
}

// The vote percentiles over the candidates (the upper one over those a ray reaches).
void vote_percentiles(const std::vector<std::uint8_t>& candidate, const Options& o, Result& r) {
  std::vector<std::int32_t> pool, crossed;
  for (std::size_t c = 0; c < candidate.size(); ++c)
    if (candidate[c]) {
      pool.push_back(r.votes[c]);
      if (r.votes[c] > 0) crossed.push_back(r.votes[c]);
    }
  r.low_votes = percentile(pool, o.low_percentile);
  r.high_votes = percentile(crossed, o.high_percentile);
}

// The decision and the evidence into the result.
void take(Decision d, ViewEvidence ev, Result& r) {
  r.label = std::move(d.label);
  r.reason = std::move(d.reason);
  r.cells = d.cells, r.interior = d.interior, r.exterior = d.exterior;
  r.free_views = std::move(ev.free_views), r.beyond_views = std::move(ev.beyond_views);
  r.hidden_views = std::move(ev.hidden_views), r.seen_views = std::move(ev.seen_views);
  r.hidden_depth = std::move(ev.hidden_depth);
  r.inside_evidence = std::move(ev.inside), r.outside_evidence = std::move(ev.outside);
}

}  // namespace

Result label_cells(const tet::TetMesh& m, const Scene& s, const QPoints& q_in, const Options& o) {
  o.check();
  const std::int32_t C = m.num_cells();
  const int finest = m.max_cell_level();
  const double cell = tet::red_edge_length(m.lat, finest);
  const MeshPoints pts(m);
  Result r;
  // The silhouettes that bound the object: the scene's, or in a scene without any, estimated from Q.
  Scene hull = s;
  const auto q_sil = estimate_q_silhouettes(s, q_in, cell, o.q_sil);
  for (int v = 0; v < s.size(); ++v)
    if (!q_sil[v].empty()) hull.sil[v] = q_sil[v], ++r.q_sil_views;
  // 1. Q filters: points that cannot lie on the surface
  const double pixel = pixel_size(s), margin = o.depth_margin_px * pixel;
  const QPoints q = filter_points(s, q_in, {o.hull_core_px, o.min_views, margin, cell},
                                  o.hull_core_px > 0 ? silhouette_distances(s) : std::vector<cv::Mat>(), q_sil, r.dropped);
  Inputs in{m, s, hull, q, o, pts, pixel, {}};
  if (hull.num_silhouettes() > 0 && o.hull_depth_px > 0) in.hull_dist = silhouette_distances(hull);
  // 2. geometry: the box boundary and the visual hull
  Proposals p(C);
  p.add(Rule::kBoundary, boundary_cells(m));
  p.add(r.q_sil_views > 0 ? Rule::kOutsideQHull : Rule::kOutsideHull, outside_visual_hull(m, pts, hull));
  std::vector<std::uint8_t> free_cell(C), candidate(C);  // candidates: free and coarser than the finest level
  for (std::int32_t c = 0; c < C; ++c) {
    free_cell[c] = p.winner(c) < 0;
    candidate[c] = free_cell[c] && m.node_level[m.cell_node[c]] < finest;
  }
  // 3. votes, what the views see of the free cells, and the lines of sight through those behind Q
  r.votes = visibility_votes(m, s, q, 0.5 * margin, &r.rays, &candidate, &pts);
  vote_percentiles(candidate, o, r);
  const double shell = o.interior_depth_px > 0 ? o.interior_depth_px * pixel : std::numeric_limits<double>::infinity();
  const EvidenceOptions eo{margin, shell, o.seen_free_wall_px * pixel, o.min_views, o.free_weight, o.seen_free_views, pixel};
  ViewEvidence ev = view_evidence(m, pts, s, visible_side_maps(s, q, cell, o.seen_free_views > 0, margin), free_cell, eo);
  SightLines sight = add_sight_lines(m, pts, s, q, free_cell, eo, cell, ev);
  r.sight_rays = std::move(sight.rays);
  r.sight_cells = sight.cells, r.sight_cast = sight.cast, r.unseen_views = sight.hidden_views;
  // 4. the rules from Q and the priors, decided by the precedence table
  if (o.hull_core_px > 0) p.add(Rule::kHullCore, hull_core_rule(in, free_cell));
  p.add(Rule::kSeenFree, seen_free_cells(in, ev, r));
  p.add(Rule::kVotedOut, voted_out_cells(in, candidate, r.votes, r.high_votes, ev, r));
  p.add(Rule::kHidden, hidden_cells(in, candidate, r.votes, r.low_votes, ev, r));
  Decision d = decide(p);
  if (d.interior == 0 && r.too_deep == 0 && o.seed_core_px > 0 && s.num_silhouettes() > 0) {
    p.add(Rule::kSeedCore, seed_core_cells(in, d, ev));
    d = decide(p);
  }
  take(std::move(d), std::move(ev), r);
  return r;
}

}  // namespace tetmvs::label
