// cut: the minimum s-t cut on the dual graph of the mesh (paper section 3.1, Eq. 1).
// Reads the final mesh, the face scores (scores.h5) and hard labels (labels.h5, or
// silfix.h5 for the second cut); writes the cut (cells' sides, energy) and the surface.
#include <filesystem>
#include <sstream>

#include "common/cut/cleanup.h"
#include "common/cut/graph_cut.h"
#include "common/cut/inputs.h"
#include "common/cut/surface.h"
#include "common/reason.h"
#include "common/budget.h"
#include "common/error.h"
#include "common/h5io.h"
#include "common/image.h"
#include "common/ply.h"
#include "common/render/shaded.h"
#include "common/scene.h"
#include "common/stage.h"
#include "common/tetmesh/mesh_io.h"
#include "common/trimesh/check.h"

namespace fs = std::filesystem;
using namespace tetmvs;

// Bytes per graph edge (of the bound 2 x faces + 4 x cells) and per node. The cup's finest
// mesh (4.3 M cells) makes 17.8 M of the 34.8 M edges the bound allows, in 335 MB (19.7 bytes
// an edge made, the nodes' arrays included): the stage peaks at 971 MB, the estimate is 1.42 GB.
constexpr double kCutBytesPerEdge = 20, kCutBytesPerNode = 8;

int main(int argc, char** argv) {
  StageCli cli("cut",
               "Minimum cut of the mesh's dual graph with Eq. 1 face costs: cells tied to the "
               "source (interior) and sink (exterior) by the labels; writes the cells' sides and "
               "the cut surface as an outward, edge-manifold PLY mesh.");
  std::string mesh_file, scores_file, labels_file, out, ply, scene_file, png;
  cli.add_input("--mesh", mesh_file, "final tetrahedral mesh (mesh_<L>.h5)")->required();
  cli.add_input("--scores", scores_file, "face scores from photoconsist --scores (scores.h5)")->required();
  cli.add_input("--labels", labels_file, "hard labels (labels.h5 or silfix.h5)")->required();
  cli.add_output("--out", out, "cut file (HDF5, schemas/cut.md)")->required();
  cli.add_output("--ply", ply, "cut surface (binary PLY)")->required();
  auto* scene_opt = cli.add_input("--scene", scene_file, "scene.h5: with --png, render the surface from four views");
  cli.add_output("--png", png, "PNG of the surface rendered from four views (needs --scene)")->needs(scene_opt);
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
    const std::vector<std::int8_t> labels = cut::read_labels(labels_file, C);
    auto lf = h5::File::open(labels_file, "tetmvs.labels");  // its other datasets
    cut::CutOptions opt;
    read_params(ctx.params, opt);
    std::vector<float> in_ev, out_ev;
    if (opt.beta > 0 && lf.has("/cells/inside_evidence") && lf.has("/cells/outside_evidence")) {
      in_ev = lf.read<float>("/cells/inside_evidence", {C}).data;
      out_ev = lf.read<float>("/cells/outside_evidence", {C}).data;
      for (std::int64_t c = 0; c < C; ++c)
        require(in_ev[c] >= 0 && in_ev[c] <= 1 && out_ev[c] >= 0 && out_ev[c] <= 1, labels_file,
                ": evidence values must lie in [0, 1]");
      opt.inside_evidence = &in_ev;
      opt.outside_evidence = &out_ev;
    }
    info("cut: ", C, " cells, ", F, " faces, lambda ", opt.lambda, ", sigma ", opt.sigma);
    cut::CutResult r = cut::min_cut(mesh, omega, labels, opt);
    // Interior labels that do not protect a speck: silhouette-fix's constraints
    // (kSilfixInterior) and the hull-core prior's (kHullCore; a core cell cut off from the body by the band
    // is a single-cell shell, not a part of the object).
    std::vector<std::uint8_t> weak(C, 0);
    if (lf.has("/cells/reason")) {
      const auto reason = lf.read<std::uint8_t>("/cells/reason", {C});
      for (std::int64_t c = 0; c < C; ++c)
        weak[c] = labels[c] > 0 && (reason.data[c] == kSilfixInterior || reason.data[c] == kHullCore);
    }
    const cut::CleanupStats cs =
        cut::clean_up_regions(mesh, labels, r.inside, ctx.params.d("cut.min_region_fraction"), &weak);
    require(r.cut_faces > 0, labels_file, ": the cut is empty (no interior cells survive); check the labels");
    cut::SurfaceStats st;
    std::vector<std::int32_t> face_ids;
    TriMesh surface = cut::cut_surface(mesh, r.inside, &st, &face_ids);
    const MeshCheck chk = check_mesh(surface);

    auto f = h5::File::create(out);
    f.write_header("tetmvs.cut", 1, "cut", ctx.params.values_for("cut"), {mesh_file, scores_file, labels_file});
    f.write("/cells/inside", r.inside, {static_cast<std::uint64_t>(C)});
    f.write("/surface/face", face_ids);
    f.set_attr("/", "energy", r.energy);
    f.set_attr("/", "data_energy", r.data_energy);
    f.set_attr("/", "area_energy", r.area_energy);
    f.set_attr("/", "cut_area", r.cut_area);
    f.set_attr("/", "visibility_energy", r.visibility_energy);
    f.set_attr("/", "max_flow", r.max_flow);
    f.set_attr("/", "cut_faces", r.cut_faces);
    f.set_attr("/", "graph_nodes", r.graph_nodes);
    f.set_attr("/", "graph_edges", r.graph_edges);
    f.set_attr("/", "graph_bytes", r.graph_bytes);
    f.set_attr("/", "split_vertices", st.split_vertices);
    f.set_attr("/", "nonmanifold_edges", st.nonmanifold_edges);
    f.set_attr("/", "reglued_edges", st.repaired_edges);
    f.set_attr("/", "split_edges", st.split_edges);
    f.set_attr("/", "voids_filled", cs.voids_filled);
    f.set_attr("/", "void_exterior_cells", cs.void_exterior_cells);
    f.set_attr("/", "specks_removed", cs.specks_removed);
    f.set_attr("/", "components", static_cast<std::int64_t>(chk.components.size()));
    f.set_attr("/", "closed", static_cast<std::int64_t>(chk.closed));
    f.set_attr("/", "edge_manifold", static_cast<std::int64_t>(chk.edge_manifold));
    f.commit();
    if (!png.empty()) write_png_rgb(png, render_sheet(surface, scene));
    // the PLY is make's target: committed last, so a stage killed before it leaves no PLY
    // whose cut file is missing
    write_ply(ply, surface, {false, "tetmvs cut: outward-oriented triangles, world frame"});
    std::ostringstream os;
    os << r.cut_faces << " faces, " << surface.nv() << " vertices, " << chk.components.size()
       << " components, " << (chk.closed ? "closed" : "OPEN") << ", "
       << (chk.edge_manifold ? "edge-manifold" : "NON-MANIFOLD") << " (" << st.split_vertices
       << " split vertices, " << st.nonmanifold_edges << " pinched edges: " << st.repaired_edges << " re-glued, "
       << st.split_edges << " split), " << cs.voids_filled << " voids filled, "
       << cs.specks_removed << " specks removed, energy " << r.energy << " (data "
       << r.data_energy << ", area " << r.area_energy << "), graph " << r.graph_nodes << " nodes "
       << r.graph_edges << " edges " << r.graph_bytes / 1048576.0 << " MB";
    ctx.summary = os.str();
  });
}
