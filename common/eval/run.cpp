#include "common/eval/run.h"

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
#include "common/tetmesh/mesh_io.h"
#include "common/trimesh/roughness.h"

namespace fs = std::filesystem;

namespace tetmvs::eval {

namespace {

constexpr double kEvalBytesPerSample = 96;

nlohmann::json roughness_json(const Roughness& r, double radius_px) {
  return {{"radius", r.radius}, {"radius_px", radius_px}, {"samples", r.samples}, {"median", r.median}, {"p90", r.p90}};
}

// No ground truth: the mesh checks and the roughness, a pixel's length taken at the centre of
// the reconstruction's box.
Outcome run_without_truth(const TriMesh& rec, const std::vector<Camera>& cams, const Params& p, const Request& q) {
  require(rec.nv() > 0, q.mesh, ": the mesh has no vertices");
  const auto [lo, hi] = bounds(rec);
  const double px = pixel_footprint(cams, 0.5 * (lo + hi));
  require(std::isfinite(px) && px > 0, q.cameras, ": the cameras give no pixel size at the mesh");
  const double radius_px = p.d("eval.roughness_radius_px");
  const Roughness rough = surface_roughness_px(rec, cams, radius_px);
  const MeshCheck check = check_mesh(rec);
  Outcome out;
  nlohmann::json& j = out.json;
  j["schema"] = "tetmvs.evaluate";
  j["schema_version"] = 1;
  j["num_cameras"] = static_cast<int>(cams.size());
  j["pixel_size"] = px;
  j["reconstruction"] = {{"point_cloud", rec.nf() == 0}, {"area", total_area(rec)}, {"check", to_json(check)}};
  j["roughness"] = roughness_json(rough, radius_px);
  j["inputs"] = {{"mesh", q.mesh}, {"cameras", q.cameras}};
  j["params"] = p.values_for("evaluate");
  std::ostringstream s;
  s.precision(4);
  s << "no ground truth: " << rec.nv() << " vertices, " << check.components.size() << " components, "
    << (check.closed ? "closed" : "open") << ", roughness=" << rough.median << " (" << rough.median / px
    << " px) within radius " << rough.radius;
  out.summary = s.str();
  return out;
}

// The hard labels the ground truth contradicts (--labels with --tetmesh).
label::LabelTruth label_truth(const Request& q, const TriMesh& g) {
  // the ground truth is checked before the tet mesh (millions of cells) is read
  require(g.nf() > 0, q.gt, ": --labels needs a ground-truth mesh with faces");
  require(check_mesh(g).closed, q.gt,
          ": --labels needs a closed ground-truth mesh (inside and outside are told by counting a ray's "
          "crossings), this one has boundary or non-manifold edges");
  const tet::TetMesh m = tet::read_mesh(q.tetmesh);
  const auto lab = cut::read_labels(q.labels, m.num_cells());
  auto lf = h5::File::open(q.labels, "tetmvs.labels");
  std::vector<std::uint8_t> reason;
  if (lf.has("/cells/reason")) reason = lf.read<std::uint8_t>("/cells/reason", {m.num_cells()}).data;
  return label::check_labels(m, lab, reason, MeshBVH(g));
}

// Surface samples (area / spacing^2 each): position, normal, face, distances, and for both
// (the ground truth's, and the reconstruction's closest ground-truth points) one visibility
// byte per camera; plus one depth and one triangle raster
// (8 bytes a pixel) per thread.
void check_budget(const TriMesh& rec, const TriMesh& g, const std::vector<Camera>& cams, const EvalOptions& o,
                  double px, const Params& p, const std::string& cameras) {
  const double s2 = o.spacing * o.spacing;
  const double ng = total_area(g) / s2, nr = rec.nf() > 0 ? total_area(rec) / s2 : rec.nv();
  const double raster = 8.0 * cams[0].width * static_cast<double>(cams[0].height);
  const double bytes = (ng + nr) * (kEvalBytesPerSample + static_cast<double>(cams.size())) +
                       omp_get_max_threads() * raster;
  std::ostringstream what;
  what << "evaluate: about " << ng + nr << " surface samples at eval.sample_spacing_px " << o.spacing / px << " ("
       << o.spacing << " world units), " << cams[0].width << " x " << cams[0].height << " pixel views (" << cameras
       << ")";
  check_memory_budget(p, bytes, what.str(), "raise eval.sample_spacing_px, or give --size");
}

std::string summary_line(const EvalResult& r, const EvalOptions& o, const Roughness& rough,
                         const std::optional<label::LabelTruth>& truth) {
  std::ostringstream s;
  s.precision(4);
  s << "accuracy" << static_cast<int>(100 * o.accuracy_fraction) << "=";
  if (r.all.accuracy.samples > 0) s << r.all.accuracy.at_fraction; else s << "none";
  if (r.all.accuracy_seen.samples > 0 && r.all.accuracy_seen.samples < r.all.accuracy.samples)
    s << " (seen part " << r.all.accuracy_seen.at_fraction << ")";
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
  return s.str();
}

}  // namespace

std::vector<Camera> load_cameras(const std::string& file, int w, int h) {
  const fs::path f = file;
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
    // the size its header declares (the memory budget covers it), else decoded
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

Plan plan(const Request& q, const Params& p) {
  require(q.png.empty() || p.i("eval.png_views") > 0, "--png needs eval.png_views > 0");
  Plan pl;
  if (!q.size.empty()) {
    char x = 0;
    std::istringstream is(q.size);
    is >> pl.width >> x >> pl.height;
    require(!is.fail() && x == 'x' && pl.width > 0 && pl.height > 0, "--size must look like 640x480, got '", q.size,
            "'");
  }
  EvalOptions& o = pl.options;
  o.thresholds = {p.d("eval.threshold")};
  if (!q.thresholds.empty()) {
    std::stringstream ss(q.thresholds);
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
  if (!q.box.empty()) {
    std::istringstream is(q.box);
    Eigen::Vector3d lo, hi;
    is >> lo.x() >> lo.y() >> lo.z() >> hi.x() >> hi.y() >> hi.z();
    require(!is.fail() && (lo.array() < hi.array()).all(), "--region-box needs six numbers, min below max");
    o.region_box = Eigen::AlignedBox3d(lo, hi);
  }
  require(q.labels.empty() == q.tetmesh.empty(), "--labels and --tetmesh go together (labels.h5 with its mesh_<L>.h5)");
  require(!q.gt.empty() || (q.png.empty() && q.labels.empty() && q.thresholds.empty() && q.box.empty()),
          "--png, --labels, --thresholds and --region-box compare with a ground truth: give --gt");
  return pl;
}

Outcome run(const Request& q, const Plan& plan, const Params& p) {
  const TriMesh rec = read_ply(q.mesh);
  if (q.gt.empty()) return run_without_truth(rec, load_cameras(q.cameras, plan.width, plan.height), p, q);
  const TriMesh g = read_ply(q.gt);
  std::optional<label::LabelTruth> truth;
  if (!q.labels.empty()) truth = label_truth(q, g);
  const std::vector<Camera> cams = load_cameras(q.cameras, plan.width, plan.height);
  // lengths given in pixels are taken at the ground truth's centre
  require(g.nv() > 0, q.gt, ": the ground truth has no vertices");
  const auto [glo, ghi] = bounds(g);
  const double px = pixel_footprint(cams, 0.5 * (glo + ghi));
  require(std::isfinite(px) && px > 0, q.cameras, ": the cameras give no pixel size at the ground truth");
  EvalOptions o = plan.options;
  o.spacing = p.d("eval.sample_spacing_px") * px;
  const double threshold_px = o.thresholds[0] / px;
  if (threshold_px < 0.1 || threshold_px > 100)
    warn("eval.threshold = ", o.thresholds[0], " world units is ", threshold_px,
         " pixels at the object: is it in the scene's units? (1.25 mm is 0.00125 in metres, 1.25 in millimetres)");
  check_budget(rec, g, cams, o, px, p, q.cameras);
  const EvalResult r = evaluate(rec, g, cams, o);
  const double radius_px = p.d("eval.roughness_radius_px");
  const Roughness rough = surface_roughness_px(rec, cams, radius_px);
  Outcome out;
  nlohmann::json& j = out.json;
  j = to_json(r);
  j["roughness"] = roughness_json(rough, radius_px);
  j["pixel_size"] = px;
  j["inputs"] = {{"mesh", q.mesh}, {"gt", q.gt}, {"cameras", q.cameras}};
  if (truth) {
    j["labels"] = label::to_json(*truth);
    j["inputs"]["labels"] = q.labels;
    j["inputs"]["tetmesh"] = q.tetmesh;
  }
  j["params"] = p.values_for("evaluate");
  if (!q.png.empty())
    out.picture = error_picture(rec, MeshBVH(g), cams, p.i("eval.png_views"), p.d("eval.png_max_error_px") * px);
  out.summary = summary_line(r, o, rough, truth);
  return out;
}

void write(const Request& q, const Outcome& r) {
  write_text_atomic(q.out, r.json.dump(2) + "\n");
  if (!q.png.empty()) write_png_rgb(q.png, r.picture);
}

}  // namespace tetmvs::eval
