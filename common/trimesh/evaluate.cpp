#include "common/trimesh/evaluate.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/trimesh/raster.h"

namespace tetmvs {

void EvalOptions::check() const {
  require(spacing > 0 && std::isfinite(spacing), "evaluate: sample spacing must be > 0, got ", spacing);
  require(!thresholds.empty(), "evaluate: no completeness threshold");
  for (double t : thresholds) require(t >= 0 && std::isfinite(t), "evaluate: bad completeness threshold ", t);
  require(accuracy_fraction > 0 && accuracy_fraction <= 1, "evaluate: accuracy fraction must be in (0, 1], got ",
          accuracy_fraction);
  require(min_views >= 0, "evaluate: min_views must be >= 0, got ", min_views);
  require(visibility_tolerance_px >= 0, "evaluate: visibility tolerance must be >= 0");
  if (region_box) require(!region_box->isEmpty(), "evaluate: empty region box");
}

std::vector<int> count_visible_views(const TriMesh& mesh, const SurfaceSamples& s, const std::vector<Camera>& cams,
                                     double tol_px) {
  const int nc = static_cast<int>(cams.size());
  const std::int64_t n = static_cast<std::int64_t>(s.size());
  std::vector<std::vector<std::uint8_t>> vis(nc);
  std::vector<std::string> errors(nc);
#pragma omp parallel for schedule(dynamic, 1)
  for (int c = 0; c < nc; ++c) {
    try {
      const Camera& cam = cams[c];
      const Raster r = rasterize(mesh, cam);
      const Eigen::Vector3d C = cam.centre();
      const double f = cam.focal();
      std::vector<std::uint8_t>& v = vis[c];
      v.assign(n, 0);
      for (std::int64_t i = 0; i < n; ++i) {
        const Eigen::Vector3d& X = s.P[i];
        const Eigen::Vector3d toC = C - X;
        const double dist = toC.norm();
        const double cosang = s.N[i].dot(toC) / dist;
        if (!(cosang > 0)) continue;
        const double z = cam.depth(X);
        if (!(z > 0)) continue;
        const Eigen::Vector2d p = cam.project(X);
        if (!(p.x() >= -0.5 && p.y() >= -0.5 && p.x() < cam.width - 0.5 && p.y() < cam.height - 0.5)) continue;
        const double tol = tol_px * z / f / std::max(cosang, 0.2);
        const int u0 = std::clamp(static_cast<int>(std::floor(p.x())), 0, cam.width - 1);
        const int v0 = std::clamp(static_cast<int>(std::floor(p.y())), 0, cam.height - 1);
        const int u1 = std::min(u0 + 1, cam.width - 1), v1 = std::min(v0 + 1, cam.height - 1);
        const float dmax = std::max({r.depth.at<float>(v0, u0), r.depth.at<float>(v0, u1), r.depth.at<float>(v1, u0),
                                     r.depth.at<float>(v1, u1)});
        v[i] = dmax >= z - tol;
      }
    } catch (const std::exception& e) {
      errors[c] = e.what();
    }
  }
  for (const auto& e : errors)
    if (!e.empty()) throw Error(e);
  std::vector<int> count(n, 0);
  for (int c = 0; c < nc; ++c)
    for (std::int64_t i = 0; i < n; ++i) count[i] += vis[c][i];
  return count;
}

std::vector<int> face_regions(const TriMesh& gt) {
  std::vector<int> reg(gt.F.size(), 0);
  if (const auto* fp = gt.fprop("region")) {
    for (std::size_t f = 0; f < reg.size(); ++f) reg[f] = static_cast<int>(std::lround((*fp)[f]));
  } else if (const auto* vp = gt.vprop("region")) {
    for (std::size_t f = 0; f < reg.size(); ++f) {
      const int a = std::lround((*vp)[gt.F[f][0]]), b = std::lround((*vp)[gt.F[f][1]]), c = std::lround((*vp)[gt.F[f][2]]);
      reg[f] = (b == c) ? b : a;
    }
  }
  for (int& r : reg) require(r >= 0 && r < 1000, "ground truth: region label ", r, " outside 0..999");
  return reg;
}

namespace {

AccuracyStats accuracy_stats(std::vector<double> d, double fraction) {
  AccuracyStats a;
  a.samples = static_cast<std::int64_t>(d.size());
  if (d.empty()) return a;
  std::sort(d.begin(), d.end());
  auto q = [&](double p) {
    const std::size_t k = static_cast<std::size_t>(std::ceil(p * d.size()));
    return d[std::clamp<std::size_t>(k, 1, d.size()) - 1];
  };
  a.at_fraction = q(fraction);
  a.p50 = q(0.5);
  a.p90 = q(0.9);
  a.p95 = q(0.95);
  double sum = 0;
  for (double x : d) sum += x;
  a.mean = sum / d.size();
  a.max = d.back();
  return a;
}

std::string region_name(int id) {
  switch (id) {
    case 0: return "body";
    case 1: return "cavity";
    case 2: return "protrusion";
    default: return "region_" + std::to_string(id);
  }
}

}  // namespace

EvalResult evaluate(const TriMesh& rec, const TriMesh& gt, const std::vector<Camera>& cams, const EvalOptions& opt) {
  opt.check();
  require(!gt.F.empty(), "evaluate: the ground truth has no faces");
  require(!rec.V.empty(), "evaluate: the reconstruction is empty");
  EvalResult res;
  res.options = opt;
  res.num_cameras = static_cast<int>(cams.size());
  res.rec_is_point_cloud = rec.F.empty();
  res.rec_check = check_mesh(rec);
  res.gt_check = check_mesh(gt);
  res.rec_area = total_area(rec);
  res.gt_area = total_area(gt);
  const std::vector<int> greg = face_regions(gt);
  int max_reg = 0;
  for (int r : greg) max_reg = std::max(max_reg, r);

  // --- completeness: ground-truth samples -> reconstruction ---
  SurfaceSamples gs = sample_surface(gt, opt.spacing, opt.seed);
  require(gs.size() > 0, "evaluate: no ground-truth samples (spacing ", opt.spacing, " too large?)");
  const MeshBVH rbvh(rec);
  const double tmax = *std::max_element(opt.thresholds.begin(), opt.thresholds.end());
  const std::int64_t ng = static_cast<std::int64_t>(gs.size());
  std::vector<double> gd(ng, std::numeric_limits<double>::infinity());
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int64_t i = 0; i < ng; ++i)
    gd[i] = rbvh.closest(gs.P[i], tmax * 1.000001 + 1e-300).dist();  // unseen samples too (within_all)

