// photoconsist: the photo-consistency steps of Algorithm 1 (paper sections 2.3 and 3.1).
//
// Level mode (one per refinement level i):
//   photoconsist --scene scene.h5 --mesh mesh_i.h5 --level i [--cache pc_{i-1}.h5] --out pc_i.h5
// finds the crossing faces of the cells made by red refinement at this level, marks
// their cells active (/cells/active, read by refine), adds the best oriented point of
// each crossing face to Q and hands the face cache to the next level.
//
// Scores mode (once, on the final mesh):
//   photoconsist --scene scene.h5 --mesh mesh_L.h5 --scores --cache pc_{L-1}.h5 --out scores.h5
//                [--points-ply points.ply]
// writes omega for each face and orientation (/faces/omega, read by cut) and all of Q
// (/points, read by label). Schemas: schemas/photoconsist.md, schemas/scores.md.
#include <cstdio>
#include <optional>
#include <sstream>

#include "common/budget.h"
#include "common/error.h"
#include "common/h5io.h"
#include "common/log.h"
#include "common/photo/views.h"
#include "common/photoconsist/face_scores.h"
#include "common/photoconsist/files.h"
#include "common/photoconsist/ground_truth.h"
#include "common/photoconsist/level_pass.h"
#include "common/photoconsist/memory.h"
#include "common/photoconsist/level_scale.h"
#include "common/photoconsist/q_hull.h"
#include "common/ply.h"
#include "common/scene.h"
#include "common/stage.h"
#include "common/tetmesh/mesh_io.h"

using namespace tetmvs;
namespace pc = tetmvs::photoconsist;

namespace {

void write_eval(h5::File& f, const pc::LevelEval& E, double cell_size) {
  f.create_group("/eval");
  f.write("/eval/face_gt_crossed", E.face_gt_crossed, {E.face_gt_crossed.size()});
  f.write("/eval/face_gt_distance", E.face_gt_distance, {E.face_gt_distance.size()});
  f.set_attr("/eval", "recall", E.recall());
  f.set_attr("/eval", "precision", E.precision());
  f.set_attr("/eval", "cell_recall", E.cell_recall());
  f.set_attr("/eval", "points_within_cell", E.points_accuracy());
  f.set_attr("/eval", "gt_crossed", E.gt_crossed);
  f.set_attr("/eval", "found", E.found);
  f.set_attr("/eval", "crossing", E.crossing);
  f.set_attr("/eval", "crossing_near", E.crossing_near);
  f.set_attr("/eval", "cell_size", cell_size);
  f.set_attr("/eval", "near_dist", E.near_dist);
}

// Depth maps of the points of Q found so far (empty when off or when Q is empty).
// Only the points found before level `below`.
pc::OcclusionMaps occluders(const photo::Views& views, const pc::LeveledPoints& all, const tet::TetMesh& mesh,
                            const pc::OcclusionOptions& o, int below = 1 << 30) {
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
  return pc::OcclusionMaps(views, q, level, cell_size, o);
}

}  // namespace

