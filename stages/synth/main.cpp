// synth: renders a synthetic scene with exact ground truth into a Middlebury-style
// dataset folder (images, <prefix>_par.txt, silhouettes/, bbox.txt, gt.ply, synth.json).
// The work lives in common/synth/.
#include <sstream>

#include <omp.h>

#include <filesystem>

#include "common/budget.h"
#include "common/error.h"
#include "common/fileio.h"
#include "common/stage.h"
#include "common/synth/colmap_export.h"
#include "common/synth/objects.h"
#include "common/synth/scene.h"

int main(int argc, char** argv) {
  using namespace tetmvs;
  StageCli cli("synth",
               "Render a synthetic scene (exact ground-truth mesh, solid texture, Lambertian shading) into a "
               "Middlebury dataset folder: <prefix>NNNN.png, <prefix>_par.txt, silhouettes/, bbox.txt, gt.ply "
               "(per-face 'region': 0 body, 1 cavity, 2 protrusion), synth.json.");
  std::string object, cameras, out, size, box;
  double texture = -1, noise = -1;
  int seed = -1, views = 0;
  std::string names;
  for (const auto& n : synth::object_names()) names += (names.empty() ? "" : "|") + n;
  cli.add_option("--object", object, names + ", or a closed mesh .ply (placed to fill the box)").required();
  cli.add_option("--cameras", cameras, "a Middlebury par file (e.g. dinoR_par.txt: its README.txt/bbox.txt gives the "
                                       "box), ring, hemisphere, or cap (a capture from one side)").required();
  cli.add_output("--out", out, "output dataset folder", PathKind::Folder).required();
  cli.add_option("--texture", texture, "texture strength in [0,1] (synth.texture)");
  cli.add_option("--noise", noise, "Gaussian noise sigma in grey levels [0,1] (synth.noise)");
  cli.add_option("--seed", seed, "random seed (synth.seed)");
  cli.add_option("--views", views, "number of views (par file: an evenly spaced subset; generated: default 48)");
  cli.add_option("--size", size, "image size WxH (generated cameras: default 640x480; par cameras are rescaled)");
  cli.add_option("--box", box, "scene box 'minx miny minz maxx maxy maxz' (overrides the dataset's box)");
  std::string colmap_dir;
  synth::ColmapExportOptions cx;
  bool colmap_no_sil = false;
  cli.add_output("--colmap", colmap_dir, "also export the scene as a COLMAP workspace here: images/, sparse/ (cameras, "
                                         "images, points3D = ground-truth surface points and their projections), "
                                         "silhouettes/, gt.ply (docs/colmap.md)", PathKind::Folder);
  cli.add_option("--colmap-points", cx.points, "surface points drawn for points3D (those seen by fewer than 2 views are dropped)")
      .range(1, 10000000);
  cli.add_flag("--colmap-binary", cx.binary, "write the binary model (.bin) instead of the text one");
  cli.add_flag("--colmap-no-silhouettes", colmap_no_sil, "leave silhouettes/ out of the COLMAP workspace");
  return cli.run(argc, argv, [&](StageContext& ctx) {
    // an object or cameras given as a file is an input
    if (std::filesystem::is_regular_file(object)) ctx.add_input(object, "--object");
    if (std::filesystem::is_regular_file(cameras)) ctx.add_input(cameras, "--cameras");
    Params& p = ctx.params;
    if (texture >= 0) p.set("synth.texture=" + std::to_string(texture));
    if (noise >= 0) p.set("synth.noise=" + std::to_string(noise));
    if (seed >= 0) p.set("synth.seed=" + std::to_string(seed));
    synth::SynthConfig c;
    c.object = object;
    c.cameras = cameras;
    c.views = views;
    if (!size.empty()) {
      char x = 0;
      std::istringstream is(size);
      is >> c.width >> x >> c.height;
      require(!is.fail() && x == 'x' && c.width > 0 && c.height > 0, "--size must look like 640x480, got '", size, "'");
    }
    if (!box.empty()) {
      std::istringstream is(box);
      Eigen::Vector3d lo, hi;
      is >> lo.x() >> lo.y() >> lo.z() >> hi.x() >> hi.y() >> hi.z();
      require(!is.fail() && (lo.array() < hi.array()).all(), "--box needs six numbers, min below max: '", box, "'");
      c.box = Eigen::AlignedBox3d(lo, hi);
    }
    read_params(p, c);
    {
      // per rendering thread the supersampled depth and triangle rasters (8 bytes a sample)
      // and the RGB accumulator, mask and PNG (about 24 bytes a pixel); a par file's cameras
      // without --size keep their images' size, which their headers declare (load_rgb checks)
      const double w = c.width ? c.width : 640, h = c.height ? c.height : 480, ss = c.supersample;
      const double bytes = omp_get_max_threads() * w * h * (8.0 * ss * ss + 24.0);
      std::ostringstream what;
      what << "synth: views of " << w << " x " << h << " pixels, synth.supersample " << c.supersample;
      check_memory_budget(p, bytes, what.str(), "use a smaller --size or synth.supersample");
    }
    const nlohmann::json meta = synth::synthesize(c, out);
    info("synth: wrote ", meta["views"].get<int>(), " views of '", object, "' to ", out);
    std::ostringstream s;
    s << "views=" << meta["views"] << " faces=" << meta["gt"]["faces"];
    if (!colmap_dir.empty()) {
      // the export reads the dataset folder: it is committed first (a failing export then
      // leaves the dataset, not the workspace)
      CommitGroup::active()->commit_all();
      cx.seed = c.seed;
      cx.silhouettes = !colmap_no_sil;
      const nlohmann::json e = synth::export_colmap(out, colmap_dir, cx);
      info("synth: COLMAP workspace ", colmap_dir, ": ", e.dump());
      s << " colmap_points=" << e["points"] << " colmap_observations=" << e["observations"];
    }
    ctx.summary = s.str();
  });
}
