#include "common/photo/oriented_point.h"

#include "common/photo/camera_select.h"

namespace tetmvs::photo {

PointResult score_point(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& nf,
                        const Options& opts, Scratch& scratch,
                        std::array<float, kNumOrientations>* per_orientation) {
  PointResult best;
  if (per_orientation) per_orientation->fill(kNoScore);
  const double lf = nf.norm();
  if (!(lf > 0)) return best;
  const Eigen::Vector3d f = nf / lf;
  const Eigen::Vector3d fallback = stable_perpendicular(f);
  detail::prepare_centre(views, X, opts, scratch);
  PatchResult r;
  for (int o = 0; o < kNumOrientations; ++o) {
    const Eigen::Vector3d& n = orientations()[o];
    if (opts.point_grid) {
      // mu x mu grid on the orientation's plane, axes as score_patch's
      const Eigen::Vector3d a1 = stable_perpendicular(n);
      const Eigen::Vector3d a2 = n.cross(a1);
      detail::score_prepared(views, n, a1, &a2, opts, scratch, r);
    } else {
      Eigen::Vector3d d = n.cross(f);
      const double ld = d.norm();
      d = ld > 1e-9 ? Eigen::Vector3d(d / ld) : fallback;
      detail::score_prepared(views, n, d, nullptr, opts, scratch, r);
    }
    if (per_orientation) (*per_orientation)[o] = r.score;
    if (r.valid() && (!best.valid() || r.score > best.score)) {
      static_cast<PatchResult&>(best) = r;
      best.orientation = o;
    }
  }
  return best;
}

void score_points(const Views& views, const double* X, const double* nf, long n, const Options& opts,
                  PointResult* out) {
#pragma omp parallel
  {
    Scratch scratch;
#pragma omp for schedule(dynamic, 64)
    for (long i = 0; i < n; ++i)
      out[i] = score_point(views, Eigen::Vector3d(X[3 * i], X[3 * i + 1], X[3 * i + 2]),
                           Eigen::Vector3d(nf[3 * i], nf[3 * i + 1], nf[3 * i + 2]), opts, scratch);
  }
}

}  // namespace tetmvs::photo
