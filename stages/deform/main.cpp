// deform: the second cut's surface S2 refined into the final mesh H (paper section 3.3,
// Algorithm 1 step 7): vertices moved by smoothness, silhouette and photometric forces, with
// red-green remeshing to edges of at most deform.max_edge_px pixels, no self-intersections.
#include <filesystem>
#include <sstream>

#include "common/budget.h"
#include "common/deform/deform.h"
#include "common/deform/stats_file.h"
#include "common/error.h"
#include "common/image.h"
#include "common/ply.h"
#include "common/render/shaded.h"
#include "common/scene.h"
#include "common/stage.h"
#include "common/trimesh/check.h"

using namespace tetmvs;

int main(int argc, char** argv) {
  StageCli cli("deform",
               "Refines a closed cut surface (cut2.ply) into the final mesh: smoothness, silhouette and photometric "
               "(multi-view NCC, coarse to fine) forces, red-green remeshing, no self-intersections. Writes a binary PLY with normals and colours "
               "and per-iteration statistics (HDF5, schemas/deform.md).");
  std::string scene_file, mesh_file, out, stats, png;
  cli.add_input("--scene", scene_file, "scene.h5 (cameras, images, silhouettes)").required();
  cli.add_input("--mesh", mesh_file, "start surface: closed, edge-manifold, outward (cut2.ply)").required();
  cli.add_output("--out", out, "final mesh (binary PLY with normals and colours)").required();
  cli.add_output("--stats", stats, "statistics per iteration (HDF5, schema tetmvs.deform)").required();
  cli.add_output("--png", png, "PNG of the final mesh rendered from four views");
  return cli.run(argc, argv, [&](StageContext& ctx) {
    const deform::Options opt = deform::Options::from_params(ctx.params);
    Scene scene = read_scene(scene_file);
    scene.load_grey();
    const TriMesh start = read_ply(mesh_file);
    {
      // per view and pixel: the grey image (4 bytes), the raster's depth and face ids (8), the
      // signed distances of the mesh's and of the true silhouette (8), the photometric force's
      // image gradients (8) and clean-pixel mask (1); the mesh grows by remeshing to edges of
      // about deform.max_edge_px: budget 16x the start's faces at ~400 bytes each
      const double pixels = static_cast<double>(scene.size()) * scene.cams[0].width * scene.cams[0].height;
      const double bytes = 29.0 * pixels + 16.0 * 400.0 * static_cast<double>(start.nf());
      std::ostringstream what;
      what << "deform: " << mesh_file << " (" << start.nf() << " faces, " << scene.size() << " views)";
      check_memory_budget(ctx.params, bytes, what.str(), "raise deform.max_edge_px or start from a coarser surface");
    }
    const deform::Result r = deform::deform_mesh(start, scene, opt);
    // the PLY is make's target: written last, so an interrupted run never leaves a final
    // mesh without its statistics and picture
    auto f = h5::File::create(stats);
    f.write_header(deform::kDeformSchema, deform::kDeformVersion, "deform", ctx.params.values_for("deform"),
                   {scene_file, mesh_file});
    deform::stats_fields().write(f, r);
    f.commit();
    if (!png.empty()) write_png_rgb(png, render_sheet(r.mesh, scene));
    write_ply(out, r.mesh, {false, "tetmvs deform: final mesh, outward triangles, world frame"});
    const MeshCheck chk = check_mesh(r.mesh);
    std::ostringstream os;
    os << r.mesh.nv() << " vertices, " << r.mesh.nf() << " faces, " << chk.components.size() << " components, "
       << (chk.closed ? "closed" : "OPEN") << ", " << (chk.edge_manifold ? "edge-manifold" : "NON-MANIFOLD")
       << ", intersections " << r.start_intersections << " -> " << r.final_intersections << ", silhouette IoU "
       << r.start_iou << " -> " << r.final_iou;
    ctx.summary = os.str();
  });
}
