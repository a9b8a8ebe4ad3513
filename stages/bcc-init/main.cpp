// bcc-init: the level-0 body-centred-cubic tetrahedral mesh M0 of the scene box
// (Algorithm 1: M0 <- BuildBCCMesh(B)). Schema: schemas/mesh.md.
#include <iostream>
#include <sstream>

#include "common/budget.h"
#include "common/error.h"
#include "common/scene.h"
#include "common/stage.h"
#include "common/tetmesh/mesh_io.h"
#include "common/tetmesh/projection.h"
#include "common/tetmesh/stage_common.h"

using namespace tetmvs;

int main(int argc, char** argv) {
  StageCli cli("bcc-init",
               "Builds M0, the BCC tetrahedral mesh covering the scene box (mesh.cells cubes along the "
               "longest side, all tets congruent), and writes mesh_0.h5. With --print-levels it only "
               "prints the number of refinement levels for the pixel target refine.target_pixels.");
  std::string scene_file, out;
  bool print_levels = false;
  tet::InspectOptions insp;
  cli.add_input("--scene", scene_file, "scene.h5 (cameras and bounding box)").required();
  cli.add_output("-o,--out", out, "output mesh file (mesh_0.h5)");
  cli.add_flag("--print-levels", print_levels,
                     "print (stdout) how many refinement levels reach refine.target_pixels, then exit");
  insp.add_to(cli);
  return cli.run(argc, argv, [&](StageContext& ctx) {
    require(print_levels || !out.empty(), "bcc-init: --out is required (unless --print-levels)");
    const Scene scene = read_scene(scene_file, /*images=*/false);
    const tet::Lattice lat = tet::lattice_for_box(scene.box, ctx.params.i("mesh.cells"));
    if (print_levels) {
      const double px = ctx.params.d("refine.target_pixels");
      const int L = tet::levels_for_pixels(lat, scene.box, scene.cams, px);
      std::cout << L << std::endl;
      ctx.summary = "levels=" + std::to_string(L) + " for " + std::to_string(px) + " px";
      return;
    }
    {
      // four tets per pair of face-adjacent cubes; building and writing hold about twice the mesh
      const double nx = lat.dims[0], ny = lat.dims[1], nz = lat.dims[2];
      const double cells = 4 * ((nx - 1) * ny * nz + nx * (ny - 1) * nz + nx * ny * (nz - 1));
      std::ostringstream what;
      what << "bcc-init: " << lat.dims[0] << "x" << lat.dims[1] << "x" << lat.dims[2] << " cubes, " << cells
           << " cells";
      check_memory_budget(ctx.params, 2.5 * mesh_bytes(cells), what.str(), "lower mesh.cells");
    }
    const tet::TetMesh m = tet::build_bcc(lat);
    tet::write_mesh(out, m, "bcc-init", ctx.params.values_for("bcc-init"), {scene_file});
    insp.write(m);
    std::ostringstream os;
    os << "cells=" << m.num_cells() << " faces=" << m.num_faces() << " vertices=" << m.num_vertices()
       << " h=" << lat.h << " grid=" << lat.dims[0] << "x" << lat.dims[1] << "x" << lat.dims[2]
       << " finest=" << tet::max_projected_cell_size(m, scene.cams) << "px";
    ctx.summary = os.str();
  });
}
