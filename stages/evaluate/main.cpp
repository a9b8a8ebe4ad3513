// evaluate: Middlebury-style accuracy and completeness of a reconstruction against a
// ground-truth mesh, per region, with mesh checks; JSON (schemas/evaluate.md) and an
// error picture. The work lives in common/trimesh/evaluate.cpp.
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>

#include "common/budget.h"
#include "common/cut/inputs.h"
#include "common/error.h"
#include "common/fileio.h"
#include "common/h5io.h"
#include "common/image.h"
#include "common/label/truth.h"
#include "common/log.h"
#include "common/par_io.h"
#include "common/ply.h"
#include "common/scene.h"
#include "common/stage.h"
#include "common/tetmesh/mesh_io.h"
#include "common/trimesh/evaluate.h"
#include "common/trimesh/roughness.h"

namespace fs = std::filesystem;

constexpr double kEvalBytesPerSample = 96;

namespace {
// Cameras from a par file (image size from the first image beside it, or --size) or scene.h5.
std::vector<tetmvs::Camera> load_cameras(const fs::path& f, int w, int h) {
  using namespace tetmvs;
  if (f.extension() == ".h5") {
    Scene s = read_scene(f, false);
    if (w > 0)
      for (auto& c : s.cams) c.width = w, c.height = h;
    return s.cams;
  }
  std::vector<Camera> cams = read_par(f);
  if (w <= 0) {
    const fs::path first = f.parent_path() / cams[0].name;
    require(fs::exists(first), f.string(), ": image size unknown (", first.string(),
            " is not there): give --size WxH");
    // the size its header declares (the memory budget below covers it), else decoded
    if (const auto d = read_image_size(first)) {
      require(d->width > 0 && d->height > 0 && d->width <= (1 << 30) && d->height <= (1 << 30), first.string(),
              ": the image header declares ", d->width, " x ", d->height, " pixels; give --size WxH");
      w = static_cast<int>(d->width);
      h = static_cast<int>(d->height);
    } else {
      const cv::Mat im = load_rgb(first);
      w = im.cols;
      h = im.rows;
    }
  }
  for (auto& c : cams) c.width = w, c.height = h;
  return cams;
}

nlohmann::json roughness_json(const tetmvs::Roughness& r, double radius_px) {
  return {{"radius", r.radius}, {"radius_px", radius_px}, {"samples", r.samples}, {"median", r.median}, {"p90", r.p90}};
}

// No ground truth: the mesh checks and the roughness, a pixel's length taken at the centre of
// the reconstruction's box. Returns the summary line.
std::string write_without_truth(const tetmvs::TriMesh& rec, const std::vector<tetmvs::Camera>& cams,
                                const tetmvs::Params& p, const std::string& mesh, const std::string& cameras,
                                const std::string& out) {
  using namespace tetmvs;
  require(rec.nv() > 0, mesh, ": the mesh has no vertices");
  const auto [lo, hi] = bounds(rec);
  const double px = pixel_footprint(cams, 0.5 * (lo + hi));
  require(std::isfinite(px) && px > 0, cameras, ": the cameras give no pixel size at the mesh");
  const double radius_px = p.d("eval.roughness_radius_px");
  const Roughness rough = surface_roughness_px(rec, cams, radius_px);
  const MeshCheck check = check_mesh(rec);
  nlohmann::json j;
  j["schema"] = "tetmvs.evaluate";
  j["schema_version"] = 1;
  j["num_cameras"] = static_cast<int>(cams.size());
  j["pixel_size"] = px;
  j["reconstruction"] = {{"point_cloud", rec.nf() == 0}, {"area", total_area(rec)}, {"check", to_json(check)}};
  j["roughness"] = roughness_json(rough, radius_px);
  j["inputs"] = {{"mesh", mesh}, {"cameras", cameras}};
  j["params"] = p.values_for("evaluate");
  write_text_atomic(out, j.dump(2) + "\n");
  std::ostringstream s;
  s.precision(4);
  s << "no ground truth: " << rec.nv() << " vertices, " << check.components.size() << " components, "
    << (check.closed ? "closed" : "open") << ", roughness=" << rough.median << " (" << rough.median / px
    << " px) within radius " << rough.radius;
  return s.str();
}
}  // namespace

