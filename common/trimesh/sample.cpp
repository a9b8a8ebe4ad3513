#include "common/trimesh/sample.h"

#include <cmath>

#include "common/error.h"
#include "common/trimesh/rng.h"

namespace tetmvs {

SurfaceSamples sample_surface(const TriMesh& m, double spacing, std::uint64_t seed) {
  require(spacing > 0 && std::isfinite(spacing), "sample_surface: spacing must be > 0, got ", spacing);
  const std::int64_t nf = static_cast<std::int64_t>(m.F.size());
  const double density = 1.0 / (spacing * spacing);
  std::vector<std::int64_t> count(nf + 1, 0);
#pragma omp parallel for schedule(static)
  for (std::int64_t f = 0; f < nf; ++f) {
    Rng r(seed, static_cast<std::uint64_t>(f));
    const double a = face_area(m, f);
    count[f + 1] = a > 0 ? static_cast<std::int64_t>(std::floor(a * density + r.uniform())) : 0;
  }
  for (std::int64_t f = 0; f < nf; ++f) count[f + 1] += count[f];
  const std::int64_t total = count[nf];
  require(total < (std::int64_t(1) << 31), "sample_surface: ", total, " samples is too many (spacing ", spacing, ")");
  SurfaceSamples s;
  s.P.resize(total);
  s.N.resize(total);
  s.face.resize(total);
#pragma omp parallel for schedule(static)
  for (std::int64_t f = 0; f < nf; ++f) {
    if (count[f + 1] == count[f]) continue;
    Rng r(seed, static_cast<std::uint64_t>(f));
    r.uniform();  // the one used for the count
    const Eigen::Vector3d &a = m.V[m.F[f][0]], &b = m.V[m.F[f][1]], &c = m.V[m.F[f][2]];
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    for (std::int64_t i = count[f]; i < count[f + 1]; ++i) {
      const double r1 = std::sqrt(r.uniform()), r2 = r.uniform();
      s.P[i] = (1 - r1) * a + r1 * (1 - r2) * b + r1 * r2 * c;
      s.N[i] = n;
      s.face[i] = static_cast<int>(f);
    }
  }
  return s;
}

}  // namespace tetmvs
