#include "common/photo/patch.h"

#include <algorithm>
#include <cmath>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "common/image.h"
#include "common/photo/camera_select.h"
#include "common/photo/ncc.h"
#include "common/photo/orientations.h"

namespace tetmvs::photo {
namespace detail {

namespace {

// The kernel below is written so that every float and double operation is the one of
// the straightforward formulation (per view: sample, normalize_patch; per pair:
// ncc_normalized), in the same order, so results are bit-identical to it
// (docs/photo.md, "Speed"). Only the layout and the loop order differ:
//   - samples are stored transposed, S[i * L + view slot] (L = k rounded up to 4), so
//     the normalization of all views and each row of the NCC matrix are computed for
//     4 views at a time in SIMD lanes, each lane summing over i in the same order as
//     the scalar loops (no reassociation);
//   - bilinear sampling takes a fast path (truncation instead of floor) when the
//     sample is strictly inside the image, which is exactly floor there.

// Bilinear sample at (u, v), as sample_bilinear of common/image.h. Returns false outside.
inline bool sample_fast(const float* data, std::size_t step, int width, int height, const cv::Mat& img,
                        double u, double v, float& out) {
  if (u >= 0.0 && v >= 0.0 && u < static_cast<double>(width - 1) && v < static_cast<double>(height - 1)) {
    // 0 <= u < width - 1: floor(u) == int(u), and u0 + 1 <= width - 1 is inside.
    const int u0 = static_cast<int>(u), v0 = static_cast<int>(v);
    const float a = static_cast<float>(u - u0), b = static_cast<float>(v - v0);
    const float* r0 = data + static_cast<std::size_t>(v0) * step + u0;
    const float* r1 = r0 + step;
    out = (1 - b) * ((1 - a) * r0[0] + a * r0[1]) + b * ((1 - a) * r1[0] + a * r1[1]);
    return true;
  }
  return sample_bilinear(img, u, v, out);  // last row/column, outside, NaN
}

#if defined(__SSE2__)
// Bilinear samples at the four points (ua, va) (two lanes) and (ub, vb) (two lanes) into
// o[0..3], every point strictly inside the image (truncation == floor, its 2 x 2
// neighbourhood inside); each lane does sample_fast's scalar operations.
inline void bilinear4_inside(const float* data, std::size_t step, __m128d ua, __m128d ub, __m128d va, __m128d vb,
                             float* o) {
  const __m128 onef = _mm_set1_ps(1.f);
  const __m128i iua = _mm_cvttpd_epi32(ua), iub = _mm_cvttpd_epi32(ub);
  const __m128i iva = _mm_cvttpd_epi32(va), ivb = _mm_cvttpd_epi32(vb);
  const __m128 a = _mm_movelh_ps(_mm_cvtpd_ps(_mm_sub_pd(ua, _mm_cvtepi32_pd(iua))),
                                 _mm_cvtpd_ps(_mm_sub_pd(ub, _mm_cvtepi32_pd(iub))));
  const __m128 b = _mm_movelh_ps(_mm_cvtpd_ps(_mm_sub_pd(va, _mm_cvtepi32_pd(iva))),
                                 _mm_cvtpd_ps(_mm_sub_pd(vb, _mm_cvtepi32_pd(ivb))));
  alignas(16) int iu[4], iv[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(iu), _mm_unpacklo_epi64(iua, iub));
  _mm_store_si128(reinterpret_cast<__m128i*>(iv), _mm_unpacklo_epi64(iva, ivb));
  alignas(16) float p00[4], p01[4], p10[4], p11[4];
  for (int q = 0; q < 4; ++q) {
    const float* r0 = data + static_cast<std::size_t>(iv[q]) * step + iu[q];
    p00[q] = r0[0];
    p01[q] = r0[1];
    p10[q] = r0[step];
    p11[q] = r0[step + 1];
  }
  const __m128 oma = _mm_sub_ps(onef, a), omb = _mm_sub_ps(onef, b);
  const __m128 top = _mm_add_ps(_mm_mul_ps(oma, _mm_load_ps(p00)), _mm_mul_ps(a, _mm_load_ps(p01)));
  const __m128 bot = _mm_add_ps(_mm_mul_ps(oma, _mm_load_ps(p10)), _mm_mul_ps(a, _mm_load_ps(p11)));
  _mm_storeu_ps(o, _mm_add_ps(_mm_mul_ps(omb, top), _mm_mul_ps(b, bot)));
}
#endif

// Samples the line h0 + (i - c) b1, i = 0..mu-1, into col[i * L]. False when a sample is
// behind the camera or outside the image.
bool sample_line(const View& v, const Eigen::Vector3d& h0, const Eigen::Vector3d& b1, int mu, float* col,
                 int L) {
  const int c = mu / 2;
  const float* data = v.grey.ptr<float>(0);
  const std::size_t step = v.grey.step1();
#if defined(__SSE2__)
  alignas(16) double us[kMaxMu + 1], vs[kMaxMu + 1];
  // Projection, two samples per step; each lane does the scalar operations
  // h = h0 + t b1, iw = 1 / hz, u = hx iw, v = hy iw.
  unsigned front = 0;
  const __m128d zero = _mm_setzero_pd(), one = _mm_set1_pd(1.0);
  const __m128d h0x = _mm_set1_pd(h0.x()), h0y = _mm_set1_pd(h0.y()), h0z = _mm_set1_pd(h0.z());
  const __m128d bx = _mm_set1_pd(b1.x()), by = _mm_set1_pd(b1.y()), bz = _mm_set1_pd(b1.z());
  for (int i = 0; i < mu; i += 2) {
    const __m128d t = _mm_set_pd(static_cast<double>(i + 1 - c), static_cast<double>(i - c));
    const __m128d hx = _mm_add_pd(h0x, _mm_mul_pd(t, bx));
    const __m128d hy = _mm_add_pd(h0y, _mm_mul_pd(t, by));
    const __m128d hz = _mm_add_pd(h0z, _mm_mul_pd(t, bz));
    front |= static_cast<unsigned>(_mm_movemask_pd(_mm_cmpgt_pd(hz, zero))) << i;
    const __m128d iw = _mm_div_pd(one, hz);
    _mm_store_pd(us + i, _mm_mul_pd(hx, iw));
    _mm_store_pd(vs + i, _mm_mul_pd(hy, iw));
  }
  const unsigned all = (1u << mu) - 1u;  // mu <= kMaxMu = 31
  if ((front & all) != all) return false;
  // Bilinear sampling, four samples per step when all four are strictly inside the image.
  const __m128d w1 = _mm_set1_pd(static_cast<double>(v.width - 1)),
                hm1 = _mm_set1_pd(static_cast<double>(v.height - 1));
  int i = 0;
  for (; i + 4 <= mu; i += 4) {
    const __m128d ua = _mm_load_pd(us + i), ub = _mm_load_pd(us + i + 2);
    const __m128d va = _mm_load_pd(vs + i), vb = _mm_load_pd(vs + i + 2);
    const __m128d ina = _mm_and_pd(_mm_and_pd(_mm_cmpge_pd(ua, zero), _mm_cmpge_pd(va, zero)),
                                   _mm_and_pd(_mm_cmplt_pd(ua, w1), _mm_cmplt_pd(va, hm1)));
    const __m128d inb = _mm_and_pd(_mm_and_pd(_mm_cmpge_pd(ub, zero), _mm_cmpge_pd(vb, zero)),
                                   _mm_and_pd(_mm_cmplt_pd(ub, w1), _mm_cmplt_pd(vb, hm1)));
    if ((_mm_movemask_pd(ina) & _mm_movemask_pd(inb)) != 3) {
      for (int q = i; q < i + 4; ++q)
        if (!sample_fast(data, step, v.width, v.height, v.grey, us[q], vs[q], col[static_cast<std::size_t>(q) * L]))
          return false;
      continue;
    }
    // Inside: truncation == floor.
    alignas(16) float o[4];
    bilinear4_inside(data, step, ua, ub, va, vb, o);
    for (int q = 0; q < 4; ++q) col[static_cast<std::size_t>(i + q) * L] = o[q];
  }
  for (; i < mu; ++i)
    if (!sample_fast(data, step, v.width, v.height, v.grey, us[i], vs[i], col[static_cast<std::size_t>(i) * L]))
      return false;
  return true;
#else
  double us[kMaxMu], vs[kMaxMu];
  bool front = true;
  for (int i = 0; i < mu; ++i) {
    const double t = static_cast<double>(i - c);
    const double hx = h0.x() + t * b1.x(), hy = h0.y() + t * b1.y(), hz = h0.z() + t * b1.z();
    front = front && (hz > 0);
    const double iw = 1.0 / hz;
    us[i] = hx * iw;
    vs[i] = hy * iw;
  }
  if (!front) return false;
  for (int i = 0; i < mu; ++i)
    if (!sample_fast(data, step, v.width, v.height, v.grey, us[i], vs[i], col[static_cast<std::size_t>(i) * L]))
      return false;
  return true;
#endif
}

// Samples the mu x mu grid around h0 into col[(j mu + i) L]: sample (i, j) at the affine
// (first-order) projection of h0 + (i - c) b1 + (j - c) b2 about the centre,
//   u = u0 + (i - c) du1 + (j - c) du2,  v = v0 + (i - c) dv1 + (j - c) dv2,
// u0 = h0.x / h0.z, du = (b.x - u0 b.z) / h0.z (and likewise v). On a patch of a few pixels
// this differs from the exact perspective projection by far less than a hundredth of a
// pixel, and it needs no division per sample. False when the centre is behind the camera
// or a sample falls outside the image.
bool sample_grid(const View& v, const Eigen::Vector3d& h0, const Eigen::Vector3d& b1, const Eigen::Vector3d& b2,
                 int mu, float* col, int L) {
  if (!(h0.z() > 0)) return false;
  const GridAxes g = grid_axes(h0, b1, b2);
  const int c = mu / 2;
  const float* data = v.grey.ptr<float>(0);
  const std::size_t step = v.grey.step1();
  // Fast path when the patch's bounding box is strictly inside the image: every sample's
  // truncation is its floor and its 2 x 2 neighbourhood is inside (as in sample_fast).
  const double ru = c * (std::abs(g.du1) + std::abs(g.du2)), rv = c * (std::abs(g.dv1) + std::abs(g.dv2));
  const bool inside = g.u0 - ru >= 0.0 && g.v0 - rv >= 0.0 && g.u0 + ru < static_cast<double>(v.width - 1) &&
                      g.v0 + rv < static_cast<double>(v.height - 1);
  if (inside) {
    // Every sample's coordinates first (the operations of the scalar loop below), then
    // the bilinear samples four at a time over the whole patch in row order.
    alignas(16) double us[kMaxMu * kMaxMu + 3], vs[kMaxMu * kMaxMu + 3];
    const int ns = mu * mu;
    for (int j = 0, q = 0; j < mu; ++j) {
      const double tj = static_cast<double>(j - c);
      const double uj = g.u0 + tj * g.du2, vj = g.v0 + tj * g.dv2;
      for (int i = 0; i < mu; ++i, ++q) {
        const double ti = static_cast<double>(i - c);
        us[q] = uj + ti * g.du1;
        vs[q] = vj + ti * g.dv1;
      }
    }
    int q = 0;
#if defined(__SSE2__)
    for (; q + 4 <= ns; q += 4) {
      alignas(16) float o[4];
      bilinear4_inside(data, step, _mm_load_pd(us + q), _mm_load_pd(us + q + 2), _mm_load_pd(vs + q),
                       _mm_load_pd(vs + q + 2), o);
      for (int r = 0; r < 4; ++r) col[static_cast<std::size_t>(q + r) * L] = o[r];
    }
#endif
    for (; q < ns; ++q) {
      const double u = us[q], w = vs[q];
      const int u0 = static_cast<int>(u), v0 = static_cast<int>(w);
      const float a = static_cast<float>(u - u0), b = static_cast<float>(w - v0);
      const float* r0 = data + static_cast<std::size_t>(v0) * step + u0;
      const float* r1 = r0 + step;
      col[static_cast<std::size_t>(q) * L] = (1 - b) * ((1 - a) * r0[0] + a * r0[1]) + b * ((1 - a) * r1[0] + a * r1[1]);
    }
    return true;
  }
  for (int j = 0; j < mu; ++j) {
    const double tj = static_cast<double>(j - c);
    const double uj = g.u0 + tj * g.du2, vj = g.v0 + tj * g.dv2;
    float* out = col + static_cast<std::size_t>(j * mu) * L;
    for (int i = 0; i < mu; ++i) {
      const double ti = static_cast<double>(i - c);
      if (!sample_fast(data, step, v.width, v.height, v.grey, uj + ti * g.du1, vj + ti * g.dv1,
                       out[static_cast<std::size_t>(i) * L]))
        return false;
    }
  }
  return true;
}

// normalize_patch (ncc.h) of the first `used` columns of S (ns = rows * mu rows of the
// transposed layout, L lanes), in place; normalize_patch_detrended when `detrend`.
void normalize_columns(float* S, int mu, int rows, int L, int used, float min_std, bool detrend) {
  const int ns = mu * rows;
  float mean[kMaxK + 3], ss[kMaxK + 3], inv[kMaxK + 3];
  for (int l = 0; l < L; ++l) mean[l] = 0.f, ss[l] = 0.f;
  for (int i = 0; i < ns; ++i) {
    const float* r = S + static_cast<std::size_t>(i) * L;
    for (int l = 0; l < L; ++l) mean[l] += r[l];
  }
  const float fn = static_cast<float>(ns);
  for (int l = 0; l < L; ++l) mean[l] /= fn;
  if (!detrend) {
    for (int i = 0; i < ns; ++i) {
      float* r = S + static_cast<std::size_t>(i) * L;
      for (int l = 0; l < L; ++l) {
        const float c = r[l] - mean[l];
        r[l] = c;
        ss[l] += c * c;
      }
    }
  } else {
    // As normalize_patch_detrended, lane by lane: centre and accumulate the ramp
    // moments, then subtract the ramps and accumulate the residual's sum of squares.
    const int c = mu / 2;
    float s1[kMaxK + 3], s2[kMaxK + 3], g1[kMaxK + 3], g2[kMaxK + 3];
    for (int l = 0; l < L; ++l) s1[l] = 0.f, s2[l] = 0.f;
    for (int j = 0; j < rows; ++j)
      for (int i = 0; i < mu; ++i) {
        float* r = S + static_cast<std::size_t>(j * mu + i) * L;
        const float t1 = static_cast<float>(i - c), t2 = static_cast<float>(j - c);
        for (int l = 0; l < L; ++l) {
          const float v = r[l] - mean[l];
          r[l] = v;
          s1[l] += v * t1;
          s2[l] += v * t2;
        }
      }
    const float d = ramp_norm2(mu, rows);
    for (int l = 0; l < L; ++l) {
      g1[l] = s1[l] / d;
      g2[l] = rows > 1 ? s2[l] / d : 0.f;
    }
    for (int j = 0; j < rows; ++j)
      for (int i = 0; i < mu; ++i) {
        float* r = S + static_cast<std::size_t>(j * mu + i) * L;
        const float t1 = static_cast<float>(i - c), t2 = static_cast<float>(j - c);
        for (int l = 0; l < L; ++l) {
          const float v = (r[l] - g1[l] * t1) - g2[l] * t2;
          r[l] = v;
          ss[l] += v * v;
        }
      }
  }
  const float thr = fn * min_std * min_std;
  bool constant = false;
  for (int l = 0; l < L; ++l) {
    const bool ok = (ss[l] > thr) && !(ss[l] <= 0.f);
    inv[l] = ok ? 1.f / std::sqrt(ss[l]) : 0.f;
    constant = constant || (!ok && l < used);
  }
  for (int i = 0; i < ns; ++i) {
    float* r = S + static_cast<std::size_t>(i) * L;
    for (int l = 0; l < L; ++l) r[l] *= inv[l];
  }
  if (constant)  // exact zeros (not -0) for constant patches, as normalize_patch writes
    for (int l = 0; l < used; ++l)
      if (inv[l] == 0.f)
        for (int i = 0; i < ns; ++i) S[static_cast<std::size_t>(i) * L + l] = 0.f;
}

// C[a * L + b] = clamp(sum_i S[i][a] S[i][b], -1, 1) for a < b < used (the sum in order of
// i, as ncc_normalized), mirrored to C[b * L + a]. The diagonal is left unspecified.
void correlate(const float* S, int ns, int L, int used, float* C) {
#if defined(__SSE2__)
  const __m128 lo = _mm_set1_ps(-1.f), hi = _mm_set1_ps(1.f);
  const int nc = L / 4;
  for (int a = 0; a + 1 < used; ++a) {
    const int c0 = a / 4;
    __m128 acc[kMaxK / 4];
    for (int q = c0; q < nc; ++q) acc[q] = _mm_setzero_ps();
    for (int i = 0; i < ns; ++i) {
      const float* r = S + static_cast<std::size_t>(i) * L;
      const __m128 s = _mm_set1_ps(r[a]);
      for (int q = c0; q < nc; ++q) acc[q] = _mm_add_ps(acc[q], _mm_mul_ps(s, _mm_loadu_ps(r + 4 * q)));
    }
    // clamp as std::clamp(x, -1, 1): x < -1 ? -1 : (1 < x ? 1 : x)
    for (int q = c0; q < nc; ++q) {
      const __m128 x = acc[q];
      __m128 y = _mm_or_ps(_mm_and_ps(_mm_cmplt_ps(hi, x), hi), _mm_andnot_ps(_mm_cmplt_ps(hi, x), x));
      y = _mm_or_ps(_mm_and_ps(_mm_cmplt_ps(x, lo), lo), _mm_andnot_ps(_mm_cmplt_ps(x, lo), y));
      _mm_storeu_ps(C + static_cast<std::size_t>(a) * L + 4 * q, y);
    }
  }
#else
  for (int a = 0; a + 1 < used; ++a) {
    float acc[kMaxK];
    for (int b = a + 1; b < used; ++b) acc[b] = 0.f;
    for (int i = 0; i < ns; ++i) {
      const float* r = S + static_cast<std::size_t>(i) * L;
      for (int b = a + 1; b < used; ++b) acc[b] += r[a] * r[b];
    }
    for (int b = a + 1; b < used; ++b) C[a * L + b] = std::clamp(acc[b], -1.f, 1.f);
  }
#endif
  for (int a = 0; a < used; ++a)
    for (int b = a + 1; b < used; ++b) C[b * L + a] = C[a * L + b];
}

}  // namespace

namespace {

// The end of the measure, on the samples of `used` views in S (columns in order of
// preference, slot t holding view s.views[t]): normalizes every column, correlates every
// pair and picks the reference whose best kp NCCs have the highest mean.
void finish(int used, int kp, int mu, int rows, const Options& opts, Scratch& s, PatchResult& out) {
  const int L = s.lanes;
  float* S = s.samples.data();
  normalize_columns(S, mu, rows, L, used, static_cast<float>(opts.min_std), opts.detrend);
  float* C = s.corr.data();
  correlate(S, mu * rows, L, used, C);

  // Each view as reference: mean of its best k' NCCs, summed in descending order (as a
  // sort of its row would); the best reference wins (ties: the earlier view, i.e. the
  // smaller angle). C is symmetric, so row j of C holds column j: the k' largest of every
  // row are kept for 4 references at a time by branch-free insertion (max/min), with the
  // diagonal set below every NCC so that it is never among them.
  for (int a = 0; a < used; ++a) C[static_cast<std::size_t>(a) * L + a] = -2.f;
  float mean_r[kMaxK + 3];
  {
    const float fkp = static_cast<float>(kp);
#if defined(__SSE2__)
    for (int q = 0; q * 4 < used; ++q) {
      __m128 topv[kMaxKPrime];
      for (int t = 0; t < kp; ++t) topv[t] = _mm_set1_ps(-3.f);
      for (int j = 0; j < used; ++j) {
        __m128 x = _mm_loadu_ps(C + static_cast<std::size_t>(j) * L + 4 * q);
        for (int t = 0; t < kp; ++t) {
          const __m128 hi = _mm_max_ps(topv[t], x);
          x = _mm_min_ps(topv[t], x);
          topv[t] = hi;
        }
      }
      __m128 sum = _mm_setzero_ps();
      for (int t = 0; t < kp; ++t) sum = _mm_add_ps(sum, topv[t]);
      _mm_storeu_ps(mean_r + 4 * q, _mm_div_ps(sum, _mm_set1_ps(fkp)));
    }
#else
    for (int r = 0; r < used; ++r) {
      float topv[kMaxKPrime];
      for (int t = 0; t < kp; ++t) topv[t] = -3.f;
      for (int j = 0; j < used; ++j) {
        float x = C[static_cast<std::size_t>(j) * L + r];
        for (int t = 0; t < kp; ++t) {
          const float hi = std::max(topv[t], x);
          x = std::min(topv[t], x);
          topv[t] = hi;
        }
      }
      float sum = 0.f;
      for (int t = 0; t < kp; ++t) sum += topv[t];
      mean_r[r] = sum / fkp;
    }
#endif
  }
  float best = -std::numeric_limits<float>::infinity();
  int best_r = -1;
  for (int r = 0; r < used; ++r)
    if (mean_r[r] > best) best = mean_r[r], best_r = r;
  {
    // The best reference's partners: its k' largest NCCs, ties by the lower view slot.
    const float* Cr = C + static_cast<std::size_t>(best_r) * L;
    int idx[kMaxK];
    int q = 0;
    for (int j = 0; j < used; ++j)
      if (j != best_r) idx[q++] = j;
    std::partial_sort(idx, idx + kp, idx + q,
                      [Cr](int a, int b) { return Cr[a] > Cr[b] || (Cr[a] == Cr[b] && a < b); });
    for (int t = 0; t < kp; ++t) {
      out.partners[t] = s.views[idx[t]];
      out.partner_ncc[t] = Cr[idx[t]];
    }
  }
  out.score = best;
  out.ref = s.views[best_r];
  out.num_partners = kp;
  out.num_views = used;
  for (int i = 0; i < used; ++i) out.views[i] = s.views[i];
}

// Options::outline_fill on the samples of a patch (line along b1, or grid along b1 and b2,
// with `rows` rows) centred at homogeneous projection h0 of the view, in col[q L]: the
// samples whose nearest pixel lies outside the silhouette take the mean of the others.
// False when fewer than half lie inside. With View::inside_px, a patch whose centre lies
// farther inside than the patch's extent is left as it is without a look at its samples.
bool fill_outside_silhouette(const View& view, const Eigen::Vector3d& h0, const Eigen::Vector3d& b1,
                             const Eigen::Vector3d& b2, int mu, int rows, float* col, int L) {
  if (view.sil.empty()) return true;
  const GridAxes g = grid_axes(h0, b1, b2);
  const int c = mu / 2, cr = rows / 2;
  const double reach = c * (std::abs(g.du1) + std::abs(g.dv1)) + cr * (std::abs(g.du2) + std::abs(g.dv2));
  const int x0 = static_cast<int>(std::lround(g.u0)), y0 = static_cast<int>(std::lround(g.v0));
  if (!view.inside_px.empty() && x0 >= 0 && y0 >= 0 && x0 < view.width && y0 < view.height &&
      view.inside_px.at<std::uint8_t>(y0, x0) > reach + 1)
    return true;
  bool outside[kMaxMu * kMaxMu];
  double sum = 0;
  int in = 0;
  for (int j = 0, q = 0; j < rows; ++j)
    for (int i = 0; i < mu; ++i, ++q) {
      outside[q] = !view.in_silhouette(g.u0 + (i - c) * g.du1 + (j - cr) * g.du2, g.v0 + (i - c) * g.dv1 + (j - cr) * g.dv2);
      if (!outside[q]) sum += col[static_cast<std::size_t>(q) * L], ++in;
    }
  if (2 * in < mu * rows) return false;
  const float mean = static_cast<float>(sum / in);
  for (int q = 0; q < mu * rows; ++q)
    if (outside[q]) col[static_cast<std::size_t>(q) * L] = mean;
  return true;
}

// Samples the patch (line along d1, or grid along d1 and d2: world steps of one sample)
// centred at homogeneous projection h0 of view v into column `slot` of the samples; with
// `fill`, Options::outline_fill.
bool sample_patch(const View& view, const Eigen::Vector3d& h0, const Eigen::Vector3d& d1, const Eigen::Vector3d* d2,
                  int mu, bool fill, Scratch& s, int slot) {
  float* S = s.samples.data() + slot;
  const Eigen::Vector3d b1 = view.project_dir(d1);
  const Eigen::Vector3d b2 = d2 ? view.project_dir(*d2) : Eigen::Vector3d::Zero();
  if (!(d2 ? sample_grid(view, h0, b1, b2, mu, S, s.lanes) : sample_line(view, h0, b1, mu, S, s.lanes))) return false;
  return !fill || fill_outside_silhouette(view, h0, b1, b2, mu, d2 ? mu : 1, S, s.lanes);
}

}  // namespace

void score_prepared(const Views& views, const Eigen::Vector3d& n, const Eigen::Vector3d& a1,
                    const Eigen::Vector3d* a2, const Options& opts, Scratch& s, PatchResult& out) {
  out = PatchResult{};
  const int m = gather_candidates(views, n, opts, s);
  const int k = opts.k, need = opts.min_views();
  const int top = std::min(m, k);
  double spacing = std::numeric_limits<double>::infinity();
  for (int i = 0; i < top; ++i) {
    const int v = s.cand[i].view;
    spacing = std::min(spacing, s.cache[v].h0.z() * views[v].inv_focal);
  }
  if (top > 0) out.spacing = static_cast<float>(spacing);
  if (m < need) return;

  const int mu = opts.mu;
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
    if (!sample_patch(views[v], s.cache[v].h0, d1, a2 ? &d2 : nullptr, mu, opts.outline_fill, s, used)) continue;
    s.views[used++] = v;
  }
  if (used < need) return;
  finish(used, opts.partners_for(used), mu, a2 ? mu : 1, opts, s, out);
}

void score_in_views(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& a1,
                    const Eigen::Vector3d* a2, double spacing, const int* view_list, int count, int kp,
                    const Options& opts, Scratch& s, PatchResult& out) {
  out = PatchResult{};
  s.reserve(views.size(), opts);
  if (count < 2 || kp < 1 || kp >= count) return;
  const int mu = opts.mu;
  const Eigen::Vector3d d1 = a1 * spacing;
  const Eigen::Vector3d d2 = a2 ? Eigen::Vector3d(*a2 * spacing) : Eigen::Vector3d::Zero();
  for (int t = 0; t < count; ++t) {
    const View& view = views[view_list[t]];
    if (!sample_patch(view, view.project_h(X), d1, a2 ? &d2 : nullptr, mu, opts.outline_fill, s, t)) return;
    s.views[t] = view_list[t];
  }
  out.spacing = static_cast<float>(spacing);
  finish(count, kp, mu, a2 ? mu : 1, opts, s, out);
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

int agreeing_views(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& n, const Eigen::Vector3d& a1,
                   const Eigen::Vector3d* a2, double spacing, int ref, double min_ncc, int max_views,
                   const Options& opts, Scratch& s, int* out) {
  Options o = opts;
  o.k = std::clamp(max_views, 1, kMaxK);
  detail::prepare_centre(views, X, o, s);
  const int m = detail::gather_candidates(views, n, o, s);
  const int top = std::min(m, o.k);
  const int L = s.lanes, mu = o.mu, rows = a2 ? mu : 1;
  const Eigen::Vector3d d1 = a1 * spacing;
  const Eigen::Vector3d d2 = a2 ? Eigen::Vector3d(*a2 * spacing) : Eigen::Vector3d::Zero();
  // the reference first (slot 0), then the other candidates
  int used = 0, ref_slot = -1;
  const View& rv = views[ref];
  if (ref >= 0 && ref < views.size() && detail::sample_patch(rv, rv.project_h(X), d1, a2 ? &d2 : nullptr, mu, o.outline_fill, s, 0)) {
    s.views[0] = ref;
    used = 1;
    ref_slot = 0;
  }
  if (ref_slot < 0) return 0;
  for (int ci = 0; ci < top; ++ci) {
    const int v = s.cand[ci].view;
    if (v == ref) continue;
    if (!detail::sample_patch(views[v], s.cache[v].h0, d1, a2 ? &d2 : nullptr, mu, o.outline_fill, s, used)) continue;
    s.views[used++] = v;
  }
  float* S = s.samples.data();
  detail::normalize_columns(S, mu, rows, L, used, static_cast<float>(o.min_std), o.detrend);
  std::pair<float, int> agree[kMaxK];
  int na = 0;
  for (int t = 1; t < used; ++t) {
    float dot = 0.f;
    for (int i = 0; i < mu * rows; ++i) dot += S[static_cast<std::size_t>(i) * L] * S[static_cast<std::size_t>(i) * L + t];
    if (dot > min_ncc) agree[na++] = {dot, s.views[t]};
  }
  std::sort(agree, agree + na, [](const auto& a, const auto& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); });
  for (int t = 0; t < na; ++t) out[t] = agree[t].second;
  return na;
}

}  // namespace tetmvs::photo
