// evaluate: Middlebury-style accuracy and completeness of a reconstruction against a
// ground-truth mesh, per region, with mesh checks; JSON (schemas/evaluate.md) and an
// error picture. The stage's work lives in common/eval/run.cpp, the measures in
// common/trimesh/evaluate.cpp.
#include "common/eval/run.h"
#include "common/stage.h"

using namespace tetmvs;

int main(int argc, char** argv) {
  StageCli cli("evaluate",
               "Accuracy (distance within which 90 % of the reconstruction lies) and completeness (share of the "
               "visible ground truth within 1.25 mm) of a reconstruction, per ground-truth region, plus mesh "
               "checks. Writes JSON (schemas/evaluate.md) and optionally a PNG of the reconstruction coloured by "
               "its error. Without --gt: the mesh checks and the surface roughness only.");
  eval::Request q;
  cli.add_input("--mesh", q.mesh, "reconstruction (PLY mesh or point cloud)").required();
  cli.add_input("--gt", q.gt,
                "ground-truth mesh (PLY; optional per-face/vertex 'region'); without it, only the mesh checks and "
                "the roughness");
  cli.add_input("--cameras", q.cameras, "cameras: a par file or scene.h5 (visibility of the ground truth)").required();
  cli.add_output("--out", q.out, "output JSON").required();
  cli.add_output("--png", q.png, "error picture (PNG)");
  cli.add_option("--size", q.size, "image size WxH when the par file's images are not beside it");
  cli.add_option("--thresholds", q.thresholds,
                 "extra completeness thresholds, comma separated (world units), after eval.threshold");
  cli.add_option("--region-box", q.box, "also report the region inside 'minx miny minz maxx maxy maxz'");
  cli.add_input("--labels", q.labels,
                 "also count the hard labels (labels.h5 or silfix.h5) that the ground truth contradicts: interior "
                 "cells outside it, exterior cells inside it (needs --tetmesh)");
  cli.add_input("--tetmesh", q.tetmesh, "the tetrahedral mesh the labels belong to (mesh_<L>.h5)");
  return cli.run(argc, argv, [&](StageContext& ctx) {
    const eval::Plan plan = eval::plan(q, ctx.params);
    const eval::Outcome r = eval::run(q, plan, ctx.params);
    eval::write(q, r);
    ctx.summary = r.summary;
  });
}
