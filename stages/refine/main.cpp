// refine: one step of photo-consistency driven refinement (Algorithm 1: M_{i+1} <-
// MeshRefine(M_i)): red (1:8) refinement of the active cells, green closure of the rest.
// Schema of the output: schemas/mesh.md.
#include <iostream>
#include <sstream>

#include "common/budget.h"
#include "common/error.h"
#include "common/scene.h"
#include "common/stage.h"
#include "common/tetmesh/mesh_io.h"
#include "common/tetmesh/projection.h"
#include "common/tetmesh/refine.h"
#include "common/tetmesh/stage_common.h"

using namespace tetmvs;

// Peak bytes per cell of the refined mesh while refine builds it (the new mesh, its edge
// map and closure work arrays, write buffers). Measured on the synthetic torus (LEVELS=3:
// 0.74 M cells by this lower bound, 0.91 M made, peak 230 MB of which 70 MB the program):
// the estimate is 241 MB.
constexpr double kRefineBytesPerCell = 300;

int main(int argc, char** argv) {
  StageCli cli("refine",
               "Red-refines the active cells of mesh_i (flags from photoconsist's file, dataset "
               "/cells/active, one uint8 per cell), green-refines their neighbours to keep the mesh "
               "conforming, and writes mesh_{i+1}.h5 with the face map photoconsist needs.");
  std::string mesh_file, active_file, out, scene_file, dataset = "/cells/active";
  bool print_levels = false, check = false;
  tet::InspectOptions insp;
  cli.add_input("--mesh", mesh_file, "input mesh (mesh_i.h5)").required();
  cli.add_input("--active", active_file, "HDF5 file with the active-cell flags");
  cli.add_option("--active-dataset", dataset, "dataset of the flags in --active");
  cli.add_output("-o,--out", out, "output mesh (mesh_{i+1}.h5)");
  cli.add_input("--scene", scene_file, "scene.h5: report the projected size of the finest cells");
  cli.add_flag("--print-levels", print_levels,
                     "print (stdout) the total number of levels reaching refine.target_pixels (needs --scene)");
  cli.add_flag("--check", check, "run the full (slow) geometric conformity check on the result");
  insp.add_to(cli);
  return cli.run(argc, argv, [&](StageContext& ctx) {
    if (print_levels) require(!scene_file.empty(), "refine: --print-levels needs --scene");
    else require(!active_file.empty() && !out.empty(), "refine: --active and --out are required");
    check_memory_budget(ctx.params, mesh_counts(mesh_file).read_bytes(), "refine: reading " + mesh_file,
                        "use a coarser mesh");
    const tet::TetMesh old = tet::read_mesh(mesh_file);
    Scene scene;
    if (!scene_file.empty()) scene = read_scene(scene_file, /*images=*/false);
    if (print_levels) {
      const int L = tet::levels_for_pixels(old.lat, scene.box, scene.cams, ctx.params.d("refine.target_pixels"));
      std::cout << L << std::endl;
      ctx.summary = "levels=" + std::to_string(L);
      return;
    }
    const auto active = tet::read_cell_flags(active_file, dataset, old.num_cells());
    {
      // every active cell becomes at least 8; the closure only adds to that
      std::int64_t na = 0;
      for (auto a : active) na += a != 0;
      const double cells = old.num_cells() + 7.0 * static_cast<double>(na);
      std::ostringstream what;
      what << "refine: " << mesh_file << " with " << na << " active cells gives at least " << cells << " cells";
      check_memory_budget(ctx.params, static_cast<double>(old.memory_bytes()) + kRefineBytesPerCell * cells,
                          what.str(), "refine fewer levels (make LEVELS=...) or start coarser (mesh.cells)");
    }
    tet::RefineStats st;
    const tet::TetMesh m = tet::refine(old, active, &st);
    if (check) tet::check_conforming(m);
    tet::write_mesh(out, m, "refine", ctx.params.values_for("refine"), {mesh_file, active_file});
    insp.write(m);
    std::ostringstream os;
    os << "level=" << m.level << " cells " << old.num_cells() << " -> " << m.num_cells()
       << " (red by activity " << st.red_active << ", by closure " << st.red_closure << ", green cells "
       << st.green_cells << ", passes " << st.rounds << ")";
    if (!scene_file.empty()) os << " finest=" << tet::max_projected_cell_size(m, scene.cams) << "px";
    ctx.summary = os.str();
  });
}
