// Normalized cross-correlation (NCC) of image patches: the kernel of the
// photo-consistency measure (paper sections 2.3 and 3.1, docs/photo.md).
//
// NCC(a, b) = sum (a_i - mean a)(b_i - mean b) / sqrt(sum (a_i - mean a)^2 sum (b_i - mean b)^2)
//
// It is invariant to gain and offset (a -> g a + o, g > 0). A patch whose standard
// deviation is below `min_std` is "constant": its NCC with anything is 0 (never NaN).
// For many pairs, normalize each patch once (normalize_patch) and take dot products
// (ncc_normalized): that is what the measure does.
#pragma once
#include <algorithm>
#include <cmath>

namespace tetmvs::photo {

namespace detail {
// The end of both normalizations: out (n centred samples, sum of squares ss) scaled to unit
// norm, or zeros and false when the standard deviation sqrt(ss / n) is below min_std
// (ss < n min_std^2; ss == 0 always counts).
inline bool scale_to_unit(float* out, int n, float ss, float min_std) {
  if (!(ss > static_cast<float>(n) * min_std * min_std) || ss <= 0.f) {
    for (int i = 0; i < n; ++i) out[i] = 0.f;
    return false;
  }
  const float inv = 1.f / std::sqrt(ss);
  for (int i = 0; i < n; ++i) out[i] *= inv;
  return true;
}
}  // namespace detail

// Writes (x - mean) / ||x - mean|| to out (out may alias x). Returns false, and writes
// zeros, when the patch is constant (standard deviation < min_std).
inline bool normalize_patch(const float* x, int n, float min_std, float* out) {
  float mean = 0.f;
  for (int i = 0; i < n; ++i) mean += x[i];
  mean /= static_cast<float>(n);
  float ss = 0.f;
  for (int i = 0; i < n; ++i) {
    const float c = x[i] - mean;
    out[i] = c;
    ss += c * c;
  }
  return detail::scale_to_unit(out, n, ss, min_std);
}

// Sum of t^2 over a rows x mu patch, t = i - mu/2 the sample's offset along a row: the
// denominator of the least-squares ramp fit of normalize_patch_detrended (exact in float).
inline float ramp_norm2(int mu, int rows) {
  const int c = mu / 2;
  return static_cast<float>(rows * (c * (c + 1) * (2 * c + 1) / 3));
}

// De-trended normalization of a rows x mu patch (rows = 1: a line; rows = mu: a grid,
// sample (j, i) at x[j * mu + i]): removes the mean and the least-squares linear ramp
// along each axis (t1 = i - mu/2, and t2 = j - mu/2 for a grid), then scales the residual
// to unit norm. A pure shading gradient leaves no residual, so on smooth untextured
// surfaces two ramps no longer correlate perfectly whatever their alignment
// (docs/photoconsist.md, "Real dinoRing"). A residual whose standard deviation is below
// min_std is "constant": zeros, and false. The operations and their order are the
// contract of the SIMD kernel (common/photo/patch.cpp), which must match them bit for bit.
inline bool normalize_patch_detrended(const float* x, int mu, int rows, float min_std, float* out) {
  const int n = mu * rows, c = mu / 2;
  float mean = 0.f;
  for (int i = 0; i < n; ++i) mean += x[i];
  mean /= static_cast<float>(n);
  float s1 = 0.f, s2 = 0.f;
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < mu; ++i) {
      const float v = x[j * mu + i] - mean;
      out[j * mu + i] = v;
      s1 += v * static_cast<float>(i - c);
      s2 += v * static_cast<float>(j - c);
    }
  const float d = ramp_norm2(mu, rows);
  const float g1 = s1 / d, g2 = rows > 1 ? s2 / d : 0.f;
  float ss = 0.f;
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < mu; ++i) {
      const float r = (out[j * mu + i] - g1 * static_cast<float>(i - c)) - g2 * static_cast<float>(j - c);
      out[j * mu + i] = r;
      ss += r * r;
    }
  return detail::scale_to_unit(out, n, ss, min_std);
}

// NCC of two normalized patches (outputs of normalize_patch): their dot product,
// clamped to [-1, 1] against rounding. 0 when either patch was constant.
inline float ncc_normalized(const float* a, const float* b, int n) {
  float s = 0.f;
  for (int i = 0; i < n; ++i) s += a[i] * b[i];
  return std::clamp(s, -1.f, 1.f);
}

// NCC of two raw patches of n samples (n <= 1024). Convenience for tests and one-off uses.
float ncc(const float* a, const float* b, int n, float min_std = 1e-3f);

}  // namespace tetmvs::photo
