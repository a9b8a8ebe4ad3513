// silhouette-fix: the first surface S1 is rendered into every view with a silhouette; its
// disagreements with the true silhouettes become new hard labels for the second cut
// (paper section 3.2, Fig. 5). Writes silfix.h5 with the layout of labels.h5 plus the
// constraints it added (schemas/silfix.md), pictures of every view, and a summary.
// `--agreement PLY` (repeatable) instead only reports the silhouette agreement of surfaces.
#include <filesystem>
#include <sstream>

#include "common/budget.h"
#include "common/cut/inputs.h"
#include "common/error.h"
#include "common/h5io.h"
#include "common/scene.h"
#include "common/silfix/fix_labels.h"
#include "common/silfix/silfix_file.h"
#include "common/stage.h"
#include "common/tetmesh/mesh_io.h"

namespace fs = std::filesystem;

// Memory estimate, bytes beyond the program (64 MB) and the mesh arrays: per face the two
// scores, per cell the labels, reasons and constraints, per pixel the silhouette and the
// renders (torus and cup: 1.2-1.4 times the measured peak).
constexpr double kBytesPerFace = 8, kBytesPerCell = 8, kBytesPerPixel = 4;
using namespace tetmvs;

int main(int argc, char** argv) {
  StageCli cli("silhouette-fix",
               "Renders the first cut's surface into every view with a silhouette; pixels where it "
               "is too big make the cells on their rays exterior, pixels where it is too small give "
               "a few sure interior cells (centre of the front/back photo-consistency peaks). Writes "
               "the updated labels for the second cut, the constraints, and pictures.");
  std::string scene_file, mesh_file, scores_file, labels_file, cut_file, surface_file, out, png_dir, agree_json;
  std::vector<std::string> agreement;
  cli.add_input("--scene", scene_file, "scene.h5 (cameras and silhouettes)").required();
  cli.add_input("--mesh", mesh_file, "final tetrahedral mesh (mesh_<L>.h5)");
  cli.add_input("--scores", scores_file, "face scores (scores.h5, /faces/omega)");
  cli.add_input("--labels", labels_file, "hard labels of the first cut (labels.h5)");
  cli.add_input("--cut", cut_file, "the first cut (cut1.h5, /cells/inside): S1 is rebuilt from it");
  cli.add_input("--surface", surface_file, "S1 as a PLY (cut1.ply) instead of rebuilding it from --cut");
  cli.add_output("--out", out, "updated labels plus constraints (silfix.h5, schemas/silfix.md)");
  cli.add_output("--png-dir", png_dir, "folder for pictures: view_<NNN>.png per view and sheet.png", PathKind::Folder);
  const StageOption agree_opt = cli.add_input(
      "--agreement", agreement,
      "only report the silhouette agreement of this surface (PLY; repeatable), e.g. cut1.ply cut2.ply");
  cli.add_output("--agreement-json", agree_json, "with --agreement: also write the numbers as JSON").needs(agree_opt);
  return cli.run(argc, argv, [&](StageContext& ctx) {
    if (agreement.empty()) {
      require(!mesh_file.empty() && !scores_file.empty() && !labels_file.empty() && !out.empty(),
              "silhouette-fix needs --mesh, --scores, --labels and --out (or --agreement)");
      require(cut_file.empty() != surface_file.empty(), "silhouette-fix needs exactly one of --cut and --surface");
    }
    const Scene scene = read_scene(scene_file, false);
    if (!agreement.empty()) {
      require(scene.num_silhouettes() > 0, scene_file, ": the scene has no silhouettes; --agreement needs them");
      ctx.summary = silfix::report_agreement(scene, agreement, agree_json);
      return;
    }
    {
      const MeshCounts mc = mesh_counts(mesh_file);
      const double pixels = static_cast<double>(scene.size()) * scene.cams[0].width * scene.cams[0].height;
      const double bytes = 64.0 * 1048576.0 + mc.read_bytes() + kBytesPerFace * static_cast<double>(mc.faces) +
                           kBytesPerCell * static_cast<double>(mc.cells) + kBytesPerPixel * pixels;
      std::ostringstream what;
      what << "silhouette-fix: " << mesh_file << " (" << mc.cells << " cells, " << scene.size() << " views)";
      check_memory_budget(ctx.params, bytes, what.str(), "use a coarser final mesh (fewer LEVELS)");
    }
    const tet::TetMesh mesh = tet::read_mesh(mesh_file);
    const std::int64_t F = mesh.num_faces(), C = mesh.num_cells();
    const std::vector<float> omega = cut::read_omega(scores_file, F);
    silfix::LabelsIn labels = silfix::read_labels_in(labels_file, C);
    const TriMesh s1 = silfix::read_first_surface(mesh, cut_file, surface_file);
    std::vector<fs::path> inputs = {scene_file, mesh_file, scores_file, labels_file};
    inputs.push_back(cut_file.empty() ? surface_file : cut_file);
    // (without any silhouette the labels pass through unchanged, whatever S1 is)
    require(scene.num_silhouettes() == 0 || s1.nf() > 0, "silhouette-fix: the first surface is empty");

    const silfix::Options o = silfix::Options::from_params(ctx.params);
    info("silhouette-fix: ", C, " cells, S1 ", s1.nf(), " triangles, ", scene.num_silhouettes(), " silhouettes");
    const silfix::Outcome r = silfix::fix_labels(mesh, scene, s1, omega, std::move(labels), o);

    auto f = h5::File::create(out);
    f.write_header("tetmvs.labels", 1, "silhouette-fix", ctx.params.values_for("silhouette-fix"), inputs);
    silfix::silfix_fields().write(f, r);
    f.commit();
    if (!png_dir.empty()) silfix::write_pictures(png_dir, scene, r, o.margin_px);
    ctx.summary = silfix::summary_line(r);
  });
}