  // --- accuracy: reconstruction samples -> ground truth ---
  SurfaceSamples rs;
  if (rec.F.empty()) {
    rs.P = rec.V;
    rs.face.assign(rec.V.size(), -1);
  } else {
    rs = sample_surface(rec, opt.spacing, opt.seed + 1);
    if (rs.size() == 0) {  // tiny reconstruction: use its vertices
      rs.P = rec.V;
      rs.face.assign(rec.V.size(), -1);
    }
  }
  const MeshBVH gbvh(gt);
  const std::int64_t nr = static_cast<std::int64_t>(rs.size());
  std::vector<double> rd(nr);
  std::vector<int> rreg(nr);
  std::vector<Eigen::Vector3d> rclosest(nr);
  std::vector<int> rface(nr);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int64_t i = 0; i < nr; ++i) {
    const ClosestHit h = gbvh.closest(rs.P[i]);
    rd[i] = h.dist();
    rreg[i] = greg[h.prim];
    rclosest[i] = h.point;
    rface[i] = h.prim;
  }

  // --- visibility of the ground-truth samples and of the reconstruction samples' closest
  // ground-truth points (appended to gs: one rasterisation per camera for both) ---
  gs.P.insert(gs.P.end(), rclosest.begin(), rclosest.end());
  gs.face.insert(gs.face.end(), rface.begin(), rface.end());
  for (const int f : rface) {
    const Eigen::Vector3i& t = gt.F[f];
    gs.N.push_back((gt.V[t[1]] - gt.V[t[0]]).cross(gt.V[t[2]] - gt.V[t[0]]).normalized());
  }
  std::vector<int> nvis = count_visible_views(gt, gs, cams, opt.visibility_tolerance_px);
  const std::vector<int> rvis(nvis.begin() + ng, nvis.end());
  nvis.resize(ng);

  // --- statistics per region ---
  auto fill = [&](RegionResult& rr, auto&& gt_in, auto&& rec_in) {
    rr.completeness.within.assign(opt.thresholds.size(), 0.0);
    std::vector<std::int64_t> hit(opt.thresholds.size(), 0);
    std::int64_t hit_all = 0;
    for (std::int64_t i = 0; i < ng; ++i) {
      if (!gt_in(i)) continue;
      rr.completeness.gt_samples++;
      hit_all += gd[i] <= opt.thresholds[0];
      if (nvis[i] < opt.min_views) continue;
      rr.completeness.visible_samples++;
      for (std::size_t k = 0; k < opt.thresholds.size(); ++k) hit[k] += gd[i] <= opt.thresholds[k];
    }
    for (std::size_t k = 0; k < opt.thresholds.size(); ++k)
      rr.completeness.within[k] =
          rr.completeness.visible_samples > 0 ? static_cast<double>(hit[k]) / rr.completeness.visible_samples : 0.0;
    rr.completeness.within_all =
        rr.completeness.gt_samples > 0 ? static_cast<double>(hit_all) / rr.completeness.gt_samples : 0.0;
    std::vector<double> d, d_seen;
    for (std::int64_t i = 0; i < nr; ++i)
      if (rec_in(i)) {
        d.push_back(rd[i]);
        if (rvis[i] >= opt.min_views) d_seen.push_back(rd[i]);
      }
    rr.accuracy = accuracy_stats(std::move(d), opt.accuracy_fraction);
    rr.accuracy_seen = accuracy_stats(std::move(d_seen), opt.accuracy_fraction);
  };
  res.all.name = "all";
  fill(res.all, [](std::int64_t) { return true; }, [](std::int64_t) { return true; });
  for (int id = 0; id <= max_reg; ++id) {
    if (std::find(greg.begin(), greg.end(), id) == greg.end()) continue;
    RegionResult rr;
    rr.name = region_name(id);
    rr.id = id;
    fill(rr, [&](std::int64_t i) { return greg[gs.face[i]] == id; }, [&](std::int64_t i) { return rreg[i] == id; });
    res.regions.push_back(std::move(rr));
  }
  if (opt.region_box) {
    RegionResult rr;
    rr.name = "box";
    const Eigen::AlignedBox3d b = *opt.region_box;
    fill(rr, [&](std::int64_t i) { return b.contains(gs.P[i]); }, [&](std::int64_t i) { return b.contains(rclosest[i]); });
    res.regions.push_back(std::move(rr));
  }
  return res;
}

