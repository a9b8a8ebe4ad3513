// label: hard interior / exterior labels of the cells (paper sections 2.1 and 2.4):
// the box boundary and the visual hull give exterior cells; visibility votes of the
// quasi-dense points Q, with an occlusion check, give interior and more exterior cells.
#include <sstream>

#include "common/budget.h"
#include "common/error.h"
#include "common/h5io.h"
#include "common/label/labels.h"
#include "common/label/labels_file.h"
#include "common/qpoints.h"
#include "common/scene.h"
#include "common/stage.h"
#include "common/tetmesh/mesh_io.h"

using namespace tetmvs;

// per pixel of every view: Q's four depth maps (front, back, near, far), and with the seen-free
// rule the exit and entry maps and their packed copies (DTU scan 37: +1.2 GB for 94 M pixels);
// per point of Q: the points as read, filtered and reduced to the views that see them, the
// lists of each view's points and every thread's splats of a view; and the libraries' and
// threads' working set (the last two fitted to the peaks of dinoRing's and eight synthetic
// scenes' runs at LEVELS=3, whose points took 100-250 bytes each over the other terms).
constexpr double kLabelBytesPerCell = 72, kLabelBytesPerPixel = 16, kSeenFreeBytesPerPixel = 13,
                 kLabelBytesPerPoint = 250, kLabelWorkingBytes = 200e6;

int main(int argc, char** argv) {
  StageCli cli("label",
               "Labels the cells of the final mesh: exterior (box boundary, outside the visual "
               "hull, many votes and seen as free space), interior (few votes, hidden behind Q in every "
               "view and close behind its visible side), or free for the cut to decide.");
  std::string scene_file, mesh_file, scores_file, out, slice;
  cli.add_input("--scene", scene_file, "scene.h5").required();
  cli.add_input("--mesh", mesh_file, "final tetrahedral mesh (mesh_<L>.h5)").required();
  cli.add_input("--scores", scores_file, "scores.h5 of photoconsist (holds the points Q)").required();
  cli.add_output("--out", out, "labels file (HDF5, schemas/labels.md)").required();
  cli.add_output("--slice-png", slice, "PNG slice through the mesh coloured by label");
  return cli.run(argc, argv, [&](StageContext& ctx) {
    label::Options::from_params(ctx.params);  // the options are checked before any work
    const Scene scene = read_scene(scene_file, false);
    const std::string one_sided = adapt_to_one_sided_capture(scene, ctx.params);
    if (!one_sided.empty()) info("label: ", one_sided);
    const label::Options o = label::Options::from_params(ctx.params);
    auto sf = h5::File::open(scores_file, "tetmvs.scores");
    {
      // the mesh, per-cell results (label, reason, votes, two evidences, view counts, the
      // rules' proposals, the cells' centroids), and
      // per view a few float images (depth maps of Q, distance transform of the silhouette;
      // the exit and entry maps of the seen-free rule)
      const MeshCounts mc = mesh_counts(mesh_file);
      const h5::Shape q_shape = sf.shape_of("/points/score");
      const double points = q_shape.empty() ? 0.0 : static_cast<double>(q_shape[0]);
      const double pixels = static_cast<double>(scene.size()) * scene.cams[0].width * scene.cams[0].height;
      const double per_pixel = kLabelBytesPerPixel + (o.seen_free_views > 0 ? kSeenFreeBytesPerPixel : 0);
      const double bytes = mc.read_bytes() + kLabelBytesPerCell * mc.cells + per_pixel * pixels +
                           kLabelBytesPerPoint * points + kLabelWorkingBytes;
      std::ostringstream what;
      what << "label: " << mesh_file << " (" << mc.cells << " cells, " << scene.size() << " views, "
           << static_cast<std::int64_t>(points) << " points)";
      check_memory_budget(ctx.params, bytes, what.str(), "use a coarser final mesh (fewer LEVELS)");
    }
    const tet::TetMesh mesh = tet::read_mesh(mesh_file);
    const QPoints q = read_qpoints(sf, scene.size());
    info("label: ", mesh.num_cells(), " cells, ", q.size(), " points, ", scene.num_silhouettes(), " silhouettes");
    const label::Result r = label::label_cells(mesh, scene, q, o);
    require(r.interior > 0, scores_file, ": no cell could be labelled interior (too few points Q?); "
            "lower label.min_views or raise label.low_percentile, or give silhouettes (label.seed_core_px)");
    auto f = h5::File::create(out);
    f.write_header("tetmvs.labels", 1, "label", ctx.params.values_for("label"), {scene_file, mesh_file, scores_file});
    label::labels_fields().write(f, r);
    f.commit();
    if (!slice.empty()) label::write_label_slice(slice, mesh, scene, r);
    ctx.summary = label::labels_fields().summary(r) + (one_sided.empty() ? "" : "; one-sided capture");
  });
}