int main(int argc, char** argv) {
  StageCli cli("photoconsist",
               "Level mode: crossing faces of the new cells of mesh_i (lattice points scored by "
               "photo-consistency), active cells, quasi-dense oriented points Q and the face cache for "
               "the next level -> pc_i.h5. Scores mode (--scores): omega of every face of the final mesh "
               "for both orientations, and all of Q -> scores.h5.");
  std::string scene_file, mesh_file, cache_file, out, points_ply, gt_file;
  int level = -1;
  bool scores = false, keep_all = false;
  auto& app = cli.app();
  cli.add_input("--scene", scene_file, "scene.h5 (cameras, images, silhouettes)")->required();
  cli.add_input("--mesh", mesh_file, "mesh_i.h5 (level mode) or the final mesh (scores mode)")->required();
  app.add_option("--level", level, "level i of the mesh (level mode; must match the mesh)");
  cli.add_input("--cache", cache_file, "pc_{i-1}.h5: face cache and Q of the previous levels");
  cli.add_output("-o,--out", out, "pc_i.h5 (level mode) or scores.h5 (scores mode)")->required();
  app.add_flag("--scores", scores, "scores mode: face scores omega of the final mesh");
  cli.add_output("--points-ply", points_ply, "also write Q (all points so far) as a PLY point cloud");
  cli.add_input("--gt", gt_file, "ground-truth mesh (synth's gt.ply): measure recall/precision of the "
                                  "crossing faces and the accuracy of Q, stored under /eval");
  app.add_flag("--keep-all", keep_all, "level mode: cache every tested face (for inspection and tuning)");
  return cli.run(argc, argv, [&](StageContext& ctx) {
    require(scores || level >= 0, "photoconsist: --level is required in level mode (or give --scores)");
    const pc::Options opts = pc::Options::from_params(ctx.params);
    Scene scene = read_scene(scene_file);
    {
      const MeshCounts mc = mesh_counts(mesh_file);
      const double pixels = static_cast<double>(scene.size()) * scene.cams[0].width * scene.cams[0].height;
      const double bytes = pc::memory_estimate(mc, pixels, scores);
      std::ostringstream what;
      what << "photoconsist: " << mesh_file << " (" << mc.faces << " faces, " << scene.size() << " views)";
      check_memory_budget(ctx.params, bytes, what.str(), "use fewer LEVELS or a coarser mesh.cells (MESH_CELLS)");
    }
    scene.load_grey();
    const tet::TetMesh mesh = tet::read_mesh(mesh_file);
    const photo::Views views(scene.cams, scene.grey, scene.sil);
    std::optional<pc::GroundTruth> gt;
    TriMesh gt_mesh;
    if (!gt_file.empty()) {
      gt_mesh = read_ply(gt_file);
      gt.emplace(gt_mesh);
    }

    // Previous levels: cache and Q.
    pc::FaceCache prev;
    bool use_prev = false;
    pc::LeveledPoints all;
    std::vector<std::filesystem::path> inputs{scene_file, mesh_file};
    if (!cache_file.empty()) {
      inputs.push_back(cache_file);
      const auto cf = h5::File::open(cache_file, pc::kLevelSchema, pc::kLevelVersion, pc::kLevelVersion);
      all = pc::read_leveled_points(cf, scene.size(), "/points_all");
      prev = pc::read_face_cache(cf);
      require(prev.lattice == pc::lattice_key(mesh.lat), cache_file,
              ": made on a different level-0 lattice than ", mesh_file, " (another run?)");
      std::string why;
      use_prev = prev.compatible(mesh.lat, opts.cache_signature(), &why);
      if (!use_prev && !scores) warn(cache_file, ": face cache not reused: ", why);
    }
    // The image scale of this level (level_scale.h); the scores mode works on the full images.
    const double cell_px = pc::level_cell_px(views, mesh.lat, mesh.level);
    int pyramid = 0;
    const photo::Views level_views = scores ? views : pc::level_views(views, mesh, opts.level_cell_px, &pyramid);
    // Codes scored on another image scale are other measurements: the cache is not reused.
    if (use_prev && prev.pyramid != pyramid) use_prev = false;
    // The hull: the given silhouettes, or in a scene without any, silhouettes estimated from
    // Q of the previous levels (photo.q_hull; none at level 0).
    const pc::QHull qh = pc::estimate_q_hull(scene, all, mesh.lat, opts);
    const pc::HullTest hull = qh.views > 0 ? pc::HullTest(views, qh.sil, opts.hull_margin_px, 0)
                                           : pc::HullTest(views, scene.sil, opts.hull_margin_px, opts.hull_core_px);
    double q_hull_gt = -1;  // share of the GT surface's vertices inside the estimated hull
    if (gt && qh.views > 0) {
      std::int64_t in = 0;
      for (const auto& V : gt_mesh.V) in += hull.inside(V);
      q_hull_gt = gt_mesh.V.empty() ? 1.0 : static_cast<double>(in) / static_cast<double>(gt_mesh.V.size());
    }
    const auto q_hull_attrs = [&](h5::File& f, std::ostringstream& os) {
      f.set_attr("/", "q_hull_views", static_cast<std::int64_t>(qh.views));
      if (qh.views > 0) os << " q_hull_views=" << qh.views;
      if (q_hull_gt >= 0) {
        f.set_attr("/", "q_hull_gt_inside", q_hull_gt);
        os << " q_hull_gt_inside=" << q_hull_gt;
      }
    };

    if (scores) {
      require(level < 0 || level == mesh.level, "photoconsist: --level ", level, " but ", mesh_file,
              " is level ", mesh.level);
      if (cache_file.empty()) warn("photoconsist --scores without --cache: Q (/points) will be empty");
      const auto sel = pc::faces_to_score(mesh);
      const pc::OcclusionMaps occl = occluders(views, all, mesh, opts.occl);
      const pc::ScoresResult S =
          pc::score_faces(mesh, views, hull, opts.face, sel, !ctx.quiet, occl.empty() ? nullptr : &occl);
      // Q in the final file: the points of the last level, found on the finest image scale
      // (coarser levels' points are as coarse as their pyramid levels: they served those
      // levels). Faces refer to earlier meshes, so they become -1.
      const int last = all.last_level();
      pc::LeveledPoints q;
      q.append(all.of_level(last), last, false);
      if (q.q.size() == 0 && !cache_file.empty())
        warn("photoconsist: ", cache_file, " holds no photo-consistent point: Q is empty, the labels and the cut "
             "rest on the silhouettes and the box alone");
      auto f = h5::File::create(out);
      f.write_header(pc::kScoresSchema, pc::kScoresVersion, "photoconsist", ctx.params.values_for("photoconsist"),
                     inputs);
      f.create_group("/faces");
      f.write("/faces/omega", S.omega, {static_cast<std::uint64_t>(mesh.num_faces()), 2});
      f.write("/faces/scored", sel, {sel.size()});
      f.set_attr("/faces", "scored_faces", S.scored_faces);
      f.set_attr("/faces", "outside_hull", S.outside_hull);
      f.set_attr("/faces", "occluders", occl.points());
      f.set_attr("/faces", "occluders_dropped", occl.dropped());
      f.set_attr("/faces", "hidden_faces", S.hidden);
      f.set_attr("/", "level", static_cast<std::int64_t>(mesh.level));
      pc::write_leveled_points(f, q, "/points");
      std::ostringstream os;
      os << "faces=" << mesh.num_faces() << " scored=" << S.scored_faces << " outside_hull=" << S.outside_hull
         << " defined_orientations=" << S.defined << " points=" << q.q.size();
      if (!occl.empty())
        os << " occluders=" << occl.points() << " (dropped " << occl.dropped() << ") hidden_faces=" << S.hidden;
      if (gt) {
        const double cs = tet::red_edge_length(mesh.lat, mesh.level);
        const double acc = pc::fraction_within(q.q, *gt, cs);
        f.set_attr("/points", "within_final_cell_of_gt", acc);
        os << " Q_within_cell=" << acc;
      }
      q_hull_attrs(f, os);
      if (!points_ply.empty()) write_qpoints_ply(points_ply, q.q);  // before make's target
      f.commit();
      ctx.summary = os.str();
      return;
    }

    require(level == mesh.level, "photoconsist: --level ", level, " but ", mesh_file, " is level ", mesh.level);
    if (level > 0 && cache_file.empty())
      warn("photoconsist: level ", level, " without --cache: every face is scored from scratch and Q holds "
           "only this level's points");
    if (use_prev)
      require(prev.level == level - 1, cache_file, ": its cache is of level ", prev.level, ", expected ",
              level - 1);

    // Occluders: Q of the previous levels (nothing at level 0).
    const pc::OcclusionMaps occl = occluders(views, all, mesh, opts.occl);
    // The occluders the cached codes were scored with (those of the previous level).
    const pc::OcclusionMaps occl_prev =
        use_prev ? occluders(views, all, mesh, opts.occl, level - 1) : pc::OcclusionMaps{};

    pc::LevelInput in;
    in.occl = occl.empty() ? nullptr : &occl;
    in.occl_prev = occl_prev.empty() ? nullptr : &occl_prev;
    in.mesh = &mesh;
    in.views = &level_views;
    in.full = &views;
    in.hull = &hull;
    in.prev = use_prev ? &prev : nullptr;
    in.keep_all = keep_all;
    in.recheck_hull = qh.views > 0;
    // The previous level's points of Q (photo.orientation_prior).
    QPoints prior;
    if (opts.orientation_prior && level > 0) {
      prior = all.of_level(level - 1);
      in.prior = &prior;
      in.prior_radius = tet::red_edge_length(mesh.lat, level - 1);
    }
    in.progress = !ctx.quiet;
    pc::LevelResult R = pc::run_level(in, opts);
    R.cache.pyramid = pyramid;
    if (R.points.size() == 0)
      warn("photoconsist: level ", level, " of ", mesh_file, ": no photo-consistent point (", R.consistent_points,
           " of ", R.scored_points, " scored lattice points above photo.T, ", R.crossing_faces,
           " crossing faces): no cell is refined here; without points at any level the cut rests on the "
           "silhouettes alone (check the images' texture and exposure, or lower photo.T)");
    all.append(R.points, level, true);

    auto f = h5::File::create(out);
    f.write_header(pc::kLevelSchema, pc::kLevelVersion, "photoconsist", ctx.params.values_for("photoconsist"),
                   inputs);
    f.set_attr("/", "level", static_cast<std::int64_t>(level));
    f.set_attr("/", "pyramid", static_cast<std::int64_t>(pyramid));
    f.set_attr("/", "cell_px", cell_px);
    f.create_group("/cells");
    f.write("/cells/active", R.active, {R.active.size()});
    f.create_group("/faces");
    const std::uint64_t T = R.face.size();
    f.write("/faces/tested", R.face, {T});
    f.write("/faces/divisions", R.divisions, {T});
    f.write("/faces/samples", R.samples, {T});
    f.write("/faces/consistent", R.consistent, {T});
    f.write("/faces/crossing", R.crossing, {T});
    f.write("/faces/reused", R.reused, {T});
    f.write("/faces/best_score", R.best_score, {T});
    f.set_attr("/faces", "distinct_points", R.distinct_points);
    f.set_attr("/faces", "occluders", occl.points());
    f.set_attr("/faces", "occluders_dropped", occl.dropped());
    f.set_attr("/faces", "hidden_points", R.hidden_points);
    f.set_attr("/faces", "rescored_points", R.rescored_points);
    f.set_attr("/faces", "hull_dropped_points", R.hull_dropped_points);
    f.set_attr("/faces", "hull_added_points", R.hull_added_points);
    write_qpoints(f, R.points, "/points");
    pc::write_leveled_points(f, all, "/points_all");
    pc::write_face_cache(f, R.cache);
    std::ostringstream os;
    os << "level=" << level << " pyramid=" << pyramid << " faces_tested=" << T << " reused=" << R.reused_faces
       << " lattice_points=" << R.lattice_points << " distinct_points=" << R.distinct_points << " in_hull=" << R.sample_points
       << " scored=" << R.scored_points << " consistent=" << R.consistent_points
       << " crossing_faces=" << R.crossing_faces << " active_cells=" << R.active_cells << "/" << mesh.num_cells()
       << " points=" << R.points.size() << " Q=" << all.q.size();
    if (!occl.empty())
      os << " occluders=" << occl.points() << " (dropped " << occl.dropped() << ") hidden_points=" << R.hidden_points
         << " rescored=" << R.rescored_points;
    if (qh.views > 0) os << " hull_dropped=" << R.hull_dropped_points << " hull_added=" << R.hull_added_points;
    q_hull_attrs(f, os);
    if (gt) {
      const double cs = tet::red_edge_length(mesh.lat, level);
      const pc::LevelEval E = pc::evaluate_level(mesh, R, *gt, cs);
      write_eval(f, E, cs);
      char buf[256];
      std::snprintf(buf, sizeof buf, " recall=%.4f (%lld/%lld) precision=%.4f cell_recall=%.4f Q_within_cell=%.3f",
                    E.recall(), static_cast<long long>(E.found), static_cast<long long>(E.gt_crossed),
                    E.precision(), E.cell_recall(), E.points_accuracy());
      os << buf;
    }
    if (!points_ply.empty()) write_qpoints_ply(points_ply, all.q);  // before make's target
    f.commit();
    ctx.summary = os.str();
  });
}