int main(int argc, char** argv) {
  using namespace tetmvs;
  StageCli cli("evaluate",
               "Accuracy (distance within which 90 % of the reconstruction lies) and completeness (share of the "
               "visible ground truth within 1.25 mm) of a reconstruction, per ground-truth region, plus mesh "
               "checks. Writes JSON (schemas/evaluate.md) and optionally a PNG of the reconstruction coloured by "
               "its error. Without --gt: the mesh checks and the surface roughness only.");
  std::string mesh, gt, cameras, out, png, size, box, thresholds, labels, tetmesh;
  auto& app = cli.app();
  cli.add_input("--mesh", mesh, "reconstruction (PLY mesh or point cloud)")->required();
  cli.add_input("--gt", gt,
                "ground-truth mesh (PLY; optional per-face/vertex 'region'); without it, only the mesh checks and "
                "the roughness");
  cli.add_input("--cameras", cameras, "cameras: a par file or scene.h5 (visibility of the ground truth)")->required();
  cli.add_output("--out", out, "output JSON")->required();
  cli.add_output("--png", png, "error picture (PNG)");
  app.add_option("--size", size, "image size WxH when the par file's images are not beside it");
  app.add_option("--thresholds", thresholds,
                 "extra completeness thresholds, comma separated (world units), after eval.threshold");
  app.add_option("--region-box", box, "also report the region inside 'minx miny minz maxx maxy maxz'");
  cli.add_input("--labels", labels,
                 "also count the hard labels (labels.h5 or silfix.h5) that the ground truth contradicts: interior "
                 "cells outside it, exterior cells inside it (needs --tetmesh)");
  cli.add_input("--tetmesh", tetmesh, "the tetrahedral mesh the labels belong to (mesh_<L>.h5)");
  return cli.run(argc, argv, [&](StageContext& ctx) {
    const Params& p = ctx.params;
    require(png.empty() || p.i("eval.png_views") > 0, "--png needs eval.png_views > 0");
    int w = 0, h = 0;
    if (!size.empty()) {
      char x = 0;
      std::istringstream is(size);
      is >> w >> x >> h;
      require(!is.fail() && x == 'x' && w > 0 && h > 0, "--size must look like 640x480, got '", size, "'");
    }
    EvalOptions o;
    o.thresholds = {p.d("eval.threshold")};
    if (!thresholds.empty()) {
      std::stringstream ss(thresholds);
      std::string tok;
      while (std::getline(ss, tok, ',')) {
        std::size_t used = 0;
        double t = -1;
        try {
          t = std::stod(tok, &used);
        } catch (const std::exception&) {
        }
        require(used == tok.size() && t >= 0, "--thresholds: bad value '", tok, "'");
        o.thresholds.push_back(t);
      }
    }
    o.accuracy_fraction = p.d("eval.accuracy_fraction");
    o.min_views = p.i("eval.min_views");
    o.visibility_tolerance_px = p.d("eval.visibility_tolerance_px");
    o.seed = static_cast<std::uint64_t>(p.i("eval.seed"));
    if (!box.empty()) {
      std::istringstream is(box);
      Eigen::Vector3d lo, hi;
      is >> lo.x() >> lo.y() >> lo.z() >> hi.x() >> hi.y() >> hi.z();
      require(!is.fail() && (lo.array() < hi.array()).all(), "--region-box needs six numbers, min below max");
      o.region_box = Eigen::AlignedBox3d(lo, hi);
    }
    require(labels.empty() == tetmesh.empty(), "--labels and --tetmesh go together (labels.h5 with its mesh_<L>.h5)");
    require(!gt.empty() || (png.empty() && labels.empty() && thresholds.empty() && box.empty()),
            "--png, --labels, --thresholds and --region-box compare with a ground truth: give --gt");
    const TriMesh rec = read_ply(mesh);
    if (gt.empty()) {
      const std::vector<Camera> cams = load_cameras(cameras, w, h);
      ctx.summary = write_without_truth(rec, cams, p, mesh, cameras, out);
      return;
    }
    const TriMesh g = read_ply(gt);
    std::optional<label::LabelTruth> truth;
    if (!labels.empty()) {
      // the ground truth is checked before the tet mesh (millions of cells) is read
      require(g.nf() > 0, gt, ": --labels needs a ground-truth mesh with faces");
      require(check_mesh(g).closed, gt,
              ": --labels needs a closed ground-truth mesh (inside and outside are told by counting a ray's "
              "crossings), this one has boundary or non-manifold edges");
      const tet::TetMesh m = tet::read_mesh(tetmesh);
      const auto lab = cut::read_labels(labels, m.num_cells());
      auto lf = h5::File::open(labels, "tetmvs.labels");
      std::vector<std::uint8_t> reason;
      if (lf.has("/cells/reason")) reason = lf.read<std::uint8_t>("/cells/reason", {m.num_cells()}).data;
      truth = label::check_labels(m, lab, reason, MeshBVH(g));
    }
    const std::vector<Camera> cams = load_cameras(cameras, w, h);
    // lengths given in pixels are taken at the ground truth's centre
    require(g.nv() > 0, gt, ": the ground truth has no vertices");
    const auto [glo, ghi] = bounds(g);
    const double px = pixel_footprint(cams, 0.5 * (glo + ghi));
    require(std::isfinite(px) && px > 0, cameras, ": the cameras give no pixel size at the ground truth");
    o.spacing = p.d("eval.sample_spacing_px") * px;
    const double threshold_px = o.thresholds[0] / px;
    if (threshold_px < 0.1 || threshold_px > 100)
      warn("eval.threshold = ", o.thresholds[0], " world units is ", threshold_px,
           " pixels at the object: is it in the scene's units? (1.25 mm is 0.00125 in metres, 1.25 in millimetres)");
    {
      // surface samples (area / spacing^2 each): position, normal, face, distances, and for
      // the ground truth's one visibility byte per camera; plus one depth and one triangle
      // raster (8 bytes a pixel) per thread
      const double s2 = o.spacing * o.spacing;
      const double ng = total_area(g) / s2, nr = rec.nf() > 0 ? total_area(rec) / s2 : rec.nv();
      const double raster = 8.0 * cams[0].width * static_cast<double>(cams[0].height);
      const double bytes = ng * (kEvalBytesPerSample + static_cast<double>(cams.size())) + nr * kEvalBytesPerSample +
                           omp_get_max_threads() * raster;
      std::ostringstream what;
      what << "evaluate: about " << ng + nr << " surface samples at eval.sample_spacing_px " << o.spacing / px << " ("
           << o.spacing << " world units), "
           << cams[0].width << " x " << cams[0].height << " pixel views (" << cameras << ")";
      check_memory_budget(p, bytes, what.str(), "raise eval.sample_spacing_px, or give --size");
    }
    const EvalResult r = evaluate(rec, g, cams, o);
    const double radius_px = p.d("eval.roughness_radius_px");
    const Roughness rough = surface_roughness_px(rec, cams, radius_px);
    nlohmann::json j = to_json(r);
    j["roughness"] = roughness_json(rough, radius_px);
    j["pixel_size"] = px;
    j["inputs"] = {{"mesh", mesh}, {"gt", gt}, {"cameras", cameras}};
    if (truth) {
      j["labels"] = label::to_json(*truth);
      j["inputs"]["labels"] = labels;
      j["inputs"]["tetmesh"] = tetmesh;
    }
    j["params"] = p.values_for("evaluate");
    write_text_atomic(out, j.dump(2) + "\n");
    if (!png.empty()) {
      write_png_rgb(png, error_picture(rec, MeshBVH(g), cams, p.i("eval.png_views"), p.d("eval.png_max_error_px") * px));
    }
    std::ostringstream s;
    s.precision(4);
    s << "accuracy" << static_cast<int>(100 * o.accuracy_fraction) << "=";
    if (r.all.accuracy.samples > 0) s << r.all.accuracy.at_fraction; else s << "none";
    s << " completeness=" << 100 * r.all.completeness.within[0] << "%";
    for (const auto& rr : r.regions)
      if (rr.completeness.visible_samples > 0) {
        s << " " << rr.name << "=" << 100 * rr.completeness.within[0] << "%";
        if (rr.completeness.visible_samples < rr.completeness.gt_samples)  // part unseen: also over all of it
          s << " (all " << 100 * rr.completeness.within_all << "%, seen " << 100.0 * rr.completeness.visible_samples / rr.completeness.gt_samples << "%)";
      }
    s << " roughness=" << rough.median << " (radius " << rough.radius << ")";
    if (truth)
      s << " wrong labels: " << truth->interior.wrong << " interior (" << truth->interior.wrong_whole << " wholly), "
        << truth->exterior.wrong << " exterior (" << truth->exterior.wrong_whole << " wholly)";
    ctx.summary = s.str();
  });
}
