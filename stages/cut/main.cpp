// cut: the minimum s-t cut on the dual graph of the mesh (paper section 3.1, Eq. 1).
// Reads the final mesh, the face scores (scores.h5) and hard labels (labels.h5, or
// silfix.h5 for the second cut); writes the cut (cells' sides, energy) and the surface.
#include <filesystem>
#include <sstream>

#include "common/cut/cut_file.h"
#include "common/cut/cut_mesh.h"
#include "common/cut/inputs.h"
#include "common/budget.h"
#include "common/error.h"
#include "common/h5io.h"
#include "common/image.h"
#include "common/ply.h"
#include "common/render/shaded.h"
#include "common/scene.h"
#include "common/stage.h"
#include "common/tetmesh/mesh_io.h"

namespace fs = std::filesystem;
using namespace tetmvs;

// Bytes per graph edge (of the bound 2 x faces + 4 x cells) and per node. The cup's finest
// mesh (4.3 M cells) makes 17.8 M of the 34.8 M edges the bound allows, in 335 MB (19.7 bytes
// an edge made, the nodes' arrays included): the stage peaks at 971 MiB, the estimate is 1386 MiB.
constexpr double kCutBytesPerEdge = 20, kCutBytesPerNode = 8;

int main(int argc, char** argv) {
  StageCli cli("cut",
               "Minimum cut of the mesh's dual graph with Eq. 1 face costs: cells tied to the "
               "source (interior) and sink (exterior) by the labels; writes the cells' sides and "
               "the cut surface as an outward, edge-manifold PLY mesh.");
  std::string mesh_file, scores_file, labels_file, out, ply, scene_file, png;
  cli.add_input("--mesh", mesh_file, "final tetrahedral mesh (mesh_<L>.h5)").required();
  cli.add_input("--scores", scores_file, "face scores from photoconsist --scores (scores.h5)").required();
  cli.add_input("--labels", labels_file, "hard labels (labels.h5 or silfix.h5)").required();
  cli.add_output("--out", out, "cut file (HDF5, schemas/cut.md)").required();
  cli.add_output("--ply", ply, "cut surface (binary PLY)").required();
  const StageOption scene_opt = cli.add_input("--scene", scene_file, "scene.h5: with --png, render the surface from four views");
  cli.add_output("--png", png, "PNG of the surface rendered from four views (needs --scene)").needs(scene_opt);
  return cli.run(argc, argv, [&](StageContext& ctx) {
    const Scene scene = png.empty() ? Scene() : read_scene(scene_file, false);  // (checked before the work)
    {
      // the mesh, then the graph: one node per cell, two directed edges per face plus up to
      // two terminal edges per cell (visibility term); per edge: target, reverse, capacity,
      // residual, two descriptors, CSR storage; per node: BK's work arrays
      const MeshCounts mc = mesh_counts(mesh_file);
      const double edges = 2.0 * mc.faces + 4.0 * mc.cells;
      const double bytes = mc.read_bytes() + kCutBytesPerEdge * edges + kCutBytesPerNode * mc.cells;
      std::ostringstream what;
      what << "cut: graph of " << mesh_file << " (" << mc.cells << " nodes, up to " << edges << " edges)";
      check_memory_budget(ctx.params, bytes, what.str(), "use a coarser final mesh (fewer LEVELS)");
    }
    const tet::TetMesh mesh = tet::read_mesh(mesh_file);
    const std::int64_t F = mesh.num_faces(), C = mesh.num_cells();
    const std::vector<float> omega = cut::read_omega(scores_file, F);
    cut::CutOptions opt;
    read_params(ctx.params, opt);
    const cut::LabelInput labels = cut::read_label_input(labels_file, C, opt.beta > 0);
    info("cut: ", C, " cells, ", F, " faces, lambda ", opt.lambda, ", sigma ", opt.sigma);
    const cut::Cut c = cut::cut_mesh(mesh, omega, labels, opt, ctx.params.d("cut.min_region_fraction"));

    auto f = h5::File::create(out);
    f.write_header("tetmvs.cut", 1, "cut", ctx.params.values_for("cut"), {mesh_file, scores_file, labels_file});
    cut::cut_fields().write(f, c);
    f.commit();
    if (!png.empty()) write_png_rgb(png, render_sheet(c.surface, scene));
    // the PLY is make's target: committed last, so a stage killed before it leaves no PLY
    // whose cut file is missing
    write_ply(ply, c.surface, {false, "tetmvs cut: outward-oriented triangles, world frame"});
    ctx.summary = cut::summary_line(c);
  });
}
