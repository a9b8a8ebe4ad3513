// ingest: a dataset folder (Middlebury layout) or a COLMAP workspace/model -> scene.h5
// (schemas/scene.md).
// Step 1 of the pipeline: cameras, images, silhouettes, bounding box.
#include <filesystem>

#include "common/h5io.h"
#include "common/image.h"
#include "common/ingest/colmap.h"
#include "common/ingest/dataset.h"
#include "common/par_io.h"
#include "common/scene.h"
#include "common/stage.h"

namespace fs = std::filesystem;
using namespace tetmvs;

int main(int argc, char** argv) {
  StageCli cli("ingest",
               "Reads a dataset folder (one <prefix>_par.txt, the images it names, optional "
               "silhouettes/, *_good_silhouette_images.txt, README.txt or bbox.txt) and writes "
               "scene.h5: cameras, RGB images, silhouettes and the bounding box. A COLMAP workspace "
               "(images/ + sparse/ or sparse/0/, text or binary model) or model folder is recognised "
               "and read instead (docs/colmap.md).");
  std::string dir, out, sheet;
  cli.add_input("dataset", dir, "dataset folder", PathKind::Folder).required();
  cli.add_output("-o,--out", out, "output scene file (HDF5)").required();
  cli.add_output("--contact-sheet", sheet, "also write a PNG of every view with its silhouette outlined");
  return cli.run(argc, argv, [&](StageContext& ctx) {
    info("ingest: reading ", dir);
    Scene s;
    std::vector<fs::path> inputs;
    if (const auto layout = colmap::find_layout(dir)) {
      info("ingest: COLMAP model ", layout->model_dir.string(), ", images in ", layout->image_dir.string());
      const fs::path& md = layout->model_dir;
      const bool bin = fs::exists(md / "cameras.bin") && fs::exists(md / "images.bin") && fs::exists(md / "points3D.bin");
      for (const char* f : {"cameras", "images", "points3D"}) inputs.push_back(md / (std::string(f) + (bin ? ".bin" : ".txt")));
      for (const auto& i : inputs) ctx.add_input(i, "COLMAP model file");
      s = colmap::read_scene(*layout, ctx.params);
    } else {
      inputs = {find_par_file(dir)};
      ctx.add_input(inputs[0], "camera file");
      s = read_dataset(dir, ctx.params);
    }
    for (const auto& w : check_scene_images(s, dir)) warn(w);  // refuses when all are uniform
    auto f = h5::File::create(out);
    f.write_header(kSceneSchema, kSceneVersion, "ingest", ctx.params.values_for("ingest"), inputs);
    write_scene(f, s);
    f.commit();
    if (!sheet.empty()) write_png_rgb(sheet, contact_sheet(s));
    const Eigen::Vector3d lo = s.box.min(), hi = s.box.max();
    std::ostringstream os;
    os << s.size() << " views " << s.cams[0].width << "x" << s.cams[0].height << ", "
       << s.num_silhouettes() << " silhouettes, box (" << lo.transpose() << ") - (" << hi.transpose()
       << ") from " << s.box_source;
    ctx.summary = os.str();
  });
}