namespace {
nlohmann::json region_json(const RegionResult& r, const EvalOptions& o) {
  nlohmann::json j;
  j["name"] = r.name;
  if (r.id >= 0) j["id"] = r.id;
  nlohmann::json c;
  c["threshold"] = o.thresholds[0];
  c["gt_samples"] = r.completeness.gt_samples;
  c["visible_samples"] = r.completeness.visible_samples;
  if (r.completeness.visible_samples > 0) c["value"] = r.completeness.within[0];
  else c["value"] = nullptr;
  if (r.completeness.gt_samples > 0) {
    c["value_all"] = r.completeness.within_all;
    c["visible_share"] = static_cast<double>(r.completeness.visible_samples) / r.completeness.gt_samples;
  } else {
    c["value_all"] = nullptr;
    c["visible_share"] = nullptr;
  }
  nlohmann::json by = nlohmann::json::array();
  for (std::size_t k = 0; k < o.thresholds.size(); ++k)
    by.push_back({{"threshold", o.thresholds[k]},
                  {"value", r.completeness.visible_samples > 0 ? nlohmann::json(r.completeness.within[k]) : nlohmann::json(nullptr)}});
  c["by_threshold"] = by;
  j["completeness"] = c;
  nlohmann::json a;
  a["fraction"] = o.accuracy_fraction;
  a["samples"] = r.accuracy.samples;
  const bool ok = r.accuracy.samples > 0;
  auto val = [&](double x) { return ok ? nlohmann::json(x) : nlohmann::json(nullptr); };
  a["value"] = val(r.accuracy.at_fraction);
  a["p50"] = val(r.accuracy.p50);
  a["p90"] = val(r.accuracy.p90);
  a["p95"] = val(r.accuracy.p95);
  a["mean"] = val(r.accuracy.mean);
  a["max"] = val(r.accuracy.max);
  a["samples_seen"] = r.accuracy_seen.samples;
  a["value_seen"] = r.accuracy_seen.samples > 0 ? nlohmann::json(r.accuracy_seen.at_fraction) : nlohmann::json(nullptr);
  j["accuracy"] = a;
  return j;
}
}  // namespace

nlohmann::json to_json(const EvalResult& r) {
  nlohmann::json j;
  j["schema"] = "tetmvs.evaluate";
  j["schema_version"] = 1;
  const nlohmann::json all = region_json(r.all, r.options);
  j["accuracy"] = all["accuracy"];
  j["completeness"] = all["completeness"];
  nlohmann::json regs = nlohmann::json::array();
  for (const auto& rr : r.regions) regs.push_back(region_json(rr, r.options));
  j["regions"] = regs;
  j["options"] = {{"sample_spacing", r.options.spacing},
                  {"thresholds", r.options.thresholds},
                  {"accuracy_fraction", r.options.accuracy_fraction},
                  {"min_views", r.options.min_views},
                  {"visibility_tolerance_px", r.options.visibility_tolerance_px},
                  {"seed", r.options.seed}};
  if (r.options.region_box) {
    const auto& b = *r.options.region_box;
    j["options"]["region_box"] = {{b.min().x(), b.min().y(), b.min().z()}, {b.max().x(), b.max().y(), b.max().z()}};
  }
  j["num_cameras"] = r.num_cameras;
  j["reconstruction"] = {{"point_cloud", r.rec_is_point_cloud}, {"area", r.rec_area}, {"check", to_json(r.rec_check)}};
  j["ground_truth"] = {{"area", r.gt_area}, {"check", to_json(r.gt_check)}};
  return j;
}

