// label: hard interior / exterior labels of the cells (paper sections 2.1 and 2.4):
// the box boundary and the visual hull give exterior cells; visibility votes of the
// quasi-dense points Q, with an occlusion check, give interior and more exterior cells.
#include <sstream>

#include "common/budget.h"
#include "common/error.h"
#include "common/h5io.h"
#include "common/label/labels.h"
#include "common/qpoints.h"
#include "common/scene.h"
#include "common/stage.h"
#include "common/image.h"
#include "common/tetmesh/mesh_io.h"
#include "common/tetmesh/slice.h"

using namespace tetmvs;

constexpr double kLabelBytesPerCell = 36, kLabelBytesPerPixel = 16;

int main(int argc, char** argv) {
  StageCli cli("label",
               "Labels the cells of the final mesh: exterior (box boundary, outside the visual "
               "hull, many votes and seen as free space), interior (few votes, hidden behind Q in every "
               "view and close behind its visible side), or free for the cut to decide.");
  std::string scene_file, mesh_file, scores_file, out, slice;
  cli.add_input("--scene", scene_file, "scene.h5")->required();
  cli.add_input("--mesh", mesh_file, "final tetrahedral mesh (mesh_<L>.h5)")->required();
  cli.add_input("--scores", scores_file, "scores.h5 of photoconsist (holds the points Q)")->required();
  cli.add_output("--out", out, "labels file (HDF5, schemas/labels.md)")->required();
  cli.add_output("--slice-png", slice, "PNG slice through the mesh coloured by label");
  return cli.run(argc, argv, [&](StageContext& ctx) {
    require(ctx.params.d("label.low_percentile") < ctx.params.d("label.high_percentile"),
            "label.low_percentile must be below label.high_percentile");
    const Scene scene = read_scene(scene_file, false);
    {
      // the mesh, per-cell results (label, reason, votes, two evidences, hull flags), and
      // per view a few float images (depth maps of Q, distance transform of the silhouette)
      const MeshCounts mc = mesh_counts(mesh_file);
      const double pixels = static_cast<double>(scene.size()) * scene.cams[0].width * scene.cams[0].height;
      const double bytes = mc.read_bytes() + kLabelBytesPerCell * mc.cells + kLabelBytesPerPixel * pixels;
      std::ostringstream what;
      what << "label: " << mesh_file << " (" << mc.cells << " cells, " << scene.size() << " views)";
      check_memory_budget(ctx.params, bytes, what.str(), "use a coarser final mesh (fewer LEVELS)");
    }
    const tet::TetMesh mesh = tet::read_mesh(mesh_file);
    auto sf = h5::File::open(scores_file, "tetmvs.scores");
    const QPoints q = read_qpoints(sf, scene.size());
    label::Options o;
    o.low_percentile = ctx.params.d("label.low_percentile");
    o.high_percentile = ctx.params.d("label.high_percentile");
    o.min_exterior_votes = ctx.params.i("label.min_exterior_votes");
    o.min_occluding_views = ctx.params.i("label.min_occluding_views");
    o.vote_offset = ctx.params.d("label.vote_offset");
    o.depth_margin = ctx.params.d("label.depth_margin");
    o.free_views = ctx.params.i("label.free_views");
    o.free_weight = ctx.params.d("label.free_weight");
    o.hull_core_px = ctx.params.d("label.hull_core_px");
    o.interior_depth = ctx.params.d("label.interior_depth");
    o.seen_free_views = ctx.params.i("label.seen_free_views");
    o.seen_free_window = ctx.params.d("label.seen_free_window");
    o.seen_free_clearance = ctx.params.d("label.seen_free_clearance");
    o.seen_free_exit_share = ctx.params.d("label.seen_free_exit_share");
    o.seen_free_hull_depth = ctx.params.d("label.seen_free_hull_depth");
    o.voted_out_hull_depth = ctx.params.d("label.voted_out_hull_depth");
    o.interior_min_share = ctx.params.d("label.interior_min_share");
    o.seen_free_min_cells = static_cast<int>(ctx.params.i("label.seen_free_min_cells"));
    o.conflict_cells = ctx.params.d("label.conflict_cells");
    o.drop_free_points = ctx.params.b("label.drop_free_points");
    o.q_silhouettes = ctx.params.b("label.q_silhouettes");
    o.q_sil_close_px = ctx.params.d("label.q_sil_close_px");
    o.q_sil_margin_px = ctx.params.d("label.q_sil_margin_px");
    o.q_sil_min_points = ctx.params.i("label.q_sil_min_points");
    o.seed_core_px = ctx.params.d("label.seed_core_px");
    o.median_free_views = ctx.params.i("label.median_free_views");
    o.median_passes = ctx.params.i("label.median_passes");
    o.quantile_free_views = ctx.params.i("label.quantile_free_views");
    o.free_quantile = ctx.params.d("label.free_quantile");
    o.quantile_free_share = ctx.params.d("label.quantile_free_share");
    info("label: ", mesh.num_cells(), " cells, ", q.size(), " points, ", scene.num_silhouettes(), " silhouettes");
    const label::Result r = label::label_cells(mesh, scene, q, o);
    require(r.interior > 0, scores_file, ": no cell could be labelled interior (too few points Q?); "
            "lower label.min_occluding_views or raise label.low_percentile, or give silhouettes (label.seed_core_px)");
    auto f = h5::File::create(out);
    f.write_header("tetmvs.labels", 1, "label", ctx.params.values_for("label"), {scene_file, mesh_file, scores_file});
    f.write("/cells/label", r.label);
    f.write("/cells/reason", r.reason);
    f.write("/cells/votes", r.votes);
    f.write("/cells/inside_evidence", r.inside_evidence);
    f.write("/cells/outside_evidence", r.outside_evidence);
    f.write("/cells/free_views", r.free_views);
    f.write("/cells/beyond_views", r.beyond_views);
    f.write("/cells/hidden_views", r.hidden_views);
    f.write("/cells/seen_views", r.seen_views);
    f.write("/cells/hidden_depth", r.hidden_depth);
    f.set_attr("/", "low_votes", r.low_votes);
    f.set_attr("/", "high_votes", r.high_votes);
    f.set_attr("/", "interior", r.interior);
    f.set_attr("/", "exterior", r.exterior);
    f.set_attr("/", "boundary", r.boundary);
    f.set_attr("/", "hull_exterior", r.hull_exterior);
    f.set_attr("/", "voted_out", r.voted_out);
    f.set_attr("/", "voted_out_near_hull", r.voted_out_near_hull);
    f.set_attr("/", "interior_islands", r.interior_islands);
    f.set_attr("/", "seen_free_islands", r.seen_free_islands);
    f.set_attr("/", "conflict_interior", r.conflict_interior);
    f.set_attr("/", "conflict_exterior", r.conflict_exterior);
    f.set_attr("/", "hull_core", r.hull_core);
    f.set_attr("/", "q_dropped", r.q_dropped);
    f.set_attr("/", "too_deep", r.too_deep);
    f.set_attr("/", "seen_free", r.seen_free);
    f.set_attr("/", "q_in_free_space", r.q_in_free_space);
    f.set_attr("/", "rays", r.rays);
    f.set_attr("/", "q_sil_views", r.q_sil_views);
    f.set_attr("/", "q_outside_hull", r.q_outside_hull);
    f.set_attr("/", "q_hull_exterior", r.q_hull_exterior);
    f.set_attr("/", "seed_core", r.seed_core);
    f.set_attr("/", "q_in_front_of_median", r.q_in_front_of_median);
    f.set_attr("/", "q_in_front_of_quantile", r.q_in_front_of_quantile);
    f.commit();
    if (!slice.empty()) {
      // a slice through the box centre, cells coloured by label
      tet::SliceSpec spec;
      spec.axis = 2;
      spec.position = scene.box.center().z();
      const std::vector<int> lab(r.label.begin(), r.label.end());
      write_png_rgb(slice, tet::render_slice(mesh, spec, tet::colours_by_label(lab)));
    }
    std::ostringstream os;
    os << r.interior << " interior, " << r.exterior << " exterior (" << r.boundary << " boundary, "
       << r.hull_exterior << " hull, " << r.q_hull_exterior << " hull of Q, " << r.voted_out << " votes, " << r.seen_free << " seen free), " << r.hull_core << " interior by the hull core (" << r.q_dropped << " points of Q in it dropped), " << r.seed_core << " interior seeds by the hull core (Q gave none), "
       << r.q_sil_views << " silhouettes estimated from Q (" << r.q_outside_hull << " points of Q outside dropped), " << r.q_in_front_of_median << " points of Q in front of the median dropped, " << r.q_in_front_of_quantile
       << " in front of the depth quantile dropped, "
       << r.q_in_free_space << " points of Q in free space dropped, " << r.too_deep << " hidden but too deep (left free), " << r.interior_islands << " hidden and " << r.seen_free_islands << " seen-free cells in islands (left free), " << r.voted_out_near_hull << " voted out but near the hull's surface (left free), " << r.conflict_interior << " interior and " << r.conflict_exterior << " exterior cells in conflict (left free), " << r.rays << " rays, vote percentiles "
       << r.low_votes << " / " << r.high_votes;
    ctx.summary = os.str();
  });
}
