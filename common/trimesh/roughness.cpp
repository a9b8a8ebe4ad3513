#include "common/trimesh/roughness.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "common/error.h"

namespace tetmvs {

namespace {
constexpr int kRoughMinNeighbours = 6;

struct RoughCell {
  std::int64_t x, y, z;
  bool operator==(const RoughCell& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct RoughCellHash {
  std::size_t operator()(const RoughCell& k) const {
    return static_cast<std::size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
  }
};
}  // namespace

Roughness surface_roughness(const TriMesh& mesh, double radius, int max_samples) {
  require(std::isfinite(radius) && radius > 0, "surface_roughness: radius ", radius, " must be positive");
  require(max_samples > 0, "surface_roughness: max_samples must be positive");
  Roughness r;
  r.radius = radius;
  const std::int64_t nv = static_cast<std::int64_t>(mesh.nv());
  if (nv == 0) return r;
  // uniform grid of cells one radius wide: vertex ids sorted by cell, one range per cell
  const auto key_of = [&](const Eigen::Vector3d& p) {
    return RoughCell{static_cast<std::int64_t>(std::floor(p.x() / radius)),
                   static_cast<std::int64_t>(std::floor(p.y() / radius)),
                   static_cast<std::int64_t>(std::floor(p.z() / radius))};
  };
  std::unordered_map<RoughCell, std::vector<int>, RoughCellHash> grid;
  for (std::int64_t v = 0; v < nv; ++v) grid[key_of(mesh.V[v])].push_back(static_cast<int>(v));

  const std::int64_t stride = std::max<std::int64_t>(1, (nv + max_samples - 1) / max_samples);
  const std::int64_t ns = (nv + stride - 1) / stride;
  std::vector<double> rms(ns, -1.0);
  const double r2 = radius * radius;
#pragma omp parallel for schedule(dynamic, 64)
  for (std::int64_t s = 0; s < ns; ++s) {
    const Eigen::Vector3d& c = mesh.V[s * stride];
    const RoughCell k = key_of(c);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d sq = Eigen::Matrix3d::Zero();
    int n = 0;
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find(RoughCell{k.x + dx, k.y + dy, k.z + dz});
          if (it == grid.end()) continue;
          for (int v : it->second) {
            const Eigen::Vector3d d = mesh.V[v] - c;  // relative to the sample: no cancellation
            if (d.squaredNorm() > r2) continue;
            sum += d;
            sq += d * d.transpose();
            ++n;
          }
        }
    if (n < kRoughMinNeighbours) continue;
    const Eigen::Vector3d mean = sum / n;
    const Eigen::Matrix3d cov = sq / n - mean * mean.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov, Eigen::EigenvaluesOnly);
    rms[s] = std::sqrt(std::max(0.0, es.eigenvalues()(0)));  // mean squared distance to the best plane
  }
  std::vector<double> v;
  v.reserve(ns);
  for (double x : rms)
    if (x >= 0) v.push_back(x);
  r.samples = static_cast<std::int64_t>(v.size());
  if (v.empty()) return r;
  std::sort(v.begin(), v.end());
  r.median = v[(v.size() - 1) / 2];
  r.p90 = v[std::min(v.size() - 1, static_cast<std::size_t>(std::ceil(0.9 * v.size())) - 1)];
  return r;
}

Roughness surface_roughness_px(const TriMesh& mesh, const std::vector<Camera>& cams, double radius_px,
                               int max_samples) {
  if (mesh.nv() == 0) return Roughness{};
  Eigen::AlignedBox3d box;
  for (const auto& p : mesh.V) box.extend(p);
  return surface_roughness(mesh, radius_px * pixel_footprint(cams, box.center()), max_samples);
}

}  // namespace tetmvs
