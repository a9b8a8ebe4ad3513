#include "common/photoconsist/modes.h"

#include <optional>

#include "common/error.h"
#include "common/h5io.h"
#include "common/log.h"
#include "common/photoconsist/ground_truth.h"
#include "common/photoconsist/hull.h"
#include "common/photoconsist/level_scale.h"
#include "common/photoconsist/occlusion.h"
#include "common/photoconsist/q_hull.h"

namespace tetmvs::photoconsist {

namespace {

// Depth maps of the points of Q found so far (empty when off or when Q is empty).
// Only the points found before level `below`.
OcclusionMaps q_occluders(const photo::Views& views, const LeveledPoints& all, const tet::TetMesh& mesh,
                          const OcclusionOptions& o, int below = 1 << 30) {
  if (!o.enabled) return {};
  std::vector<double> cell_size;
  for (int l = 0; l <= mesh.level; ++l) cell_size.push_back(tet::red_edge_length(mesh.lat, l));
  QPoints q;
  std::vector<std::int32_t> level;
  std::vector<std::int32_t> cams;
  for (std::int64_t p = 0; p < all.q.size(); ++p) {
    if (all.level[p] >= below) continue;
    cams.assign(all.q.cams.begin() + all.q.cam_offsets[p], all.q.cams.begin() + all.q.cam_offsets[p + 1]);
    q.add(all.q.pos(p), all.q.nrm(p), all.q.score[p], cams, -1);
    level.push_back(all.level[p]);
  }
  if (q.size() == 0) return {};
  return OcclusionMaps(views, q, level, cell_size, o);
}

// The hull test of both modes: the given silhouettes, or in a scene without any, silhouettes
// estimated from Q of the previous levels (photo.q_hull; none at level 0).
struct Hull {
  QHull qh;
  HullTest test;
  std::optional<double> gt_inside;  // share of the GT surface's vertices inside the estimated hull
};

Hull hull_of(const ModeInput& in, const LeveledPoints& all, const Options& opts) {
  Hull h;
  h.qh = estimate_q_hull(*in.scene, all, in.mesh->lat, opts);
  h.test = h.qh.views > 0 ? HullTest(*in.views, h.qh.sil, opts.hull_margin_px, 0)
                          : HullTest(*in.views, in.scene->sil, opts.hull_margin_px, opts.hull_core_px);
  if (in.gt_mesh && h.qh.views > 0) {
    const TriMesh& gt = *in.gt_mesh;
    std::int64_t inside = 0;
    for (const auto& V : gt.V) inside += h.test.inside(V);
    h.gt_inside = gt.V.empty() ? 1.0 : static_cast<double>(inside) / static_cast<double>(gt.V.size());
  }
  return h;
}

}  // namespace

Previous read_previous(const std::filesystem::path& file, const std::filesystem::path& mesh_file, int num_cameras,
                       const tet::TetMesh& mesh, const Options& opts, bool warn_unused) {
  Previous p;
  p.file = file;
  const auto cf = h5::File::open(file, kLevelSchema, kLevelVersion, kLevelVersion);
  p.all = read_leveled_points(cf, num_cameras, "/points_all");
  p.cache = read_face_cache(cf);
  require(p.cache.lattice == lattice_key(mesh.lat), file.string(), ": made on a different level-0 lattice than ",
          mesh_file.string(), " (another run?)");
  std::string why;
  p.reusable = p.cache.compatible(mesh.lat, opts.cache_signature(), &why);
  if (!p.reusable && warn_unused) warn(file.string(), ": face cache not reused: ", why);
  return p;
}

LevelOutput run_level_mode(const ModeInput& in, Previous prev, int level, bool keep_all, const Options& opts) {
  const tet::TetMesh& mesh = *in.mesh;
  const photo::Views& views = *in.views;
  LevelOutput out;
  out.level = level;
  out.num_cells = mesh.num_cells();
  // The image scale of this level (level_scale.h); codes scored on another scale are other
  // measurements: the cache is not reused.
  out.cell_px = level_cell_px(views, mesh.lat, mesh.level);
  const photo::Views scaled = level_views(views, mesh, opts.level_cell_px, &out.pyramid);
  const bool use_prev = !prev.file.empty() && prev.reusable && prev.cache.pyramid == out.pyramid;
  const Hull hull = hull_of(in, prev.all, opts);
  out.q_hull_views = hull.qh.views;
  out.q_hull_gt_inside = hull.gt_inside;
  if (use_prev)
    require(prev.cache.level == level - 1, prev.file.string(), ": its cache is of level ", prev.cache.level,
            ", expected ", level - 1);

  // Occluders: Q of the previous levels (nothing at level 0), and those the cached codes
  // were scored with (the previous level's).
  const OcclusionMaps occl = q_occluders(views, prev.all, mesh, opts.occl);
  const OcclusionMaps occl_prev = use_prev ? q_occluders(views, prev.all, mesh, opts.occl, level - 1) : OcclusionMaps{};
  out.occlusion = !occl.empty();
  out.occluders = occl.points();
  out.occluders_dropped = occl.dropped();

  LevelInput li;
  li.occl = occl.empty() ? nullptr : &occl;
  li.occl_prev = occl_prev.empty() ? nullptr : &occl_prev;
  li.mesh = &mesh;
  li.views = &scaled;
  li.full = &views;
  li.hull = &hull.test;
  li.prev = use_prev ? &prev.cache : nullptr;
  li.keep_all = keep_all;
  li.recheck_hull = hull.qh.views > 0;
  // Lines of sight of Q of the previous levels (photo.sight_views).
  SightLines sight;
  if (opts.sight_views > 0 && prev.all.q.size() > 0) {
    sight = SightLines(views, prev.all.q, opts.sight_margin_px, opts.sight_views);
    li.sight = &sight;
  }
  // The previous level's points of Q (photo.orientation_prior).
  QPoints prior;
  if (opts.orientation_prior && level > 0) {
    prior = prev.all.of_level(level - 1);
    li.prior = &prior;
    li.prior_radius = tet::red_edge_length(mesh.lat, level - 1);
  }
  li.progress = in.progress;
  out.pass = run_level(li, opts);
  LevelResult& R = out.pass;
  R.cache.pyramid = out.pyramid;
  if (R.points.size() == 0)
    warn("photoconsist: level ", level, " of ", in.mesh_file.string(), ": no photo-consistent point (",
         R.consistent_points, " of ", R.scored_points, " scored lattice points above photo.T, ", R.crossing_faces,
         " crossing faces): no cell is refined here; without points at any level the cut rests on the "
         "silhouettes alone (check the images' texture and exposure, or lower photo.T)");
  out.all = std::move(prev.all);
  out.all.append(R.points, level, true);
  if (in.gt) {
    LevelEvalOutput e;
    e.cell_size = tet::red_edge_length(mesh.lat, level);
    e.eval = evaluate_level(mesh, R, *in.gt, e.cell_size);
    out.eval = std::move(e);
  }
  return out;
}

ScoresOutput run_scores_mode(const ModeInput& in, const Previous& prev, const Options& opts) {
  const tet::TetMesh& mesh = *in.mesh;
  const photo::Views& views = *in.views;
  ScoresOutput out;
  out.level = mesh.level;
  out.num_faces = mesh.num_faces();
  const Hull hull = hull_of(in, prev.all, opts);
  out.q_hull_views = hull.qh.views;
  out.q_hull_gt_inside = hull.gt_inside;
  out.scored = faces_to_score(mesh);
  const OcclusionMaps occl = q_occluders(views, prev.all, mesh, opts.occl);
  out.occlusion = !occl.empty();
  out.occluders = occl.points();
  out.occluders_dropped = occl.dropped();
  out.scores = score_faces(mesh, views, hull.test, opts.face, out.scored, in.progress, occl.empty() ? nullptr : &occl);
  // Q in the final file: the points of the last level, found on the finest image scale
  // (coarser levels' points are as coarse as their pyramid levels: they served those
  // levels). Faces refer to earlier meshes, so they become -1.
  const int last = prev.all.last_level();
  out.q.append(prev.all.of_level(last), last, false);
  if (out.q.q.size() == 0 && !prev.file.empty())
    warn("photoconsist: ", prev.file.string(), " holds no photo-consistent point: Q is empty, the labels and the cut "
         "rest on the silhouettes and the box alone");
  if (in.gt) out.q_within_cell = fraction_within(out.q.q, *in.gt, tet::red_edge_length(mesh.lat, mesh.level));
  return out;
}

}  // namespace tetmvs::photoconsist
