// ingest: a dataset folder (Middlebury layout) -> scene.h5 (schemas/scene.md).
// Step 1 of the pipeline: cameras, images, silhouettes, bounding box.
#include <filesystem>

#include "common/h5io.h"
#include "common/image.h"
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
               "scene.h5: cameras, RGB images, silhouettes and the bounding box.");
  std::string dir, out, sheet;
  cli.app().add_option("dataset", dir, "dataset folder")->required();
  cli.app().add_option("-o,--out", out, "output scene file (HDF5)")->required();
  cli.app().add_option("--contact-sheet", sheet, "also write a PNG of every view with its silhouette outlined");
  return cli.run(argc, argv, [&](StageContext& ctx) {
    info("ingest: reading ", dir);
    Scene s = read_dataset(dir, ctx.params);
    std::vector<fs::path> inputs = {find_par_file(dir)};
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
