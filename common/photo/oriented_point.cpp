#include "common/photo/oriented_point.h"

#include "common/photo/camera_select.h"

#include <algorithm>

namespace tetmvs::photo {

namespace {
// The in-plane axes of orientation n's patch at a point of a face of unit normal f:
// a grid's two axes, or the line's direction n x f (a stable perpendicular of f when n || f).
void patch_axes(const Eigen::Vector3d& n, const Eigen::Vector3d& f, bool grid, Eigen::Vector3d& a1, Eigen::Vector3d& a2) {
  if (grid) {
    a1 = stable_perpendicular(n);
    a2 = n.cross(a1);
  } else {
    const Eigen::Vector3d d = n.cross(f);
    const double ld = d.norm();
    a1 = ld > 1e-9 ? Eigen::Vector3d(d / ld) : stable_perpendicular(f);
    a2 = Eigen::Vector3d::Zero();
  }
}
}  // namespace

PointResult score_point(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& nf,
                        const Options& opts, Scratch& scratch,
                        std::array<float, kNumOrientations>* per_orientation, std::uint16_t orientation_mask) {
  PointResult best;
  if (per_orientation) per_orientation->fill(kNoScore);
  const double lf = nf.norm();
  if (!(lf > 0)) return best;
  const Eigen::Vector3d f = nf / lf;
  detail::prepare_centre(views, X, opts, scratch);
  PatchResult r;
  Eigen::Vector3d a1, a2;
  for (int o = 0; o < kNumOrientations; ++o) {
    if (!(orientation_mask >> o & 1u)) continue;
    const Eigen::Vector3d& n = orientations()[o];
    // a grid on the orientation's plane (axes as score_patch's), or the line on the face plane
    patch_axes(n, f, opts.point_grid, a1, a2);
    detail::score_prepared(views, n, a1, opts.point_grid ? &a2 : nullptr, opts, scratch, r);
    if (per_orientation) (*per_orientation)[o] = r.score;
    if (r.valid() && (!best.valid() || r.score > best.score)) {
      static_cast<PatchResult&>(best) = r;
      best.orientation = o;
    }
  }
  return best;
}

PointResult score_orientation(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& nf, int o,
                              const Options& opts, Scratch& scratch) {
  PointResult out;
  const double lf = nf.norm();
  if (!(lf > 0) || o < 0 || o >= kNumOrientations) return out;
  detail::prepare_centre(views, X, opts, scratch);
  const Eigen::Vector3d& n = orientations()[o];
  Eigen::Vector3d a1, a2;
  patch_axes(n, nf / lf, opts.point_grid, a1, a2);
  detail::score_prepared(views, n, a1, opts.point_grid ? &a2 : nullptr, opts, scratch, out);
  if (out.valid()) out.orientation = o;
  return out;
}

float score_offset(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& nf, const PointResult& best,
                   double t, const Options& opts, Scratch& scratch) {
  if (!best.valid()) return kNoScore;
  const Eigen::Vector3d& n = orientations()[best.orientation];
  Eigen::Vector3d a1, a2;
  patch_axes(n, nf.normalized(), opts.point_grid, a1, a2);
  PatchResult r;
  detail::score_in_views(views, X + (t * static_cast<double>(best.spacing)) * n, a1, opts.point_grid ? &a2 : nullptr,
                         best.spacing, best.views.data(), best.num_views, best.num_partners, opts, scratch, r);
  return r.valid() ? r.score : kNoScore;
}

double peak_offset(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& nf, const PointResult& best,
                   const Options& opts, Scratch& scratch, int steps, float* peak_score) {
  if (peak_score) *peak_score = best.score;
  if (!best.valid() || steps < 1 || steps > 16) return 0;
  const auto at = [&](int t) { return score_offset(views, X, nf, best, t, opts, scratch); };
  // Hill climb from 0 toward the higher neighbour, at most `steps` samples (the score is
  // unimodal across the band); lo and hi end as the scores next to the crest b (kNoScore
  // at the end of the range: no parabola there).
  float lo = at(-1), c = best.score, hi = at(1);
  int b = 0;
  if (hi > c || lo > c) {
    const int dir = hi > lo ? 1 : -1;
    float back = c, fwd = kNoScore;
    b = dir;
    c = dir > 0 ? hi : lo;
    while (std::abs(b) < steps) {
      fwd = at(b + dir);
      if (!(fwd > c)) break;
      back = c;
      c = fwd;
      b += dir;
      fwd = kNoScore;
    }
    lo = dir > 0 ? back : fwd;
    hi = dir > 0 ? fwd : back;
  }
  if (peak_score) *peak_score = c;
  double off = b;
  if (lo != kNoScore && hi != kNoScore) {
    const double den = static_cast<double>(lo) - 2.0 * c + hi;
    if (den < 0) off += std::clamp(0.5 * (static_cast<double>(lo) - hi) / den, -0.5, 0.5);
  }
  return off;
}

int visible_views(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& nf, const PointResult& best,
                  double min_ncc, const Options& opts, Scratch& scratch, int* out) {
  if (!best.valid()) return 0;
  const Eigen::Vector3d& n = orientations()[best.orientation];
  Eigen::Vector3d a1, a2;
  patch_axes(n, nf.normalized(), opts.point_grid, a1, a2);
  out[0] = best.ref;
  const int na = agreeing_views(views, X, n, a1, opts.point_grid ? &a2 : nullptr, best.spacing, best.ref, min_ncc,
                                kMaxK - 1, opts, scratch, out + 1);
  return 1 + na;
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
