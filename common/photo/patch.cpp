#include "common/photo/patch.h"

#include <algorithm>
#include <limits>

#include "common/image.h"
#include "common/photo/camera_select.h"
#include "common/photo/ncc.h"
#include "common/photo/orientations.h"

namespace tetmvs::photo {
namespace detail {

namespace {
// Samples the patch in one view into row (mu or mu*mu values). False when a sample is
// behind the camera or outside the image.
bool sample_view(const View& v, const Eigen::Vector3d& h0, const Eigen::Vector3d& b1,
                 const Eigen::Vector3d* b2, int mu, float* row) {
  const int c = mu / 2;
  if (!b2) {
    for (int i = 0; i < mu; ++i) {
      const Eigen::Vector3d h = h0 + static_cast<double>(i - c) * b1;
      if (!(h.z() > 0)) return false;
      const double iw = 1.0 / h.z();
      if (!sample_bilinear(v.grey, h.x() * iw, h.y() * iw, row[i])) return false;
    }
    return true;
  }
  for (int j = 0; j < mu; ++j) {
    const Eigen::Vector3d hj = h0 + static_cast<double>(j - c) * (*b2);
    for (int i = 0; i < mu; ++i) {
      const Eigen::Vector3d h = hj + static_cast<double>(i - c) * b1;
      if (!(h.z() > 0)) return false;
      const double iw = 1.0 / h.z();
      if (!sample_bilinear(v.grey, h.x() * iw, h.y() * iw, row[j * mu + i])) return false;
    }
  }
  return true;
}
}  // namespace

void score_prepared(const Views& views, const Eigen::Vector3d& n, const Eigen::Vector3d& a1,
                    const Eigen::Vector3d* a2, const Options& opts, Scratch& s, PatchResult& out) {
  out = PatchResult{};
  const int m = gather_candidates(views, n, opts, s);
  const int k = opts.k, need = opts.adaptive_k ? std::min(opts.k_prime() + 1, 4) : opts.k_prime() + 1;
  int kp = opts.k_prime();
  const int top = std::min(m, k);
  double spacing = std::numeric_limits<double>::infinity();
  for (int i = 0; i < top; ++i) {
    const int v = s.cand[i].view;
    spacing = std::min(spacing, s.cache[v].h0.z() * views[v].inv_focal);
  }
  if (top > 0) out.spacing = static_cast<float>(spacing);
  if (m < need) return;

  const int mu = opts.mu;
  const int ns = a2 ? mu * mu : mu;
  const Eigen::Vector3d d1 = a1 * spacing;
  const Eigen::Vector3d d2 = a2 ? Eigen::Vector3d(*a2 * spacing) : Eigen::Vector3d::Zero();
  int used = 0;
  bool rest_sorted = (top == m);
  for (int ci = 0; ci < m && used < k; ++ci) {
    if (used + (m - ci) < need) break;  // too few candidates left: cannot become defined
    if (ci == top && !rest_sorted) {
      std::sort(s.cand.begin() + top, s.cand.begin() + m, better_candidate);
      rest_sorted = true;
    }
    const int v = s.cand[ci].view;
    const View& view = views[v];
    const Eigen::Vector3d b1 = view.project_dir(d1);
    const Eigen::Vector3d b2 = view.project_dir(d2);
    float* row = s.samples.data() + static_cast<size_t>(used) * ns;
    if (!sample_view(view, s.cache[v].h0, b1, a2 ? &b2 : nullptr, mu, row)) continue;
    normalize_patch(row, ns, static_cast<float>(opts.min_std), row);
    s.views[used++] = v;
  }
  if (used < need) return;
  if (opts.adaptive_k && used < k) kp = std::max(used / 2, 3);

  // Pairwise NCC (symmetric).
  float* C = s.corr.data();
  for (int a = 0; a < used; ++a) {
    C[a * k + a] = 1.f;
    const float* ra = s.samples.data() + static_cast<size_t>(a) * ns;
    for (int b = a + 1; b < used; ++b) {
      const float x = ncc_normalized(ra, s.samples.data() + static_cast<size_t>(b) * ns, ns);
      C[a * k + b] = x;
      C[b * k + a] = x;
    }
  }
  // Each view as reference: mean of its best k' NCCs; the best reference wins
  // (ties: the earlier view, i.e. the smaller angle).
  float best = -std::numeric_limits<float>::infinity();
  int best_r = -1;
  int idx[kMaxK];
  for (int r = 0; r < used; ++r) {
    int q = 0;
    for (int j = 0; j < used; ++j)
      if (j != r) idx[q++] = j;
    const float* Cr = C + r * k;
    std::partial_sort(idx, idx + kp, idx + q,
                      [Cr](int a, int b) { return Cr[a] > Cr[b] || (Cr[a] == Cr[b] && a < b); });
    float sum = 0.f;
    for (int t = 0; t < kp; ++t) sum += Cr[idx[t]];
    const float mean = sum / static_cast<float>(kp);
    if (mean > best) {
      best = mean;
      best_r = r;
      for (int t = 0; t < kp; ++t) out.partners[t] = s.views[idx[t]];
    }
  }
  out.score = best;
  out.ref = s.views[best_r];
  out.num_partners = kp;
  out.num_views = used;
  for (int i = 0; i < used; ++i) out.views[i] = s.views[i];
}

}  // namespace detail

PatchResult score_line(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& nx,
                       const Eigen::Vector3d& nf, const Options& opts, Scratch& scratch) {
  PatchResult out;
  const double lx = nx.norm(), lf = nf.norm();
  if (!(lx > 0) || !(lf > 0)) return out;
  const Eigen::Vector3d n = nx / lx, f = nf / lf;
  Eigen::Vector3d d = n.cross(f);
  const double ld = d.norm();
  d = ld > 1e-9 ? Eigen::Vector3d(d / ld) : stable_perpendicular(f);
  detail::prepare_centre(views, X, opts, scratch);
  detail::score_prepared(views, n, d, nullptr, opts, scratch, out);
  return out;
}

PatchResult score_patch(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& n,
                        const Options& opts, Scratch& scratch) {
  PatchResult out;
  const double ln = n.norm();
  if (!(ln > 0)) return out;
  const Eigen::Vector3d u = n / ln;
  const Eigen::Vector3d a1 = stable_perpendicular(u);
  const Eigen::Vector3d a2 = u.cross(a1);
  detail::prepare_centre(views, X, opts, scratch);
  detail::score_prepared(views, u, a1, &a2, opts, scratch, out);
  return out;
}

}  // namespace tetmvs::photo
