#include "common/synth/colmap_export.h"

#include <omp.h>

#include <cmath>

#include "common/error.h"
#include "common/fileio.h"
#include "common/image.h"
#include "common/par_io.h"
#include "common/ply.h"
#include "common/trimesh/bvh.h"
#include "common/trimesh/sample.h"

namespace tetmvs::synth {
namespace fs = std::filesystem;

colmap::Model colmap_model(const std::vector<Camera>& cams, const TriMesh& gt, const std::vector<cv::Mat>* rgb,
                           int points, std::uint64_t seed) {
  require(!cams.empty(), "colmap export: no cameras");
  require(points > 0, "colmap export: the number of points must be positive, got ", points);
  colmap::Model m;
  // cameras: one PINHOLE record per distinct K (COLMAP's pixel centres are at +0.5)
  std::vector<std::uint32_t> cam_id(cams.size());
  for (std::size_t i = 0; i < cams.size(); ++i) {
    const Camera& c = cams[i];
    require(c.width > 0 && c.height > 0, "colmap export: camera ", c.name, " has no image size");
    require(c.K(0, 1) == 0 && c.K(1, 0) == 0 && c.K(2, 0) == 0 && c.K(2, 1) == 0 && c.K(2, 2) == 1,
            "colmap export: camera ", c.name, " has skew or a non-standard K; COLMAP's PINHOLE cannot hold it");
    colmap::Intrinsics in;
    in.model = 1;
    in.width = c.width;
    in.height = c.height;
    in.params = {c.K(0, 0), c.K(1, 1), c.K(0, 2) + 0.5, c.K(1, 2) + 0.5};
    std::uint32_t id = 0;
    for (const auto& [k, e] : m.cameras)
      if (e.params == in.params && e.width == in.width && e.height == in.height) id = k;
    if (!id) {
      id = static_cast<std::uint32_t>(m.cameras.size() + 1);
      in.id = id;
      m.cameras.emplace(id, in);
    }
    cam_id[i] = id;
    colmap::Image im;
    im.id = static_cast<std::uint32_t>(i + 1);
    im.q = colmap::rotation_to_quaternion(c.R);
    im.t = c.t;
    im.camera_id = id;
    im.name = c.name;
    m.images.push_back(im);
  }
  // points: area-uniform samples of the surface, observed where visible
  const double spacing = std::sqrt(total_area(gt) / points);
  const SurfaceSamples S = sample_surface(gt, spacing, seed);
  const MeshBVH bvh(gt);
  const int n = static_cast<int>(S.size()), nc = static_cast<int>(cams.size());
  std::vector<std::vector<int>> seen(n);
#pragma omp parallel for schedule(dynamic, 64)
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d& X = S.P[k];
    for (int v = 0; v < nc; ++v) {
      const Camera& c = cams[v];
      if (c.depth(X) <= 0 || !c.sees(X)) continue;
      const Eigen::Vector3d C = c.centre();
      const double d = (X - C).norm();
      const RayHit h = bvh.raycast(C, (X - C) / d, 0, d * (1 - 1e-4));
      if (h.face < 0) seen[k].push_back(v);
    }
  }
  for (int k = 0; k < n; ++k) {
    if (seen[k].size() < 2) continue;
    colmap::Point3D p;
    p.id = m.points.size() + 1;
    p.xyz = S.P[k];
    for (int v : seen[k]) {
      colmap::Image& im = m.images[v];
      const Eigen::Vector2d x = cams[v].project(S.P[k]);
      p.track.push_back({im.id, static_cast<std::uint32_t>(im.points2d.size())});
      im.points2d.push_back({x.x() + 0.5, x.y() + 0.5, p.id});
    }
    if (rgb && !rgb->empty()) {
      const int v = seen[k][0];
      const Eigen::Vector2d x = cams[v].project(S.P[k]);
      const cv::Mat& img = (*rgb)[v];
      const int u = std::clamp(int(std::lround(x.x())), 0, img.cols - 1),
                w = std::clamp(int(std::lround(x.y())), 0, img.rows - 1);
      const cv::Vec3b c = img.at<cv::Vec3b>(w, u);
      for (int j = 0; j < 3; ++j) p.rgb[j] = c[j];
    }
    m.points.push_back(std::move(p));
  }
  return m;
}

nlohmann::json export_colmap(const fs::path& dataset, const fs::path& out, const ColmapExportOptions& o) {
  std::vector<Camera> cams = read_par(find_par_file(dataset));
  std::vector<cv::Mat> rgb(cams.size());
  for (std::size_t i = 0; i < cams.size(); ++i) {
    rgb[i] = load_rgb(dataset / cams[i].name);
    cams[i].width = rgb[i].cols;
    cams[i].height = rgb[i].rows;
  }
  const TriMesh gt = read_ply(dataset / "gt.ply");
  const colmap::Model m = colmap_model(cams, gt, &rgb, o.points, o.seed);
  const auto copy = [](const fs::path& a, const fs::path& b) { write_text_atomic(b, read_file(a)); };
  for (const Camera& c : cams) copy(dataset / c.name, out / "images" / c.name);
  if (o.silhouettes)
    for (const Camera& c : cams)
      if (fs::exists(dataset / "silhouettes" / c.name)) copy(dataset / "silhouettes" / c.name, out / "silhouettes" / c.name);
  copy(dataset / "gt.ply", out / "gt.ply");
  if (o.binary)
    colmap::write_binary_model(out / "sparse", m);
  else
    colmap::write_text_model(out / "sparse", m);
  std::size_t obs = 0;
  for (const auto& p : m.points) obs += p.track.size();
  return {{"images", m.images.size()}, {"cameras", m.cameras.size()}, {"points", m.points.size()}, {"observations", obs}};
}

}  // namespace tetmvs::synth
