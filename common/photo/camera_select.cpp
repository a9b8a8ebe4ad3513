#include "common/photo/camera_select.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tetmvs::photo {

void Scratch::reserve(int nv, const Options& opts) {
  if (nv == num_views && opts.k == k && opts.mu == mu) return;
  if (nv != num_views) {
    cache.assign(nv, ViewCache{});
    cand.assign(nv, Candidate{});
  }
  num_views = nv;
  k = opts.k;
  mu = opts.mu;
  lanes = (k + 3) / 4 * 4;
  // grown only: callers that switch between k (agreeing_views) do not reallocate
  const std::size_t ns = static_cast<std::size_t>(lanes) * mu * mu, nc = static_cast<std::size_t>(lanes) * lanes;
  if (samples.size() < ns) samples.assign(ns, 0.f);
  if (corr.size() < nc) corr.assign(nc, 0.f);
  if (static_cast<int>(views.size()) < k) views.assign(k, -1);
  if (static_cast<int>(row.size()) < k) row.assign(k, 0.f);
  if (static_cast<int>(row_idx.size()) < k) row_idx.assign(k, -1);
}

namespace detail {

void prepare_centre(const Views& views, const Eigen::Vector3d& X, const Options& opts, Scratch& s) {
  s.reserve(views.size(), opts);
  for (int i = 0; i < views.size(); ++i) {
    const View& v = views[i];
    Scratch::ViewCache& c = s.cache[i];
    c.usable = false;
    if (s.hidden && s.hidden[i]) continue;
    c.h0 = v.project_h(X);
    if (!(c.h0.z() > 0)) continue;
    const double u = c.h0.x() / c.h0.z(), w = c.h0.y() / c.h0.z();
    if (!(u >= 0 && w >= 0 && u <= v.width - 1 && w <= v.height - 1)) continue;
    if (opts.use_silhouettes && !v.in_silhouette(u, w)) continue;
    c.dir = (v.centre - X).normalized();
    c.usable = true;
  }
}

int gather_candidates(const Views& views, const Eigen::Vector3d& n, const Options& opts, Scratch& s) {
  const double cos_cone = std::cos(opts.cone_deg * std::numbers::pi / 180.0);
  int m = 0;
  for (int i = 0; i < views.size(); ++i) {
    const Scratch::ViewCache& c = s.cache[i];
    if (!c.usable) continue;
    const double cs = n.dot(c.dir);
    if (cs >= cos_cone) s.cand[m++] = Candidate{cs, i};
  }
  const int top = std::min(m, opts.k);
  std::partial_sort(s.cand.begin(), s.cand.begin() + top, s.cand.begin() + m, better_candidate);
  return m;
}

}  // namespace detail

std::vector<Candidate> select_cameras(const Views& views, const Eigen::Vector3d& X,
                                      const Eigen::Vector3d& n, const Options& opts) {
  Scratch s;
  detail::prepare_centre(views, X, opts, s);
  const int m = detail::gather_candidates(views, n.normalized(), opts, s);
  std::vector<Candidate> out(s.cand.begin(), s.cand.begin() + m);
  std::sort(out.begin(), out.end(), better_candidate);
  return out;
}

}  // namespace tetmvs::photo