namespace {
cv::Vec3b ramp(double t) {  // 0 blue, 1/3 green, 2/3 yellow, 1 red
  t = std::clamp(t, 0.0, 1.0);
  double r, g, b;
  if (t < 1.0 / 3) { const double s = 3 * t; r = 0; g = s; b = 1 - s; }
  else if (t < 2.0 / 3) { const double s = 3 * t - 1; r = s; g = 1; b = 0; }
  else { const double s = 3 * t - 2; r = 1; g = 1 - s; b = 0; }
  return cv::Vec3b(static_cast<uchar>(std::lround(255 * r)), static_cast<uchar>(std::lround(255 * g)),
                   static_cast<uchar>(std::lround(255 * b)));
}
}  // namespace

cv::Mat error_picture(const TriMesh& rec, const MeshBVH& gt, const std::vector<Camera>& cams, int views,
                      double max_error) {
  require(!cams.empty(), "error picture: no cameras");
  require(max_error > 0, "error picture: max error must be > 0");
  views = std::clamp(views, 1, static_cast<int>(cams.size()));
  std::vector<int> idx;
  for (int k = 0; k < views; ++k) idx.push_back(static_cast<int>(static_cast<std::size_t>(k) * cams.size() / views));
  const int cols = views <= 1 ? 1 : (views <= 4 ? 2 : (views <= 9 ? 3 : 4));
  const int rows = (views + cols - 1) / cols;
  const int W = cams[idx[0]].width, H = cams[idx[0]].height;
  for (int k : idx) require(cams[k].width == W && cams[k].height == H, "error picture: cameras differ in size");
  const int legend = 40;
  cv::Mat out(rows * H + legend, cols * W, CV_8UC3, cv::Scalar(0, 0, 0));
  std::vector<cv::Mat> tiles(views);
#pragma omp parallel for schedule(dynamic, 1)
  for (int k = 0; k < views; ++k) {
    const Camera& cam = cams[idx[k]];
    cv::Mat tile(H, W, CV_8UC3, cv::Scalar(0, 0, 0));
    const Eigen::Vector3d C = cam.centre();
    if (!rec.F.empty()) {
      const Raster r = rasterize(rec, cam);
      for (int v = 0; v < H; ++v)
        for (int u = 0; u < W; ++u) {
          const int f = r.tri.at<int>(v, u);
          if (f < 0) continue;
          Eigen::Vector3d X;
          if (!pixel_point_on_triangle(rec, f, cam, u, v, X)) continue;
          const double e = gt.closest(X).dist();
          const Eigen::Vector3d n = face_cross(rec, f).normalized();
          const double shade = 0.35 + 0.65 * std::abs(n.dot((C - X).normalized()));
          const cv::Vec3b c = ramp(e / max_error);
          tile.at<cv::Vec3b>(v, u) = cv::Vec3b(c[0] * shade, c[1] * shade, c[2] * shade);
        }
    } else {  // point cloud: nearest point per pixel
      cv::Mat zb(H, W, CV_32F, cv::Scalar(std::numeric_limits<float>::infinity()));
      for (const auto& X : rec.V) {
        const double z = cam.depth(X);
        if (!(z > 0)) continue;
        const Eigen::Vector2d p = cam.project(X);
        const int u = static_cast<int>(std::lround(p.x())), v = static_cast<int>(std::lround(p.y()));
        if (u < 0 || v < 0 || u >= W || v >= H || z >= zb.at<float>(v, u)) continue;
        zb.at<float>(v, u) = static_cast<float>(z);
        tile.at<cv::Vec3b>(v, u) = ramp(gt.closest(X).dist() / max_error);
      }
    }
    cv::putText(tile, cam.name, {8, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(200, 200, 200), 1, cv::LINE_AA);
    tiles[k] = tile;
  }
  for (int k = 0; k < views; ++k) tiles[k].copyTo(out(cv::Rect((k % cols) * W, (k / cols) * H, W, H)));
  // Legend: colour bar from 0 to max_error.
  const int y0 = rows * H + 8, bw = std::min(out.cols - 20, 400);
  for (int x = 0; x < bw; ++x)
    cv::line(out, {10 + x, y0}, {10 + x, y0 + 12}, cv::Scalar(ramp(double(x) / (bw - 1))[0], ramp(double(x) / (bw - 1))[1],
                                                           ramp(double(x) / (bw - 1))[2]));
  char buf[128];
  std::snprintf(buf, sizeof buf, "distance to ground truth: 0 .. %.4g (and above)", max_error);
  cv::putText(out, buf, {10, y0 + 28}, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(220, 220, 220), 1, cv::LINE_AA);
  return out;
}

}  // namespace tetmvs
