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
#include <optional>
#include <sstream>

#include "common/budget.h"
#include "common/error.h"
#include "common/h5io.h"
#include "common/log.h"
#include "common/photo/views.h"
#include "common/photoconsist/files.h"
#include "common/photoconsist/ground_truth.h"
#include "common/photoconsist/memory.h"
#include "common/photoconsist/modes.h"
#include "common/ply.h"
#include "common/scene.h"
#include "common/stage.h"
#include "common/tetmesh/mesh_io.h"

using namespace tetmvs;
namespace pc = tetmvs::photoconsist;

int main(int argc, char** argv) {
  StageCli cli("photoconsist",
               "Level mode: crossing faces of the new cells of mesh_i (lattice points scored by "
               "photo-consistency), active cells, quasi-dense oriented points Q and the face cache for "
               "the next level -> pc_i.h5. Scores mode (--scores): omega of every face of the final mesh "
               "for both orientations, and all of Q -> scores.h5.");
  std::string scene_file, mesh_file, cache_file, out, points_ply, gt_file;
  int level = -1;
  bool scores = false, keep_all = false;
  cli.add_input("--scene", scene_file, "scene.h5 (cameras, images, silhouettes)").required();
  cli.add_input("--mesh", mesh_file, "mesh_i.h5 (level mode) or the final mesh (scores mode)").required();
  cli.add_option("--level", level, "level i of the mesh (level mode; must match the mesh)");
  cli.add_input("--cache", cache_file, "pc_{i-1}.h5: face cache and Q of the previous levels");
  cli.add_output("-o,--out", out, "pc_i.h5 (level mode) or scores.h5 (scores mode)").required();
  cli.add_flag("--scores", scores, "scores mode: face scores omega of the final mesh");
  cli.add_output("--points-ply", points_ply, "also write Q (all points so far) as a PLY point cloud");
  cli.add_input("--gt", gt_file, "ground-truth mesh (synth's gt.ply): measure recall/precision of the "
                                  "crossing faces and the accuracy of Q, stored under /eval");
  cli.add_flag("--keep-all", keep_all, "level mode: cache every tested face (for inspection and tuning)");
  return cli.run(argc, argv, [&](StageContext& ctx) {
    require(scores || level >= 0, "photoconsist: --level is required in level mode (or give --scores)");
    pc::Options::from_params(ctx.params);  // the options are checked before any work
    Scene scene = read_scene(scene_file);
    const std::string one_sided = adapt_to_one_sided_capture(scene, ctx.params);
    if (!one_sided.empty()) info("photoconsist: ", one_sided);
    const std::string capture_note = one_sided.empty() ? "" : "; one-sided capture";  // the summaries' tail
    const pc::Options opts = pc::Options::from_params(ctx.params);
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
    const photo::Views views(scene.cams, scene.grey, scene.sil, opts.line.outline_fill);
    std::optional<pc::GroundTruth> gt;
    TriMesh gt_mesh;
    if (!gt_file.empty()) {
      gt_mesh = read_ply(gt_file);
      gt.emplace(gt_mesh);
    }

    // Q and the face cache of the previous levels.
    pc::Previous prev;
    std::vector<std::filesystem::path> inputs{scene_file, mesh_file};
    if (!cache_file.empty()) {
      inputs.push_back(cache_file);
      prev = pc::read_previous(cache_file, mesh_file, scene.size(), mesh, opts, !scores);
    }
    pc::ModeInput in;
    in.scene = &scene;
    in.views = &views;
    in.mesh = &mesh;
    in.mesh_file = mesh_file;
    in.gt_mesh = gt ? &gt_mesh : nullptr;
    in.gt = gt ? &*gt : nullptr;
    in.progress = !ctx.quiet;

    if (scores) {
      require(level < 0 || level == mesh.level, "photoconsist: --level ", level, " but ", mesh_file,
              " is level ", mesh.level);
      if (cache_file.empty()) warn("photoconsist --scores without --cache: Q (/points) will be empty");
      const pc::ScoresOutput S = pc::run_scores_mode(in, prev, opts);
      auto f = h5::File::create(out);
      f.write_header(pc::kScoresSchema, pc::kScoresVersion, "photoconsist", ctx.params.values_for("photoconsist"),
                     inputs);
      pc::scores_fields().write(f, S);
      if (!points_ply.empty()) write_qpoints_ply(points_ply, S.q.q);  // before make's target
      f.commit();
      ctx.summary = pc::scores_fields().summary(S) + capture_note;
      return;
    }

    require(level == mesh.level, "photoconsist: --level ", level, " but ", mesh_file, " is level ", mesh.level);
    if (level > 0 && cache_file.empty())
      warn("photoconsist: level ", level, " without --cache: every face is scored from scratch and Q holds "
           "only this level's points");
    const pc::LevelOutput L = pc::run_level_mode(in, std::move(prev), level, keep_all, opts);
    auto f = h5::File::create(out);
    f.write_header(pc::kLevelSchema, pc::kLevelVersion, "photoconsist", ctx.params.values_for("photoconsist"),
                   inputs);
    pc::level_fields().write(f, L);
    if (!points_ply.empty()) write_qpoints_ply(points_ply, L.all.q);  // before make's target
    f.commit();
    ctx.summary = pc::level_fields().summary(L) + capture_note;
  });
}
